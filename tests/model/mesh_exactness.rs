//! A fine STL tessellation of an analytic tool gives the analytic tool's answer:
//! the presets' punch and die written as triangles (1 mm surface nets, vertices on the
//! surface) and drawn again must give the max shear within 0.5°, the punch force within 2 %
//! and the draw-in within 0.2 mm; a coarser tessellation (2 mm) is further off in force.
//! Quarter models both ways, so that the two runs differ in their tools only.

use std::sync::Arc;

use wovenform::core::drawing::{self, DrawingProblem, DrawingResult, Symmetry, Tooling};
use wovenform::core::tools::capped::tool_surfaces;
use wovenform::core::tools::mesh_tool::{MeshTool, Role};
use wovenform::scene::Scene;

fn problem(preset: &str) -> DrawingProblem {
    let path = format!("{}/presets/{preset}.toml", env!("CARGO_MANIFEST_DIR"));
    let mut p = Scene::load(Some(std::path::Path::new(&path)), &[])
        .unwrap()
        .to_problem();
    p.symmetry = Symmetry::Quarter;
    p
}

/// The same drawing with its tools tessellated at `spacing` mm.
fn meshed(p: &DrawingProblem, spacing: f64) -> DrawingProblem {
    let (punch, die) = tool_surfaces(&p.tooling, p.blank_mm, p.stroke_mm, spacing);
    let mut q = p.clone();
    q.tooling = Tooling::Mesh {
        punch: Arc::new(MeshTool::new(Role::Punch, "punch", &punch, 1.0, 1.0).unwrap()),
        die: Arc::new(MeshTool::new(Role::Die, "die", &die, 1.0, 1.0).unwrap()),
    };
    q
}

/// Shear (°), force (relative) and draw-in (mm) differences from the analytic run.
fn departures(a: &DrawingResult, b: &DrawingResult) -> [f64; 3] {
    assert!(
        a.converged && b.converged,
        "{:?} {:?}",
        a.failure,
        b.failure
    );
    wovenform::study::mesh_bench::departures(a, b)
}

fn check(preset: &str) -> [f64; 3] {
    let p = problem(preset);
    let analytic = drawing::solve(&p, &mut |_| {});
    let mesh = drawing::solve(&meshed(&p, 1.0), &mut |_| {});
    let [shear, force, draw_in] = departures(&analytic, &mesh);
    eprintln!(
        "{preset}: shear {shear:+.3}°, force {:+.2} %, draw-in {draw_in:+.3} mm",
        100.0 * force
    );
    assert!(shear.abs() <= 0.5, "{preset}: shear off by {shear}°");
    assert!(
        force.abs() <= 0.02,
        "{preset}: force off by {} %",
        100.0 * force
    );
    assert!(
        draw_in.abs() <= 0.2,
        "{preset}: draw-in off by {draw_in} mm"
    );
    [shear, force, draw_in]
}

#[test]
fn a_tessellated_hemisphere_gives_the_hemispheres_answer() {
    check("hemisphere");
}

#[test]
fn a_tessellated_ellipsoid_gives_the_ellipsoids_answer() {
    check("paper-ellipsoid");
}

#[test]
fn a_tessellated_box_gives_the_boxs_answer_and_a_coarser_one_is_further_off() {
    let fine = check("paper-box-open");
    let p = problem("paper-box-open");
    let analytic = drawing::solve(&p, &mut |_| {});
    let coarse = departures(&analytic, &drawing::solve(&meshed(&p, 2.0), &mut |_| {}));
    eprintln!("coarse (2 mm): force {:+.2} %", 100.0 * coarse[1]);
    assert!(coarse[1].abs() > fine[1].abs(), "{coarse:?} vs {fine:?}");
}
