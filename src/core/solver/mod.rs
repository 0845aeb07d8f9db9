//! The implicit solver (paper eqs 28–30): Newton's method on the equilibrium of the woven blank
//! at each load step, the load path walked in steps that grow and cut back.
//!
//! - `model.rs`: the elements, the dof numbering, the tangent's pattern and the current state;
//! - `assembly.rs`: one configuration into a residual, a merit and a tangent;
//! - `correction.rs`: the Newton correction (sparse Cholesky, GMRES over the non-symmetric rest);
//! - `line_search.rs`: backtracking along the correction;
//! - `newton.rs`: the iterations of one load step;
//! - `stepping.rs`: the load path: predictor, steps, cut-backs;
//! - `site.rs`: where an iteration's residual sits (recorded with `record_residuals`).
//!
//! The paper's fabric has no in-plane shear stiffness and no bending stiffness, so parts of a
//! sheet can be mechanisms. The Newton corrections are stabilised by a pseudo-transient term:
//! `δ · (C̄/L̄0) · cells(node)` on the diagonal of the tangent, `δ = κ (‖r‖/‖r₀‖)²` (κ the
//! `stabilisation`, `r₀` the step's first residual) plus a Levenberg–Marquardt part that grows
//! when the line search has to cut hard. It damps the corrections only: the residual is the
//! model's own, so a converged state carries no stabilisation force and the answer does not
//! depend on κ.

mod assembly;
mod correction;
mod drape;
mod line_search;
mod model;
mod newton;
mod reshape;
mod site;
mod stepping;
mod terms;

pub use model::{BadElement, Model};
pub use newton::NewtonError;
pub use site::ResidualSite;
pub use stepping::Failure;
pub use terms::{
    LinearPrescribed, NoNodalTerms, NodalSums, NodalTerms, NodeBlock, NodeStiffness, OwnStiffness,
    Prescribed, RankOne,
};

use assembly::Workspace;

