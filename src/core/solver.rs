//! The implicit solver: assembly on a sparsity pattern built once per mesh, Newton with a
//! backtracking line search, and load stepping with automatic cut-back and growth.
//!
//! The paper's fabric has no in-plane shear stiffness and no bending stiffness, so a stress-free
//! sheet is a mechanism. It is stabilised by a pseudo-transient (viscous) term
//! `Fs = μ (u − u_step_start)` on every node, with `μ = κ · (C̄/L̄0) · cells(node)`; the force fades
//! with the step size and its work is reported beside the internal work, so a user can see how
//! much of the answer is the stabiliser rather than the paper's model.

use rayon::prelude::*;
use std::ops::ControlFlow;
use std::time::Instant;

use super::element::{self, ElementGeometry, ElementOutput, GAUSS, GeometryError};
use super::law::{CellLaw, CrimpState};
use super::linear::{SparseCholesky, UpperPattern};
use super::mesh::Mesh;

/// Node-local terms added to the residual and tangent (contact, pressure, friction, loads).
/// `x` is the current nodal positions; the residual convention is `r = f_int − f_ext`.
pub trait NodalTerms: Sync {
    /// Called once at the start of each load step attempt, with the converged positions.
    fn begin_step(&mut self, _lambda: f64, _x: &[[f64; 3]]) {}
    /// Adds `∂(terms)/∂x` blocks (upper triangle of each node's 3×3: xx xy xz yy yz zz) when
    /// `blocks` is given, and the forces to `r`. Returns the magnitude of the forces added and
    /// their potential, or `None` if the configuration is inadmissible (the line search then
    /// shortens the step).
    fn add(
        &self,
        lambda: f64,
        x: &[[f64; 3]],
        r: &mut [f64],
        blocks: Option<&mut [[f64; 6]]>,
    ) -> Option<NodalSums>;
    /// Called when a step is accepted.
    fn end_step(&mut self, _lambda: f64, _x: &[[f64; 3]]) {}
}

/// What [`NodalTerms::add`] returns besides the forces.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NodalSums {
    /// The norm over nodes of each node's largest single force, N (forces that cancel each
    /// other at a node still count): the load scale of the convergence test.
    pub scale: f64,
    /// The potential of the terms at `x` (N·mm), whose gradient is what `add` adds: the line
    /// search's merit. Terms without a potential give 0 (the residual norm then decides).
    pub energy: f64,
}

/// No nodal terms.
pub struct NoNodalTerms;

impl NodalTerms for NoNodalTerms {
    fn add(
        &self,
        _: f64,
        _: &[[f64; 3]],
        _: &mut [f64],
        _: Option<&mut [[f64; 6]]>,
    ) -> Option<NodalSums> {
        Some(NodalSums::default())
    }
}

/// The prescribed displacements: which dofs (3·node + component) and their values along the
/// load path `λ ∈ [0, 1]`.
pub trait Prescribed: Sync {
    fn dofs(&self) -> &[usize];
    /// `out[i]` receives the displacement of `dofs()[i]` at `λ`.
    fn values(&self, lambda: f64, out: &mut [f64]);
}

/// Prescribed displacements proportional to the load factor: `u = λ ū`.
#[derive(Clone, Debug, Default)]
pub struct LinearPrescribed {
    pub dofs: Vec<usize>,
    pub at_full_load: Vec<f64>,
}

impl Prescribed for LinearPrescribed {
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }
    fn values(&self, lambda: f64, out: &mut [f64]) {
        for (o, v) in out.iter_mut().zip(&self.at_full_load) {
            *o = lambda * v;
        }
    }
}

/// Solver settings.
#[derive(Clone, Debug, PartialEq)]
pub struct SolverOptions {
    /// First load increment (fraction of the full load).
    pub initial_step: f64,
    /// Smallest increment before the run is declared failed.
    pub min_step: f64,
    /// Largest increment.
    pub max_step: f64,
    /// Newton iterations allowed in a step before it is cut back.
    pub max_iterations: u32,
    /// Force residual tolerance, relative to the load scale.
    pub tol_force: f64,
    /// Displacement increment tolerance, relative to the element size.
    pub tol_displacement: f64,
    /// Viscous stabilisation `κ` (dimensionless; 0 turns it off).
    pub stabilisation: f64,
    /// Assemble elements on rayon's pool (set false inside a parallel sweep if wanted).
    pub parallel: bool,
    /// Keep the residual history of each step (for convergence studies).
    pub record_residuals: bool,
    /// Fading of the stabilisation at the end of the load path: passes that re-solve the last
    /// state with the viscous reference moved to the current state, so the viscous force decays
    /// wherever the fabric's tension holds the nodes.
    pub relaxation_passes: u32,
    /// Levenberg–Marquardt damping at the start of each step (times the cells' stiffness).
    pub initial_damping: f64,
    /// Extrapolate the previous step's increment as the first guess of a step.
    pub secant_predictor: bool,
    /// Relax the stabilisation after every step (one pass), not only at the end.
    pub relax_every_step: bool,
    /// At the end of the run, time factorization + solve alone on the last tangent
    /// (`SolveStats::bare_factor_solve_s`), for the benchmark.
    pub time_bare_factorization: bool,
}

