//! A load step may end before its forces balance to the tolerance, in two ways, each judged
//! against the same drawing held to the force tolerance alone (both off): on a box off the
//! paper's grid and off the presets (8/13/6 mm, μ 0.22), each must end steps sooner, leave the
//! figures within a tenth of the standard level's band (0.12° of shear, 0.5 % of the punch
//! force, 3.5 % of the max tension) and keep the forces out of balance within its bound on the
//! punch's work (a run is trusted up to 10⁻²).
//! - On the work its residual leaves undone (`SolverOptions::tol_work`): within 100 force
//!   tolerances, when `|r · Δu|` over the step is at most 10⁻³ of the stored energy the step
//!   added; its bound is 10⁻³.
//! - On a small Newton decrement (`SolverOptions::tol_decrement`): within 1,000 force
//!   tolerances, a correction whose `|r · Δu|` is at most 10⁻³ of that energy is the last, when
//!   the state it reaches leaves at most 10⁻² of it as the residual's work over the step; its
//!   bound is 10⁻².

use wovenform::core::drawing::{self, DrawingResult};

use crate::common;

fn run(tol_work: f64, tol_decrement: f64) -> DrawingResult {
    let mut problem = common::off_grid_box();
    problem.solver.tol_work = tol_work;
    problem.solver.tol_decrement = tol_decrement;
    let r = drawing::solve(&problem, &mut |_| {});
    assert!(r.converged, "{:?}", r.failure);
    r
}

/// `ended` took fewer Newton iterations than `strict`, moved no figure by a tenth of the
/// standard band, and its forces out of balance did at most `bound` of the punch's work.
fn ends_sooner_and_moves_no_figure(strict: &DrawingResult, ended: &DrawingResult, bound: f64) {
    let (a, b) = (&strict.stats, &ended.stats);
    assert!(
        b.newton_iterations < a.newton_iterations,
        "Newton iterations: {} ending sooner, {} without",
        b.newton_iterations,
        a.newton_iterations
    );
    let (shear, force, tension) = common::moves_no_figure(strict, ended);
    let share = b.unbalanced_work / ended.punch_work_nmm;
    println!(
        "Newton {} -> {}; shear {shear:.4} deg, force {:.4} %, tension {:.3} %, out of balance {share:.2e}",
        a.newton_iterations,
        b.newton_iterations,
        100.0 * force,
        100.0 * tension
    );
    assert!(
        share <= bound,
        "forces out of balance did {share:.2e} of the punch's work"
    );
}

#[test]
fn the_work_test_ends_steps_sooner_and_moves_no_figure() {
    let strict = run(0.0, 0.0);
    ends_sooner_and_moves_no_figure(&strict, &run(drawing::TOL_WORK, 0.0), 1e-3);
}

#[test]
fn a_small_decrement_ends_steps_sooner_and_moves_no_figure() {
    let strict = run(0.0, 0.0);
    ends_sooner_and_moves_no_figure(&strict, &run(0.0, drawing::TOL_DECREMENT), 1e-2);
    // Both, as the drawings run.
    ends_sooner_and_moves_no_figure(
        &strict,
        &run(drawing::TOL_WORK, drawing::TOL_DECREMENT),
        1e-2,
    );
}
