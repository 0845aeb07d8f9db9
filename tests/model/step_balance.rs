//! A load step may end on the work its residual leaves undone (`SolverOptions::tol_work`):
//! within 100 force tolerances, when `|r · Δu|` over the step is at most 10⁻³ of the stored
//! energy the step added. The reference is the same drawing held to the force tolerance alone
//! (`tol_work = 0`): on a box off the paper's grid and off the presets (8/13/6 mm, μ 0.22), the
//! work test must end steps sooner, leave the figures within a tenth of the standard level's
//! band (0.12° of shear, 0.5 % of the punch force) and keep the forces out of balance under
//! 10⁻³ of the punch's work (a run is trusted up to 10⁻²).

use wovenform::core::drawing::{self, DrawingResult};

use crate::common;

fn run(tol_work: f64) -> DrawingResult {
    let mut problem = common::preset_problem(
        "paper-box-open.toml",
        &[
            "tools.r=8",
            "tools.rp=13",
            "tools.rm=6",
            "process.friction=0.22",
        ],
    );
    problem.solver.tol_work = tol_work;
    let r = drawing::solve(&problem, &mut |_| {});
    assert!(r.converged, "{:?}", r.failure);
    r
}

fn max(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::MIN, f64::max)
}

#[test]
fn the_work_test_ends_steps_sooner_and_moves_no_figure() {
    let strict = run(0.0);
    let on_work = run(drawing::TOL_WORK);
    let (a, b) = (&strict.stats, &on_work.stats);
    assert!(
        b.newton_iterations < a.newton_iterations,
        "Newton iterations: {} with the work test, {} without",
        b.newton_iterations,
        a.newton_iterations
    );
    let shear = (max(&on_work.shear_deg) - max(&strict.shear_deg)).abs();
    assert!(shear <= 0.12, "max shear moved {shear:.4}°");
    let force = (on_work.punch_force_n / strict.punch_force_n - 1.0).abs();
    assert!(force <= 0.005, "punch force moved {:.3} %", 100.0 * force);
    let share = b.unbalanced_work / on_work.punch_work_nmm;
    assert!(
        share <= 1e-3,
        "forces out of balance did {share:.2e} of the punch's work"
    );
}
