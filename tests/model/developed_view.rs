//! The developed view of a run (`shear_developed.png`): the field on the flat blank before
//! forming. Checked on the paper's open box, coarse, against what the scene says the blank is
//! and where the tools put the material:
//!
//! ```text
//!   blank 170 × 170 mm, quarter solved      the map: the full blank, undeformed
//!   ┌─────────────┐                          ┌───────────────┐ ±85 mm exactly
//!   │      ┌──┐   │  ── forming ──►           │   ╭┄┄┄┄┄╮    │ dashed: the material
//!   │      └──┘   │                          │   ╰┄┄┄┄┄╯    │ now at the die edge
//!   └─────────────┘                          └───────────────┘
//! ```

use wovenform::core::drawing::{self, Tooling};
use wovenform::presets::PAPER_BOX_OPEN;
use wovenform::report::maps::{FullBlank, MapContext, MaterialLine, OutlineStyle, shear_developed};
use wovenform::scene::Scene;

#[test]
fn the_developed_map_is_the_flat_blank_and_its_dashed_line_the_die_edge() {
    let mut scene = Scene::from_toml_str(PAPER_BOX_OPEN, "paper-box-open.toml", &[]).unwrap();
    scene.mesh.element_size = 5.0;
    let problem = scene.to_problem();
    let result = drawing::solve(&problem, &mut |_| {});
    assert!(result.converged, "{:?}", result.failure);
    assert!(result.quarter, "the open box is solved on a quarter");
    let ctx = MapContext {
        scene: "paper-box-open",
        verdict: "",
        tooling: problem.tooling.clone(),
        stroke_mm: problem.stroke_mm,
        design: "",
    };
    let map = shear_developed(&result, &ctx, scene.fabric.locking_angle_deg);

    // Every corner is an initial node, mirrored: z = 0 before forming, so the blank is flat.
    let initial = &result.mesh.nodes;
    assert!(initial.iter().all(|p| p[2] == 0.0));
    for q in &map.quads {
        for c in q {
            let found = initial.iter().any(|p| {
                [1.0, -1.0].iter().any(|sx| {
                    [1.0, -1.0]
                        .iter()
                        .any(|sy| sx * p[0] == c[0] && sy * p[1] == c[1])
                })
            });
            assert!(found, "corner {c:?} is no initial node");
        }
    }
    // Four copies of the quarter, each element's |shear| four times.
    assert_eq!(map.quads.len(), 4 * result.mesh.quads.len());
    let sum = |v: &mut dyn Iterator<Item = f64>| v.sum::<f64>();
    let want = 4.0 * sum(&mut result.shear_deg.iter().map(|s| s.abs()));
    let got = sum(&mut map.values.iter().copied());
    assert!((got - want).abs() < 1e-9 * want, "{got} vs {want}");
    // The bounding box is the scene's blank, centred on the punch.
    let [w, h] = scene.blank.size.0;
    let corners = map.quads.iter().flatten();
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for c in corners {
        (x0, x1, y0, y1) = (x0.min(c[0]), x1.max(c[0]), y0.min(c[1]), y1.max(c[1]));
    }
    let tol = 1e-9 * w;
    assert!(
        (x0 + w / 2.0).abs() < tol && (x1 - w / 2.0).abs() < tol,
        "{x0} {x1}"
    );
    assert!(
        (y0 + h / 2.0).abs() < tol && (y1 - h / 2.0).abs() < tol,
        "{y0} {y1}"
    );

    // The dashed line: one closed line, around the centre, whose material ended on the die
    // opening's edge in plan, within the clearance (the wall hangs in the gap between punch
    // and die).
    let Tooling::Box { rm, clearance, .. } = problem.tooling else {
        panic!("a box");
    };
    let lines = MaterialLine::of(&problem.tooling, result.stroke_reached_mm);
    assert_eq!(lines[0], (MaterialLine::DieEdge, rm));
    let dashed: Vec<_> = map
        .outlines
        .iter()
        .filter(|o| o.style == OutlineStyle::Dashed)
        .collect();
    assert_eq!(dashed.len(), 1, "one die-edge line");
    let line = &dashed[0].points;
    assert_eq!(line.first(), line.last(), "closed");
    let blank = FullBlank::of(&result);
    let at_edge = blank.material_at_depth(rm);
    assert_eq!(at_edge.len(), 1);
    let (_, die) = problem.tooling.tools();
    let mut worst: f64 = 0.0;
    for (p, flat) in at_edge[0].iter().zip(line) {
        // The same material point on the flat blank and where it ended.
        let [x, y, _] = p.at(&blank.initial);
        assert_eq!([x, y], *flat);
        let [fx, fy, fz] = p.at(&blank.last);
        assert!((fz + rm).abs() < 1e-9, "depth {}", -fz);
        let (d, _, _) = die.opening_distance(fx, fy).unwrap();
        worst = worst.max(d.abs());
        // Drawn in: the material started further out than it ended.
        assert!(x.hypot(y) > fx.hypot(fy), "({x}, {y}) → ({fx}, {fy})");
    }
    println!("die-edge material within {worst:.2} mm of the die opening's edge");
    assert!(worst < clearance, "{worst} mm");
}
