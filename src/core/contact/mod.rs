//! Node-to-surface contact of the blank with the rigid tools: normal penalty ([`normal`]),
//! Coulomb friction ([`friction`]) and the blank holder ([`holder`]), for every node.
//!
//! The penalty of a node is `k = factor · (C̄/L̄0) · cells(node)`: the stiffness of the cells it
//! carries, so the penetration stays a small fraction of the element size for the forces the
//! yarns can carry. Friction acts on both faces of the flange: the die face through the die's
//! normal force (which carries the holder force) and the holder face with `μ p A w`, so a
//! sliding flange carries `2 μ p` per unit area.

mod balance;
pub mod friction;
mod held;
pub mod holder;
pub mod normal;
mod predict;

pub use holder::{Holder, Plate};

use super::solver::{NodalSums, NodalTerms, NodeBlock, NodeStiffness, RankOne};
use super::tools::{Distance, Tool};

/// One tool's role in the drawing.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolMotion {
    pub tool: Tool,
    /// Tip height at load 0 and its change at full load (punches; 0 for dies).
    pub tip_start: f64,
    pub stroke: f64,
}

impl ToolMotion {
    pub fn tip(&self, lambda: f64) -> f64 {
        self.tip_start - lambda * self.stroke
    }

    pub fn at(&self, lambda: f64) -> Tool {
        if self.tool.is_punch() {
            self.tool.at_tip(self.tip(lambda))
        } else {
            self.tool.clone()
        }
    }

    /// The tool's translation (along z) from load `from` to load `to`, mm.
    fn travel(&self, from: f64, to: f64) -> f64 {
        if self.tool.is_punch() {
            self.tip(to) - self.tip(from)
        } else {
            0.0
        }
    }
}

/// Contact settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactOptions {
    /// Coulomb friction coefficient between fabric and tools.
    pub friction: f64,
    /// Slip that mobilises full friction, mm.
    pub slip_regularisation: f64,
    /// Penalty factor (dimensionless, times the cells' stiffness).
    pub penalty_factor: f64,
    /// Gap over which the penalty's force and stiffness fade in, mm.
    pub contact_smoothing: f64,
    /// Friction's normal force and normal and the holder's weights lagged (taken from the last
    /// [`NodalTerms::relag`], at the start of each step) instead of the current state: kept to
    /// measure against, not the default.
    pub lagged: bool,
}

/// Per node and tool: the friction anchor and what the line search's merit freezes.
#[derive(Clone, Copy, Debug, Default)]
struct Pair {
    /// The friction anchor at the step's start (the tool's position then), mm.
    anchor: [f64; 3],
    /// The elastic slip carried over from the last step, mm.
    carried: [f64; 3],
    /// Signed distance at the step's start, mm.
    d_start: f64,
    /// The node's position at the step's start, mm.
    x_start: [f64; 3],
    /// Friction's normal force and unit normal taken at the Newton iterate by
    /// [`NodalTerms::freeze`] (the line search's merit), or lagged (`ContactOptions::lagged`).
    lag_force: f64,
    lag_normal: [f64; 3],
}

/// The contact terms of a drawing: tools, friction and holder, for every node of the blank.
pub struct Contact {
    pub tools: Vec<ToolMotion>,
    pub holder: Option<Holder>,
    pub options: ContactOptions,
    /// Initial tributary area of each node, mm².
    pub area: Vec<f64>,
    /// Penalty of each node, N/mm.
    pub penalty: Vec<f64>,
    pairs: Vec<Pair>,
    /// Holder weight of each node frozen by [`NodalTerms::freeze`].
    frozen_weight: Vec<f64>,
    lambda_start: f64,
    /// Nodes within reach of each tool at the step's start (the rest are skipped).
    active: Vec<Vec<u32>>,
    /// Nodes the holder may press during the step.
    held: Vec<u32>,
    reach: f64,
    /// The holder's plate at the positions last asked ([`Holder::plate_force_n`]).
    plate: std::sync::Mutex<Option<Plate>>,
    /// A dead load along z on each node, N, held at every load factor (the trigger of a
    /// buckling problem, [`crate::core::wrinkles::trigger`]); empty: none.
    pub trigger: Vec<f64>,
    /// Load factor and the force of the first tool (the punch) on the fabric (z component, N)
    /// at the end of every accepted step.
    pub punch_history: Vec<(f64, f64)>,
    /// The last distance asked of each node and mesh tool (see [`Contact::distance`]).
    memo: std::sync::Mutex<Vec<Memo>>,
}

