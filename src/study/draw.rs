//! One drawing of one scene, as `run` and the explorer's "write the files" make it: solved with
//! a progress callback, timed and summed up, with the reason its answer cannot be used.

use crate::core::drawing::{self, DrawingFailure, DrawingProblem, DrawingResult};
use crate::scene::Scene;
use crate::summary::RunSummary;

/// A scene drawn: its problem, the solver's result and the summary of it.
pub struct Drawn {
    pub problem: DrawingProblem,
    pub result: DrawingResult,
    pub summary: RunSummary,
}

/// Solves `scene` (called `name` in the summary); `progress` hears the fraction of the stroke
/// done.
pub fn draw(name: &str, scene: &Scene, progress: &mut dyn FnMut(f64)) -> Drawn {
    solve(name, scene, scene.to_problem(), progress)
}

/// [`draw`] with every Newton iteration recorded (`result.stats`: residuals, active-set
/// changes, line search lengths, where each residual sits) for `run --newton-trace`. The
/// recording costs a little time; the answer is the same.
pub fn draw_traced(name: &str, scene: &Scene, progress: &mut dyn FnMut(f64)) -> Drawn {
    let mut problem = scene.to_problem();
    problem.solver.record_residuals = true;
    solve(name, scene, problem, progress)
}

fn solve(
    name: &str,
    scene: &Scene,
    problem: DrawingProblem,
    progress: &mut dyn FnMut(f64),
) -> Drawn {
    let start = std::time::Instant::now();
    let result = drawing::solve(&problem, progress);
    let wall_s = start.elapsed().as_secs_f64();
    let summary = RunSummary::new(name, scene, &result, wall_s);
    Drawn {
        problem,
        result,
        summary,
    }
}

impl Drawn {
    /// Why the answer cannot be used (an unsound result, a scene without answer, a drawing that
    /// did not converge), as a sentence; `None` when it can.
    pub fn refusal(&self) -> Option<String> {
        if !self.summary.unsound.is_empty() {
            return Some(format!(
                "the result cannot be trusted: {}",
                self.summary.unsound.join("; ")
            ));
        }
        if self.result.converged {
            return None;
        }
        let what = match self.result.failure {
            Some(DrawingFailure::NoUniqueShape { .. }) => "the drawing has no answer",
            _ => "the drawing did not converge",
        };
        let cause =
            (self.result.failure.as_ref()).map_or("no cause given".into(), |f| f.to_string());
        Some(format!("{what}: {cause}"))
    }
}
