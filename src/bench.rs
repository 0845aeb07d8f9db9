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
    /// GMRES iterations over the run (the non-symmetric part of the friction).
    pub krylov_iterations: u32,
    /// Median and all repetitions of the whole run's wall time, s.
    pub wall_s: f64,
    pub samples: Vec<f64>,
    /// Timed on the final state, each a median of repetitions, s: an assembly with the tangent
    /// (elements, law, contact), the contact terms alone with their blocks, and a
    /// factorization + solve of that tangent with nothing else around it.
    pub assembly_s: f64,
    pub contact_s: f64,
    pub bare_factor_solve_s: f64,
}

impl BoxRun {
    /// One Newton iteration's wall time: the median run over its Newton iterations
    /// (everything included: assemblies, line searches, Krylov, step bookkeeping).
    pub fn iteration_s(&self) -> f64 {
        self.wall_s / self.newton_iterations.max(1) as f64
    }

    /// One Newton iteration's wall time over a bare factorization + solve of the same matrix:
    /// how close an iteration comes to the linear solver's limit.
    pub fn iteration_over_factor_solve(&self) -> f64 {
        self.iteration_s() / self.bare_factor_solve_s
    }
}

/// The median wall time of `repetitions` calls of `run`, s.
fn median_time(repetitions: usize, mut run: impl FnMut()) -> f64 {
    median(
        (0..repetitions.max(1))
            .map(|_| {
                let t = Instant::now();
                run();
                t.elapsed().as_secs_f64()
            })
            .collect(),
    )
}

/// Runs the open box `repetitions` times on one thread, then times the parts of an iteration
/// on its final state.
pub fn paper_box_run(element_size_mm: f64, repetitions: usize) -> BoxRun {
    use crate::core::solver::{NodalTerms, NodeBlock, Solver};
    let p = paper_box(element_size_mm);
    let mut samples = Vec::new();
    let mut last = None;
    for _ in 0..repetitions.max(1) {
        let mut prepared = p.prepare().map_err(|e| e.2).expect("the open box is well posed");
        let t = Instant::now();
        let mut solver = Solver::new(&mut prepared.model, p.solver.clone());
        let outcome = solver.solve(&prepared.prescribed, &mut prepared.contact, &mut |_| {
            std::ops::ControlFlow::Continue(())
        });
        samples.push(t.elapsed().as_secs_f64());
        assert!(outcome.is_ok(), "the open box did not converge: {outcome:?}");
        let stats = solver.stats.clone();
        drop(solver);
        last = Some((prepared, stats));
    }
    let (mut prepared, stats) = last.expect("one run at least");
    let dofs = prepared.model.free_dofs();
    let contact = &prepared.contact;
    let x = prepared.model.positions();
    let mut r = vec![0.0; 3 * x.len()];
    let mut blocks = vec![NodeBlock::default(); x.len()];
    let contact_s = median_time(15, || {
        r.iter_mut().for_each(|v| *v = 0.0);
        blocks.iter_mut().for_each(|b| *b = NodeBlock::default());
        black_box(contact.add(1.0, &x, &mut r, Some(&mut blocks)));
    });
    let mut solver = Solver::new(&mut prepared.model, p.solver.clone());
    let assembly_s = median_time(15, || solver.assemble_tangent(1.0, contact));
    let n = solver.model.free_dofs();
    let bare_factor_solve_s = median_time(15, || {
        let mut rhs = vec![1.0; n];
        black_box(solver.factor_solve_last_tangent(&mut rhs));
    });
    BoxRun {
        dofs,
        steps: stats.steps,
        newton_iterations: stats.newton_iterations,
        krylov_iterations: stats.krylov_iterations,
        wall_s: median(samples.clone()),
        samples,
        assembly_s,
        contact_s,
        bare_factor_solve_s,
    }
}

/// Wall time against dofs over a mesh ladder of the open box (one run each, one thread), and
/// the least-squares exponent of `wall ∝ dofs^k`.
pub fn dof_scaling(sizes_mm: &[f64]) -> (Vec<(usize, f64)>, f64) {
    let points: Vec<(usize, f64)> = sizes_mm
        .iter()
        .map(|&h| {
            let t = Instant::now();
            let r = crate::core::drawing::solve(&paper_box(h), &mut |_| {});
            (r.dofs, t.elapsed().as_secs_f64())
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
