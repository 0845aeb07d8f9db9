//! `form.png`: the formed blank in an oblique, shaded 3-D view, coloured by shear. The part is
//! turned over (seen from the punch's side, the dome up) and looked at from 35° above the
//! flange's plane and 30° round from the x axis; each element is shaded by the light on it
//! (from over the viewer's left shoulder), so that a wrinkle shows as bands of light and dark
//! where the colour alone would not show it. Elements are drawn far first: the near hide the
//! far (a painter's order, exact for a part seen from one side like this).

use super::{FieldMap, MapContext, PlanQuad, Unit, View};
use crate::core::drawing::DrawingResult;
use crate::core::vec3::{cross, dot, sub, unit};

/// The view's azimuth and elevation, degrees.
const AZIMUTH_DEG: f64 = -30.0;
const ELEVATION_DEG: f64 = 35.0;

/// The view's right, up and towards-the-viewer directions.
fn camera() -> [[f64; 3]; 3] {
    let (az, el) = (AZIMUTH_DEG.to_radians(), ELEVATION_DEG.to_radians());
    // Towards the viewer: from the part, back along the azimuth and up by the elevation.
    let back = [-az.sin() * el.cos(), -az.cos() * el.cos(), el.sin()];
    let right = unit(cross([0.0, 0.0, 1.0], back));
    let up = cross(back, right);
    [right, up, back]
}

/// Every element of the full blank (the solved quarter's mirror images added) as its four
/// corners, turned over (z up the dome), with its |shear| (degrees).
fn full_blank(result: &DrawingResult) -> Vec<([[f64; 3]; 4], f64)> {
    let mirrors: &[[f64; 2]] = if result.quarter {
        &[[1.0, 1.0], [-1.0, 1.0], [1.0, -1.0], [-1.0, -1.0]]
    } else {
        &[[1.0, 1.0]]
    };
    let mut out = Vec::with_capacity(mirrors.len() * result.mesh.quads.len());
    for m in mirrors {
        for (q, s) in result.mesh.quads.iter().zip(&result.shear_deg) {
            let corners = q.map(|n| {
                let p = result.positions[n];
                [m[0] * p[0], m[1] * p[1], -p[2]]
            });
            out.push((corners, s.abs()));
        }
    }
    out
}

/// The formed blank seen obliquely and shaded, coloured by shear (`form.png`).
pub fn form_view(result: &DrawingResult, ctx: &MapContext, locking_angle_deg: f64) -> FieldMap {
    let [right, up, back] = camera();
    let light = unit([
        back[0] - 0.5 * right[0] + 0.6 * up[0],
        back[1] - 0.5 * right[1] + 0.6 * up[1],
        back[2] - 0.5 * right[2] + 0.6 * up[2],
    ]);
    let mut elements = full_blank(result);
    // Far first.
    let depth = |c: &[[f64; 3]; 4]| c.iter().map(|p| dot(*p, back)).sum::<f64>();
    elements.sort_by(|a, b| depth(&a.0).total_cmp(&depth(&b.0)));
    let project = |p: [f64; 3]| [dot(p, right), dot(p, up)];
    let quads: Vec<PlanQuad> = elements.iter().map(|(c, _)| c.map(project)).collect();
    let shade = elements
        .iter()
        .map(|(c, _)| {
            let n = unit(cross(sub(c[2], c[0]), sub(c[3], c[1])));
            0.35 + 0.65 * dot(n, light).abs()
        })
        .collect();
    let values: Vec<f64> = elements.iter().map(|(_, s)| *s).collect();
    let (e, max) = result.max_shear();
    let at = (!result.shear_deg.is_empty()).then(|| {
        let c = result.element_centre(e);
        project([c[0], c[1], -c[2]])
    });
    let title = format!(
        "{}: the formed blank, max shear {} over a woven cell — {}",
        ctx.scene,
        Unit::Degrees.show(max),
        ctx.verdict
    );
    let subtitle = format!(
        "Turned over (the punch's side up), seen from {ELEVATION_DEG}° above the flange, \
         shaded by the light on each element: {}",
        crate::summary::stroke_reached(result, ctx.stroke_mm)
    );
    FieldMap {
        design: ctx.design.to_string(),
        max_at: at,
        peak: Some(max),
        view: Some(View {
            shade,
            axes: ["across the view (mm)".into(), "up the view (mm)".into()],
        }),
        ..FieldMap::shear(title, subtitle, quads, values, locking_angle_deg)
    }
}