/// Solver settings.
#[derive(Clone, Debug, PartialEq)]
pub struct SolverOptions {
    /// First load increment (fraction of the full load).
    pub initial_step: f64,
    /// Smallest increment before the run is declared failed.
    pub min_step: f64,
    /// Largest increment: bounds how far friction's path is walked in one step (at 0.1 the
    /// max shear of a design of the paper's grid, 10/6/5 at μ 0.25, moved 0.15° from its
    /// value at 0.05).
    pub max_step: f64,
    /// The Newton iterations a step should take: the next increment doubles after a step that
    /// took half as many (see `stepping.rs`, `next_step`).
    pub target_iterations: u32,
    /// Accepted steps allowed before the run is declared failed.
    pub max_steps: u32,
    /// Newton iterations allowed in a step before it is cut back. 40: on a fine mesh a step
    /// that converges may take 25–40 (its slack, sliding and lifting nodes settling one by
    /// one), and cutting such a step by 4 cost more steps and iterations than finishing it
    /// (the 81 designs of the paper's grid at 1.25 mm: cut-backs 124 → 1, iterations −17 %).
    pub max_iterations: u32,
    /// Force residual tolerance, relative to the load scale.
    pub tol_force: f64,
    /// The floor of the force tolerance, as a yarn strain (times the yarn stiffness C).
    pub tol_floor: f64,
    /// A step of a model without bending also ends when its residual is within
    /// [`WORK_FORCE_SPAN`] force tolerances and the residual's work over the step's increment is
    /// at most this share of the fabric's stored energy gained in the step. 0 (the default):
    /// off; the drawings set [`crate::core::drawing::TOL_WORK`]. Not for a reaction read off a
    /// nearly free mechanism: the bias-extension's clamp force at the first millimetres moved
    /// 4 % with it, where a soft trellis turns a small residual into a large displacement.
    pub tol_work: f64,
    /// A step of a model without bending also ends with a correction that would release at most
    /// this share of the fabric's stored energy gained in the step (Newton's decrement `|r·Δu|`,
    /// the energy still between the state and its balance), taken as searched, when the
    /// residual is within [`DECREMENT_FORCE_SPAN`] force tolerances and the state it reaches
    /// leaves at most [`DECREMENT_WORK_SHARE`] of that energy as the residual's work over the
    /// step. 0 (the default): off; the drawings set [`crate::core::drawing::TOL_DECREMENT`]. It
    /// ends the tails where Newton halves a lifting node's depth in the contact's eased gap,
    /// micrometres from its balance (`guide::solver`, "The end of a step").
    pub tol_decrement: f64,
    /// Put each node's share of a Newton correction along a tool's normal where its own
    /// balance with the penalty lies, the rest of the correction held ([`NodalTerms::reshape`],
    /// `guide::solver`, "Contact: the eased penalty and each node's balance"): a node lifting off a tool, whose depth in the
    /// eased gap Newton's linear model halves at each correction, reaches its balance in one;
    /// one coming onto a tool is not thrown through the gap. On by default.
    pub reshape_contact: bool,
    /// Pseudo-transient stabilisation `κ` of the Newton corrections (dimensionless; 0 turns it
    /// off), fading with the square of the residual's fall in the step. 10⁻² (with the square):
    /// 4.7 % fewer iterations on the paper's 81-design grid than 10⁻⁴ with the residual's fall
    /// itself, every figure within 0.04° (`guide::solver`, "The stabilisation and its fade").
    pub stabilisation: f64,
    /// Solve each correction with the nodal terms' non-symmetric part (GMRES); without it the
    /// corrections use the symmetric part only and converge linearly where friction acts.
    pub exact_jacobian: bool,
    /// Solves of a step again after its lagged terms were updated (0: lag at the step's start).
    pub max_lag_passes: u32,
    /// Move the predicted state back onto the tools the nodes touched.
    pub project_predictor: bool,
    /// In that, a node sliding on a tool at rest keeps the distance the predictor slid it
    /// (`NodalTerms::project`): put back along the normal on the die's radius it fell short of
    /// its neighbour on the flat, and the yarn between them went slack (`guide::solver`,
    /// "The predictor"). On by default.
    pub keep_slide: bool,
    /// A step with no secant to start from (the first, or the retry after a cut) starts with
    /// the nodes the tools touched moved with their tool and the rest draped harmonically
    /// between them (`drape`); off, the start state is only projected onto the tools. On by
    /// default: the first step of each design on the paper's grid took 9 iterations instead of
    /// 11–15 (`guide::solver`, "The predictor").
    pub drape_predictor: bool,
    /// Put the nodes a correction throws into a tool they did not touch onto its surface.
    pub project_trials: bool,
    /// Assemble elements on rayon's pool (set false inside a parallel sweep if wanted; with
    /// `factor_threads` 0 it also decides the factorization's threads). Best
    /// asked for from a worker of the pool (`machine::on_pool`, as `wovenform run` solves): from
    /// outside it, each assembly waits for the pool to wake, which cost the open box at fine
    /// 10 % on a 2-core machine.
    pub parallel: bool,
    /// Threads the sparse factorization and its solves may use: 0 (the default) as many as the
    /// assembly (rayon's pool when `parallel`, else one), 1 one, 2 or more two. On two, the
    /// equations are split into two halves of the blank and the line of nodes between them, each
    /// half factorized on its own thread ([`crate::core::sparse::split_cholesky`]): the open box at fine
    /// ran 1.2–1.3× faster on a 2-core machine (`bench --scaling` measures it on any machine),
    /// to round-off the same answer (`guide::solver`, "The factorization on one thread and on two").
    pub factor_threads: u32,
    /// Keep the residual history of each step (for convergence studies).
    pub record_residuals: bool,
}

impl SolverOptions {
    /// The threads the factorization will use ([`SolverOptions::factor_threads`] resolved).
    pub fn factorization_threads(&self) -> usize {
        match self.factor_threads {
            0 if self.parallel => rayon::current_num_threads(),
            0 => 1,
            n => n as usize,
        }
    }
}

