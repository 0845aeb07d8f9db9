//! The load path: steps from `λ = 0` to `λ = 1`, each started from a secant predictor moved
//! back onto the tools, grown while Newton converges fast and cut back when it does not.

use std::ops::ControlFlow;

use super::Solver;
use super::newton::{History, NewtonError};
use super::terms::{NodalTerms, Prescribed};

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

impl Solver<'_> {
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
        let mut previous: Option<(f64, Vec<f64>)> = None;
        while lambda < 1.0 - 1e-12 {
            if self.stats.steps >= self.options.max_steps {
                self.ws.assemble(self.model, lambda, &*terms, false);
                return Err(Failure::TooManySteps {
                    lambda,
                    steps: self.stats.steps,
                });
            }
            let target = (lambda + step).min(1.0);
            let u_start = self.model.u.clone();
            let crimp_start = self.model.crimp.clone();
            terms.begin_step(lambda, target, &self.model.positions());
            self.predict(
                target,
                previous
                    .as_ref()
                    .map(|(dl, du)| ((target - lambda) / dl, du)),
            );
            self.apply_prescribed(target, prescribed);
            if self.options.project_predictor {
                let mut x = self.model.positions();
                terms.project(target, &mut x);
                self.model.set_free_positions(&x);
            }
            let mut history = History::default();
            let mut outcome = self.newton(target, terms, &u_start, &mut history);
            // Terms that lag (friction's normal force) are solved again from the converged
            // state until a pass needs no iteration: the fixed point within the step.
            for _ in 0..self.options.max_lag_passes {
                let Ok(done) = outcome else { break };
                let x = self.model.positions();
                if done == 0 || !terms.relag(target, &x) {
                    break;
                }
                outcome = self
                    .newton(target, terms, &u_start, &mut history)
                    .map(|more| done + more);
                if outcome == Ok(done) {
                    break;
                }
            }
            match outcome {
                Ok(iterations) => {
                    let du: Vec<f64> = self
                        .model
                        .u
                        .iter()
                        .zip(&u_start)
                        .map(|(a, b)| a - b)
                        .collect();
                    self.account_unbalanced_work(target, &*terms, &du);
                    terms.end_step(target, &self.model.positions());
                    previous = Some((target - lambda, du));
                    lambda = target;
                    self.stats.steps += 1;
                    self.stats.lambda = lambda;
                    if self.options.record_residuals {
                        self.stats.residuals.push(history.residuals);
                        self.stats.active_changes.push(history.changes);
                        self.stats.alphas.push(history.alphas);
                        self.stats.damping.push(history.damping);
                    }
                    if progress(lambda).is_break() {
                        return Err(Failure::Stopped { lambda });
                    }
                    step = self.next_step(step, iterations);
                }
                Err(cause) => {
                    self.model.u = u_start;
                    self.model.crimp = crimp_start;
                    self.stats.cutbacks += 1;
                    step *= 0.25;
                    previous = None;
                    if step < self.options.min_step {
                        // Leave the element outputs at the last converged state.
                        self.ws.assemble(self.model, lambda, &*terms, false);
                        return Err(Failure::StepFailed {
                            lambda,
                            step,
                            cause,
                            mechanism: self.stats.mechanism,
                        });
                    }
                }
            }
        }
        // Leave the element outputs at the final state.
        self.ws.assemble(self.model, lambda, &*terms, false);
        Ok(())
    }

    /// The next load increment after one that took `iterations` Newton iterations: scaled by
    /// the target over the iterations taken, at most doubled or halved.
    fn next_step(&self, step: f64, iterations: u32) -> f64 {
        let target = self.options.target_iterations as f64;
        let factor = (target / iterations.max(1) as f64).clamp(0.5, 2.0);
        (step * factor).min(self.options.max_step)
    }

    /// The secant predictor on the free dofs: the previous step's increment scaled by `ratio`.
    fn predict(&mut self, _target: f64, previous: Option<(f64, &Vec<f64>)>) {
        let Some((ratio, du)) = previous else {
            return;
        };
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

    /// Adds the work of the residual left at convergence over the step's increment (free dofs).
    fn account_unbalanced_work(&mut self, lambda: f64, terms: &dyn NodalTerms, du: &[f64]) {
        let a = self.ws.assemble(self.model, lambda, terms, false);
        let m = &*self.model;
        let w: f64 =
            m.eq.iter()
                .enumerate()
                .filter(|(_, q)| **q != usize::MAX)
                .map(|(d, &q)| a.r[q] * du[d])
                .sum();
        self.stats.unbalanced_work += w.abs();
    }
}
