//! The predicted state of a load step moved back onto the tools
//! ([`crate::core::solver::NodalTerms::project`]).
//!
//! A node a tool pressed at the step's start is put back at its gap then (and so at about its
//! pressure), one that was free is kept out of the tool's reach. Put back along the normal, a
//! node the secant predictor slid over a tool at rest loses distance where the tool is curved:
//! on the die's radius the secant leaves the surface, the normal brings it back short, while its
//! neighbour on the flat keeps the whole step. The yarn between them shortens; one that carried
//! the draw-in goes slack, and the first correction, seeing the flange held by sliding friction
//! alone, throws it outward (`guide::solver`, "The predictor"). With `keep_slide` such a
//! node is moved on along the tool to the distance it slid in the secant and put back again,
//! [`SLIDE_PASSES`] times. Not on a moving tool (the punch): there it measured worse.

use super::Contact;
use crate::core::vec3::{dot, sub};

/// Moves along the tool that restore a node's slid distance (see the module).
const SLIDE_PASSES: usize = 3;

impl Contact {
    /// Moves predicted positions `x` at `lambda` back onto the tools (see the module).
    pub(super) fn project_predicted(&self, lambda: f64, x: &mut [[f64; 3]], keep_slide: bool) {
        let n = x.len();
        let delta = self.options.contact_smoothing;
        for t in 0..self.tools.len() {
            let tool = self.tools[t].at(lambda);
            let at_rest = !self.tools[t].tool.is_punch();
            for &i in &self.active[t] {
                let i = i as usize;
                let pair = &self.pairs[t * n + i];
                let dist = self.distance(t, i, &tool, x[i], false).0;
                let goal = if pair.d_start < delta {
                    pair.d_start
                } else if dist.d < delta {
                    delta
                } else {
                    continue;
                };
                let moved = sub(x[i], pair.x_start);
                let slid = dot(moved, moved).sqrt();
                for m in 0..3 {
                    x[i][m] += (goal - dist.d) * dist.n[m];
                }
                if !(keep_slide && at_rest && pair.d_start < delta) {
                    continue;
                }
                // Each pass leaves a shortfall of about the last one's times (L/2R)² (on the
                // die's radius 5 mm, 1.2 mm short by 0.025, then 3.6e-4, then 5e-6).
                for _ in 0..SLIDE_PASSES {
                    let v = sub(x[i], pair.x_start);
                    let len = dot(v, v).sqrt();
                    if !(len > 0.0 && len < slid) {
                        break;
                    }
                    x[i] = std::array::from_fn(|m| pair.x_start[m] + v[m] * slid / len);
                    let dist = self.distance(t, i, &tool, x[i], false).0;
                    for m in 0..3 {
                        x[i][m] += (goal - dist.d) * dist.n[m];
                    }
                }
            }
        }
    }
}
