//! The analytic punch and die as closed triangle surfaces: each unbounded tool cut by a box
//! ([`capped`]) and tessellated ([`tessellate`]).
//!
//! The grid is laid so that the axes x = 0, y = 0 and the plane z = 0 pass through cell
//! centres (its nodes at half cells): the cell around a punch's lowest point on the axis gets
//! its vertex on the axis, which Newton's steps put on the tip, so the tessellated punch's
//! lowest point is the analytic one (z = 0) to rounding, and no node lies on the die's face.

use super::Tool;
use super::surface::TriSurface;
use super::tessellate::{box_field, capped, tessellate};
use super::tooling::Tooling;

/// How far the punch's capping box reaches beyond the die opening in plan, mm (it does not
/// cut the punch, whose plan lies inside the opening).
const PUNCH_PLAN_MARGIN_MM: f64 = 5.0;
/// The die's capping box reaches this far beyond the blank's half sides, mm.
const DIE_PLAN_MARGIN_MM: f64 = 15.0;
/// Both tools reach this far beyond the stroke in z (the punch above, the die below), mm.
const DEPTH_MARGIN_MM: f64 = 10.0;

/// The smallest half extent at least one cell beyond `extent` whose end is a node of a grid
/// of cell `h` with its nodes at half cells (cell centres at whole multiples of `h`).
fn half_cell_beyond(extent: f64, h: f64) -> f64 {
    ((extent / h).ceil() + 1.5) * h
}

/// The punch (tip at z = 0) and the die (face z = 0) of `tooling` as closed surfaces, for a
/// blank of sides `blank` (mm) and a punch travel `stroke_mm`, on a grid of `spacing_mm`.
///
/// The punch is cut at z = stroke + 10 mm (its plan inside the opening, not cut); the die
/// is cut in plan at the blank's half sides + 15 mm and below at z = −(stroke + 10 mm); its
/// face is the plane z = 0, where its vertices lie to rounding (the field there is z itself).
pub fn tool_surfaces(
    tooling: &Tooling,
    blank: [f64; 2],
    stroke_mm: f64,
    spacing_mm: f64,
) -> (TriSurface, TriSurface) {
    let (punch, die) = tooling.tools();
    let [(punch_plan, z_range), (die_plan, _)] = boxes(tooling, blank, stroke_mm);
    let surface = |tool: Tool, plan| {
        let is_punch = tool.is_punch();
        let field = move |p: [f64; 3]| tool.distance(p).d;
        capped_surface(&field, is_punch, plan, z_range, spacing_mm)
    };
    (surface(punch, punch_plan), surface(die, die_plan))
}

/// The tool of signed field `field` (a punch above z = 0 when `is_punch`, else a die below
/// it) cut by the box `|x| ≤ plan[0]`, `|y| ≤ plan[1]`, `z_range[0] ≤ z ≤ z_range[1]` and
/// tessellated on a grid of `spacing_mm` laid as the module's note says.
pub fn capped_surface(
    field: &(dyn Fn([f64; 3]) -> f64 + Sync),
    is_punch: bool,
    plan: [f64; 2],
    z_range: [f64; 2],
    spacing_mm: f64,
) -> TriSurface {
    let lo = [-plan[0], -plan[1], z_range[0]];
    let hi = [plan[0], plan[1], z_range[1]];
    let cut = |p: [f64; 3]| capped(field(p), box_field(p, lo, hi));
    let (grid_lo, grid_hi) = grid_box(is_punch, plan, z_range, spacing_mm);
    tessellate(&cut, grid_lo, grid_hi, spacing_mm)
}

/// The box of the grid that [`capped_surface`] samples: the punch lies above z = 0 and the
/// die below it, so the grid covers that side and a cell and a half of the other.
fn grid_box(is_punch: bool, plan: [f64; 2], z_range: [f64; 2], h: f64) -> ([f64; 3], [f64; 3]) {
    let (z_lo, z_hi) = if is_punch {
        (0.0, z_range[1])
    } else {
        (z_range[0], 0.0)
    };
    let lo = [
        -half_cell_beyond(plan[0], h),
        -half_cell_beyond(plan[1], h),
        -half_cell_beyond(-z_lo, h),
    ];
    let hi = [
        half_cell_beyond(plan[0], h),
        half_cell_beyond(plan[1], h),
        half_cell_beyond(z_hi, h),
    ];
    (lo, hi)
}

/// The grid points that [`tool_surfaces`] samples for the larger of its two tools (each takes
/// a `f64` and a `u32` of memory, with the surface's vertices and triangles on top).
pub fn grid_points(tooling: &Tooling, blank: [f64; 2], stroke_mm: f64, spacing_mm: f64) -> f64 {
    let [(punch_plan, z_range), (die_plan, _)] = boxes(tooling, blank, stroke_mm);
    let count = |is_punch, plan| {
        let (lo, hi) = grid_box(is_punch, plan, z_range, spacing_mm);
        (0..3)
            .map(|i| ((hi[i] - lo[i]) / spacing_mm).round() + 1.0)
            .product::<f64>()
    };
    count(true, punch_plan).max(count(false, die_plan))
}

