//! Throughput measurements for `wovenform bench`: medians of repeated timings, one thread.

use std::hint::black_box;
use std::time::Instant;

use crate::core::element::{self, ElementGeometry, ElementOutput, GAUSS};
use crate::core::law::{CellLaw, CellParams};

/// One measured rate.
#[derive(Clone, Debug)]
pub struct Rate {
    pub name: &'static str,
    /// Median over the repetitions, evaluations per second.
    pub per_second: f64,
    /// All repetitions, evaluations per second.
    pub samples: Vec<f64>,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn measure(name: &'static str, repetitions: usize, mut run: impl FnMut() -> usize) -> Rate {
    run(); // warm-up
    let samples: Vec<f64> = (0..repetitions)
        .map(|_| {
            let t = Instant::now();
            let n = run();
            n as f64 / t.elapsed().as_secs_f64()
        })
        .collect();
    Rate {
        name,
        per_second: median(samples.clone()),
        samples,
    }
}

/// Law evaluations (tensions + tangent) per second, each cell warm-started from its previous
/// state along a loading path, as the solver calls it: strains march in small increments.
pub fn law_rate(repetitions: usize) -> Rate {
    let law = CellLaw::new(CellParams::PAPER_GLASS);
    let cells = 1000;
    let steps = 200;
    measure(
        "law evaluations (with tangent, warm-started)",
        repetitions,
        || {
            let mut states = vec![law.initial_state(); cells];
            for step in 0..steps {
                for (i, s) in states.iter_mut().enumerate() {
                    let k = 1.0 + (i % 7) as f64;
                    let e1 = 2e-5 * step as f64 * (1.0 + 0.001 * i as f64);
                    let r = law.evaluate(black_box([e1, e1 / k]), *s);
                    *s = r.crimp;
                    black_box(r.dt);
                }
            }
            cells * steps
        },
    )
}

/// Element internal force + tangent evaluations per second (2×2 Gauss points, woven law).
pub fn element_rate(repetitions: usize) -> Rate {
    let law = CellLaw::new(CellParams::PAPER_GLASS);
    let x0 = [
        [0.0, 0.0, 0.0],
        [5.0, 0.0, 0.0],
        [5.2, 4.9, 0.0],
        [0.1, 5.0, 0.0],
    ];
    let geo = ElementGeometry::new(
        &x0,
        Some([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
        law.p.l0[0] * law.p.l0[1],
    )
    .expect("valid element");
    let n = 20_000;
    let mut out = ElementOutput::default();
    measure("element force + tangent evaluations", repetitions, || {
        let mut crimp = [law.initial_state(); GAUSS];
        for i in 0..n {
            let e = 0.002 + 1e-7 * (i % 100) as f64;
            let x = x0.map(|p| [p[0] * (1.0 + e), p[1] * (1.0 + 0.5 * e), 0.01 * p[0]]);
            element::evaluate(&geo, &law, black_box(&x), &mut crimp, true, &mut out);
            black_box(&out.k);
        }
        n
    })
}

/// The paper's open box (the preset, `standard`: 2.5 mm elements), as a problem on one thread.
pub fn paper_box(element_size_mm: f64) -> crate::core::drawing::DrawingProblem {
    let scene = crate::scene::Scene::from_toml_str(
        include_str!("../presets/paper-box-open.toml"),
        "presets/paper-box-open.toml",
        &[],
    )
    .expect("the embedded preset is valid");
    let mut p = scene.to_problem();
    p.element_size = element_size_mm;
    p.solver.parallel = false;
    p
}

/// A whole run of the paper's open box, and where one Newton iteration's time goes.
#[derive(Clone, Debug)]
pub struct BoxRun {
    pub dofs: usize,
    pub steps: u32,
    pub newton_iterations: u32,
    /// Median and all repetitions of the whole run's wall time, s.
    pub wall_s: f64,
    pub samples: Vec<f64>,
    /// Per Newton iteration (from the median run), s: the element assembly (law, element
    /// forces and tangents into the sparse matrix), the contact terms, the factorization and
    /// solve, and the rest (line search, step bookkeeping, outputs).
    pub assembly_s: f64,
    pub contact_s: f64,
    pub factor_solve_s: f64,
    pub other_s: f64,
    /// A factorization + solve of the run's last tangent timed on its own, nothing else
    /// around it (median over the repetitions), s.
    pub bare_factor_solve_s: f64,
}

impl BoxRun {
    /// One Newton iteration's wall time.
    pub fn iteration_s(&self) -> f64 {
        self.assembly_s + self.contact_s + self.factor_solve_s + self.other_s
    }

    /// One Newton iteration's wall time over a bare factorization + solve of the same matrix:
    /// how close an iteration comes to the linear solver's limit.
    pub fn iteration_over_factor_solve(&self) -> f64 {
        self.iteration_s() / self.bare_factor_solve_s
    }
}

/// Runs the open box `repetitions` times on one thread.
pub fn paper_box_run(element_size_mm: f64, repetitions: usize) -> BoxRun {
    let mut p = paper_box(element_size_mm);
    let mut runs: Vec<crate::core::drawing::DrawingResult> = (0..repetitions.max(1))
        .map(|_| crate::core::drawing::solve(&p, &mut |_| {}))
        .collect();
    let samples: Vec<f64> = runs.iter().map(|r| r.wall_s).collect();
    // One more run that ends by timing its last tangent's factorization + solve alone (kept
    // out of the runs above, whose wall time it would add to).
    p.solver.time_bare_factorization = true;
    let bare = crate::core::drawing::solve(&p, &mut |_| {})
        .stats
        .bare_factor_solve_s
        .unwrap_or(f64::NAN);
    runs.sort_by(|a, b| a.wall_s.total_cmp(&b.wall_s));
    let r = &runs[runs.len() / 2];
    let n = r.stats.newton_iterations.max(1) as f64;
    let (a, c, f) = (r.stats.assembly_s, r.stats.nodal_s, r.stats.factor_solve_s);
    BoxRun {
        dofs: r.dofs,
        steps: r.stats.steps,
        newton_iterations: r.stats.newton_iterations,
        wall_s: median(samples.clone()),
        samples,
        assembly_s: a / n,
        contact_s: c / n,
        factor_solve_s: f / n,
        other_s: (r.wall_s - a - c - f).max(0.0) / n,
        bare_factor_solve_s: bare,
    }
}

/// Wall time against dofs over a mesh ladder of the open box (one run each, one thread), and
/// the least-squares exponent of `wall ∝ dofs^k`.
pub fn dof_scaling(sizes_mm: &[f64]) -> (Vec<(usize, f64)>, f64) {
    let points: Vec<(usize, f64)> = sizes_mm
        .iter()
        .map(|&h| {
            let r = crate::core::drawing::solve(&paper_box(h), &mut |_| {});
            (r.dofs, r.wall_s)
        })
        .collect();
    let xy: Vec<(f64, f64)> = points
        .iter()
        .map(|&(d, w)| ((d as f64).ln(), w.ln()))
        .collect();
    let n = xy.len() as f64;
    let (mx, my) = (
        xy.iter().map(|p| p.0).sum::<f64>() / n,
        xy.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxy: f64 = xy.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = xy.iter().map(|p| (p.0 - mx).powi(2)).sum();
    (points, sxy / sxx)
}

/// Designs per minute of the explorer's default grid (the paper's tight and open radii,
/// 8 designs) at `coarse` accuracy with `jobs` workers, written into a temporary folder.
pub fn sweep_throughput(jobs: usize) -> Result<f64, String> {
    use crate::tui::params::{Parameters, default_source};
    let mut params = Parameters::new(default_source())?;
    params.step_accuracy(false);
    let plan = params.plan.clone();
    let dir = std::env::temp_dir().join(format!(
        "wovenform-bench-{}-{jobs}-{}",
        std::process::id(),
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_nanos())
            .unwrap_or(0)
    ));
    let options = crate::sweep::Options {
        jobs: Some(jobs),
        skip_report: true,
        ..Default::default()
    };
    let outcome = crate::sweep::run(&plan, &dir, &options, &|_| {}).map_err(|e| e.to_string());
    let _ = std::fs::remove_dir_all(&dir);
    let outcome = outcome?;
    Ok(outcome.ran as f64 / outcome.run_wall_s * 60.0)
}