impl Default for SolverOptions {
    fn default() -> Self {
        SolverOptions {
            initial_step: 0.05,
            min_step: 1e-5,
            max_step: 0.25,
            max_iterations: 25,
            tol_force: 1e-6,
            tol_displacement: 1e-6,
            stabilisation: 1e-4,
            parallel: true,
            record_residuals: false,
            relaxation_passes: 3,
            initial_damping: 0.0,
            secant_predictor: true,
            relax_every_step: false,
            time_bare_factorization: false,
        }
    }
}

/// Why a run stopped short.
#[derive(Clone, Debug, PartialEq)]
pub enum Failure {
    /// An element is degenerate in the initial mesh.
    BadElement {
        element: usize,
        cause: GeometryError,
    },
    /// The caller asked to stop (through the progress callback) at this load factor.
    Stopped { lambda: f64 },
    /// The load increment fell below the minimum without converging.
    StepFailed {
        lambda: f64,
        step: f64,
        cause: String,
    },
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::BadElement { element, cause } => {
                write!(f, "element {element} is unusable: {cause:?}")
            }
            Failure::Stopped { lambda } => write!(f, "stopped on request at load {lambda:.4}"),
            Failure::StepFailed {
                lambda,
                step,
                cause,
            } => write!(
                f,
                "the step from load {lambda:.4} could not converge even at an increment of \
                 {step:.2e}: {cause}"
            ),
        }
    }
}

/// Counters and timings of a run.
#[derive(Clone, Debug, Default)]
pub struct SolveStats {
    pub steps: u32,
    pub cutbacks: u32,
    pub newton_iterations: u32,
    pub law_iterations: u64,
    /// Solves that needed a diagonal shift (non-positive-definite tangent).
    pub shifted_solves: u32,
    /// A solve met a singular tangent during the run: part of the blank was a mechanism
    /// (zero-stiffness trellising or slack yarns) held only by the stabilisation, or by nothing.
    pub mechanism: bool,
    /// Residual norms of each Newton iteration, per accepted step (if recorded).
    pub residuals: Vec<Vec<f64>>,
    /// Work of the internal forces, N·mm.
    pub internal_work: f64,
    /// Work done against the stabilisation, N·mm.
    pub stabilisation_work: f64,
    pub assembly_s: f64,
    pub nodal_s: f64,
    pub factor_solve_s: f64,
    /// Load factor reached.
    pub lambda: f64,
    /// Norm of the stabilisation force over the norm of the internal force, at the end.
    pub stabilisation_force_ratio: f64,
    /// Median wall time of a factorization + solve of the run's last tangent on its own, s
    /// (when `SolverOptions::time_bare_factorization`).
    pub bare_factor_solve_s: Option<f64>,
}

impl SolveStats {
    /// The stabilisation's share of the internal work.
    pub fn stabilisation_share(&self) -> f64 {
        let total = self.internal_work.abs() + self.stabilisation_work.abs();
        if total > 0.0 {
            self.stabilisation_work.abs() / total
        } else {
            0.0
        }
    }
}

/// The finite-element model of a woven blank and its current state.
pub struct Model {
    pub mesh: Mesh,
    pub law: CellLaw,
    pub geometry: Vec<ElementGeometry>,
    /// Displacements, `[3·node + m]`, mm.
    pub u: Vec<f64>,
    /// Crimp state of each Gauss point's cells.
    pub crimp: Vec<[CrimpState; GAUSS]>,
    /// Equation number of each dof (`usize::MAX` when prescribed).
    eq: Vec<usize>,
    prescribed_dofs: Vec<usize>,
    /// Slots of each element's upper-triangle pairs (`i ≤ j` over 12 dofs), `u32::MAX` if none.
    element_slots: Vec<[u32; 78]>,
    /// Slots of each node's 3×3 upper triangle.
    node_slots: Vec<[u32; 6]>,
    linear: SparseCholesky,
    /// Viscous coefficient of each node, N/mm.
    viscosity: Vec<f64>,
    outputs: Vec<ElementOutput>,
    /// Reference length for displacement tolerances: the mean element size, mm.
    pub element_size: f64,
}

/// Index of the pair `(i, j)`, `i ≤ j < 12`, in the 78 upper-triangle pairs.
fn pair_index(i: usize, j: usize) -> usize {
    i * 12 - i * (i + 1) / 2 + j
}