/// The capping boxes of the punch and the die: plan half sides and z range.
fn boxes(tooling: &Tooling, blank: [f64; 2], stroke_mm: f64) -> [([f64; 2], [f64; 2]); 2] {
    let opening = tooling.opening_half();
    let depth = stroke_mm + DEPTH_MARGIN_MM;
    let punch_plan = [
        opening[0] + PUNCH_PLAN_MARGIN_MM,
        opening[1] + PUNCH_PLAN_MARGIN_MM,
    ];
    let die_plan = [
        0.5 * blank[0] + DIE_PLAN_MARGIN_MM,
        0.5 * blank[1] + DIE_PLAN_MARGIN_MM,
    ];
    [(punch_plan, [-depth, depth]), (die_plan, [-depth, depth])]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn presets() -> Vec<(&'static str, Tooling, [f64; 2], f64)> {
        vec![
            (
                "box",
                Tooling::Box {
                    side: [60.0, 60.0],
                    r: 10.0,
                    rp: 15.0,
                    rm: 10.0,
                    clearance: 1.5,
                },
                [170.0, 170.0],
                28.0,
            ),
            (
                "hemisphere",
                Tooling::Hemisphere {
                    radius: 30.0,
                    rm: 5.0,
                    clearance: 1.5,
                },
                [120.0, 120.0],
                20.0,
            ),
            (
                "ellipsoid",
                Tooling::Ellipsoid {
                    axes: [40.0, 25.0, 20.0],
                    rm: 5.0,
                    clearance: 1.5,
                },
                [130.0, 100.0],
                15.0,
            ),
        ]
    }

    #[test]
    fn the_tools_are_closed_with_the_punch_tip_and_the_die_face_at_zero() {
        for (name, tooling, blank, stroke) in presets() {
            let (punch, die) = tool_surfaces(&tooling, blank, stroke, 2.0);
            punch
                .check()
                .unwrap_or_else(|e| panic!("{name} punch: {e}"));
            die.check().unwrap_or_else(|e| panic!("{name} die: {e}"));
            // No two vertices coincide: welding the soup (as reading an STL does) keeps them.
            for s in [&punch, &die] {
                let welded = TriSurface::from_soup(&s.soup()).unwrap();
                assert_eq!(welded.vertices.len(), s.vertices.len(), "{name}");
                assert_eq!(welded.triangles.len(), s.triangles.len(), "{name}");
            }
            let (lo, hi) = punch.bounds();
            assert!(lo[2].abs() < 1e-6, "{name}: the punch's lowest z {}", lo[2]);
            assert!(
                (hi[2] - stroke - 10.0).abs() < 1e-9,
                "{name}: punch top {}",
                hi[2]
            );
            let (lo, hi) = die.bounds();
            assert!(hi[2].abs() < 1e-9, "{name}: the die's highest z {}", hi[2]);
            assert!(
                (lo[2] + stroke + 10.0).abs() < 1e-9,
                "{name}: die bottom {}",
                lo[2]
            );
            for i in 0..2 {
                let half = 0.5 * blank[i] + 15.0;
                assert!((hi[i] - half).abs() < 1e-9 && (lo[i] + half).abs() < 1e-9);
            }
            // The face: every vertex beyond the entry radius and a cell inside the cap lies
            // in it.
            let (_, die_tool) = tooling.tools();
            let on_face = |v: &&[f64; 3]| {
                let (d, _, rm) = die_tool.opening_distance(v[0], v[1]).unwrap();
                d > rm && (0..2).all(|i| v[i].abs() < 0.5 * blank[i] + 13.0) && v[2] > -2.0
            };
            let near: Vec<f64> = die.vertices.iter().filter(on_face).map(|v| v[2]).collect();
            assert!(
                near.len() > 1000,
                "{name}: {} vertices near the face",
                near.len()
            );
            assert!(near.iter().all(|z| z.abs() < 1e-9), "{name}: off the face");
        }
    }

    #[test]
    fn the_box_punch_is_its_analytic_solid() {
        // Volume of the capped box punch: its plan area times the height, less what the nose
        // radius takes off (a quarter-round strip along the perimeter, less at the corners).
        let (_, tooling, blank, stroke) = presets().remove(0);
        let (punch, _) = tool_surfaces(&tooling, blank, stroke, 1.0);
        let volume = punch.check().unwrap();
        let (side, r, rp, height) = (60.0f64, 10.0f64, 15.0f64, 38.0f64);
        let plan_area = side * side - (4.0 - std::f64::consts::PI) * r * r;
        let upper = plan_area * height;
        assert!(volume < upper, "{volume} against the plan prism {upper}");
        let nose_loss = (1.0 - std::f64::consts::PI / 4.0) * rp * rp * 4.0 * side;
        assert!(
            volume > upper - nose_loss,
            "{volume}: lost more than the nose strip"
        );
        // Every vertex on the punch (or its cap) to rounding.
        let (punch_tool, _) = tooling.tools();
        let worst = punch
            .vertices
            .iter()
            .filter(|v| v[2] < 37.0)
            .map(|v| punch_tool.distance(*v).d.abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-6, "a vertex {worst} mm off the punch");
    }
}
