//! The load path: steps from `λ = 0` to `λ = 1`, each started from a secant predictor moved
//! back onto the tools (a step with no secant, from the drape: [`super::drape`]), grown while
//! Newton converges fast and cut back when it does not.

use std::ops::ControlFlow;

use super::newton::{History, NewtonError};
use super::terms::{NodalTerms, Prescribed};
use super::{RELAXED_TOLERANCE, Solver};

/// Why a run stopped short.
#[derive(Clone, Debug, PartialEq)]
pub enum Failure {
    /// The caller asked to stop (through the progress callback) at this load factor.
    Stopped { lambda: f64 },
    /// The load increment fell below the minimum without converging.
    StepFailed {
        lambda: f64,
        step: f64,
        cause: NewtonError,
        /// A singular tangent was met on the way (part of the blank held by nothing).
        mechanism: bool,
    },
    /// The allowed number of steps was used up before the full load.
    TooManySteps { lambda: f64, steps: u32 },
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::Stopped { lambda } => write!(f, "stopped on request at load {lambda:.4}"),
            Failure::StepFailed {
                lambda,
                step,
                cause,
                mechanism,
            } => {
                write!(
                    f,
                    "the step from load {lambda:.4} could not converge even at an increment of \
                     {step:.2e}: {cause}"
                )?;
                if *mechanism {
                    write!(
                        f,
                        "; the tangent was singular: part of the fabric is a mechanism (no \
                         shear or bending stiffness, slack yarns) that nothing holds"
                    )?;
                }
                Ok(())
            }
            Failure::TooManySteps { lambda, steps } => write!(
                f,
                "{steps} load steps used up at load {lambda:.4}: the path needs ever smaller \
                 steps"
            ),
        }
    }
}

/// The load step being solved: from `lambda` to `target`, from the state saved at its start.
struct Attempt {
    lambda: f64,
    target: f64,
    u_start: Vec<f64>,
    crimp_start: Vec<[crate::core::fabric::law::CrimpState; crate::core::membrane::element::GAUSS]>,
}