impl Default for SolverOptions {
    fn default() -> Self {
        SolverOptions {
            initial_step: 0.1,
            min_step: 1e-5,
            max_step: 0.05,
            target_iterations: 12,
            max_steps: 1000,
            max_iterations: 40,
            tol_force: 1e-6,
            tol_floor: 1e-7,
            tol_work: 0.0,
            tol_decrement: 0.0,
            reshape_contact: true,
            stabilisation: 1e-2,
            exact_jacobian: true,
            max_lag_passes: 20,
            project_predictor: true,
            keep_slide: true,
            drape_predictor: true,
            project_trials: true,
            parallel: true,
            factor_threads: 0,
            record_residuals: false,
        }
    }
}

/// Counters of a run.
#[derive(Clone, Debug, Default)]
pub struct SolveStats {
    pub steps: u32,
    pub cutbacks: u32,
    pub newton_iterations: u32,
    /// GMRES iterations over all corrections.
    pub krylov_iterations: u32,
    /// Newton iterations whose line search cut the correction below half.
    pub damped_iterations: u32,
    /// Trial assemblies of the line searches.
    pub line_search_trials: u32,
    pub law_iterations: u64,
    /// Factorizations that needed a diagonal shift (non-positive-definite tangent).
    pub shifted_solves: u32,
    /// Steps accepted at [`RELAXED_TOLERANCE`] times the force tolerance: Newton stalled on them
    /// even at the smallest increment, within that many tolerances of balance.
    pub relaxed_steps: u32,
    /// A solve met a singular tangent during the run: part of the blank was a mechanism
    /// (zero-stiffness trellising or slack yarns) held by nothing.
    pub mechanism: bool,
    /// Residual norms of each Newton iteration, per attempted load step (if recorded): the
    /// attempts that were cut back or failed are kept too, marked in `step_accepted`.
    pub residuals: Vec<Vec<f64>>,
    /// For the same iterations: how many yarns changed between slack and taut, or nodes between
    /// touching a tool and not, since the iteration before (the active set's changes).
    pub active_changes: Vec<Vec<u32>>,
    /// For the same iterations: the line search's length and the damping (times the cells'
    /// stiffness) of each correction.
    pub alphas: Vec<Vec<f64>>,
    pub damping: Vec<Vec<f64>>,
    /// For the same iterations: where the residual sits.
    pub sites: Vec<Vec<ResidualSite>>,
    /// The load factor each recorded attempt aimed at.
    pub step_loads: Vec<f64>,
    /// Whether each recorded attempt converged (false: it was cut back, or the run failed on it).
    pub step_accepted: Vec<bool>,
    /// Work of the forces left out of balance at each converged step (the residual within the
    /// tolerance) along the path, N·mm: what of the punch's work is not the model's.
    pub unbalanced_work: f64,
    /// Load factor reached.
    pub lambda: f64,
}

impl SolveStats {
    /// Whether recorded attempt `s` converged (one not marked in `step_accepted` counts as
    /// converged).
    pub fn accepted(&self, s: usize) -> bool {
        self.step_accepted.get(s).copied().unwrap_or(true)
    }
}