/// A mesh tool's distance at a point, kept: the Newton loop asks for it at the same point
/// several times (the assembly, friction's freeze, the trial's projection), and a mesh tool's
/// answer costs an interpolation.
#[derive(Clone, Copy, Debug, Default)]
struct Memo {
    /// The point in the tool's frame, and whether it is set.
    at: Option<[f64; 3]>,
    dist: Option<Distance>,
    curvature: Option<[[f64; 3]; 3]>,
    /// The holder's weight and its gradient there (a mesh die's flange interpolates too).
    weight: Option<(f64, [f64; 2])>,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The unit normal `n̂ = n/|n|` of a distance gradient `n`, and with the curvature `H = ∇n`
/// also `∇n̂ = (I − n̂ n̂ᵀ) H/|n|`. The gradient is a unit vector wherever the tool's field is a
/// true distance; in a punch's variable-radius corner blend it is not, and friction must project
/// on the tangent plane with a unit normal.
fn unit_normal(n: [f64; 3], h: Option<&[[f64; 3]; 3]>) -> ([f64; 3], Option<[[f64; 3]; 3]>) {
    let len = dot(n, n).sqrt();
    if len == 0.0 {
        return (n, h.copied());
    }
    let u = n.map(|v| v / len);
    let dh = h.map(|h| {
        let mut out = [[0.0; 3]; 3];
        for a in 0..3 {
            for b in 0..3 {
                let mut v = 0.0;
                for c in 0..3 {
                    let p_ac = (a == c) as u8 as f64 - u[a] * u[c];
                    v += p_ac * h[c][b];
                }
                out[a][b] = v / len;
            }
        }
        out
    });
    (u, dh)
}

fn add_into(m: &mut [[f64; 3]; 3], a: &[[f64; 3]; 3]) {
    for i in 0..3 {
        for j in 0..3 {
            m[i][j] += a[i][j];
        }
    }
}

impl Contact {
    /// `area` and `cells` per node (initial), `stiffness_per_cell` = C̄/L̄0 (N/mm), `reach` (mm):
    /// nodes farther than this from a tool at a step's start (beyond the tool's travel) are not
    /// tested during the step.
    pub fn new(
        tools: Vec<ToolMotion>,
        holder: Option<Holder>,
        options: ContactOptions,
        area: Vec<f64>,
        cells: &[f64],
        stiffness_per_cell: f64,
        reach: f64,
    ) -> Contact {
        let n = area.len();
        let penalty = cells
            .iter()
            .map(|c| options.penalty_factor * stiffness_per_cell * c)
            .collect();
        let nt = tools.len();
        Contact {
            tools,
            holder,
            options,
            area,
            penalty,
            pairs: vec![Pair::default(); n * nt],
            frozen_weight: vec![0.0; n],
            lambda_start: 0.0,
            active: vec![(0..n as u32).collect(); nt],
            held: (0..n as u32).collect(),
            reach,
            plate: std::sync::Mutex::new(None),
            trigger: Vec::new(),
            punch_history: Vec::new(),
            memo: std::sync::Mutex::new(vec![Memo::default(); n * nt]),
        }
    }

    /// The distance of node `i` to `tool` (tool `t` placed at the current load) at `p`, with
    /// the curvature when `curvature`: for a mesh tool one interpolation answers both, and is
    /// remembered for the node; an analytic tool is asked directly.
    fn distance(
        &self,
        t: usize,
        i: usize,
        tool: &Tool,
        p: [f64; 3],
        curvature: bool,
    ) -> (Distance, Option<[[f64; 3]; 3]>) {
        let Tool::Mesh { shape, tip } = tool else {
            let h = curvature.then(|| tool.curvature(p, self.reach));
            return (tool.distance(p), h);
        };
        let local = [p[0], p[1], p[2] - tip];
        let mut memo = self.memo.lock().unwrap_or_else(|e| e.into_inner());
        let m = &mut memo[t * self.nodes() + i];
        if let Some(d) = m.dist.filter(|_| m.at == Some(local))
            && (m.curvature.is_some() || !curvature)
        {
            return (d, m.curvature.filter(|_| curvature));
        }
        let e = shape.distance.evaluate(local, curvature);
        let dist = Distance { d: e.d, n: e.n };
        *m = Memo {
            at: Some(local),
            dist: Some(dist),
            curvature: e.hessian,
            weight: None,
        };
        (dist, e.hessian)
    }

