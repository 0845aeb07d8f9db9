//! The toe of a yarn's tension curve: the slack/taut kink of the paper's law (`T = C max(ε, 0)`)
//! rounded over a small strain `w`, so that the tension and its slope are continuous.
//!
//! ```text
//!   T/C = φ(ε) = 0                 ε ≤ 0       (slack)
//!              = ε²/(2w)           0 < ε < w   (the toe: the slope rises from 0 to C)
//!              = ε − w/2           ε ≥ w       (taut: the paper's slope C)
//!   energy per cell  L0 C Φ(ε),  Φ = ε³/(6w) on the toe,  ε²/2 − wε/2 + w²/6 beyond
//! ```
//!
//! Why: on the kink Newton's tangent jumps from 0 to `C` (38 000 N for the paper's glass
//! fabric) between two iterations for every yarn whose strain crosses zero, and on a fine
//! mesh thousands of yarns in the walls and the flange do so, again and again: the active set
//! never settles and the load steps shrink until the run gives up. On the toe a crossing yarn's
//! stiffness grows from zero in proportion to its strain. A taut yarn carries `C w/2` less
//! tension at the same strain (with `w = 10⁻³`: a strain of 5·10⁻⁴ more for the same tension),
//! which the drawings' equilibrium absorbs: their figures move by a small fraction of the
//! accuracy bands (measured in `guide::accuracy`). `w = 0` is the paper's law, bit for bit.

/// `φ(ε)` and `φ'(ε)` for a toe of width `w` (`w = 0`: the paper's kink, slack at zero).
#[inline]
pub fn phi(strain: f64, w: f64) -> (f64, f64) {
    if strain <= 0.0 {
        (0.0, 0.0)
    } else if strain < w {
        (strain * strain / (2.0 * w), strain / w)
    } else {
        (strain - 0.5 * w, 1.0)
    }
}

/// `Φ(ε) = ∫₀^ε φ` for a toe of width `w ≥ 0`.
#[inline]
pub fn energy(strain: f64, w: f64) -> f64 {
    if strain <= 0.0 {
        0.0
    } else if strain < w {
        strain.powi(3) / (6.0 * w)
    } else {
        0.5 * strain * strain - 0.5 * w * strain + w * w / 6.0
    }
}

/// `φ(ε)`, `φ'(ε)` for a toe of width `w ≥ 0` and yarns that resist compression with the slope
/// `r` (a fraction of `C`): `rε` below zero, `rε + (1 − r)ε²/2w` on the toe (its slope rising
/// from `r` to 1), `ε − (1 − r)w/2` beyond; C¹ for `w > 0`.
#[inline]
pub fn phi_compressive(strain: f64, w: f64, r: f64) -> (f64, f64) {
    if strain <= 0.0 {
        (r * strain, r)
    } else if strain < w {
        (
            r * strain + (1.0 - r) * strain * strain / (2.0 * w),
            r + (1.0 - r) * strain / w,
        )
    } else {
        (strain - 0.5 * (1.0 - r) * w, 1.0)
    }
}

/// `∫₀^ε φ` of [`phi_compressive`].
#[inline]
pub fn energy_compressive(strain: f64, w: f64, r: f64) -> f64 {
    if strain <= 0.0 {
        0.5 * r * strain * strain
    } else if strain < w {
        0.5 * r * strain * strain + (1.0 - r) * strain.powi(3) / (6.0 * w)
    } else {
        0.5 * strain * strain - 0.5 * (1.0 - r) * w * strain + (1.0 - r) * w * w / 6.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn continuous_with_its_slope_and_the_derivative_of_its_energy() {
        let w = 1e-3;
        for s in [-1e-3, 1e-5, 5e-4, 0.999e-3, 1e-3, 1.001e-3, 0.02] {
            let h = 1e-8;
            let (f, df) = phi(s, w);
            let fd = (phi(s + h, w).0 - phi(s - h, w).0) / (2.0 * h);
            assert!((df - fd).abs() < 1e-5, "slope at {s}: {df} against {fd}");
            let ed = (energy(s + h, w) - energy(s - h, w)) / (2.0 * h);
            assert!((f - ed).abs() < 1e-9, "energy at {s}: {f} against {ed}");
        }
        // Beyond the toe: the paper's slope, shifted by half the toe.
        assert_eq!(phi(0.01, w), (0.01 - 0.5e-3, 1.0));
        assert_eq!(phi(-0.01, w), (0.0, 0.0));
    }

    #[test]
    fn a_compressive_toe_is_continuous_with_its_slope_and_its_energy() {
        for (w, r) in [(1e-3, 0.01), (0.0, 0.01), (1e-3, 0.0)] {
            for s in [-1e-3, -1e-6, 1e-5, 5e-4, 0.999e-3, 1.001e-3, 0.02] {
                let h = 1e-9;
                let (f, df) = phi_compressive(s, w, r);
                let fd =
                    (phi_compressive(s + h, w, r).0 - phi_compressive(s - h, w, r).0) / (2.0 * h);
                assert!((df - fd).abs() < 1e-5, "slope at {s}: {df} against {fd}");
                let ed =
                    (energy_compressive(s + h, w, r) - energy_compressive(s - h, w, r)) / (2.0 * h);
                assert!((f - ed).abs() < 1e-9, "energy at {s}: {f} against {ed}");
            }
        }
        // No compressive slope: the toe itself.
        assert_eq!(phi_compressive(5e-4, 1e-3, 0.0).0, phi(5e-4, 1e-3).0);
    }
}
