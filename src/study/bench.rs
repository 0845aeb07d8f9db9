//! Throughput measurements for `wovenform bench`: medians of repeated timings, one thread.

use std::hint::black_box;
use std::time::Instant;

use super::timing::{median, preset};
use crate::accuracy::Accuracy;
use crate::core::drawing::DrawingFailure;
use crate::core::fabric::law::{CellLaw, CellParams};
use crate::core::membrane::element::{self, ElementGeometry, ElementOutput, GAUSS};
use crate::core::solver::Failure;
use crate::presets::{PAPER_BOX_OPEN, PAPER_BOX_TIGHT};
use crate::study::sweep::SweepError;
use crate::study::sweep::embedded::explorer_sweep;

/// Why a measurement could not be taken: the drawing (or the sweep) that failed, and why.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The drawing cannot be set up (it has no unique shape).
    #[error("{0}")]
    Unprepared(DrawingFailure),
    /// The drawing stopped short of the full stroke.
    #[error("{0}")]
    Stopped(Failure),
    /// One of the timed drawings failed: its name, and why.
    #[error("{case}: {why}")]
    Case {
        case: &'static str,
        why: Box<BenchError>,
    },
    /// The explorer's default sweep makes no plan.
    #[error("{0}")]
    SweepPlan(SweepError),
    #[error("cannot make a temporary folder: {0}")]
    TempFolder(std::io::Error),
    /// The sweep stopped while running.
    #[error("{0}")]
    Sweep(SweepError),
}

