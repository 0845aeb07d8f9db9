//! Where a Newton iteration's residual sits: its largest node, and the shares of it at nodes a
//! tool touches and at nodes with a yarn on the law's toe. Recorded with `record_residuals`
//! (the trace of `wovenform run --newton-trace`), to tell which nonlinearity a step's
//! iterations are spent on: the contact's edge, the toe's slack/taut settling, or neither.

use super::model::Model;
use super::terms::NodeBlock;

/// One iteration's residual, located.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ResidualSite {
    /// The node with the largest residual (the norm of its three components).
    pub node: usize,
    /// Its position at this iteration, mm.
    pub position_mm: [f64; 3],
    /// Its residual, N.
    pub residual_n: f64,
    /// Whether a tool touches it (its contact block is not zero).
    pub touching: bool,
    /// Whether one of its elements has a yarn on the toe (tension between zero and `C w/2`).
    pub on_toe: bool,
    /// Share of the squared residual at nodes a tool touches (0–1).
    pub share_touching: f64,
    /// Share of the squared residual at nodes with a yarn on the toe (0–1; the two shares
    /// overlap where a node is both).
    pub share_on_toe: f64,
}

/// Locates the residual `r` (over the equations) of the state the model's element outputs and
/// the nodal `blocks` were assembled at.
pub(super) fn locate(model: &Model, blocks: &[NodeBlock], r: &[f64]) -> ResidualSite {
    let nodes = model.mesh.nodes.len();
    let mut r2 = vec![0.0; nodes];
    for (d, &q) in model.eq.iter().enumerate() {
        if q != usize::MAX {
            r2[d / 3] += r[q] * r[q];
        }
    }
    let on_toe = toe_nodes(model);
    let touching = |n: usize| blocks.get(n).is_some_and(|b| !b.is_zero());
    let total: f64 = r2.iter().sum();
    let share = |pick: &dyn Fn(usize) -> bool| {
        let s: f64 = (0..nodes).filter(|&n| pick(n)).map(|n| r2[n]).sum();
        if total > 0.0 { s / total } else { 0.0 }
    };
    let node = (0..nodes)
        .max_by(|&a, &b| r2[a].total_cmp(&r2[b]))
        .unwrap_or(0);
    let x = model.mesh.nodes.get(node).copied().unwrap_or_default();
    let position_mm = std::array::from_fn(|m| x[m] + model.u.get(3 * node + m).unwrap_or(&0.0));
    ResidualSite {
        node,
        position_mm,
        residual_n: r2.get(node).map_or(0.0, |v| v.sqrt()),
        touching: touching(node),
        on_toe: on_toe.get(node).copied().unwrap_or(false),
        share_touching: share(&|n| touching(n)),
        share_on_toe: share(&|n| on_toe[n]),
    }
}

/// The nodes of every element with a yarn on the toe at its last evaluation.
fn toe_nodes(model: &Model) -> Vec<bool> {
    let mut on = vec![false; model.mesh.nodes.len()];
    let w = model.law.toe();
    if w <= 0.0 {
        return on;
    }
    let top = [0.5 * model.law.p.c[0] * w, 0.5 * model.law.p.c[1] * w];
    for (quad, out) in model.mesh.quads.iter().zip(&model.outputs) {
        let any = out
            .tension
            .iter()
            .any(|t| (0..2).any(|a| t[a] > 0.0 && t[a] < top[a]));
        if any {
            for &n in quad {
                on[n] = true;
            }
        }
    }
    on
}
