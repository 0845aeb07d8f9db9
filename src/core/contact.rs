//! Node-to-surface contact with the rigid tools, Coulomb friction and the blank holder.
//!
//! Normal contact is a penalty on the energy `½ k g²` for a penetration `g = d < 0`: force
//! `−k g n` on the node and tangent `k (n nᵀ + g ∂n/∂x)` (the curvature term). The penalty of a
//! node is `k = factor · (C̄/L̄0) · cells(node)`: the stiffness of the cells it carries, so the
//! penetration stays a small fraction of the element size for the forces the yarns can carry.
//!
//! Friction is regularised Coulomb with the normal force `N` and the normal `n` lagged at the
//! start of each load step: the slip `s = P (x − x_start − Δtool)`, `P = I − n nᵀ`, derives from
//! the convex potential `μ N (sqrt(|s|² + ε²) − ε)`, so its tangent is symmetric and the
//! symmetric solver applies. Full sliding carries `μ N`; `ε` is the slip that mobilises it.
//!
//! The blank holder presses the part of the blank currently on the flange (outside the die's
//! entry radius) onto the die face with the pressure `p`: a force `p A w` on a node of area `A`,
//! `w` going smoothly from 0 to 1 across one band outside the entry radius (lagged per step).
//! Friction acts on both faces: the die face through the die's normal force (which carries the
//! holder force) and the holder face with `μ p A w`, so a sliding flange carries `2 μ p` per
//! unit area.

use super::solver::{NodalSums, NodalTerms};
use super::tools::Tool;

/// One tool's role in the drawing.
#[derive(Clone, Copy, Debug, PartialEq)]
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
            self.tool
        }
    }
}

/// The blank holder.
#[derive(Clone, Copy, Debug, PartialEq)]
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
    /// The fraction of the holder pressure a node at `(x, y)` on the die face receives.
    pub fn weight(&self, x: f64, y: f64) -> f64 {
        let Some((d_open, rm)) = self.die.opening_distance(x, y) else {
            return 0.0;
        };
        let t = ((d_open - rm) / self.band).clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
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
}