impl Model {
    /// Builds the model: element geometry, the dof numbering with `prescribed_dofs` removed, the
    /// sparsity pattern and its symbolic factorization.
    pub fn new(mesh: Mesh, law: CellLaw, prescribed_dofs: &[usize]) -> Result<Model, Failure> {
        let cell_lengths = law.p.l0[0] * law.p.l0[1];
        let mut geometry = Vec::with_capacity(mesh.quads.len());
        for (e, q) in mesh.quads.iter().enumerate() {
            let x0 = [
                mesh.nodes[q[0]],
                mesh.nodes[q[1]],
                mesh.nodes[q[2]],
                mesh.nodes[q[3]],
            ];
            let g = ElementGeometry::new(&x0, mesh.yarns, cell_lengths)
                .map_err(|cause| Failure::BadElement { element: e, cause })?;
            geometry.push(g);
        }
        let ndof = mesh.dofs();
        let mut eq = vec![0usize; ndof];
        let mut is_prescribed = vec![false; ndof];
        for &d in prescribed_dofs {
            is_prescribed[d] = true;
        }
        let mut n = 0;
        for d in 0..ndof {
            if is_prescribed[d] {
                eq[d] = usize::MAX;
            } else {
                eq[d] = n;
                n += 1;
            }
        }
        let edof = |q: &[usize; 4], i: usize| 3 * q[i / 3] + i % 3;
        let couplings = mesh.quads.iter().flat_map(|q| {
            let eq = &eq;
            (0..12).flat_map(move |i| {
                (i..12).filter_map(move |j| {
                    let (a, b) = (eq[edof(q, i)], eq[edof(q, j)]);
                    (a != usize::MAX && b != usize::MAX).then_some((a, b))
                })
            })
        });
        let linear = SparseCholesky::new(UpperPattern::from_couplings(n, couplings));
        let slot = |a: usize, b: usize| -> u32 {
            if a == usize::MAX || b == usize::MAX {
                u32::MAX
            } else {
                linear.slot(a, b).expect("pair in pattern") as u32
            }
        };
        let element_slots = mesh
            .quads
            .iter()
            .map(|q| {
                let mut s = [u32::MAX; 78];
                for i in 0..12 {
                    for j in i..12 {
                        s[pair_index(i, j)] = slot(eq[edof(q, i)], eq[edof(q, j)]);
                    }
                }
                s
            })
            .collect();
        let node_slots = (0..mesh.nodes.len())
            .map(|nd| {
                let d = |m: usize| eq[3 * nd + m];
                [
                    slot(d(0), d(0)),
                    slot(d(0), d(1)),
                    slot(d(0), d(2)),
                    slot(d(1), d(1)),
                    slot(d(1), d(2)),
                    slot(d(2), d(2)),
                ]
            })
            .collect();
        // Viscosity: κ-free part C̄/L̄0 times the cells around each node.
        let c_mean = 0.5 * (law.p.c[0] + law.p.c[1]);
        let l_mean = 0.5 * (law.p.l0[0] + law.p.l0[1]);
        let mut viscosity = vec![0.0; mesh.nodes.len()];
        for (q, g) in mesh.quads.iter().zip(&geometry) {
            for &nd in q {
                viscosity[nd] += 0.25 * g.cell_count() * c_mean / l_mean;
            }
        }
        let element_size =
            (geometry.iter().map(|g| g.area0).sum::<f64>() / geometry.len().max(1) as f64).sqrt();
        let ne = mesh.quads.len();
        Ok(Model {
            u: vec![0.0; ndof],
            crimp: vec![[law.initial_state(); GAUSS]; ne],
            eq,
            prescribed_dofs: prescribed_dofs.to_vec(),
            element_slots,
            node_slots,
            linear,
            viscosity,
            outputs: vec![ElementOutput::default(); ne],
            element_size,
            geometry,
            mesh,
            law,
        })
    }

    /// The prescribed dofs (where reactions act).
    pub fn prescribed_dofs(&self) -> &[usize] {
        &self.prescribed_dofs
    }

    /// Free (solved-for) dofs.
    pub fn free_dofs(&self) -> usize {
        self.linear.n()
    }

    /// Non-zeros of the tangent's upper triangle and of its Cholesky factor.
    pub fn sparsity(&self) -> (usize, usize) {
        (self.linear.nnz(), self.linear.factor_nnz())
    }

    /// Current nodal positions.
    pub fn positions(&self) -> Vec<[f64; 3]> {
        self.mesh
            .nodes
            .iter()
            .enumerate()
            .map(|(i, x0)| {
                [
                    x0[0] + self.u[3 * i],
                    x0[1] + self.u[3 * i + 1],
                    x0[2] + self.u[3 * i + 2],
                ]
            })
            .collect()
    }

