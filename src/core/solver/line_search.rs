//! Backtracking along a Newton correction.
//!
//! The problem has a merit `Π` (stored energy, contact penalty, holder work, and friction's
//! potential with its normal force and direction frozen at the base point, so that `∇Π` there is
//! the residual). A correction with `r · Δu < 0` descends it: accept the length `α` when `Π`
//! satisfies Armijo, `Π(α) ≤ Π(0) + 1e-4 α r·Δu`, or when the residual norm falls (which decides
//! near convergence, where `Π` is all round-off). Trial lengths minimise the quadratic through
//! `Π(0)`, `Π'(0)` and `Π(α)`, kept within `[0.05 α, 0.5 α]`.

use super::assembly::Assembly;

/// Where the search starts.
pub(super) struct Base {
    /// `Π(0)`, N·mm.
    pub merit: f64,
    /// `‖r(0)‖`, N.
    pub residual: f64,
    /// `r(0) · Δu`, N·mm.
    pub slope: f64,
    /// A residual that ends the Newton iterations, N.
    pub tolerance: f64,
}

/// What the search settled on.
pub(super) struct Accepted {
    pub alpha: f64,
    /// The trial's assembly, when it was assembled with its tangent (the next iteration's).
    pub carried: Option<Assembly>,
    /// Trial assemblies made.
    pub trials: u32,
}

const MAX_TRIALS: u32 = 16;

/// Searches along the correction; `eval(α, tangent)` sets the state to `base + α Δu` and
/// assembles it. `speculate`: assemble the first (full) trial with its tangent. When no trial
/// is acceptable the state is set to the best one if its residual is under 10× the base's;
/// otherwise `None` is returned (the state is then at the last trial; the caller restores it).
pub(super) fn backtrack(
    base: &Base,
    speculate: bool,
    mut eval: impl FnMut(f64, bool) -> Assembly,
) -> Option<Accepted> {
    let mut alpha = 1.0;
    let mut best = (f64::INFINITY, 0.0);
    for trial in 0..MAX_TRIALS {
        let tangent = trial == 0 && speculate;
        let a = eval(alpha, tangent);
        let (norm, merit) = if a.admissible {
            (
                a.r.iter().map(|v| v * v).sum::<f64>().sqrt(),
                a.energy_frozen,
            )
        } else {
            (f64::INFINITY, f64::INFINITY)
        };
        if norm < best.0 {
            best = (norm, alpha);
        }
        let armijo = base.slope < 0.0 && merit <= base.merit + 1e-4 * alpha * base.slope;
        if armijo || norm <= (1.0 - 1e-4 * alpha) * base.residual || norm <= base.tolerance {
            return Some(Accepted {
                alpha,
                carried: tangent.then_some(a),
                trials: trial + 1,
            });
        }
        let next = if merit.is_finite() && base.slope < 0.0 {
            -base.slope * alpha * alpha / (2.0 * (merit - base.merit - base.slope * alpha))
        } else {
            0.05 * alpha
        };
        alpha = if next.is_finite() {
            next.clamp(0.05 * alpha, 0.5 * alpha)
        } else {
            0.5 * alpha
        };
    }
    if best.0.is_finite() && best.0 < 10.0 * base.residual {
        eval(best.1, false);
        return Some(Accepted {
            alpha: best.1,
            carried: None,
            trials: MAX_TRIALS + 1,
        });
    }
    None
}
