//! The developed view: a run's field drawn on the flat blank before forming, each element
//! where it started. Seen from above, a box's walls stand on edge and their shear is squashed
//! into a line along the die opening; on the flat blank they keep their width.
//!
//! The lines drawn over it are material lines, found on the flat blank from where the
//! material ended (its final depth below the die face, z = 0):
//! - dashed: the material at the foot of the die's entry radius (depth rm), that is at the
//!   die-opening edge — outside it the flange and the die radius, inside it what was drawn in;
//! - dotted (a box's flat-nosed punch only): the material at the top of the punch's nose
//!   radius (depth stroke − rp), that is at the foot of the walls — inside it the bottom.
//!
//! A dome punch has no wall/bottom edge, so it gets the die-opening line only.

use super::{FieldMap, MapContext, Outline, shear_map, tension_map};
use crate::core::drawing::{DrawingResult, Tooling};
use crate::report::contour::{EdgePoint, level_lines};
use crate::report::mirror::MirroredMesh;

/// The full blank of a run: its mesh (the solved quarter mirrored, or the solved mesh), and
/// each node's initial and final position (mm).
pub struct FullBlank {
    pub mesh: MirroredMesh,
    pub initial: Vec<[f64; 3]>,
    pub last: Vec<[f64; 3]>,
}

impl FullBlank {
    pub fn of(result: &DrawingResult) -> FullBlank {
        let nodes = &result.mesh.nodes;
        let mesh = if result.quarter {
            MirroredMesh::of_quarter(nodes, &result.mesh.quads)
        } else {
            MirroredMesh::identity(nodes.len(), &result.mesh.quads)
        };
        let n = mesh.nodes.len();
        let initial = (0..n).map(|i| mesh.point(i, nodes)).collect();
        let last = (0..n).map(|i| mesh.point(i, &result.positions)).collect();
        FullBlank {
            mesh,
            initial,
            last,
        }
    }

    /// The material lines that ended `depth` mm below the die face, as edge points.
    pub fn material_at_depth(&self, depth: f64) -> Vec<Vec<EdgePoint>> {
        let below: Vec<f64> = self.last.iter().map(|p| -p[2]).collect();
        level_lines(&self.mesh.quads, &below, depth)
    }

    /// A line of edge points on the flat blank (initial plan positions).
    pub fn on_flat_blank(&self, line: &[EdgePoint]) -> Vec<[f64; 2]> {
        line.iter()
            .map(|p| {
                let [x, y, _] = p.at(&self.initial);
                [x, y]
            })
            .collect()
    }
}

/// What a line on the developed view marks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MaterialLine {
    /// The material at the die-opening edge: depth rm.
    DieEdge,
    /// The material at the top of the punch's nose radius: depth stroke − rp.
    PunchNose,
}

impl MaterialLine {
    /// The lines meaningful for these tools after `stroke` mm, with their depths (mm): the die
    /// edge always; the punch's nose for a box when a wall stands between the two.
    pub fn of(tooling: &Tooling, stroke: f64) -> Vec<(MaterialLine, f64)> {
        let (rm, nose) = match *tooling {
            Tooling::Box { rm, rp, .. } => (rm, Some(rp)),
            Tooling::Ellipsoid { rm, .. } | Tooling::Hemisphere { rm, .. } => (rm, None),
            // A mesh tool's radii are not known: no line.
            Tooling::Mesh { .. } => return Vec::new(),
        };
        let mut lines = Vec::new();
        if stroke > rm {
            lines.push((MaterialLine::DieEdge, rm));
        }
        if let Some(rp) = nose.filter(|rp| stroke - rp > rm + 1.0) {
            lines.push((MaterialLine::PunchNose, stroke - rp));
        }
        lines
    }
}

/// The shear map on the flat blank.
pub fn shear_developed(
    result: &DrawingResult,
    ctx: &MapContext,
    locking_angle_deg: f64,
) -> FieldMap {
    let values: Vec<f64> = result.shear_deg.iter().map(|s| s.abs()).collect();
    let (peak, _) = result.max_shear();
    developed(
        shear_map(result, ctx, locking_angle_deg),
        result,
        ctx,
        (&values, peak),
        "Shear angle of the yarns",
    )
}

/// The largest-yarn-tension map on the flat blank.
pub fn tension_developed(
    result: &DrawingResult,
    ctx: &MapContext,
    break_tension_n: f64,
) -> FieldMap {
    let (peak, _) = result.neighbourhood_peak(&result.tension_max_n, result.cell_mm);
    developed(
        tension_map(result, ctx, break_tension_n),
        result,
        ctx,
        (&result.tension_max_n, peak),
        "Largest yarn tension",
    )
}

/// A top-view map `map` redrawn on the flat blank: `values` per solved element, the peak's
/// marker at element `peak`'s initial centre.
fn developed(
    mut map: FieldMap,
    result: &DrawingResult,
    ctx: &MapContext,
    (values, peak): (&[f64], usize),
    what: &str,
) -> FieldMap {
    let blank = FullBlank::of(result);
    let xy = |p: [f64; 3]| [p[0], p[1]];
    map.quads = blank
        .mesh
        .quads
        .iter()
        .map(|q| q.map(|n| xy(blank.initial[n])))
        .collect();
    map.values = blank
        .mesh
        .elements
        .iter()
        .map(|&(e, _)| values.get(e).copied().unwrap_or(0.0))
        .collect();
    map.max_at = map.max_at.and_then(|_| {
        let q = result.mesh.quads.get(peak)?;
        let c = q.iter().fold([0.0; 2], |c, &n| {
            let p = result.mesh.nodes[n];
            [c[0] + 0.25 * p[0], c[1] + 0.25 * p[1]]
        });
        Some(c)
    });
    map.outlines.clear();
    let mut legend = Vec::new();
    for (line, depth) in MaterialLine::of(&ctx.tooling, result.stroke_reached_mm) {
        let found = blank.material_at_depth(depth);
        if found.is_empty() {
            continue;
        }
        for l in &found {
            let points = blank.on_flat_blank(l);
            map.outlines.push(match line {
                MaterialLine::DieEdge => Outline::dashed(points),
                MaterialLine::PunchNose => Outline::dotted(points),
            });
        }
        legend.push(match line {
            MaterialLine::DieEdge => "dashed: the material now at the die-opening edge",
            MaterialLine::PunchNose => {
                "dotted: now at the top of the punch's nose radius; the walls lie between the two"
            }
        });
    }
    let part = if result.quarter {
        "full blank, the solved quarter mirrored"
    } else {
        "full blank"
    };
    let stroke = crate::summary::stroke_reached(result, ctx.stroke_mm);
    let mut subtitle = format!(
        "Developed view: {} on the flat blank before forming, each element where it started ({part}, {stroke})",
        what.to_lowercase()
    );
    if !legend.is_empty() {
        subtitle.push('\n');
        subtitle.push_str(&legend.join("; "));
    }
    map.subtitle = subtitle;
    map
}