    fn element_positions(&self, e: usize, x: &[[f64; 3]]) -> [[f64; 3]; 4] {
        let q = self.mesh.quads[e];
        [x[q[0]], x[q[1]], x[q[2]], x[q[3]]]
    }

    /// Element outputs (forces, tensions) of the last evaluation.
    pub fn element_outputs(&self) -> &[ElementOutput] {
        &self.outputs
    }

    /// Evaluates every element at the current displacements (tensions, forces, optionally
    /// tangents) in parallel when `parallel`.
    pub fn evaluate_elements(&mut self, tangent: bool, parallel: bool) -> u64 {
        let x = self.positions();
        self.evaluate_elements_at(&x, tangent, parallel)
    }

    /// [`Model::evaluate_elements`] at given nodal positions (those of the current
    /// displacements), so a caller that needs them too computes them once.
    fn evaluate_elements_at(&mut self, x: &[[f64; 3]], tangent: bool, parallel: bool) -> u64 {
        let quads = &self.mesh.quads;
        let geometry = &self.geometry;
        let law = &self.law;
        let work = |(e, (out, crimp)): (usize, (&mut ElementOutput, &mut [CrimpState; GAUSS]))| {
            let q = quads[e];
            let xe = [x[q[0]], x[q[1]], x[q[2]], x[q[3]]];
            element::evaluate(&geometry[e], law, &xe, crimp, tangent, out);
            out.law_iterations as u64
        };
        if parallel {
            self.outputs
                .par_iter_mut()
                .zip(self.crimp.par_iter_mut())
                .enumerate()
                .with_min_len(64)
                .map(work)
                .sum()
        } else {
            self.outputs
                .iter_mut()
                .zip(self.crimp.iter_mut())
                .enumerate()
                .map(work)
                .sum()
        }
    }

    /// The internal force vector of all dofs (reactions at prescribed dofs), from the last
    /// element evaluation.
    pub fn internal_force(&self) -> Vec<f64> {
        let mut f = vec![0.0; self.u.len()];
        for (q, out) in self.mesh.quads.iter().zip(&self.outputs) {
            for i in 0..12 {
                f[3 * q[i / 3] + i % 3] += out.f[i];
            }
        }
        f
    }

    /// Stored energy of the fabric at the last evaluation, N·mm.
    pub fn stored_energy(&self) -> f64 {
        self.outputs.iter().map(|o| o.energy).sum()
    }

    /// Shear angle of each element, degrees.
    pub fn shear_angles_deg(&self) -> Vec<f64> {
        let x = self.positions();
        (0..self.mesh.quads.len())
            .map(|e| element::shear_angle_deg(&self.geometry[e], &self.element_positions(e, &x)))
            .collect()
    }

    /// Largest yarn tension of each element (over its Gauss points and yarns), N.
    pub fn max_tension_n(&self) -> Vec<f64> {
        self.outputs
            .iter()
            .map(|o| o.tension.iter().flatten().fold(0.0f64, |a, &b| a.max(b)))
            .collect()
    }
}

/// What the assembly of one configuration produced.
struct Assembled {
    /// Residual over the free dofs.
    r: Vec<f64>,
    /// Total potential: stored energy, stabilisation and nodal terms, N·mm.
    energy: f64,
    /// Load scale: the largest of the internal, nodal-term and stabilisation force norms, N.
    scale: f64,
    admissible: bool,
}

/// Drives a model along the load path.
pub struct Solver<'a> {
    pub model: &'a mut Model,
    pub options: SolverOptions,
    pub stats: SolveStats,
    values: Vec<f64>,
    blocks: Vec<[f64; 6]>,
    u_step_start: Vec<f64>,
    /// Levenberg–Marquardt damping `λ` added as `λ D` to the tangent for the step only (D: the
    /// cells' stiffness at each node), so nodes that nothing holds yet take short steps instead
    /// of freezing the whole step in the line search. It never enters the residual, so the
    /// converged state is the same; it decays to 0 while full steps are accepted.
    damping: f64,
}

impl<'a> Solver<'a> {
    pub fn new(model: &'a mut Model, options: SolverOptions) -> Self {
        let nnz = model.linear.nnz();
        let nn = model.mesh.nodes.len();
        let u0 = model.u.clone();
        Solver {
            model,
            options,
            stats: SolveStats::default(),
            values: vec![0.0; nnz],
            blocks: vec![[0.0; 6]; nn],
            u_step_start: u0,
            damping: 0.0,
        }
    }

