//! What a finer answer costs, as ratios any machine can check (`wovenform bench --scaling`):
//! the wall time of designs of the paper's grid at `fine` over `standard`, and of the long
//! bias-extension specimen over the short one. Each run on one thread, each stopped at a
//! deadline so that a run that does not finish gives a lower bound, never a hung benchmark.
//! Each wall time is the median of the repetitions asked for, the runs of a ratio interleaved
//! (standard, fine, standard, fine, …) so that a change of the machine's load between them
//! falls on both sides of the ratio alike.

use std::ops::ControlFlow;
use std::time::Instant;

use super::timing::preset;
use crate::accuracy::Accuracy;
use crate::core::specimens::bias::BiasError;
use crate::presets::PAPER_BOX_OPEN;
use crate::scene::SceneError;

/// The designs of the paper's grid (beyond the presets) whose fine runs are timed: corner,
/// nose and die radii (mm), friction and holder pressure (MPa) as overrides.
pub const DESIGNS: [(&str, &[&str]); 5] = [
    (
        "6/9/6, μ 0.12",
        &[
            "tools.r=6",
            "tools.rp=9",
            "tools.rm=6",
            "process.friction=0.12",
        ],
    ),
    (
        "9/12/4, μ 0.2, 0.8 MPa",
        &[
            "tools.r=9",
            "tools.rp=12",
            "tools.rm=4",
            "process.friction=0.2",
            "process.holder_pressure=0.8",
        ],
    ),
    ("4/8/8", &["tools.r=4", "tools.rp=8", "tools.rm=8"]),
    ("5/6/10", &["tools.r=5", "tools.rp=6", "tools.rm=10"]),
    ("5/15/10", &["tools.r=5", "tools.rp=15", "tools.rm=10"]),
];

/// One timed run.
#[derive(Clone, Debug, PartialEq)]
pub struct Timed {
    pub wall_s: f64,
    pub dofs: usize,
    /// Load steps (for the bias-extension test: the points of its curve reached, each solved
    /// as a load path of its own).
    pub steps: u32,
    pub newton_iterations: u32,
    /// Reached the end (the full stroke) before the deadline and without failing.
    pub finished: bool,
    /// Why it did not, if it did not.
    pub failure: Option<String>,
}

/// A design at standard and at fine.
#[derive(Clone, Debug, PartialEq)]
pub struct FineOverStandard {
    pub name: &'static str,
    pub standard: Timed,
    pub fine: Timed,
}

impl FineOverStandard {
    /// Fine wall time over standard's (a lower bound when the fine run did not finish).
    pub fn wall_ratio(&self) -> f64 {
        self.fine.wall_s / self.standard.wall_s
    }

    /// Load steps at fine over those at standard.
    pub fn step_ratio(&self) -> f64 {
        f64::from(self.fine.steps) / f64::from(self.standard.steps.max(1))
    }
}

/// Go on while less than `deadline_s` has passed since `start`.
fn until(start: Instant, deadline_s: f64) -> ControlFlow<()> {
    if start.elapsed().as_secs_f64() > deadline_s {
        ControlFlow::Break(())
    } else {
        ControlFlow::Continue(())
    }
}

/// A drawing run on one thread, stopped after `deadline_s`.
pub fn timed_drawing(p: &crate::core::drawing::DrawingProblem, deadline_s: f64) -> Timed {
    let start = Instant::now();
    let r = crate::core::drawing::solve_until(p, &mut |_| until(start, deadline_s));
    Timed {
        wall_s: start.elapsed().as_secs_f64(),
        dofs: r.dofs,
        steps: r.stats.steps,
        newton_iterations: r.stats.newton_iterations,
        finished: r.converged,
        failure: r.failure.map(|f| f.to_string()),
    }
}

/// The first of `runs` with the median of their wall times (the solver is deterministic: their
/// counters agree).
fn median_run(mut runs: Vec<Timed>) -> Timed {
    let wall_s = super::timing::median(runs.iter().map(|r| r.wall_s).collect());
    let mut first = runs.swap_remove(0);
    first.wall_s = wall_s;
    first
}

/// `repetitions` interleaved rounds of `runs` (each a closure timing one run), the median of
/// each; a run that did not finish is not repeated (its first time is a lower bound already).
/// The first error a run returns is returned.
pub fn interleaved<const N: usize, E>(
    repetitions: usize,
    runs: [&dyn Fn() -> Result<Timed, E>; N],
) -> Result<[Timed; N], E> {
    let mut all: [Vec<Timed>; N] = std::array::from_fn(|_| Vec::new());
    for round in 0..repetitions.max(1) {
        for (run, times) in runs.iter().zip(all.iter_mut()) {
            if round == 0 || times[0].finished {
                times.push(run()?);
            }
        }
    }
    Ok(all.map(median_run))
}

