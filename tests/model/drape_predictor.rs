//! The drape predictor of a step with no secant (`SolverOptions::drape_predictor`): the nodes
//! a tool touched move with it, the rest hang between them, harmonic over the mesh's edges.
//! Without it the first step's projection left one element's yarns carrying the punch's
//! travel. On a box off the paper's grid and off the presets (8/13/6 mm, μ 0.22), on and off:
//! the first step's residual starts lower and the step takes fewer Newton iterations, the
//! run fewer in all in the same load steps, and no figure moves by a tenth of the standard
//! level's band (0.12° of shear, 0.5 % of the punch force, 3.5 % of the max tension).

use wovenform::core::drawing::{self, DrawingResult};

use crate::common;

fn run(drape: bool) -> DrawingResult {
    let mut problem = common::off_grid_box();
    problem.solver.drape_predictor = drape;
    problem.solver.record_residuals = true;
    let r = drawing::solve(&problem, &mut |_| {});
    assert!(r.converged, "{:?}", r.failure);
    r
}

#[test]
fn the_drape_shortens_the_first_step_and_moves_no_figure_on_a_box() {
    let (plain, draped) = (run(false), run(true));
    let (a, b) = (&plain.stats, &draped.stats);
    // Each step's residuals: its first before any correction, then one per iteration.
    let (first_a, first_b) = (&a.residuals[0], &b.residuals[0]);
    println!(
        "first step: residual {:.3e} -> {:.3e} N, iterations {} -> {}; run {} -> {} in {} -> {} steps",
        first_a[0],
        first_b[0],
        first_a.len() - 1,
        first_b.len() - 1,
        a.newton_iterations,
        b.newton_iterations,
        a.steps,
        b.steps
    );
    assert!(first_b[0] < 0.7 * first_a[0], "the drape's first residual");
    assert!(first_b.len() < first_a.len(), "the first step's iterations");
    assert!(b.newton_iterations < a.newton_iterations);
    assert!(b.steps <= a.steps);
    common::moves_no_figure(&plain, &draped);
}