    /// Residual (and tangent values if `tangent`) at the model's current displacements.
    fn assemble(&mut self, lambda: f64, terms: &dyn NodalTerms, tangent: bool) -> Assembled {
        let t0 = Instant::now();
        let parallel = self.options.parallel;
        let m = &mut *self.model;
        let x = m.positions();
        self.stats.law_iterations += m.evaluate_elements_at(&x, tangent, parallel);
        let ndof = m.u.len();
        let mut f_all = vec![0.0; ndof];
        if tangent {
            self.values.iter_mut().for_each(|v| *v = 0.0);
        }
        for (e, q) in m.mesh.quads.iter().enumerate() {
            let out = &m.outputs[e];
            for i in 0..12 {
                f_all[3 * q[i / 3] + i % 3] += out.f[i];
            }
            if tangent {
                let slots = &m.element_slots[e];
                let mut p = 0;
                for i in 0..12 {
                    for j in i..12 {
                        let s = slots[p];
                        if s != u32::MAX {
                            self.values[s as usize] += out.k[i][j];
                        }
                        p += 1;
                    }
                }
            }
        }
        let internal_norm = norm2(&f_all);
        self.stats.assembly_s += t0.elapsed().as_secs_f64();
        // Stabilisation.
        let kappa = self.options.stabilisation;
        let mut stab_norm2 = 0.0;
        if kappa > 0.0 {
            for (nd, mu) in m.viscosity.iter().enumerate() {
                let mu = kappa * mu;
                for c in 0..3 {
                    let d = 3 * nd + c;
                    let fs = mu * (m.u[d] - self.u_step_start[d]);
                    f_all[d] += fs;
                    stab_norm2 += fs * fs;
                }
                if tangent {
                    for k in [0, 3, 5] {
                        let s = m.node_slots[nd][k];
                        if s != u32::MAX {
                            self.values[s as usize] += mu;
                        }
                    }
                }
            }
        }
        // Nodal terms.
        let t1 = Instant::now();
        let mut f_terms = vec![0.0; ndof];
        let added = if tangent {
            self.blocks.iter_mut().for_each(|b| *b = [0.0; 6]);
            let added = terms.add(lambda, &x, &mut f_terms, Some(&mut self.blocks));
            for (nd, b) in self.blocks.iter().enumerate() {
                for k in 0..6 {
                    let s = m.node_slots[nd][k];
                    if s != u32::MAX && b[k] != 0.0 {
                        self.values[s as usize] += b[k];
                    }
                }
            }
            added
        } else {
            terms.add(lambda, &x, &mut f_terms, None)
        };
        let admissible = added.is_some();
        let sums = added.unwrap_or_default();
        for (a, b) in f_all.iter_mut().zip(&f_terms) {
            *a += b;
        }
        self.stats.nodal_s += t1.elapsed().as_secs_f64();
        let mut energy = m.stored_energy() + sums.energy;
        if kappa > 0.0 {
            for (nd, mu) in m.viscosity.iter().enumerate() {
                for c in 0..3 {
                    let d = 3 * nd + c;
                    energy += 0.5 * kappa * mu * (m.u[d] - self.u_step_start[d]).powi(2);
                }
            }
        }
        let mut r = vec![0.0; m.free_dofs()];
        for (d, &q) in m.eq.iter().enumerate() {
            if q != usize::MAX {
                r[q] = f_all[d];
            }
        }
        let finite = r.iter().all(|v| v.is_finite());
        Assembled {
            r,
            energy,
            scale: internal_norm.max(sums.scale).max(stab_norm2.sqrt()),
            admissible: admissible && finite,
        }
    }

    /// True when `du` lies in a near-null space of the assembled tangent: its Rayleigh quotient
    /// `du·K·du / du·du` is below `1e-12` of the largest diagonal entry. `du` solved `K du = −r`
    /// (`slope = r·du`), so `du·K·du = −slope` up to round-off: the product with `K` is formed
    /// only when that estimate is within a factor 100 of the threshold.
    fn near_null(&self, du: &[f64], slope: f64) -> bool {
        let den: f64 = du.iter().map(|a| a * a).sum();
        if den == 0.0 {
            return false;
        }
        let threshold = 1e-12 * self.model.linear.diagonal_max(&self.values) * den;
        if -slope > 100.0 * threshold {
            return false;
        }
        let mut kdu = vec![0.0; du.len()];
        self.model.linear.mul(&self.values, du, &mut kdu);
        let num: f64 = du.iter().zip(&kdu).map(|(a, b)| a * b).sum();
        num <= threshold
    }

    /// Sets the prescribed dofs at `lambda`.
    fn apply_prescribed(&mut self, lambda: f64, prescribed: &dyn Prescribed) {
        let mut vals = vec![0.0; prescribed.dofs().len()];
        prescribed.values(lambda, &mut vals);
        for (&d, v) in prescribed.dofs().iter().zip(vals) {
            self.model.u[d] = v;
        }
    }