/// Each of [`DESIGNS`] at standard and at fine (one thread; the fine run stopped after
/// `deadline_s`), each the median of `repetitions` interleaved runs; `note` hears each design
/// start.
pub fn fine_over_standard(
    deadline_s: f64,
    repetitions: usize,
    note: &dyn Fn(&str),
) -> Vec<FineOverStandard> {
    DESIGNS
        .iter()
        .map(|&(name, overrides)| {
            note(name);
            let at = |level: Accuracy| {
                let mut p = preset(PAPER_BOX_OPEN, "presets/paper-box-open.toml", overrides);
                p.element_size_mm = level.element_size_mm();
                timed_drawing(&p, deadline_s)
            };
            let at = |level: Accuracy| Ok::<_, std::convert::Infallible>(at(level));
            let [standard, fine] = interleaved(
                repetitions,
                [&|| at(Accuracy::Standard), &|| at(Accuracy::Fine)],
            )
            .unwrap_or_else(|never| match never {});
            FineOverStandard {
                name,
                standard,
                fine,
            }
        })
        .collect()
}

/// Why the bias-extension pair could not be timed.
#[derive(Debug, thiserror::Error)]
pub enum BiasPairError {
    /// `presets/box-with-shear.toml` is refused.
    #[error("{0}")]
    Scene(SceneError),
    /// A specimen's size is refused.
    #[error("{0}")]
    Specimen(SceneError),
    /// A specimen's test has no answer.
    #[error("{0}")]
    Test(BiasError),
}

impl serde::Serialize for BiasPairError {
    /// As its message (`bench --json`'s `failure`).
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// The two bias-extension specimens: length × width (mm) and grip displacement (mm).
pub const BIAS_SPECIMENS: [[f64; 3]; 2] = [[300.0, 150.0, 55.0], [450.0, 150.0, 105.0]];

/// The bias-extension test of `presets/box-with-shear.toml`'s fabric (the glass fabric's fitted
/// shear law) on the short and the long specimen of [`BIAS_SPECIMENS`], 5 mm elements, 40
/// points, one thread, each stopped after `deadline_s`, each the median of `repetitions`
/// interleaved runs.
pub fn bias_pair(deadline_s: f64, repetitions: usize) -> Result<[Timed; 2], BiasPairError> {
    let scene = crate::scene::Scene::from_toml_str(
        crate::presets::BOX_WITH_SHEAR,
        "presets/box-with-shear.toml",
        &[],
    )
    .map_err(BiasPairError::Scene)?;
    let problem = |size: [f64; 3]| {
        let mut p = crate::scene::specimen::bias_problem(&scene, size, 5.0, 40)
            .map_err(BiasPairError::Specimen)?;
        p.solver.parallel = false;
        Ok::<_, BiasPairError>(p)
    };
    let [short, long] = [problem(BIAS_SPECIMENS[0])?, problem(BIAS_SPECIMENS[1])?];
    let run = |problem: &crate::core::specimens::bias::BiasProblem| {
        let start = Instant::now();
        let r = problem
            .solve_until(&mut |_| until(start, deadline_s))
            .map_err(BiasPairError::Test)?;
        Ok(Timed {
            wall_s: start.elapsed().as_secs_f64(),
            dofs: 2 * r.mesh.nodes.len(),
            steps: r.displacement_mm.len().saturating_sub(1) as u32,
            newton_iterations: r.newton_iterations,
            finished: r.failure.is_none(),
            failure: r.failure.map(|f| f.to_string()),
        })
    };
    interleaved(repetitions, [&|| run(&short), &|| run(&long)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::RefCell;

    fn timed(wall_s: f64, finished: bool) -> Timed {
        Timed {
            wall_s,
            dofs: 10,
            steps: 20,
            newton_iterations: 100,
            finished,
            failure: None,
        }
    }

    #[test]
    fn interleaved_runs_take_turns_give_the_median_and_do_not_repeat_an_unfinished_run() {
        let calls = RefCell::new(Vec::new());
        let walls = RefCell::new(vec![3.0, 9.0, 1.0, 2.0, 7.0].into_iter());
        let a = || {
            calls.borrow_mut().push('a');
            Ok::<_, String>(timed(walls.borrow_mut().next().unwrap(), true))
        };
        let b = || {
            calls.borrow_mut().push('b');
            Ok(timed(50.0, false))
        };
        let c = || {
            calls.borrow_mut().push('c');
            Ok(timed(4.0, true))
        };
        let [a, b, c] = interleaved(3, [&a, &b, &c]).unwrap();
        // Round after round, the unfinished run once only.
        assert_eq!(calls.borrow().iter().collect::<String>(), "abcacac");
        // a ran 3.0, 9.0, 1.0 (the walls were taken in turn with nothing else): median 3.0.
        assert_eq!(a.wall_s, 3.0);
        assert_eq!((b.wall_s, b.finished), (50.0, false));
        assert_eq!(c.wall_s, 4.0);
        // An even count gives the mean of the middle two.
        let walls = RefCell::new(vec![1.0, 5.0].into_iter());
        let d = || Ok::<_, String>(timed(walls.borrow_mut().next().unwrap(), true));
        assert_eq!(interleaved(2, [&d]).unwrap()[0].wall_s, 3.0);
        // A run's error ends the rounds and is returned.
        let calls = RefCell::new(0);
        let e = || {
            *calls.borrow_mut() += 1;
            Err::<Timed, _>("no specimen".to_string())
        };
        let ok = || Ok(timed(1.0, true));
        assert_eq!(interleaved(3, [&ok, &e]).unwrap_err(), "no specimen");
        assert_eq!(*calls.borrow(), 1);
    }
}