/// Per node and tool, what is lagged at the start of a step.
#[derive(Clone, Copy, Debug, Default)]
struct Lag {
    normal_force: f64,
    normal: [f64; 3],
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
    lag: Vec<Lag>,
    holder_weight: Vec<f64>,
    x_step_start: Vec<[f64; 3]>,
    /// Per node and tool, the friction anchor's offset from the node at the step start (the
    /// elastic slip carried over, in the tool's frame), mm.
    carried_slip: Vec<[f64; 3]>,
    lambda_step_start: f64,
    /// Nodes within reach of each tool at the step start (the rest are skipped).
    active: Vec<Vec<u32>>,
    reach: f64,
    /// Load factor and the force of the first tool (the punch) on the fabric (z component, N)
    /// at the end of every accepted step.
    pub punch_history: Vec<(f64, f64)>,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The positive semi-definite part of a symmetric 3×3 block (negative eigenvalues set to 0).
///
/// The exact Hessian of the penalty, `k (n nᵀ + g ∂n/∂x)`, is indefinite for a node pressed
/// against a convex tool (`g < 0`): it would slide off unless the fabric holds it. Where it is
/// positive semi-definite it is kept exactly (and Newton converges quadratically); elsewhere its
/// negative part is dropped, so the tangent stays factorizable by Cholesky.
fn positive_part(m: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    if is_positive_semidefinite(&m) {
        return m;
    }
    let mat = nalgebra::Matrix3::from_fn(|i, j| m[i][j]);
    let eig = mat.symmetric_eigen();
    if eig.eigenvalues.iter().all(|&l| l >= 0.0) {
        return m;
    }
    let mut out = [[0.0; 3]; 3];
    for (l, v) in eig.eigenvalues.iter().zip(eig.eigenvectors.column_iter()) {
        if *l > 0.0 {
            for i in 0..3 {
                for j in 0..3 {
                    out[i][j] += l * v[i] * v[j];
                }
            }
        }
    }
    out
}

/// Whether a symmetric 3×3 block is positive semi-definite, by its principal minors (all of
/// them non-negative, up to round-off of the size of the block's trace): the cheap test that
/// spares the eigen-decomposition on flat tool faces, where the block is `k n nᵀ`.
fn is_positive_semidefinite(m: &[[f64; 3]; 3]) -> bool {
    let scale = (m[0][0].abs() + m[1][1].abs() + m[2][2].abs()).max(f64::MIN_POSITIVE);
    let tol = 1e-14 * scale;
    let minor2 = |a: usize, b: usize| m[a][a] * m[b][b] - m[a][b] * m[b][a];
    let det = m[0][0] * minor2(1, 2) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    (0..3).all(|a| m[a][a] >= -tol)
        && [(0, 1), (0, 2), (1, 2)]
            .iter()
            .all(|&(a, b)| minor2(a, b) >= -tol * scale)
        && det >= -tol * scale * scale
}

/// Index of `(i, j)`, `i ≤ j`, in a node block `[xx xy xz yy yz zz]`.
const BLOCK: [[usize; 3]; 3] = [[0, 1, 2], [1, 3, 4], [2, 4, 5]];

impl Contact {
    /// `area` and `cells` per node (initial), `stiffness_per_cell` = C̄/L̄0 (N/mm), `reach` (mm):
    /// nodes farther than this from a tool at a step's start are not tested during the step.
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
            lag: vec![Lag::default(); n * nt],
            holder_weight: vec![0.0; n],
            x_step_start: vec![[0.0; 3]; n],
            carried_slip: vec![[0.0; 3]; n * nt],
            lambda_step_start: 0.0,
            active: vec![(0..n as u32).collect(); nt],
            reach,
            punch_history: Vec::new(),
        }
    }

    /// Signed distances of every node to tool `t` at load `lambda`.
    pub fn distances(&self, t: usize, lambda: f64, x: &[[f64; 3]]) -> Vec<f64> {
        let tool = self.tools[t].at(lambda);
        x.iter().map(|p| tool.distance(*p).d).collect()
    }

    /// The largest penetration of any node into any tool, mm.
    pub fn max_penetration(&self, lambda: f64, x: &[[f64; 3]]) -> f64 {
        (0..self.tools.len())
            .flat_map(|t| self.distances(t, lambda, x))
            .fold(0.0f64, |m, d| m.max(-d))
    }

    /// The force the tool `t` exerts on the fabric at load `lambda` (normal and friction), N.
    pub fn tool_force(&self, t: usize, lambda: f64, x: &[[f64; 3]]) -> [f64; 3] {
        let mut r = vec![0.0; 3 * x.len()];
        for i in 0..x.len() {
            self.add_node_tool(i, t, lambda, x[i], &mut r, None);
        }
        let mut f = [0.0; 3];
        for i in 0..x.len() {
            for m in 0..3 {
                f[m] -= r[3 * i + m];
            }
        }
        f
    }

    /// Nodes in contact with tool `t` at load `lambda`.
    pub fn in_contact(&self, t: usize, lambda: f64, x: &[[f64; 3]]) -> Vec<bool> {
        self.distances(t, lambda, x)
            .iter()
            .map(|d| *d < 0.0)
            .collect()
    }

    /// The holder force currently on each node (N), lagged at the step start.
    pub fn holder_force(&self) -> Vec<f64> {
        match &self.holder {
            Some(h) => self
                .holder_weight
                .iter()
                .zip(&self.area)
                .map(|(w, a)| h.pressure * a * w)
                .collect(),
            None => vec![0.0; self.area.len()],
        }
    }

    /// The friction acting between node `i` and tool `t`: the lagged normal force (plus the
    /// holder face's `p A w` on the die) and the normal it was lagged with.
    fn friction_normal(&self, t: usize, i: usize) -> (f64, [f64; 3]) {
        let lag = self.lag[t * self.area.len() + i];
        let mut normal_force = lag.normal_force;
        if !self.tools[t].tool.is_punch()
            && let Some(h) = &self.holder
        {
            normal_force += h.pressure * self.area[i] * self.holder_weight[i];
        }
        (normal_force, lag.normal)
    }

    /// The tangential slip of node `i` at `p` relative to tool `t` since its friction anchor
    /// (the step start less the carried slip, moving with the tool), projected on the plane
    /// normal to `n`, mm.
    fn slip(&self, t: usize, i: usize, lambda: f64, p: [f64; 3], n: [f64; 3]) -> [f64; 3] {
        let motion = &self.tools[t];
        let dz = if motion.tool.is_punch() {
            motion.tip(lambda) - motion.tip(self.lambda_step_start)
        } else {
            0.0
        };
        let x0 = self.x_step_start[i];
        let c0 = self.carried_slip[t * self.area.len() + i];
        let rel = [
            p[0] - x0[0] + c0[0],
            p[1] - x0[1] + c0[1],
            p[2] - x0[2] - dz + c0[2],
        ];
        let rn = dot(rel, n);
        [rel[0] - rn * n[0], rel[1] - rn * n[1], rel[2] - rn * n[2]]
    }

    /// Adds node `i`'s terms with tool `t`: normal penalty and lagged friction. Returns the
    /// largest single force added (N) and the potential of the terms (N·mm).
    fn add_node_tool(
        &self,
        i: usize,
        t: usize,
        lambda: f64,
        p: [f64; 3],
        r: &mut [f64],
        block: Option<&mut [f64; 6]>,
    ) -> (f64, f64) {
        let mut largest = 0.0f64;
        let mut energy = 0.0;
        let motion = &self.tools[t];
        let tool = motion.at(lambda);
        let k = self.penalty[i];
        let dist = tool.distance(p);
        let mut local_k = [[0.0; 3]; 3];
        let want_k = block.is_some();
        // Touching counts as contact for the tangent (the force starts at zero), so a node lying
        // on a tool is not left with no stiffness against it.
        if dist.d <= 0.0 {
            let g = dist.d;
            largest = largest.max(-k * g);
            energy += 0.5 * k * g * g;
            for m in 0..3 {
                r[3 * i + m] += k * g * dist.n[m];
            }
            if want_k {
                let h = tool.curvature(p, self.reach);
                let mut block = [[0.0; 3]; 3];
                for a in 0..3 {
                    for b in 0..3 {
                        block[a][b] = k * (dist.n[a] * dist.n[b] + g * h[a][b]);
                    }
                }
                let block = positive_part(block);
                for a in 0..3 {
                    for b in 0..3 {
                        local_k[a][b] += block[a][b];
                    }
                }
            }
        }
        // Friction with the lagged normal force (plus the holder face on the die).
        let (normal_force, n) = self.friction_normal(t, i);
        let mu = self.options.friction;
        if mu > 0.0 && normal_force > 0.0 {
            let s = self.slip(t, i, lambda, p, n);
            let eps = self.options.slip_regularisation;
            let rho = (dot(s, s) + eps * eps).sqrt();
            let c = mu * normal_force;
            largest = largest.max(c * dot(s, s).sqrt() / rho);
            energy += c * (rho - eps);
            for m in 0..3 {
                r[3 * i + m] += c * s[m] / rho;
            }
            if want_k {
                for a in 0..3 {
                    for b in 0..3 {
                        let pab = if a == b { 1.0 } else { 0.0 } - n[a] * n[b];
                        local_k[a][b] += c * (pab / rho - s[a] * s[b] / rho.powi(3));
                    }
                }
            }
        }
        if let Some(blk) = block {
            for a in 0..3 {
                for b in a..3 {
                    blk[BLOCK[a][b]] += local_k[a][b];
                }
            }
        }
        (largest, energy)
    }
}