    /// Sets the displacements to `base + alpha du` on the free dofs.
    fn set_free(&mut self, base: &[f64], du: &[f64], alpha: f64) {
        let m = &mut *self.model;
        for (d, &q) in m.eq.iter().enumerate() {
            if q != usize::MAX {
                m.u[d] = base[d] + alpha * du[q];
            }
        }
    }

    /// Newton iterations at load `lambda` from the current displacements. Returns the
    /// iteration count on convergence, or the cause of failure.
    fn newton(
        &mut self,
        lambda: f64,
        terms: &dyn NodalTerms,
        history: &mut Vec<f64>,
    ) -> Result<u32, String> {
        let mut singular = false;
        let result = self.newton_iterations(lambda, terms, history, &mut singular);
        result.map_err(|cause| {
            if singular {
                format!(
                    "{cause}; the tangent was singular: the fabric is a mechanism here (zero-stiffness \
                     trellising or slack yarns with no stabilisation)"
                )
            } else {
                cause
            }
        })
    }

    fn newton_iterations(
        &mut self,
        lambda: f64,
        terms: &dyn NodalTerms,
        history: &mut Vec<f64>,
        singular: &mut bool,
    ) -> Result<u32, String> {
        let tol_u = self.options.tol_displacement * self.model.element_size;
        // An absolute floor: a yarn force of 1e-7 C (a yarn strain of 1e-7), for problems whose
        // forces are all nearly zero (a free, slack blank, whose yarns sit on the slack/taut
        // kink of the law).
        let abs_floor = 1e-7 * 0.5 * (self.model.law.p.c[0] + self.model.law.p.c[1]);
        let mut last_du = f64::INFINITY;
        let mut last_shift = 0.0;
        // Each step starts damped (its first iteration meets the punch's new position).
        self.damping = self.damping.max(self.options.initial_damping);
        // The assembly (with tangent) of a full step accepted at its first trial, which is the
        // next iteration's.
        let mut carried: Option<Assembled> = None;
        let mut last_full_step = false;
        let mut u_base = Vec::new();
        for it in 0..=self.options.max_iterations {
            let a = match carried.take() {
                Some(a) => a,
                None => self.assemble(lambda, terms, true),
            };
            if !a.admissible {
                return Err("inadmissible or non-finite state".into());
            }
            let rn = norm2(&a.r);
            history.push(rn);
            let tol_r = self.options.tol_force * a.scale + abs_floor;
            // The correction must also be small: against the element size, or against what the
            // step has moved so far.
            let step_move = self
                .model
                .u
                .iter()
                .zip(&self.u_step_start)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            let du_ok = last_du <= tol_u.max(1e-4 * step_move);
            if rn <= tol_r && (du_ok || rn == 0.0) {
                // Sticky: once a solve met a singular tangent, part of the blank was a mechanism
                // (held only by the stabilisation, or by nothing without it).
                if *singular || last_shift > 0.0 {
                    self.stats.mechanism = true;
                }
                return Ok(it);
            }
            if it == self.options.max_iterations {
                break;
            }
            let mut du: Vec<f64> = a.r.iter().map(|v| -v).collect();
            if self.damping > 0.0 {
                let m = &*self.model;
                for (nd, d) in m.viscosity.iter().enumerate() {
                    for k in [0, 3, 5] {
                        let s = m.node_slots[nd][k];
                        if s != u32::MAX {
                            self.values[s as usize] += self.damping * d;
                        }
                    }
                }
            }
            let t0 = Instant::now();
            let info = self
                .model
                .linear
                .factor_solve(&self.values, &mut du)
                .map_err(|_| "the tangent could not be factorized".to_string())?;
            self.stats.factor_solve_s += t0.elapsed().as_secs_f64();
            last_shift = info.shift;
            if info.shift > 0.0 {
                *singular = true;
                self.stats.shifted_solves += 1;
            }
            if !du.iter().all(|v| v.is_finite()) {
                return Err("the linear solve gave a non-finite increment".into());
            }
            // A step along a (near) null direction of the tangent means a mechanism, even when
            // round-off let the factorization through: compare its Rayleigh quotient with the
            // diagonal scale.
            let slope: f64 = a.r.iter().zip(&du).map(|(r, d)| r * d).sum();
            if info.shift == 0.0 && self.near_null(&du, slope) {
                *singular = true;
                last_shift = f64::MIN_POSITIVE;
            }
            self.stats.newton_iterations += 1;
            // Backtracking line search. The problem has a potential Π (stored energy, contact
            // penalty, friction potential, holder work, stabilisation) and the tangent is positive
            // definite, so the Newton step descends Π: accept α when Π satisfies Armijo,
            // Π(α) ≤ Π(0) + 1e-4 α r·du, or when the residual norm falls (which decides near
            // convergence, where Π is all round-off). Trial lengths minimise the quadratic through
            // Π(0), Π'(0) and Π(α), within [0.05 α, 0.5 α].
            let pi0 = a.energy;
            let mut alpha = 1.0;
            let mut best = (f64::INFINITY, 0.0);
            let mut accepted = false;
            u_base.clone_from(&self.model.u);
            for trial_number in 0..16 {
                // After a full step the next one is most likely full too: its trial is then
                // assembled with the tangent, kept for the next iteration if accepted.
                let speculate = trial_number == 0 && last_full_step;
                self.set_free(&u_base, &du, alpha);
                let trial = self.assemble(lambda, terms, speculate);
                let (tn, pi) = if trial.admissible {
                    (norm2(&trial.r), trial.energy)
                } else {
                    (f64::INFINITY, f64::INFINITY)
                };
                if tn < best.0 {
                    best = (tn, alpha);
                }
                let armijo = slope < 0.0 && pi <= pi0 + 1e-4 * alpha * slope;
                if armijo || tn <= (1.0 - 1e-4 * alpha) * rn || tn <= tol_r {
                    accepted = true;
                    if speculate {
                        carried = Some(trial);
                    }
                    break;
                }
                self.model.u.copy_from_slice(&u_base);
                let next = if pi.is_finite() && slope < 0.0 {
                    -slope * alpha * alpha / (2.0 * (pi - pi0 - slope * alpha))
                } else {
                    0.05 * alpha
                };
                alpha = if next.is_finite() {
                    next.clamp(0.05 * alpha, 0.5 * alpha)
                } else {
                    0.5 * alpha
                };
            }
            if !accepted {
                if best.0.is_finite() && best.0 < 10.0 * rn {
                    alpha = best.1;
                    self.set_free(&u_base, &du, alpha);
                } else {
                    return Err(format!(
                        "the line search found no acceptable point (residual {rn:.3e} N)"
                    ));
                }
            }
            // Adapt the damping: more after a hard cut, less (down to none) after full steps.
            if alpha >= 0.999 {
                self.damping = if self.damping < 1e-6 {
                    0.0
                } else {
                    0.1 * self.damping
                };
            } else if alpha < 0.1 {
                self.damping = (10.0 * self.damping).clamp(1e-4, 1e2);
            }
            last_full_step = alpha >= 0.999;
            last_du = alpha * norm_inf(&du);
        }
        Err(format!(
            "no convergence in {} Newton iterations (residual {:.3e} N)",
            self.options.max_iterations,
            history.last().copied().unwrap_or(f64::NAN)
        ))
    }