/// Drives a model along the load path.
pub struct Solver<'a> {
    pub model: &'a mut Model,
    pub options: SolverOptions,
    pub stats: SolveStats,
    ws: Workspace,
    /// Levenberg–Marquardt damping on top of the stabilisation (times the cells' stiffness):
    /// grows when the line search cuts hard, decays to 0 while full corrections are accepted.
    levenberg: f64,
    /// The damping a step starts with: the Levenberg–Marquardt damping after the last step's
    /// first correction that the line search took (more than a tenth of it), see `newton.rs`.
    start_damping: f64,
    /// Whether the current step's first taken correction has set `start_damping`.
    start_damping_set: bool,
    /// The force tolerance's multiple in force (1, or [`RELAXED_TOLERANCE`] on a step's last
    /// attempt).
    relax: f64,
    /// The displacements at the current step's start and the fabric's stored energy there
    /// (N·mm): the origin of the work criterion ([`SolverOptions::tol_work`]). The energy is
    /// taken when a step is accepted (the last evaluation is then the converged state; after a
    /// failed attempt it is not), and is 0 before the first: a blank starts unstrained.
    step_origin: (Vec<f64>, f64),
    /// Newton may take [`DESCENT_ITERATIONS`] on this attempt: a model with bending passing a
    /// buckle (see `stepping.rs`).
    descent: bool,
}

/// Newton's iterations on a step of a model with bending that failed in the usual number: a
/// buckling fabric's equilibrium lies far from the unbuckled one, across an indefinite tangent,
/// and the line search's energy descent gets there in tens to hundreds of iterations, where
/// cutting the increment does not help (the open box's tight radii with locking at 0.01 MPa:
/// stopped at 16.5 mm with 25, through with 400).
pub const DESCENT_ITERATIONS: u32 = 400;

/// The multiple of the force tolerance a step may end at when Newton stalls on it even at the
/// smallest increment (the active set chattering between two states, each out of balance by a
/// few tolerances): 10 × (1e-6 of the load + a yarn strain of 1e-7) is still a millionth of the
/// punch force. Each such step is counted (`SolveStats::relaxed_steps`) and its unbalanced
/// work joins the rest, which the soundness check bounds.
pub const RELAXED_TOLERANCE: f64 = 10.0;

/// The multiple of the force tolerance within which the work criterion may end a step
/// ([`SolverOptions::tol_work`]): 100, a residual of 10⁻⁴ of the load.
pub const WORK_FORCE_SPAN: f64 = 100.0;

/// The multiple of the force tolerance within which a small Newton decrement may end a step
/// ([`SolverOptions::tol_decrement`]): 1,000, a residual of 10⁻³ of the load, so that the forces
/// left out of balance at a step's end stay a small fraction of the punch force's band.
pub const DECREMENT_FORCE_SPAN: f64 = 1000.0;

/// The largest work the forces left out of balance by a step ended on a small decrement may do
/// over the step's increment, as a share of the stored energy the fabric gained in the step:
/// 0.01, the drawings' soundness limit on a whole run
/// ([`crate::core::drawing::UNBALANCED_WORK_LIMIT`]), so that these steps cannot trip it.
pub const DECREMENT_WORK_SHARE: f64 = 0.01;

impl<'a> Solver<'a> {
    /// Newton's iteration cap on the current attempt.
    fn iteration_cap(&self) -> u32 {
        if self.descent {
            self.options.max_iterations.max(DESCENT_ITERATIONS)
        } else {
            self.options.max_iterations
        }
    }

    pub fn new(model: &'a mut Model, options: SolverOptions) -> Self {
        let ws = Workspace::new(model, options.parallel);
        let threads = options.factorization_threads();
        let key = (threads > 1).then(|| model.cut_key());
        model.linear.set_threads(threads, key.as_deref());
        Solver {
            model,
            options,
            stats: SolveStats::default(),
            ws,
            levenberg: 0.0,
            start_damping: 0.0,
            start_damping_set: false,
            relax: 1.0,
            step_origin: (Vec::new(), 0.0),
            descent: false,
        }
    }

    /// One assembly with the tangent at the current state (for benchmarks).
    pub fn assemble_tangent(&mut self, lambda: f64, terms: &dyn NodalTerms) {
        self.ws.assemble(self.model, lambda, terms, true);
    }

    /// Factorizes the last assembled tangent and solves for `rhs` in place (for benchmarks).
    pub fn factor_solve_last_tangent(&mut self, rhs: &mut [f64]) -> bool {
        self.model.linear.factor_solve(&self.ws.values, rhs).is_ok()
    }
}