impl NodalTerms for Contact {
    fn begin_step(&mut self, lambda: f64, x: &[[f64; 3]]) {
        let n = x.len();
        let lambda0 = self.lambda_step_start;
        self.x_step_start.copy_from_slice(x);
        for t in 0..self.tools.len() {
            let tool = self.tools[t].at(lambda0);
            // The tool's travel over this step.
            let stroke = (self.tools[t].tip(lambda) - self.tools[t].tip(lambda0)).abs();
            let mut active = Vec::new();
            for i in 0..n {
                let dist = tool.distance(x[i]);
                self.lag[t * n + i] = Lag {
                    normal_force: self.penalty[i] * (-dist.d).max(0.0),
                    normal: dist.n,
                };
                // A node farther than the reach plus the tool's travel cannot touch it this step.
                if dist.d < self.reach + stroke {
                    active.push(i as u32);
                }
            }
            self.active[t] = active;
        }
        if let Some(h) = &self.holder {
            for i in 0..n {
                // Only nodes lying on the die face are held.
                let on_face = x[i][2].abs() < self.reach;
                self.holder_weight[i] = if on_face {
                    h.weight(x[i][0], x[i][1])
                } else {
                    0.0
                };
            }
        }
    }

    fn add(
        &self,
        lambda: f64,
        x: &[[f64; 3]],
        r: &mut [f64],
        mut blocks: Option<&mut [[f64; 6]]>,
    ) -> Option<NodalSums> {
        let mut largest = vec![0.0f64; x.len()];
        let mut energy = 0.0;
        for t in 0..self.tools.len() {
            for &i in &self.active[t] {
                let i = i as usize;
                let blk = blocks.as_deref_mut().map(|b| &mut b[i]);
                let (f, e) = self.add_node_tool(i, t, lambda, x[i], r, blk);
                largest[i] = largest[i].max(f);
                energy += e;
            }
        }
        if let Some(h) = &self.holder {
            for i in 0..x.len() {
                let f = h.pressure * self.area[i] * self.holder_weight[i];
                r[3 * i + 2] += f;
                largest[i] = largest[i].max(f);
                energy += f * x[i][2];
            }
        }
        let scale = largest.iter().map(|f| f * f).sum::<f64>().sqrt();
        scale.is_finite().then_some(NodalSums { scale, energy })
    }

    fn end_step(&mut self, lambda: f64, x: &[[f64; 3]]) {
        // Carry the slip over: a node that slid keeps its anchor 10ε behind it along the slip, so
        // continued sliding starts the next step at 99.5 % of μN instead of climbing the
        // regularisation again (the anchor of elasto-plastic friction).
        let n = x.len();
        let eps = self.options.slip_regularisation;
        for t in 0..self.tools.len() {
            for i in 0..n {
                let k = t * n + i;
                let (normal_force, nn) = self.friction_normal(t, i);
                if normal_force <= 0.0 {
                    self.carried_slip[k] = [0.0; 3];
                    continue;
                }
                let sl = self.slip(t, i, lambda, x[i], nn);
                let len = dot(sl, sl).sqrt();
                let keep = (10.0 * eps).min(len);
                self.carried_slip[k] = if len > 0.0 {
                    [sl[0] * keep / len, sl[1] * keep / len, sl[2] * keep / len]
                } else {
                    [0.0; 3]
                };
            }
        }
        if !self.tools.is_empty() {
            let f = self.tool_force(0, lambda, x)[2];
            self.punch_history.push((lambda, f));
        }
        self.lambda_step_start = lambda;
    }
}
