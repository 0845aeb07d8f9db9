//! The blank holder: it presses the part of the blank currently on the flange onto the die
//! face with the pressure `p`. A node of initial area `A` at plan position `(x, y)` receives the
//! downward force `p A w(x, y)`, `w` going smoothly (C1) from 0 to 1 across one band outside
//! the die's entry radius: `w = S((d_open − rm)/band)`, `S(t) = t²(3 − 2t)` on `[0, 1]`. The
//! weight follows the node's current position.

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

    /// Whether a node at `(x, y)` can be held during a step: on the flange or within one band
    /// of it.
    pub fn may_hold(&self, x: f64, y: f64) -> bool {
        self.die
            .opening_distance(x, y)
            .is_some_and(|(d, _, rm)| d > rm - self.band)
    }
}
