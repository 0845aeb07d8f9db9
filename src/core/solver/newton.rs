//! Newton's method at one load factor: assemble, test, correct, search along the correction.

use super::Solver;
use super::assembly::Assembly;
use super::correction::{self, Correction, CorrectionError};
use super::line_search::{self, Base};
use super::terms::NodalTerms;

/// Why the Newton iterations of a step stopped without converging.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NewtonError {
    /// The configuration is inadmissible or its residual is not finite.
    Inadmissible,
    /// The tangent could not be factorized, even shifted.
    NotFactorizable,
    /// The linear solve gave a non-finite correction.
    NonFiniteCorrection,
    /// No length along the correction lowered the merit or the residual.
    LineSearch { residual_n: f64 },
    /// The residual was still above the tolerance after the allowed iterations.
    NoConvergence { iterations: u32, residual_n: f64 },
}

impl std::fmt::Display for NewtonError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NewtonError::Inadmissible => write!(f, "an inadmissible or non-finite state"),
            NewtonError::NotFactorizable => write!(f, "the tangent could not be factorized"),
            NewtonError::NonFiniteCorrection => {
                write!(f, "the linear solve gave a non-finite correction")
            }
            NewtonError::LineSearch { residual_n } => write!(
                f,
                "the line search found no acceptable point (residual {residual_n:.3e} N)"
            ),
            NewtonError::NoConvergence {
                iterations,
                residual_n,
            } => write!(
                f,
                "no convergence in {iterations} Newton iterations (residual {residual_n:.3e} N)"
            ),
        }
    }
}

impl From<CorrectionError> for NewtonError {
    fn from(e: CorrectionError) -> Self {
        match e {
            CorrectionError::NotFactorizable => NewtonError::NotFactorizable,
            CorrectionError::NonFinite => NewtonError::NonFiniteCorrection,
        }
    }
}

fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// The record of one step's iterations.
#[derive(Clone, Debug, Default)]
pub(super) struct History {
    /// The residual norm of each iteration, N.
    pub residuals: Vec<f64>,
    /// How many yarns changed between slack and taut, or nodes between touching a tool and not,
    /// since the previous iteration (recorded with `record_residuals`).
    pub changes: Vec<u32>,
    /// The damping and the line search's length of each correction (recorded likewise).
    pub damping: Vec<f64>,
    pub alphas: Vec<f64>,
    /// Where each iteration's residual sits (recorded likewise).
    pub sites: Vec<super::site::ResidualSite>,
    /// The residual of the state that converged, over the free dofs, N.
    pub converged_residual: Vec<f64>,
    last_active: Option<Vec<bool>>,
}

/// What one step's iterations carry from one to the next.
struct Progress {
    /// The residual norm of the first iteration (the scale of the pseudo-transient damping).
    first_residual: Option<f64>,
    /// The last correction was taken in full.
    last_full: bool,
    /// The damping of the last correction, times the cells' stiffness.
    damping: f64,
    /// Full corrections in a row.
    full_run: usize,
}

/// Full corrections in a row after which a residual that has not halved is a stall.
const STALL_RUN: usize = 4;

impl Progress {
    /// Records a correction searched to length `alpha` (of the correction as searched, halved
    /// or not).
    fn searched(&mut self, alpha: f64) {
        self.last_full = alpha >= 0.999;
        self.full_run = if self.last_full { self.full_run + 1 } else { 0 };
    }

    /// Newton caught in a cycle: [`STALL_RUN`] full corrections in a row that did not halve the
    /// residual (`residuals`, this one last). Seen on fine meshes at the box's corner, where
    /// yarns cross the toe's end and back at every correction and the residual alternates
    /// between two values (133 N ± 1 % for 36 iterations, then a cut-back). The line search
    /// accepts each one, since each lowers either the merit or the residual a little. Half the
    /// correction lands between the two states of the cycle and breaks it. Returns the scale
    /// applied to `c` (1 or ½).
    fn cycle_breaker(&mut self, residuals: &[f64], c: &mut Correction) -> f64 {
        let n = residuals.len();
        if self.full_run < STALL_RUN || n <= STALL_RUN {
            return 1.0;
        }
        if residuals[n - 1] <= 0.5 * residuals[n - 1 - STALL_RUN] {
            return 1.0;
        }
        for v in &mut c.du {
            *v *= 0.5;
        }
        c.slope *= 0.5;
        self.full_run = 0;
        0.5
    }
}