    /// Runs the load path from the current state to `λ = 1`. `progress` receives the load
    /// factor after every accepted step; returning `ControlFlow::Break` stops the run there
    /// (`Failure::Stopped`, the state left at that step).
    pub fn solve(
        &mut self,
        prescribed: &dyn Prescribed,
        terms: &mut dyn NodalTerms,
        progress: &mut dyn FnMut(f64) -> ControlFlow<()>,
    ) -> Result<(), Failure> {
        let mut lambda = 0.0;
        let mut step = self.options.initial_step.min(self.options.max_step);
        let mut previous_increment: Option<(f64, Vec<f64>)> = None;
        let mut f_start = {
            self.assemble(0.0, terms, false);
            self.model.internal_force()
        };
        while lambda < 1.0 - 1e-12 {
            let target = (lambda + step).min(1.0);
            let u_start = self.model.u.clone();
            let crimp_start = self.model.crimp.clone();
            self.u_step_start.clone_from(&u_start);
            let x_start = self.model.positions();
            terms.begin_step(target, &x_start);
            // Secant predictor on the free dofs.
            if let Some((dl, du)) = previous_increment
                .as_ref()
                .filter(|_| self.options.secant_predictor)
            {
                let ratio = (target - lambda) / dl;
                let m = &mut *self.model;
                for (d, &q) in m.eq.iter().enumerate() {
                    if q != usize::MAX {
                        m.u[d] += ratio * du[d];
                    }
                }
            }
            self.apply_prescribed(target, prescribed);
            let mut history = Vec::new();
            match self.newton(target, &*terms, &mut history) {
                Ok(iterations) => {
                    // Work of this step (trapezoid rule on the internal force; the elements were
                    // last evaluated at the converged state).
                    let f_end = self.model.internal_force();
                    let du: Vec<f64> = self
                        .model
                        .u
                        .iter()
                        .zip(&u_start)
                        .map(|(a, b)| a - b)
                        .collect();
                    self.stats.internal_work += 0.5
                        * du.iter()
                            .zip(f_start.iter().zip(&f_end))
                            .map(|(d, (a, b))| d * (a + b))
                            .sum::<f64>();
                    let kappa = self.options.stabilisation;
                    self.stats.stabilisation_work += self
                        .model
                        .viscosity
                        .iter()
                        .enumerate()
                        .map(|(nd, mu)| {
                            kappa * mu * (0..3).map(|c| du[3 * nd + c].powi(2)).sum::<f64>()
                        })
                        .sum::<f64>();
                    f_start = f_end;
                    if self.options.relax_every_step && self.options.stabilisation > 0.0 {
                        let reference =
                            std::mem::replace(&mut self.u_step_start, self.model.u.clone());
                        let (u_keep, crimp_keep) = (self.model.u.clone(), self.model.crimp.clone());
                        let mut h = Vec::new();
                        if self.newton(target, &*terms, &mut h).is_err() {
                            self.model.u = u_keep;
                            self.model.crimp = crimp_keep;
                        }
                        self.u_step_start = reference;
                    }
                    let x = self.model.positions();
                    terms.end_step(target, &x);
                    previous_increment = Some((target - lambda, du));
                    lambda = target;
                    self.stats.steps += 1;
                    self.stats.lambda = lambda;
                    if self.options.record_residuals {
                        self.stats.residuals.push(history);
                    }
                    if progress(lambda).is_break() {
                        self.assemble(lambda, &*terms, false);
                        return Err(Failure::Stopped { lambda });
                    }
                    if iterations <= 8 {
                        step = (step * 1.5).min(self.options.max_step);
                    } else if iterations >= 15 {
                        step *= 0.7;
                    }
                }
                Err(cause) => {
                    self.model.u = u_start;
                    self.model.crimp = crimp_start;
                    self.stats.cutbacks += 1;
                    step *= 0.25;
                    previous_increment = None;
                    if step < self.options.min_step {
                        return Err(Failure::StepFailed {
                            lambda,
                            step,
                            cause,
                        });
                    }
                }
            }
        }
        self.relax(lambda, &*terms);
        // Leave the element outputs at the final state.
        self.assemble(lambda, &*terms, false);
        if self.options.time_bare_factorization {
            self.stats.bare_factor_solve_s = Some(self.time_bare_factorization(7));
        }
        Ok(())
    }