impl Solver<'_> {
    /// Runs the load path from the model's state at `λ = 0` to `λ = 1`. `progress` receives
    /// the load factor after every accepted step; returning `ControlFlow::Break` stops the run
    /// there (`Failure::Stopped`, the state left at that step).
    pub fn solve(
        &mut self,
        prescribed: &dyn Prescribed,
        terms: &mut dyn NodalTerms,
        progress: &mut dyn FnMut(f64) -> ControlFlow<()>,
    ) -> Result<(), Failure> {
        let mut lambda = 0.0;
        let mut step = self.options.initial_step.min(self.options.max_step);
        let mut previous: Option<(f64, Vec<f64>)> = None;
        let outcome = loop {
            if lambda >= 1.0 - 1e-12 {
                break Ok(());
            }
            if self.stats.steps >= self.options.max_steps {
                break Err(Failure::TooManySteps {
                    lambda,
                    steps: self.stats.steps,
                });
            }
            let attempt = Attempt {
                lambda,
                target: (lambda + step).min(1.0),
                u_start: self.model.u.clone(),
                crimp_start: self.model.crimp.clone(),
            };
            let mut history = History::default();
            match self.attempt(&attempt, prescribed, terms, previous.as_ref(), &mut history) {
                Ok(iterations) => {
                    if self.relax > 1.0 {
                        self.stats.relaxed_steps += 1;
                        self.relax = 1.0;
                    }
                    self.descent = false;
                    let du = self.accept(&attempt, history);
                    terms.end_step(attempt.target, &self.model.positions());
                    previous = Some((attempt.target - lambda, du));
                    lambda = attempt.target;
                    if progress(lambda).is_break() {
                        return Err(Failure::Stopped { lambda });
                    }
                    step = self.next_step(step, iterations);
                }
                Err(cause) => {
                    self.record(&attempt, history, false);
                    // Back to the step's start, a quarter of the increment, no predictor. The
                    // Levenberg–Marquardt damping the failed attempt raised is kept: the retry
                    // starts cautious (resetting it made the stiffest fabrics fail).
                    self.model.u = attempt.u_start;
                    self.model.crimp = attempt.crimp_start;
                    if self.begin_descent() {
                        previous = None;
                        continue;
                    }
                    let relaxed = self.relax > 1.0;
                    self.relax = 1.0;
                    if step * 0.25 < self.options.min_step && !relaxed {
                        // The last chance: the same increment, ending within RELAXED_TOLERANCE
                        // tolerances of balance.
                        self.relax = RELAXED_TOLERANCE;
                        previous = None;
                        continue;
                    }
                    self.stats.cutbacks += 1;
                    step *= 0.25;
                    previous = None;
                    if step < self.options.min_step {
                        break Err(Failure::StepFailed {
                            lambda,
                            step,
                            cause,
                            mechanism: self.stats.mechanism,
                        });
                    }
                }
            }
        };
        // Leave the element outputs at the last converged state.
        self.ws.assemble(self.model, lambda, &*terms, false);
        outcome
    }

    /// After a failed attempt: whether to try the same increment once more with a long descent
    /// (`DESCENT_ITERATIONS`), as a model with bending passing a buckle may need, before any
    /// cut. Without bending, never: nothing changes.
    fn begin_descent(&mut self) -> bool {
        let retry = !self.descent && self.bends();
        self.descent = retry;
        retry
    }

    /// Whether the model has bending (hinges): a fabric that can buckle, whose steps pass
    /// buckles and whose path picks among buckled states.
    pub(super) fn bends(&self) -> bool {
        !self.model.hinges.is_empty()
    }

    /// Solves one step: the predictor moved back onto the tools, Newton, and for terms that lag
    /// (friction's normal force, when asked to) Newton again from the converged state until a
    /// pass has nothing left to do: the fixed point within the step.
    fn attempt(
        &mut self,
        attempt: &Attempt,
        prescribed: &dyn Prescribed,
        terms: &mut dyn NodalTerms,
        previous: Option<&(f64, Vec<f64>)>,
        history: &mut History,
    ) -> Result<u32, NewtonError> {
        let (lambda, target) = (attempt.lambda, attempt.target);
        terms.begin_step(lambda, target, &self.model.positions());
        if let Some((dl, du)) = previous {
            self.predict((target - lambda) / dl, du);
        }
        self.apply_prescribed(target, prescribed);
        if self.options.project_predictor && self.options.drape_predictor && previous.is_none() {
            self.drape(target, terms);
        } else if self.options.project_predictor {
            self.project_onto_tools(target, terms);
        }
        // A membrane step starts where the last one's first correction was taken: the mid-side
        // flange panels, hanging on sliding friction past a slack radial yarn, are a mechanism
        // the tangent cannot see, and an undamped first correction throws them outward; the
        // line search then rejects it and the damping grows a decade per rejection, every step
        // again. With bending, no: the damping steers which buckled state the descent finds
        // (the holder window's 0.01 MPa fold moved 0.03 mm, and took 22 % more iterations).
        if !self.bends() {
            self.levenberg = self.levenberg.max(self.start_damping);
        }
        self.start_damping_set = false;
        self.step_origin.0.clone_from(&attempt.u_start);
        let mut iterations = self.newton(target, terms, false, history)?;
        for _ in 0..self.options.max_lag_passes {
            if !terms.relag(target, &self.model.positions()) {
                break;
            }
            let more = self.newton(target, terms, true, history)?;
            iterations += more;
            if more == 0 {
                break;
            }
        }
        Ok(iterations)
    }

    /// Moves the predicted state back onto the tools at load `lambda` ([`NodalTerms::project`]).
    pub(super) fn project_onto_tools(&mut self, lambda: f64, terms: &dyn NodalTerms) {
        let mut x = self.model.positions();
        terms.project(lambda, &mut x, self.options.keep_slide);
        self.model.set_free_positions(&x);
    }

    /// Takes a converged step: the counters, the work its unbalanced residual did, the
    /// histories. Returns its increment.
    fn accept(&mut self, attempt: &Attempt, history: History) -> Vec<f64> {
        let du: Vec<f64> = self
            .model
            .u
            .iter()
            .zip(&attempt.u_start)
            .map(|(a, b)| a - b)
            .collect();
        // The work of the residual left at convergence over the step's increment.
        let w = self.residual_work(&history.converged_residual, &attempt.u_start);
        self.stats.unbalanced_work += w.abs();
        self.step_origin.1 = self.model.stored_energy();
        self.stats.steps += 1;
        self.stats.lambda = attempt.target;
        self.stats.law_iterations = self.ws.law_iterations;
        self.record(attempt, history, true);
        du
    }

    /// The work of the residual `r` (over the free dofs, N; missing entries 0) over the
    /// increment from `u_start` to the current displacements, N·mm.
    pub(super) fn residual_work(&self, r: &[f64], u_start: &[f64]) -> f64 {
        let m = &*self.model;
        (m.eq.iter().enumerate())
            .filter(|(_, q)| **q != usize::MAX)
            .map(|(d, &q)| r.get(q).copied().unwrap_or(0.0) * (m.u[d] - u_start[d]))
            .sum()
    }

    /// Keeps an attempt's iterations when they are recorded (`record_residuals`).
    fn record(&mut self, attempt: &Attempt, history: History, accepted: bool) {
        if self.options.record_residuals {
            self.stats.residuals.push(history.residuals);
            self.stats.active_changes.push(history.changes);
            self.stats.alphas.push(history.alphas);
            self.stats.damping.push(history.damping);
            self.stats.sites.push(history.sites);
            self.stats.step_loads.push(attempt.target);
            self.stats.step_accepted.push(accepted);
        }
    }

    /// The next load increment after one that took `iterations` Newton iterations (`n` the
    /// target): doubled up to `n/2`, grown by a quarter beyond; never above `max_step`. A
    /// converged step of the membrane is never followed by a smaller one: how many iterations
    /// Newton takes there depends on the mesh (a finer one has more slack, sliding and lifting
    /// nodes to settle), not on the increment, and shrinking the increment for them made a fine
    /// mesh take up to twice the steps of a standard one, with more iterations in all. With
    /// bending, a step that took many iterations has been passing a buckle, and a smaller
    /// increment follows the fold's branch: kept up to `3n/2`, cut by 30 % beyond (a fold
    /// walked in steps of 1/20 of the stroke came out 0.45 mm deep against 0.34 mm in steps of
    /// 1/40 and 1/80). A failed step is cut by 4 (`solve`).
    fn next_step(&self, step: f64, iterations: u32) -> f64 {
        let n = self.options.target_iterations.max(2);
        let factor = if iterations <= n / 2 {
            2.0
        } else if iterations <= n || !self.bends() {
            1.25
        } else if iterations <= n + n / 2 {
            1.0
        } else {
            0.7
        };
        (step * factor).min(self.options.max_step)
    }

    /// The secant predictor on the free dofs: the previous step's increment `du` scaled by
    /// `ratio`.
    fn predict(&mut self, ratio: f64, du: &[f64]) {
        let m = &mut *self.model;
        for (d, &q) in m.eq.iter().enumerate() {
            if q != usize::MAX {
                m.u[d] += ratio * du[d];
            }
        }
    }

    /// Sets the prescribed dofs at `lambda`.
    fn apply_prescribed(&mut self, lambda: f64, prescribed: &dyn Prescribed) {
        let mut vals = vec![0.0; prescribed.dofs().len()];
        prescribed.values(lambda, &mut vals);
        for (&d, v) in prescribed.dofs().iter().zip(vals) {
            self.model.u[d] = v;
        }
    }
}
