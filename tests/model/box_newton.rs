//! Newton on a box converges quadratically once its active set settles (shown on a
//! box, not only on the capstan's strip). The open box with radii and friction off the paper's
//! grid (7/11/8 mm, μ = 0.17) is run at standard with the equilibrium tolerance pushed to the
//! round-off floor, so that each load step's tail is long enough to read its order; every
//! iteration records its residual, its line search's length and how many yarns changed between
//! slack and taut or nodes between touching a tool and not. Where nothing changed and the
//! correction was taken in full, `r(k+1)/r(k)²` must stay bounded; the same box with the
//! friction's non-symmetric Jacobian left out (`exact_jacobian = false`) is the check that the
//! measure can fail: it converges linearly there.

use wovenform::core::drawing;
use wovenform::core::solver::SolveStats;

use crate::common;

/// The box's run at standard with the exact or the symmetric Jacobian, to the round-off floor.
fn run(exact_jacobian: bool) -> SolveStats {
    let mut problem = common::preset_problem(
        "paper-box-open.toml",
        &[
            "tools.r=7",
            "tools.rp=11",
            "tools.rm=8",
            "process.friction=0.17",
        ],
    );
    problem.solver.record_residuals = true;
    problem.solver.exact_jacobian = exact_jacobian;
    // The default tolerance (10⁻⁶ of the forces, at least a yarn force of 10⁻⁷ C, a few mN)
    // ends most steps two iterations into their quadratic tail; this one lets them run on to
    // the round-off floor, about 2·10⁻⁹ N.
    problem.solver.tol_force = 1e-11;
    problem.solver.tol_floor = 1e-14;
    problem.solver.tol_work = 0.0;
    let r = drawing::solve(&problem, &mut |_| {});
    assert!(r.converged, "{:?}", r.failure);
    r.stats
}

/// The ratios `r(k+1)/r(k)²` (N⁻¹) of the iterations that settled: `r(k)` at most 10⁻² N,
/// `r(k+1)` at least 1,000 times the run's floor (its smallest residual), the correction between
/// them taken in full and no yarn or contact changed state.
fn settled_ratios(s: &SolveStats) -> Vec<f64> {
    let floor = s
        .residuals
        .iter()
        .flatten()
        .cloned()
        .fold(f64::INFINITY, f64::min);
    let mut ratios = Vec::new();
    for ((h, changes), alphas) in s.residuals.iter().zip(&s.active_changes).zip(&s.alphas) {
        for k in 0..h.len().saturating_sub(1) {
            let (a, b) = (h[k], h[k + 1]);
            let full = alphas.get(k).is_some_and(|&al| al >= 0.999);
            if a <= 1e-2 && b >= 1000.0 * floor && full && changes[k + 1] == 0 {
                ratios.push(b / (a * a));
            }
        }
    }
    ratios
}

#[test]
fn newton_converges_quadratically_on_a_box_once_its_active_set_settles() {
    let exact = run(true);
    let symmetric = run(false);
    let worst = |r: &[f64]| r.iter().cloned().fold(0.0, f64::max);
    let (re, rs) = (settled_ratios(&exact), settled_ratios(&symmetric));
    println!(
        "exact Jacobian: {} steps, {} iterations, {} settled pairs, worst r(k+1)/r(k)² = {:.3e} N⁻¹",
        exact.steps,
        exact.newton_iterations,
        re.len(),
        worst(&re)
    );
    println!(
        "symmetric part only: {} steps, {} iterations, {} settled pairs, worst {:.3e} N⁻¹",
        symmetric.steps,
        symmetric.newton_iterations,
        rs.len(),
        worst(&rs)
    );
    // A quarter of the load steps at least show a settled pair (the others fall from above
    // 10⁻² N to near the floor in one iteration), and every such pair squares the residual
    // (measured: 10 pairs in 20 steps, at most 31 N⁻¹).
    assert!(
        re.len() >= exact.steps as usize / 4,
        "{:?}",
        exact.residuals
    );
    assert!(worst(&re) < 1e3, "not quadratic: {re:?}");
    // Without the friction's coupling the tail is linear, a residual falling by a constant
    // factor, and the same measure grows as the residual shrinks (measured: 3.3·10⁴ N⁻¹).
    assert!(worst(&rs) > 100.0 * worst(&re), "{rs:?}");
}
