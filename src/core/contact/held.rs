//! What the blank holder does to the nodes it holds ([`super::holder`]): its force on each
//! node, under a pressure or a rigid plate, the force's share in the friction on the die, and
//! its terms in the residual, the tangent and the potential.

use super::holder::{Holder, Plate};
use super::{Contact, NodeBlock};
use crate::core::solver::RankOne;
use crate::core::tools::Tool;

impl Contact {
    /// The plate at positions `x`, kept for the node terms that follow (`None`: no plate).
    pub(super) fn update_plate(&self, x: &[[f64; 3]]) -> Option<Plate> {
        let plate = self.holder.as_ref().and_then(|h| {
            let weight = |i: usize| h.weight(x[i][0], x[i][1]).0;
            let delta = self.options.contact_smoothing;
            h.plate(&self.held, x, &weight, &self.penalty, delta)
        });
        *self.plate.lock().unwrap_or_else(|e| e.into_inner()) = plate;
        plate
    }

    fn current_plate(&self) -> Option<Plate> {
        *self.plate.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The holder force on each node at positions `x` (N).
    pub fn holder_force(&self, x: &[[f64; 3]]) -> Vec<f64> {
        let Some(h) = &self.holder else {
            return vec![0.0; self.area.len()];
        };
        let plate = self.update_plate(x);
        (0..x.len())
            .map(|i| self.held_force(h, plate, i, x[i], h.weight(x[i][0], x[i][1]).0))
            .collect()
    }

    /// Node `i`'s holder force at `p` with weight `w`, N.
    fn held_force(&self, h: &Holder, plate: Option<Plate>, i: usize, p: [f64; 3], w: f64) -> f64 {
        match plate {
            Some(plate) => {
                let delta = self.options.contact_smoothing;
                plate.node(w, self.penalty[i], delta, p[2]).0
            }
            None if h.plate_force_n.is_some() => 0.0,
            None => h.pressure * self.area[i] * w,
        }
    }

    /// The holder's weight of node `i` at `p` and its gradient, remembered with the node's
    /// distance to a mesh die (where the flange's interpolation answers it).
    fn holder_weight(&self, h: &Holder, t: usize, i: usize, p: [f64; 3]) -> (f64, [f64; 2]) {
        if !matches!(self.tools[t].tool, Tool::Mesh { .. }) {
            return h.weight(p[0], p[1]);
        }
        let mut memo = self.memo.lock().unwrap_or_else(|e| e.into_inner());
        let m = &mut memo[t * self.nodes() + i];
        if m.at == Some(p) {
            if let Some(w) = m.weight {
                return w;
            }
            let w = h.weight(p[0], p[1]);
            m.weight = Some(w);
            return w;
        }
        h.weight(p[0], p[1])
    }

    /// The holder part of the friction normal force on the die (the holder face's friction),
    /// with its gradient.
    pub(super) fn holder_normal(&self, t: usize, i: usize, p: [f64; 3]) -> (f64, [f64; 3]) {
        match &self.holder {
            Some(h) if !self.tools[t].tool.is_punch() => {
                let (w, g) = self.holder_weight(h, t, i, p);
                match self.current_plate() {
                    Some(plate) => {
                        let delta = self.options.contact_smoothing;
                        let (f, dz, _) = plate.node(w, self.penalty[i], delta, p[2]);
                        let per_w = if w > 0.0 { f / w } else { 0.0 };
                        (f, [per_w * g[0], per_w * g[1], dz])
                    }
                    None => {
                        let pa = self.held_force(h, None, i, p, 1.0);
                        (pa * w, [pa * g[0], pa * g[1], 0.0])
                    }
                }
            }
            _ => (0.0, [0.0; 3]),
        }
    }

    /// The holder's force on each held node at `x` into `r` (and its derivative into
    /// `blocks`), each node's largest force into `largest`; returns the holder's potential and
    /// that with the weights frozen (N·mm).
    pub(super) fn add_held(
        &self,
        x: &[[f64; 3]],
        r: &mut [f64],
        largest: &mut [f64],
        mut blocks: Option<&mut [NodeBlock]>,
    ) -> (f64, f64) {
        let Some(h) = &self.holder else {
            return (0.0, 0.0);
        };
        let plate = self.current_plate();
        // The plate's load: F h (the force presses it down).
        let (mut energy, mut energy_frozen) = plate.map_or((0.0, 0.0), |p| {
            let e = p.force_n * p.height;
            (e, e)
        });
        let delta = self.options.contact_smoothing;
        for &i in &self.held {
            let i = i as usize;
            let (mut w, mut g) = h.weight(x[i][0], x[i][1]);
            if self.options.lagged {
                (w, g) = (self.frozen_weight[i], [0.0; 2]);
            }
            let frozen = self.frozen_weight[i];
            let (f, dz, e, e_frozen) = match plate {
                Some(plate) => {
                    let (f, dz, e) = plate.node(w, self.penalty[i], delta, x[i][2]);
                    let e_frozen = plate.node(frozen, self.penalty[i], delta, x[i][2]).2;
                    (f, dz, e, e_frozen)
                }
                None => {
                    let pa = self.held_force(h, None, i, x[i], 1.0);
                    (pa * w, 0.0, pa * w * x[i][2], pa * frozen * x[i][2])
                }
            };
            r[3 * i + 2] += f;
            largest[i] = largest[i].max(f);
            energy += e;
            energy_frozen += e_frozen;
            if let Some(b) = blocks.as_deref_mut() {
                let per_w = if w > 0.0 { f / w } else { 0.0 };
                b[i].rest[2][0] += per_w * g[0];
                b[i].rest[2][1] += per_w * g[1];
                b[i].spd[2][2] += dz;
            }
        }
        (energy, energy_frozen)
    }

    /// The plate's coupling at `x` (`None`: no plate): each held node's contact stiffness
    /// `u = w φ''` — the plate follows every node, so a node's push moves the others' forces
    /// by `−u_i u_j / Σu` (the part of the tangent beyond each node's own block).
    pub(super) fn plate_coupling(&self, x: &[[f64; 3]]) -> Option<RankOne> {
        let h = self.holder.as_ref()?;
        let plate = self.current_plate()?;
        let delta = self.options.contact_smoothing;
        let nodes = (self.held.iter())
            .filter_map(|&i| {
                let i = i as usize;
                let w = if self.options.lagged {
                    self.frozen_weight[i]
                } else {
                    h.weight(x[i][0], x[i][1]).0
                };
                let k = super::normal::law(self.penalty[i], delta, plate.height - x[i][2]).1;
                (w * k > 0.0).then_some((i, w * k))
            })
            .collect();
        Some(RankOne {
            nodes,
            total: plate.stiffness_sum,
        })
    }
}
