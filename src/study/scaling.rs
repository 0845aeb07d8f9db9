//! What a finer answer costs, as ratios any machine can check (`wovenform bench --scaling`):
//! the wall time of designs of the paper's grid at `fine` over `standard`, and of the long
//! bias-extension specimen over the short one. Each run on one thread, each stopped at a
//! deadline so that a run that does not finish gives a lower bound, never a hung benchmark.

use std::ops::ControlFlow;
use std::time::Instant;

use super::timing::preset;
use crate::accuracy::Accuracy;
use crate::presets::PAPER_BOX_OPEN;

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

/// Each of [`DESIGNS`] at standard and at fine (one thread; the fine run stopped after
/// `deadline_s`); `note` hears each design start.
pub fn fine_over_standard(deadline_s: f64, note: &dyn Fn(&str)) -> Vec<FineOverStandard> {
    DESIGNS
        .iter()
        .map(|&(name, overrides)| {
            note(name);
            let at = |level: Accuracy| {
                let mut p = preset(PAPER_BOX_OPEN, "presets/paper-box-open.toml", overrides);
                p.element_size = level.element_size_mm();
                timed_drawing(&p, deadline_s)
            };
            FineOverStandard {
                name,
                standard: at(Accuracy::Standard),
                fine: at(Accuracy::Fine),
            }
        })
        .collect()
}

/// The two bias-extension specimens: length × width (mm) and grip displacement (mm).
pub const BIAS_SPECIMENS: [[f64; 3]; 2] = [[300.0, 150.0, 55.0], [450.0, 150.0, 105.0]];

/// The bias-extension test of `presets/box-with-shear.toml`'s fabric (the glass fabric's fitted
/// shear law) on the short and the long specimen of [`BIAS_SPECIMENS`], 5 mm elements, 40
/// points, one thread, each stopped after `deadline_s`.
pub fn bias_pair(deadline_s: f64) -> Result<[Timed; 2], String> {
    let scene = crate::scene::Scene::from_toml_str(
        crate::presets::BOX_WITH_SHEAR,
        "presets/box-with-shear.toml",
        &[],
    )
    .map_err(|e| e.to_string())?;
    let run = |size: [f64; 3]| -> Result<Timed, String> {
        let mut problem = crate::scene::specimen::bias_problem(&scene, size, 5.0, 40)
            .map_err(|e| e.to_string())?;
        problem.solver.parallel = false;
        let start = Instant::now();
        let r = problem
            .solve_until(&mut |_| until(start, deadline_s))
            .map_err(|e| e.to_string())?;
        Ok(Timed {
            wall_s: start.elapsed().as_secs_f64(),
            dofs: 2 * r.mesh.nodes.len(),
            steps: r.displacement_mm.len().saturating_sub(1) as u32,
            newton_iterations: r.newton_iterations,
            finished: r.failure.is_none(),
            failure: r.failure.map(|f| f.to_string()),
        })
    };
    Ok([run(BIAS_SPECIMENS[0])?, run(BIAS_SPECIMENS[1])?])
}
