//! Each node's own balance with a tool along its normal, put back into a Newton correction
//! ([`crate::core::solver::NodalTerms::reshape`]): the rest of the node's normal load is taken
//! as the correction left it, linear in the node's own move with its own block of the
//! tangent less the penalty's share, and the eased penalty is solved exactly against it
//! ([`normal::balancing_move`]).

use super::{Contact, dot, normal, unit_normal};
use crate::core::solver::NodeStiffness;

/// The largest component of a tool's unit normal along a node's prescribed dof for which the
/// node is still balanced along the normal (the component is then dropped).
const HELD_NORMAL: f64 = 1e-9;

/// `aᵀ K b`.
fn quad(k: &[[f64; 3]; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3)
        .map(|i| a[i] * (0..3).map(|j| k[i][j] * b[j]).sum::<f64>())
        .sum()
}

impl Contact {
    /// For each node in one tool's eased gap (at `x`, or after correction `du`), the change of
    /// its share of `du` along the tool's normal that puts it where its penalty balances the
    /// rest of its normal load. Nodes near two tools are left as they are.
    pub(super) fn balancing_moves(
        &self,
        lambda: f64,
        x: &[[f64; 3]],
        du: &[[f64; 3]],
        stiffness: NodeStiffness,
    ) -> Vec<(usize, [f64; 3])> {
        let delta = self.options.contact_smoothing;
        let mut seen = vec![0u8; x.len()];
        let mut moves = Vec::new();
        for t in 0..self.tools.len() {
            let tool = self.tools[t].at(lambda);
            for &i in &self.active[t] {
                let i = i as usize;
                let dist = self.distance(t, i, &tool, x[i], false).0;
                let (n, _) = unit_normal(dist.n, None);
                let (y0, s_lin) = (delta - dist.d, dot(du[i], n));
                let y_lin = y0 - s_lin;
                if (y0 <= 0.0 && y_lin <= 0.0) || (y0 >= delta && y_lin >= delta) {
                    continue;
                }
                seen[i] += 1;
                let Some(own) = stiffness(i) else { continue };
                // A node held in some direction (on a symmetry plane) moves along the normal
                // when the normal lies in its free directions, as a symmetric tool's does there.
                if (0..3).any(|a| !own.free[a] && n[a].abs() > HELD_NORMAL) {
                    continue;
                }
                let n = [0, 1, 2].map(|a| if own.free[a] { n[a] } else { 0.0 });
                let own = own.k;
                let k = self.penalty[i];
                let (p0, slope, _) = normal::law(k, delta, dist.d);
                let other = (quad(&own, n, n) - slope * dot(dist.n, n).powi(2)).max(0.0);
                let g = p0 - (slope + other) * s_lin;
                if let Some(s) = normal::balancing_move(k, delta, y0, g, other) {
                    moves.push((i, n.map(|v| (s - s_lin) * v)));
                }
            }
        }
        moves.retain(|(i, _)| seen[*i] == 1);
        moves
    }
}