impl serde::Serialize for BenchError {
    /// As its message (`bench --json`'s `failure`).
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// One measured rate.
#[derive(Clone, Debug)]
pub struct Rate {
    pub name: &'static str,
    /// Median over the repetitions, evaluations per second.
    pub per_second: f64,
    /// All repetitions, evaluations per second.
    pub samples: Vec<f64>,
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

/// The paper's open box (the preset) at an element size, as a problem on one thread.
pub fn paper_box(element_size_mm: f64) -> crate::core::drawing::DrawingProblem {
    let mut p = preset(PAPER_BOX_OPEN, "presets/paper-box-open.toml", &[]);
    p.element_size_mm = element_size_mm;
    p
}

/// The bending rigidity the bench's bending entry gives the open box, N·mm per mm of width
/// (a light glass fabric's order of magnitude: a 30 mm bending length at 300 g/m²).
pub const BENCH_BENDING_RIGIDITY: [f64; 2] = [0.08, 0.08];

/// The open box at standard on one thread, whole blank, without bending and with
/// [`BENCH_BENDING_RIGIDITY`] (and the default compressive stiffness): the cost of bending at
/// the same mesh.
pub fn bending_cost() -> [crate::study::scaling::Timed; 2] {
    let open = "presets/paper-box-open.toml";
    let without = preset(PAPER_BOX_OPEN, open, &["mesh.symmetry=\"full\""]);
    let rigidity = format!(
        "fabric.bending_rigidity=[{}, {}]",
        BENCH_BENDING_RIGIDITY[0], BENCH_BENDING_RIGIDITY[1]
    );
    let with = preset(PAPER_BOX_OPEN, open, &[rigidity.as_str()]);
    [without, with].map(|p| crate::study::scaling::timed_drawing(&p, 600.0))
}

/// The drawings the benchmark times, each at `standard` (2.5 mm elements), on one thread:
/// the open box, the tight box and the open box at μ 0.05, with their names.
pub fn cases() -> [(&'static str, crate::core::drawing::DrawingProblem); 3] {
    let (open, tight) = (PAPER_BOX_OPEN, PAPER_BOX_TIGHT);
    let open_file = "presets/paper-box-open.toml";
    [
        ("open box", preset(open, open_file, &[])),
        (
            "tight box (5/6/5)",
            preset(tight, "presets/paper-box-tight.toml", &[]),
        ),
        (
            "open box, friction 0.05",
            preset(open, open_file, &["process.friction=0.05"]),
        ),
    ]
}

/// The timed drawings of [`cases`], each by its name.
#[derive(Clone, Debug)]
pub struct Drawings {
    pub open: BoxRun,
    pub tight: BoxRun,
    pub open_low_friction: BoxRun,
    /// Their names, in that order.
    pub names: [&'static str; 3],
}

impl Drawings {
    /// Each with its name: the open box, the tight box, the open box at μ 0.05.
    pub fn named(&self) -> [(&'static str, &BoxRun); 3] {
        let [a, b, c] = self.names;
        [
            (a, &self.open),
            (b, &self.tight),
            (c, &self.open_low_friction),
        ]
    }
}

/// What `wovenform bench` measures besides the rates and drawings it always times.
#[derive(Clone, Copy, Debug)]
pub struct BenchOptions {
    /// Repetitions of the law and element rates (the drawings take at most 5).
    pub repetitions: usize,
    /// Also compare how friction is resolved within a step.
    pub friction: bool,
    /// Also time tools read from STL against the same analytic tools.
    pub mesh: bool,
    /// Also measure the cost of a finer answer ([`crate::study::scaling`]), each run stopped
    /// after this many seconds.
    pub scaling: Option<f64>,
    /// Also time the open box with bending against the same box without it.
    pub bending: bool,
}

/// Everything one `bench` measured.
pub struct Measured {
    /// Repetitions of the law and element rates, and of each drawing.
    pub reps: usize,
    pub box_reps: usize,
    /// The law's and the element's evaluation rates.
    pub rates: [Rate; 2],
    pub drawings: Drawings,
    /// Dofs and wall time (s) of the open box over a mesh ladder, and the exponent of the fit.
    pub ladder: Vec<(usize, f64)>,
    pub exponent: f64,
    /// Designs per minute with one and with two jobs.
    pub sweep_per_min: [f64; 2],
    /// How friction is resolved in a step (empty unless asked for).
    pub friction: Vec<(String, Result<BoxRun, BenchError>)>,
    /// STL tools against analytic ones (empty unless asked for).
    pub mesh:
        Vec<Result<crate::study::mesh_bench::MeshRun, crate::study::mesh_bench::MeshBenchError>>,
    /// The cost of a finer answer (unless not asked for).
    pub scaling: Option<Scaling>,
    /// The open box, whole blank, at standard without and with bending (unless not asked for).
    pub bending: Option<[crate::study::scaling::Timed; 2]>,
}

/// What a finer answer costs: fine over standard on designs of the grid, the long bias
/// specimen over the short one, the open box at fine on one thread and on the pool.
pub struct Scaling {
    pub deadline_s: f64,
    pub designs: Vec<crate::study::scaling::FineOverStandard>,
    pub bias: Result<[crate::study::scaling::Timed; 2], crate::study::scaling::BiasPairError>,
    /// The open box at fine: one thread, the assembly on the pool's threads, the assembly and
    /// the factorization on them (and how many there are).
    pub open_fine: [crate::study::scaling::Timed; 3],
    pub threads: usize,
}

/// Measures everything `o` asks for; `note(what)` hears each measurement start. An error names
/// the drawing (or the sweep) that failed.
pub fn measure_all(o: &BenchOptions, note: &dyn Fn(&str)) -> Result<Measured, BenchError> {
    let reps = o.repetitions;
    note("the law and the element");
    let rates = [law_rate(reps), element_rate(reps)];
    let box_reps = reps.min(5);
    let mut runs = Vec::new();
    for (name, problem) in cases() {
        note(&format!("the {name} at standard accuracy"));
        runs.push(
            drawing_run(&problem, box_reps).map_err(|why| BenchError::Case {
                case: name,
                why: Box::new(why),
            })?,
        );
    }
    let [open, tight, open_low_friction] = <[BoxRun; 3]>::try_from(runs).expect("three cases");
    let names = cases().map(|(n, _)| n);
    note("wall time against dofs (5, 3.5, 2.5, 1.75 mm)");
    let (ladder, exponent) = dof_scaling([5.0, 3.5, 2.5, 1.75], box_reps);
    note("sweep throughput with 1 and 2 jobs");
    let sweep_per_min = [sweep_throughput(1)?, sweep_throughput(2)?];
    let mut friction = Vec::new();
    if o.friction {
        note("friction resolved within the step against lagged, on the open box");
        friction = friction_resolution(box_reps.min(3));
    }
    let mut mesh = Vec::new();
    if o.mesh {
        note("STL tools against the analytic ones (open box, tight box, hemisphere)");
        mesh = crate::study::mesh_bench::mesh_tools(box_reps.min(3));
    }
    let scaling = o
        .scaling
        .map(|deadline_s| scaling(deadline_s, box_reps, note));
    let bending = o.bending.then(|| {
        note("the open box, whole blank, at standard without and with bending");
        bending_cost()
    });
    let drawings = Drawings {
        open,
        tight,
        open_low_friction,
        names,
    };
    Ok(Measured {
        reps,
        box_reps,
        rates,
        drawings,
        ladder,
        exponent,
        sweep_per_min,
        friction,
        mesh,
        scaling,
        bending,
    })
}

/// What a finer answer costs (`bench --scaling`): the open box at fine on one thread, assembling
/// on all, and factorizing on all too; the designs of the grid at fine over standard; the long
/// bias-extension specimen over the short one. Each run stops after `deadline_s`; each time is
/// the median of `box_reps` interleaved runs.
fn scaling(deadline_s: f64, box_reps: usize, note: &dyn Fn(&str)) -> Scaling {
    note("the open box at fine on one thread, assembling on all, and factorizing on all too");
    let serial = paper_box(1.25);
    // As `wovenform run` solves one design: on a worker of rayon's pool.
    let mut parallel = paper_box(1.25);
    parallel.solver.parallel = true;
    parallel.solver.factor_threads = 1;
    let mut factorized = parallel.clone();
    factorized.solver.factor_threads = 0;
    let timed = |p: &crate::core::drawing::DrawingProblem, pooled: bool| {
        let run = || crate::study::scaling::timed_drawing(p, deadline_s);
        Ok::<_, std::convert::Infallible>(if pooled {
            crate::machine::on_pool(run)
        } else {
            run()
        })
    };
    // Interleaved and repeated: a single run of each moved by ±10 % with the machine's load,
    // as much as two threads gain.
    let [one, assembly, all] = crate::study::scaling::interleaved(
        box_reps,
        [
            &|| timed(&serial, false),
            &|| timed(&parallel, true),
            &|| timed(&factorized, true),
        ],
    )
    .unwrap_or_else(|never| match never {});
    note("designs of the grid at standard and fine");
    let designs = crate::study::scaling::fine_over_standard(deadline_s, box_reps, &|name| {
        note(&format!("  {name}"))
    });
    note("the bias-extension test, 300 × 150 mm to 55 mm and 450 × 150 mm to 105 mm");
    Scaling {
        deadline_s,
        designs,
        bias: crate::study::scaling::bias_pair(deadline_s, box_reps),
        open_fine: [one, assembly, all],
        threads: rayon::current_num_threads(),
    }
}

/// One drawing's runs: its counters, its wall times, and (on its final state) where one Newton
/// iteration's time goes.
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
    /// The run's wall time in bare factorizations + solves: the median over the repetitions of
    /// each run's wall time over the bare factorization timed right after it.
    pub wall_in_factorizations: f64,
    /// The peaks over one woven cell (shear and tension) on the final state, s: what the
    /// verdict's figures cost beyond the solve.
    pub cell_peaks_s: f64,
    /// What the run found: max shear (°), max tension (N), punch force (N).
    pub max_shear_deg: f64,
    pub max_tension_n: f64,
    pub punch_force_n: f64,
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
        self.wall_in_factorizations / self.newton_iterations.max(1) as f64
    }

    /// Newton iterations per load step.
    pub fn iterations_per_step(&self) -> f64 {
        self.newton_iterations as f64 / self.steps.max(1) as f64
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

/// Runs a drawing `repetitions` times on one thread, each followed by the bare
/// factorization + solve of its final tangent (so that each run is counted in factorizations
/// timed within a second of it, whatever the machine's load did between runs), then times the
/// other parts of an iteration on the last run's final state; `Err` with the failure when a
/// run does not reach the full stroke.
pub fn drawing_run(
    p: &crate::core::drawing::DrawingProblem,
    repetitions: usize,
) -> Result<BoxRun, BenchError> {
    use crate::core::solver::{NodalTerms, NodeBlock, Solver};
    let mut samples = Vec::new();
    let mut bare = Vec::new();
    let mut last = None;
    for _ in 0..repetitions.max(1) {
        let mut prepared = p.prepare().map_err(BenchError::Unprepared)?;
        let t = Instant::now();
        let mut solver = Solver::new(&mut prepared.model, p.solver.clone());
        let outcome = solver.solve(&prepared.prescribed, &mut prepared.contact, &mut |_| {
            std::ops::ControlFlow::Continue(())
        });
        samples.push(t.elapsed().as_secs_f64());
        outcome.map_err(BenchError::Stopped)?;
        let stats = solver.stats.clone();
        solver.assemble_tangent(1.0, &prepared.contact);
        let n = solver.model.free_dofs();
        bare.push(median_time(BARE_REPETITIONS, || {
            let mut rhs = vec![1.0; n];
            black_box(solver.factor_solve_last_tangent(&mut rhs));
        }));
        drop(solver);
        last = Some((prepared, stats));
    }
    let (mut prepared, stats) = last.expect("one run at least");
    let result = prepared.result(p, stats.clone());
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
    let cell_peaks_s = median_time(15, || {
        black_box((result.max_shear(), result.max_tension_n()));
    });
    let in_factorizations = samples.iter().zip(&bare).map(|(w, b)| w / b).collect();
    Ok(BoxRun {
        cell_peaks_s,
        dofs: result.dofs,
        steps: stats.steps,
        newton_iterations: stats.newton_iterations,
        krylov_iterations: stats.krylov_iterations,
        wall_s: median(samples.clone()),
        samples,
        assembly_s,
        contact_s,
        bare_factor_solve_s: median(bare),
        wall_in_factorizations: median(in_factorizations),
        max_shear_deg: result.max_shear().1,
        max_tension_n: result.max_tension_n(),
        punch_force_n: result.punch_force_n,
    })
}

/// Bare factorizations + solves timed after each run (their median is that run's unit).
const BARE_REPETITIONS: usize = 9;

/// How friction's normal force and direction are resolved within a load step, compared on the
/// open box: at the current state with the exact Jacobian (the solver's way), with the
/// symmetric part of the Jacobian only, lagged to the step's start, and lagged with the step
/// solved again from its converged state `passes` times. Each: the name and its run (or why
/// it failed).
pub fn friction_resolution(repetitions: usize) -> Vec<(String, Result<BoxRun, BenchError>)> {
    let base = paper_box(2.5);
    let mut variants: Vec<(String, crate::core::drawing::DrawingProblem)> = Vec::new();
    variants.push(("implicit, exact Jacobian (GMRES)".into(), base.clone()));
    let mut p = base.clone();
    p.solver.exact_jacobian = false;
    variants.push(("implicit, symmetric part only".into(), p));
    let mut p = base.clone();
    p.lagged_friction = true;
    p.solver.max_lag_passes = 0;
    variants.push(("lagged to the step's start".into(), p));
    for passes in [1, 2, 3] {
        let mut p = base.clone();
        p.lagged_friction = true;
        p.solver.max_lag_passes = passes;
        variants.push((format!("lagged, {passes} fixed-point passes"), p));
    }
    variants
        .into_iter()
        .map(|(name, p)| (name, drawing_run(&p, repetitions)))
        .collect()
}

/// Wall time against dofs over a mesh ladder of the open box (one thread; each rung's time the
/// median of `repetitions` runs, the rungs taken in turn round after round so that a change of
/// the machine's load falls on all of them alike), and the least-squares exponent of
/// `wall ∝ dofs^k`.
pub fn dof_scaling<const N: usize>(
    sizes_mm: [f64; N],
    repetitions: usize,
) -> (Vec<(usize, f64)>, f64) {
    use crate::study::scaling::{interleaved, timed_drawing};
    let runs = sizes_mm.map(|h| {
        move || Ok::<_, std::convert::Infallible>(timed_drawing(&paper_box(h), f64::INFINITY))
    });
    type Run<'a> = &'a dyn Fn() -> Result<crate::study::scaling::Timed, std::convert::Infallible>;
    let rungs: [_; N] = interleaved(repetitions, std::array::from_fn(|i| &runs[i] as Run))
        .unwrap_or_else(|never| match never {});
    let points: Vec<(usize, f64)> = rungs.iter().map(|t| (t.dofs, t.wall_s)).collect();
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

/// Designs per minute of the explorer's default grid (`presets/paper-box-explorer.toml`: the
/// paper's tight and open radii, 8 designs) at `coarse` accuracy with `jobs` workers, written
/// into a temporary folder.
pub fn sweep_throughput(jobs: usize) -> Result<f64, BenchError> {
    let plan = explorer_sweep(&Accuracy::Coarse.overrides()).map_err(BenchError::SweepPlan)?;
    let dir = tempfile::Builder::new()
        .prefix("wovenform-bench-")
        .tempdir()
        .map_err(BenchError::TempFolder)?;
    let options = crate::study::sweep::Options {
        jobs: Some(jobs),
        ..Default::default()
    };
    let outcome = crate::study::sweep::run(&plan, dir.path(), &options, &|_| {})
        .map_err(BenchError::Sweep)?;
    Ok(outcome.ran as f64 / outcome.run_wall_s * 60.0)
}
