//! The blank holder: it presses the part of the blank currently on the flange onto the die
//! face with the pressure `p`. A node of initial area `A` at plan position `(x, y)` receives the
//! downward force `p A w(x, y)`, `w` going smoothly (C1) from 0 to 1 across one band outside
//! the die's entry radius: `w = S((d_open − rm)/band)`, `S(t) = t²(3 − 2t)` on `[0, 1]`. The
//! weight follows the node's current position.
//!
//! Or, with [`Holder::plate_force_n`], a rigid plate as a press applies it: a flat face at a
//! height `h` that is an unknown, pressed down with a total force `F`, touching each node of the
//! footprint through the same eased penalty as the tools (`normal::law` on the gap `h − z`,
//! times the weight `w`). For given positions `h` is where the plate's contacts carry `F`
//! ([`Holder::plate`]); a wrinkle that lifts a node lifts the plate, and the force goes to the
//! crests. Condensing `h` out, node `i`'s force `f_i = w_i p(h − z_i)` has the derivative
//! `∂f_i/∂z_j = c_i (δ_ij − c_j/C)` (`c_i = w_i φ''_i`, `C = Σ c`): its diagonal joins the
//! tangent, the rank-one coupling (the plate following a node) is left to Newton's iterations.
//! The potential is `Σ w_i φ(h − z_i) + F h`, conservative.

use crate::core::tools::Tool;

/// The blank holder.
#[derive(Clone, Debug, PartialEq)]
pub struct Holder {
    /// Pressure on the flange, MPa (N/mm²).
    pub pressure: f64,
    /// The die whose face the holder presses onto (its opening and entry radius define the
    /// flange).
    pub die: Tool,
    /// Width of the band over which the holder's grip fades in, mm.
    pub band: f64,
    /// A rigid plate pressed with this total force, N, instead of the pressure on each node.
    pub plate_force_n: Option<f64>,
}

/// The plate's state at some positions: its height and the sum `C` of its contacts'
/// stiffnesses (`w φ''`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plate {
    pub height: f64,
    pub stiffness_sum: f64,
    pub force_n: f64,
}

impl Plate {
    /// Node's force (N, down), its derivative along z (the diagonal of the condensed
    /// stiffness, N/mm) and its energy `w φ` (N·mm) for weight `w`, penalty `k`, smoothing gap
    /// `delta` and height `z`.
    pub fn node(&self, w: f64, k: f64, delta: f64, z: f64) -> (f64, f64, f64) {
        let (p, s, e) = super::normal::law(k, delta, self.height - z);
        let c = w * s;
        let diagonal = if self.stiffness_sum > 0.0 {
            c * (1.0 - c / self.stiffness_sum)
        } else {
            c
        };
        (w * p, diagonal, w * e)
    }
}

impl Holder {
    /// The fraction of the holder pressure a node at `(x, y)` receives, and its gradient in the
    /// plane (1/mm).
    pub fn weight(&self, x: f64, y: f64) -> (f64, [f64; 2]) {
        let Some((d_open, g, rm)) = self.die.opening_distance(x, y) else {
            return (0.0, [0.0; 2]);
        };
        if self.band <= 0.0 {
            // No band: the holder grips the flange outside the entry radius, and nothing else.
            return (if d_open > rm { 1.0 } else { 0.0 }, [0.0; 2]);
        }
        let t = (d_open - rm) / self.band;
        if t <= 0.0 {
            return (0.0, [0.0; 2]);
        }
        if t >= 1.0 {
            return (1.0, [0.0; 2]);
        }
        let ds = 6.0 * t * (1.0 - t) / self.band;
        (t * t * (3.0 - 2.0 * t), [ds * g[0], ds * g[1]])
    }

    /// The plate at positions `x` of the nodes `held` (weights `w`, penalties `k`, smoothing gap
    /// `delta`): the height where `Σ w p(h − z) = F`, by bisection (the sum falls as `h`
    /// rises). `None` without a plate, or when no node is under it (nothing to carry `F`).
    pub fn plate(
        &self,
        held: &[u32],
        x: &[[f64; 3]],
        weight: &dyn Fn(usize) -> f64,
        k: &[f64],
        delta: f64,
    ) -> Option<Plate> {
        let force = self.plate_force_n?;
        let under: Vec<(usize, f64)> = (held.iter())
            .map(|&i| (i as usize, weight(i as usize)))
            .filter(|(_, w)| *w > 0.0)
            .collect();
        if under.is_empty() || force <= 0.0 {
            return None;
        }
        let carried = |h: f64| -> f64 {
            (under.iter())
                .map(|&(i, w)| w * super::normal::law(k[i], delta, h - x[i][2]).0)
                .sum()
        };
        let top = under.iter().map(|&(i, _)| x[i][2]).fold(f64::MIN, f64::max);
        let (mut lo, mut hi) = (top - delta, top + delta);
        let mut span = delta.max(1e-9);
        while carried(lo) < force {
            span *= 2.0;
            lo = top - span;
            if span > 1e9 {
                return None;
            }
        }
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if carried(mid) > force {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi - lo <= 1e-14 * (1.0 + top.abs()) {
                break;
            }
        }
        let height = 0.5 * (lo + hi);
        let stiffness_sum = (under.iter())
            .map(|&(i, w)| w * super::normal::law(k[i], delta, height - x[i][2]).1)
            .sum();
        Some(Plate {
            height,
            stiffness_sum,
            force_n: force,
        })
    }

    /// Whether a node at `(x, y)` can be held during a step: on the flange or within one band
    /// of it.
    pub fn may_hold(&self, x: f64, y: f64) -> bool {
        self.die
            .opening_distance(x, y)
            .is_some_and(|(d, _, rm)| d > rm - self.band)
    }
}