    fn nodes(&self) -> usize {
        self.area.len()
    }

    /// The largest penetration of any node into any tool at load `lambda`, mm.
    pub fn max_penetration(&self, lambda: f64, x: &[[f64; 3]]) -> f64 {
        self.tools
            .iter()
            .flat_map(|m| {
                let tool = m.at(lambda);
                x.iter().map(move |p| -tool.distance(*p).d)
            })
            .fold(0.0f64, f64::max)
    }

    /// The force the tool `t` exerts on the fabric at load `lambda` (normal and friction), N.
    pub fn tool_force(&self, t: usize, lambda: f64, x: &[[f64; 3]]) -> [f64; 3] {
        let mut f = [0.0; 3];
        for (i, p) in x.iter().enumerate() {
            let r = self.node_tool(i, t, lambda, *p, false).residual;
            for m in 0..3 {
                f[m] -= r[m];
            }
        }
        f
    }

    /// Nodes the tool `t` presses at load `lambda`.
    pub fn in_contact(&self, t: usize, lambda: f64, x: &[[f64; 3]]) -> Vec<bool> {
        let tool = self.tools[t].at(lambda);
        let delta = self.options.contact_smoothing;
        x.iter().map(|p| tool.distance(*p).d < delta).collect()
    }

    /// The friction anchor of node `i` and tool `t` at load `lambda`.
    fn anchor(&self, t: usize, i: usize, lambda: f64) -> [f64; 3] {
        let mut a = self.pairs[t * self.nodes() + i].anchor;
        a[2] += self.tools[t].travel(self.lambda_start, lambda);
        a
    }

    /// Node `i`'s terms with tool `t` at `p`: penalty and friction.
    fn node_tool(&self, i: usize, t: usize, lambda: f64, p: [f64; 3], tangent: bool) -> Terms {
        let tool = self.tools[t].at(lambda);
        // A mesh tool gives its curvature with its distance: ask for both when the tangent is.
        let mesh = matches!(tool, Tool::Mesh { .. });
        let (dist, mut curvature) = self.distance(t, i, &tool, p, tangent && mesh);
        let pair = &self.pairs[t * self.nodes() + i];
        let (mu, eps) = (self.options.friction, self.options.slip_regularisation);
        let mut out = Terms::default();
        let rel = self.relative(t, i, lambda, p);
        // The merit's friction, frozen at the Newton iterate, counts wherever the trial lies.
        if mu > 0.0 && pair.lag_force > 0.0 {
            out.energy_frozen += friction::potential(mu, eps, pair.lag_force, pair.lag_normal, rel);
        }
        let (k, delta) = (self.penalty[i], self.options.contact_smoothing);
        let (pressed, stiffness, _) = normal::law(k, delta, dist.d);
        let (held, held_gradient) = self.holder_normal(t, i, p);
        let normal_force = if self.options.lagged {
            pair.lag_force
        } else {
            pressed + held
        };
        let rubbing = mu > 0.0 && normal_force > 0.0;
        if dist.d >= delta && !rubbing {
            return out;
        }
        let h = if tangent {
            Some(match curvature.take() {
                Some(h) => h,
                None => tool.curvature(p, self.reach),
            })
        } else {
            None
        };
        if let Some(pen) = normal::penalty(k, delta, dist.d, dist.n, h.as_ref()) {
            out.largest = pen.force;
            out.energy += pen.energy;
            out.energy_frozen += pen.energy;
            out.residual = pen.residual;
            out.block.spd = pen.spd;
            out.block.rest = pen.rest;
        }
        if rubbing {
            // ∇N: the penalty's stiffness along the normal, and the holder's weight in the plane.
            let mut gradient = held_gradient;
            for m in 0..3 {
                gradient[m] -= stiffness * dist.n[m];
            }
            let (n, h) = unit_normal(dist.n, h.as_ref());
            let at = if self.options.lagged {
                (pair.lag_normal, [0.0; 3], tangent.then_some([[0.0; 3]; 3]))
            } else {
                (n, gradient, h)
            };
            let c = friction::Contact {
                mu,
                eps,
                normal_force,
                normal_force_gradient: at.1,
                n: at.0,
                rel,
            };
            let f = friction::friction(&c, at.2.as_ref());
            out.largest = out.largest.max(f.magnitude);
            out.energy += f.energy;
            for m in 0..3 {
                out.residual[m] += f.residual[m];
            }
            add_into(&mut out.block.spd, &f.spd);
            add_into(&mut out.block.rest, &f.rest);
        }
        out
    }