impl Solver<'_> {
    /// Newton iterations at load `lambda` from the current displacements (`from_converged`:
    /// the state converged before its lagged terms were updated); `history` receives the
    /// residual norm of each iteration. Returns the iterations taken.
    pub(super) fn newton(
        &mut self,
        lambda: f64,
        terms: &mut dyn NodalTerms,
        from_converged: bool,
        history: &mut History,
    ) -> Result<u32, NewtonError> {
        let mut carried = None;
        let mut progress = Progress {
            first_residual: None,
            last_full: false,
            damping: 0.0,
            full_run: 0,
        };
        let cap = self.iteration_cap();
        for it in 0..=cap {
            let a = match carried.take() {
                Some(a) => a,
                None => self.ws.assemble(self.model, lambda, &*terms, true),
            };
            if !a.admissible {
                return Err(NewtonError::Inadmissible);
            }
            let rn = norm2(&a.r);
            history.residuals.push(rn);
            if self.options.record_residuals {
                self.record_state(history, &a.r);
            }
            // Converged when the forces balance to the tolerance at a state this call has
            // corrected (or that converged a moment ago). No test on the correction's size:
            // along the mechanisms of the slack fabric a residual far below the tolerance
            // still moves nodes by micrometres, and waiting for that to stop cost a fine mesh
            // a fifth of its iterations without moving any figure.
            let tolerance = self.residual_tolerance(&a);
            let balanced = rn <= tolerance || self.work_balanced(&a, rn, tolerance);
            if balanced && (it > 0 || from_converged) {
                history.converged_residual = a.r;
                return Ok(it);
            }
            if it == cap {
                break;
            }
            let mut c = self.correction(&a, rn, lambda, &*terms, &mut progress)?;
            let last = self.decrement_small(&c, rn, tolerance);
            let scale = progress.cycle_breaker(&history.residuals, &mut c);
            let x = self.model.positions();
            terms.freeze(lambda, &x);
            let base = Base {
                merit: a.energy,
                residual: rn,
                slope: c.slope,
                tolerance,
            };
            let searched = self.search(lambda, &*terms, &x, &c, &base, progress.last_full);
            // A failed search's correction was counted: its row says no length was taken.
            let taken = searched.as_ref().map_or(0.0, |(alpha, _)| alpha * scale);
            if self.options.record_residuals {
                history.alphas.push(taken);
                history.damping.push(progress.damping);
            }
            let (alpha, next) = searched?;
            carried = next;
            if last {
                match self.end_on_decrement(lambda, &*terms, carried.take(), history) {
                    None => return Ok(it + 1),
                    left => carried = left,
                }
            }
            self.adapt_damping(alpha);
            if !self.start_damping_set && alpha >= 0.1 {
                self.start_damping_set = true;
                self.start_damping = self.levenberg;
            }
            progress.searched(alpha);
        }
        Err(NewtonError::NoConvergence {
            iterations: cap,
            residual_n: history.residuals.last().copied().unwrap_or(f64::NAN),
        })
    }

    /// Whether correction `c` (at residual `rn`, N) is a step's last: a model without bending,
    /// `rn` within [`super::DECREMENT_FORCE_SPAN`] force tolerances, and Newton's decrement
    /// `|r·Δu|` at most [`super::SolverOptions::tol_decrement`] of the stored energy the fabric
    /// gained in the step. The decrement is the energy the correction would release: what is
    /// left between the state and its balance (to second order). It is small where the force
    /// residual is not, at a node lifting off a tool whose depth Newton halves each iteration
    /// in the contact's eased gap (a force of `k y²/2δ` micrometres from its balance).
    fn decrement_small(&self, c: &Correction, rn: f64, tolerance: f64) -> bool {
        let share = self.options.tol_decrement;
        if share <= 0.0 || self.bends() || rn > super::DECREMENT_FORCE_SPAN * tolerance {
            return false;
        }
        c.slope.abs() <= share * self.step_gain()
    }

    /// After a step's last correction (by [`Solver::decrement_small`]): ends the step (`None`)
    /// when the state it reached is [`Solver::fairly_balanced`], else returns that state's
    /// assembly (`carried`, or assembled here) for the next iteration.
    fn end_on_decrement(
        &mut self,
        lambda: f64,
        terms: &dyn NodalTerms,
        carried: Option<Assembly>,
        history: &mut History,
    ) -> Option<Assembly> {
        let a = carried.unwrap_or_else(|| self.ws.assemble(self.model, lambda, terms, true));
        if self.fairly_balanced(&a) {
            self.finish(a, history);
            return None;
        }
        Some(a)
    }

    /// Whether the forces out of balance at assembly `a` (the state a step's last correction
    /// reached) did at most [`super::DECREMENT_WORK_SHARE`] of the stored energy the fabric
    /// gained in the step as work over the step's increment: the drawings' soundness limit on
    /// the whole run, asked of each step, so that no run ended this way can exceed it.
    fn fairly_balanced(&self, a: &Assembly) -> bool {
        self.step_work(a) <= super::DECREMENT_WORK_SHARE * self.step_gain()
    }

    /// Ends a step at the state its last correction reached, assembly `a`: its residual
    /// recorded as the converged one.
    fn finish(&mut self, a: Assembly, history: &mut History) {
        history.residuals.push(norm2(&a.r));
        if self.options.record_residuals {
            self.record_state(history, &a.r);
        }
        history.converged_residual = a.r;
    }

    /// Records an iteration's state: the active set's changes since the last one, and where the
    /// residual `r` sits.
    fn record_state(&self, history: &mut History, r: &[f64]) {
        let active = self.active_set();
        let changes = history.last_active.as_ref().map_or(0, |last| {
            last.iter().zip(&active).filter(|(a, b)| a != b).count()
        });
        history.changes.push(changes as u32);
        history.last_active = Some(active);
        (history.sites).push(super::site::locate(self.model, &self.ws.blocks, r));
    }

    /// Which yarns are slack (each Gauss point's two) and which nodes the tools touch, at the
    /// last assembly with the tangent.
    fn active_set(&self) -> Vec<bool> {
        let slack = self
            .model
            .outputs
            .iter()
            .flat_map(|o| o.tension.iter().flat_map(|t| [t[0] == 0.0, t[1] == 0.0]));
        let touched = self.ws.blocks.iter().map(|b| !b.is_zero());
        slack.chain(touched).collect()
    }

    /// The residual that ends the iterations, N: relative to the load scale, with a floor of a
    /// yarn force of `tol_floor` C (default 1e-7: a yarn strain of 1e-7) for problems whose forces are all nearly
    /// zero (a free, slack blank on the law's slack/taut kink).
    fn residual_tolerance(&self, a: &Assembly) -> f64 {
        let c = 0.5 * (self.model.law.p.c[0] + self.model.law.p.c[1]);
        self.relax * (self.options.tol_force * a.scale + self.options.tol_floor * c)
    }

    /// Whether the residual `rn` (N) of assembly `a`, within [`super::WORK_FORCE_SPAN`] force
    /// tolerances, did at most [`super::SolverOptions::tol_work`] of the stored energy the fabric
    /// gained in the step as work over the step's increment: the share of the run's work that
    /// the soundness check bounds, taken step by step. Models with bending never: a buckled
    /// path is picked by how far each step is balanced.
    fn work_balanced(&self, a: &Assembly, rn: f64, tolerance: f64) -> bool {
        let share = self.options.tol_work;
        if share <= 0.0 || self.bends() || rn > super::WORK_FORCE_SPAN * tolerance {
            return false;
        }
        self.step_work(a) <= share * self.step_gain()
    }

    /// The work of assembly `a`'s residual over the step's increment, `|r · Δu|`, N·mm.
    fn step_work(&self, a: &Assembly) -> f64 {
        self.residual_work(&a.r, &self.step_origin.0).abs()
    }

    /// The stored energy the fabric gained in the step so far, N·mm.
    fn step_gain(&self) -> f64 {
        self.model.stored_energy() - self.step_origin.1
    }

    /// The Newton correction from the assembled tangent, damped by the pseudo-transient
    /// stabilisation (fading with the square of the residual's fall since the step's first
    /// iteration, so that it is gone from the quadratic tail) and the Levenberg–Marquardt part,
    /// with each node's contact at load `lambda` solved in it ([`Solver::reshape`]).
    fn correction(
        &mut self,
        a: &Assembly,
        rn: f64,
        lambda: f64,
        terms: &dyn NodalTerms,
        progress: &mut Progress,
    ) -> Result<Correction, NewtonError> {
        let r0 = *progress.first_residual.get_or_insert(rn);
        let fade = (rn / r0).min(1.0);
        let damping = self.options.stabilisation * fade * fade + self.levenberg;
        progress.damping = damping;
        self.ws.add_damping(self.model, damping);
        if !self.options.exact_jacobian {
            self.ws.rest.clear();
        }
        // The Krylov solve's forcing, tight enough to keep Newton quadratic.
        let forcing = (rn / a.scale.max(f64::MIN_POSITIVE)).clamp(1e-10, 1e-2);
        let c = correction::solve(self.model, &self.ws, &a.r, forcing)?;
        self.stats.krylov_iterations += c.krylov_iterations;
        if c.shift > 0.0 {
            // Part of the blank is a mechanism (held by nothing).
            self.stats.shifted_solves += 1;
            self.stats.mechanism = true;
        }
        self.stats.newton_iterations += 1;
        Ok(self.reshape(lambda, terms, &a.r, c))
    }

    /// The line search along `c` from the current state (positions `x`); returns the length
    /// taken and the accepted trial's assembly when it holds the tangent there.
    fn search(
        &mut self,
        lambda: f64,
        terms: &dyn NodalTerms,
        x: &[[f64; 3]],
        c: &Correction,
        base: &Base,
        speculate: bool,
    ) -> Result<(f64, Option<Assembly>), NewtonError> {
        let u_base = self.model.u.clone();
        let project = self.options.project_trials;
        let (model, ws) = (&mut *self.model, &mut self.ws);
        let accepted = line_search::backtrack(base, speculate, |alpha, tangent| {
            for (d, &q) in model.eq.iter().enumerate() {
                if q != usize::MAX {
                    model.u[d] = u_base[d] + alpha * c.du[q];
                }
            }
            if project {
                let mut trial = model.positions();
                terms.project_trial(lambda, x, &mut trial);
                model.set_free_positions(&trial);
            }
            ws.assemble(model, lambda, terms, tangent)
        })
        .ok_or(NewtonError::LineSearch {
            residual_n: base.residual,
        })?;
        self.stats.line_search_trials += accepted.trials;
        if accepted.alpha < 0.5 {
            self.stats.damped_iterations += 1;
        }
        Ok((accepted.alpha, accepted.carried))
    }

    /// More Levenberg–Marquardt damping after a hard cut, less (down to none) after full steps.
    fn adapt_damping(&mut self, alpha: f64) {
        if alpha >= 0.999 {
            self.levenberg = if self.levenberg < 1e-6 {
                0.0
            } else {
                0.1 * self.levenberg
            };
        } else if alpha < 0.1 {
            self.levenberg = (10.0 * self.levenberg).clamp(1e-4, 1e2);
        }
    }
}