    /// The median wall time of `repetitions` factorizations + solves of the last assembled
    /// tangent, with nothing else around them, s.
    fn time_bare_factorization(&mut self, repetitions: usize) -> f64 {
        let values = self.values.clone();
        let n = self.model.free_dofs();
        let mut times: Vec<f64> = (0..repetitions.max(1))
            .map(|_| {
                let mut rhs = vec![1.0; n];
                let t = Instant::now();
                let _ = self.model.linear.factor_solve(&values, &mut rhs);
                t.elapsed().as_secs_f64()
            })
            .collect();
        times.sort_by(f64::total_cmp);
        times[times.len() / 2]
    }

    /// The stabilisation force at the current state over the internal force, both as norms.
    fn stabilisation_force_ratio(&mut self, lambda: f64, terms: &dyn NodalTerms) -> f64 {
        let kappa = self.options.stabilisation;
        let m = &*self.model;
        let fs: f64 = m
            .viscosity
            .iter()
            .enumerate()
            .map(|(nd, mu)| {
                (0..3)
                    .map(|c| {
                        (kappa * mu * (m.u[3 * nd + c] - self.u_step_start[3 * nd + c])).powi(2)
                    })
                    .sum::<f64>()
            })
            .sum::<f64>()
            .sqrt();
        let a = self.assemble(lambda, terms, false);
        if a.scale > 0.0 { fs / a.scale } else { 0.0 }
    }

    /// Fades the stabilisation at the final load: re-solves with the viscous reference at the
    /// current state, keeping a pass only if it converges.
    fn relax(&mut self, lambda: f64, terms: &dyn NodalTerms) {
        for _ in 0..self.options.relaxation_passes {
            if self.options.stabilisation == 0.0 {
                break;
            }
            let u_before = self.model.u.clone();
            let crimp_before = self.model.crimp.clone();
            let reference = self.u_step_start.clone();
            self.u_step_start.clone_from(&self.model.u);
            let mut history = Vec::new();
            if self.newton(lambda, terms, &mut history).is_err() {
                self.model.u = u_before;
                self.model.crimp = crimp_before;
                self.u_step_start = reference;
                break;
            }
            // Restore the reference of this pass, to measure what force the stabiliser still
            // carries in the state returned.
            let moved: f64 = self
                .model
                .u
                .iter()
                .zip(&self.u_step_start)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            if moved <= self.options.tol_displacement * self.model.element_size {
                break;
            }
        }
        self.stats.stabilisation_force_ratio = self.stabilisation_force_ratio(lambda, terms);
    }
}

fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn norm_inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |a, &b| a.max(b.abs()))
}