    /// `x − a`: node `i`'s position `p` from its friction anchor against tool `t` at `lambda`.
    fn relative(&self, t: usize, i: usize, lambda: f64, p: [f64; 3]) -> [f64; 3] {
        let a = self.anchor(t, i, lambda);
        [p[0] - a[0], p[1] - a[1], p[2] - a[2]]
    }

    /// Takes friction's normal force and normal and the holder's weights at `x`.
    fn set_lag(&mut self, lambda: f64, x: &[[f64; 3]]) {
        self.update_plate(x);
        let n = x.len();
        for t in 0..self.tools.len() {
            for k in 0..self.active[t].len() {
                let i = self.active[t][k] as usize;
                let (f, normal) = self.friction_normal(t, i, lambda, x[i]);
                let pair = &mut self.pairs[t * n + i];
                pair.lag_force = f;
                pair.lag_normal = normal;
            }
        }
        if let Some(h) = &self.holder {
            for &i in &self.held {
                let i = i as usize;
                self.frozen_weight[i] = h.weight(x[i][0], x[i][1]).0;
            }
        }
    }

    /// The friction normal force and unit normal of node `i` against tool `t` at `p`.
    fn friction_normal(&self, t: usize, i: usize, lambda: f64, p: [f64; 3]) -> (f64, [f64; 3]) {
        let dist = self.distance(t, i, &self.tools[t].at(lambda), p, false).0;
        let held = self.holder_normal(t, i, p).0;
        let pressed = normal::law(self.penalty[i], self.options.contact_smoothing, dist.d).0;
        (pressed + held, unit_normal(dist.n, None).0)
    }
}

/// What one node–tool pair adds.
#[derive(Clone, Copy, Debug, Default)]
struct Terms {
    residual: [f64; 3],
    energy: f64,
    energy_frozen: f64,
    largest: f64,
    block: NodeBlock,
}

impl NodalTerms for Contact {
    fn begin_step(&mut self, lambda_start: f64, lambda: f64, x: &[[f64; 3]]) {
        let n = x.len();
        self.lambda_start = lambda_start;
        for t in 0..self.tools.len() {
            let tool = self.tools[t].at(lambda_start);
            let travel = self.tools[t].travel(lambda_start, lambda).abs();
            let mut active = Vec::new();
            for i in 0..n {
                let d = tool.distance(x[i]).d;
                let pair = &mut self.pairs[t * n + i];
                pair.d_start = d;
                pair.x_start = x[i];
                for m in 0..3 {
                    pair.anchor[m] = x[i][m] - pair.carried[m];
                }
                // A node farther than the reach plus the tool's travel cannot touch it this step.
                if d < self.reach + travel {
                    active.push(i as u32);
                }
            }
            self.active[t] = active;
        }
        if let Some(h) = &self.holder {
            self.held = (0..n as u32)
                .filter(|&i| h.may_hold(x[i as usize][0], x[i as usize][1]))
                .collect();
        }
        if self.options.lagged {
            self.set_lag(lambda_start, x);
        }
    }

    fn project(&self, lambda: f64, x: &mut [[f64; 3]], keep_slide: bool) {
        self.project_predicted(lambda, x, keep_slide);
    }

    fn carried_at_start(&self, lambda: f64) -> Vec<Option<f64>> {
        let n = self.area.len();
        let delta = self.options.contact_smoothing;
        let mut carried: Vec<Option<f64>> = vec![None; n];
        for t in 0..self.tools.len() {
            let travel = self.tools[t].travel(self.lambda_start, lambda);
            for &i in &self.active[t] {
                let i = i as usize;
                // A node a tool at rest holds stays held by it.
                if self.pairs[t * n + i].d_start < delta && carried[i] != Some(0.0) {
                    carried[i] = Some(travel);
                }
            }
        }
        carried
    }

    fn project_trial(&self, lambda: f64, x_base: &[[f64; 3]], x: &mut [[f64; 3]]) {
        let delta = self.options.contact_smoothing;
        for t in 0..self.tools.len() {
            let tool = self.tools[t].at(lambda);
            for &i in &self.active[t] {
                let i = i as usize;
                let dist = self.distance(t, i, &tool, x[i], false).0;
                if dist.d < 0.0 && tool.distance(x_base[i]).d >= delta {
                    for m in 0..3 {
                        x[i][m] -= dist.d * dist.n[m];
                    }
                }
            }
        }
    }

    fn reshape(
        &self,
        lambda: f64,
        x: &[[f64; 3]],
        du: &mut [[f64; 3]],
        stiffness: NodeStiffness,
    ) -> bool {
        let moves = self.balancing_moves(lambda, x, du, stiffness);
        for (i, shift) in &moves {
            for m in 0..3 {
                du[*i][m] += shift[m];
            }
        }
        !moves.is_empty()
    }

    fn freeze(&mut self, lambda: f64, x: &[[f64; 3]]) {
        if !self.options.lagged {
            self.set_lag(lambda, x);
        }
    }

    fn relag(&mut self, lambda: f64, x: &[[f64; 3]]) -> bool {
        if self.options.lagged {
            self.set_lag(lambda, x);
        }
        self.options.lagged
    }

    fn add(
        &self,
        lambda: f64,
        x: &[[f64; 3]],
        r: &mut [f64],
        mut blocks: Option<&mut [NodeBlock]>,
    ) -> Option<NodalSums> {
        self.update_plate(x);
        let mut largest = vec![0.0f64; x.len()];
        let (mut energy, mut energy_frozen) = (0.0, 0.0);
        let tangent = blocks.is_some();
        for t in 0..self.tools.len() {
            for &i in &self.active[t] {
                let i = i as usize;
                let terms = self.node_tool(i, t, lambda, x[i], tangent);
                for m in 0..3 {
                    r[3 * i + m] += terms.residual[m];
                }
                largest[i] = largest[i].max(terms.largest);
                energy += terms.energy;
                energy_frozen += terms.energy_frozen;
                if let Some(b) = blocks.as_deref_mut() {
                    add_into(&mut b[i].spd, &terms.block.spd);
                    add_into(&mut b[i].rest, &terms.block.rest);
                }
            }
        }
        let (e, e_frozen) = self.add_held(x, r, &mut largest, blocks);
        energy += e;
        energy_frozen += e_frozen;
        for (i, f) in self.trigger.iter().enumerate() {
            r[3 * i + 2] -= f;
            largest[i] = largest[i].max(f.abs());
            energy -= f * x[i][2];
            energy_frozen -= f * x[i][2];
        }
        let scale = largest.iter().map(|f| f * f).sum::<f64>().sqrt();
        scale.is_finite().then_some(NodalSums {
            scale,
            energy,
            energy_frozen,
        })
    }

    fn coupling(&self, x: &[[f64; 3]]) -> Option<RankOne> {
        self.plate_coupling(x)
    }

    fn end_step(&mut self, lambda: f64, x: &[[f64; 3]]) {
        self.update_plate(x);
        // Carry the slip over: a node that slid keeps its anchor 10ε behind it along the slip, so
        // continued sliding starts the next step at 99.5 % of μN instead of climbing the
        // regularisation again (the anchor of elasto-plastic friction).
        let n = x.len();
        let eps = self.options.slip_regularisation;
        for t in 0..self.tools.len() {
            for i in 0..n {
                let (normal_force, normal) = if self.options.lagged {
                    let pair = &self.pairs[t * n + i];
                    (pair.lag_force, pair.lag_normal)
                } else {
                    self.friction_normal(t, i, lambda, x[i])
                };
                let carried = if normal_force > 0.0 {
                    let s = friction::tangential(normal, self.relative(t, i, lambda, x[i]));
                    let len = dot(s, s).sqrt();
                    let keep = (10.0 * eps).min(len);
                    if len > 0.0 {
                        s.map(|v| v * keep / len)
                    } else {
                        [0.0; 3]
                    }
                } else {
                    [0.0; 3]
                };
                self.pairs[t * n + i].carried = carried;
            }
        }
        if !self.tools.is_empty() {
            let f = self.tool_force(0, lambda, x)[2];
            self.punch_history.push((lambda, f));
        }
    }
}
