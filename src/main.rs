//! The command line: one thin function per subcommand.
//!
//! Exit codes: 0 success, 1 a failed run, 2 bad input (the message on stderr names the file or
//! option, the key and what was expected). Clap's own usage errors also exit with 2.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde::Serialize;

use wovenform::core::drawing;
use wovenform::core::law::{CellLaw, CellParams};
use wovenform::fit::{self as fitting, FitOptions, STRAIN_RANGE};
use wovenform::report::figure6;
use wovenform::report::summary::{self, RunSummary};
use wovenform::scene::{Override, Scene};
use wovenform::sweep::{self, Plan, Progress, Shard, SweepError};

mod cli;

use cli::{
    BenchArgs, Cli, Command, ConvergeArgs, FitArgs, LawArgs, MergeArgs, RunArgs, SceneArgs,
    SweepArgs, TuiArgs, with_accuracy,
};

impl SceneArgs {
    fn load(&self) -> Result<Scene, Failure> {
        let overrides = self
            .set
            .iter()
            .map(|s| s.parse::<Override>())
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| Failure::BadInput(e.to_string()))?;
        Scene::load(self.scene.as_deref(), &overrides).map_err(|e| Failure::BadInput(e.to_string()))
    }
}

/// Why a command did not succeed.
#[derive(Debug)]
enum Failure {
    /// Exit code 2.
    BadInput(String),
    /// Exit code 1.
    Run(String),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match cli.command {
        None if std::io::stdout().is_terminal() && std::io::stdin().is_terminal() => {
            tui(TuiArgs { sweep: None })
        }
        None => overview(),
        Some(Command::Tui(args)) => tui(args),
        Some(Command::Converge(args)) => converge(args),
        Some(Command::Run(args)) => run(args),
        Some(Command::Sweep(args)) => sweep_cmd(args),
        Some(Command::Merge(args)) => merge_cmd(args),
        Some(Command::Law(args)) => law(args),
        Some(Command::Fit(args)) => fit(args),
        Some(Command::Bench(args)) => bench(args),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::BadInput(m)) => {
            eprintln!("error: {m}");
            ExitCode::from(2)
        }
        Err(Failure::Run(m)) => {
            eprintln!("error: {m}");
            ExitCode::from(1)
        }
    }
}

/// `wovenform converge`: the mesh and step ladders, their errors and cost, the table, the CSV
/// and the error-against-time chart.
fn converge(args: ConvergeArgs) -> Result<(), Failure> {
    use wovenform::converge as study;
    let scene = SceneArgs {
        scene: Some(args.scene.clone()),
        set: args.set.clone(),
    }
    .load()?;
    let h = scene.mesh.element_size;
    let sizes = if args.sizes.is_empty() {
        [2.0, 2f64.sqrt(), 1.0, 0.5f64.sqrt(), 0.5]
            .iter()
            .map(|k| (h * k * 1000.0).round() / 1000.0)
            .collect()
    } else {
        args.sizes.clone()
    };
    let counts = if args.steps.is_empty() {
        vec![4, 8, 16, 32, 64]
    } else {
        args.steps.clone()
    };
    if sizes.len() < 2 || sizes.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return Err(Failure::BadInput(format!(
            "--sizes {sizes:?}: expected two or more element sizes > 0 mm, coarse to fine"
        )));
    }
    if counts.len() < 2 || counts.contains(&0) {
        return Err(Failure::BadInput(format!(
            "--steps {counts:?}: expected two or more step counts ≥ 1, few to many"
        )));
    }
    std::fs::create_dir_all(&args.out).map_err(|e| {
        Failure::BadInput(format!(
            "{}: cannot write the output folder: {e}",
            args.out.display()
        ))
    })?;
    let total = (sizes.len() + counts.len()) as u64;
    let bar = stderr_bar(
        total,
        "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} solves, {msg}",
    );
    let mut tick = |r: &study::Rung| {
        bar.inc(1);
        bar.set_message(format!(
            "last: {} mm, {} steps, {:.1} s",
            r.element_size_mm, r.steps, r.wall_s
        ));
    };
    let mesh = study::mesh_ladder(&scene, &sizes, &mut tick);
    let steps = study::step_ladder(&scene, &counts, &mut tick);
    bar.finish_and_clear();

    print!("{}", wovenform::report::converge::table(&mesh, &steps));
    println!(
        "\nerror against wall time (S, F: the mesh ladder's max shear in °, punch force in %; \
         s, f: the step ladder's)\n{}",
        wovenform::report::converge::text_chart(&mesh, &steps, 60, 14)
    );
    let csv_path = args.out.join("converge.csv");
    std::fs::write(&csv_path, wovenform::report::converge::csv(&mesh, &steps))
        .map_err(|e| Failure::Run(format!("{}: {e}", csv_path.display())))?;
    let png = args.out.join("converge.png");
    wovenform::report::converge::chart(&mesh, &steps)
        .write_png(&png)
        .map_err(Failure::Run)?;
    println!("wrote {} and {}", csv_path.display(), png.display());
    Ok(())
}

/// `wovenform tui [SWEEP.toml]` (and `wovenform` alone in a terminal): the explorer.
fn tui(args: TuiArgs) -> Result<(), Failure> {
    let source = match &args.sweep {
        Some(path) => wovenform::tui::source_of_file(path).map_err(Failure::BadInput)?,
        None => wovenform::tui::params::default_source(),
    };
    let params = wovenform::tui::params::Parameters::new(source).map_err(Failure::BadInput)?;
    if !std::io::stdout().is_terminal() {
        return Err(Failure::BadInput(
            "the explorer needs a terminal; use `wovenform sweep SWEEP.toml --out DIR` in scripts"
                .into(),
        ));
    }
    let stamp = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    let session =
        std::env::temp_dir().join(format!("wovenform-explorer-{stamp}-{}", std::process::id()));
    wovenform::tui::explore(params, session).map_err(Failure::Run)
}

/// No subcommand and no terminal: the law at the paper's reference strains and a pointer to
/// --help.
fn overview() -> Result<(), Failure> {
    let p = CellParams::PAPER_GLASS;
    let law = CellLaw::new(p);
    println!("wovenform: deep drawing of woven fabrics (Boisse et al. 1997)");
    println!(
        "paper glass fabric: L0 = {} mm, e0 = {} mm, C = {} N, A = {} mm, B = {} 1/N",
        p.l0[0], p.e0[0], p.c[0], p.a, p.b
    );
    println!("   ε11     ε22    T11 (N)    T22 (N)  closure (mm)");
    for eps in [[0.004, 0.004], [0.010, 0.0], [0.006, 0.003]] {
        let r = law.evaluate(eps, law.initial_state());
        println!(
            "{:6.3}  {:6.3}  {:9.4}  {:9.4}  {:10.6}",
            eps[0], eps[1], r.t[0], r.t[1], r.crimp.s
        );
    }
    println!();
    println!("draw the paper's box:  wovenform run presets/paper-box-open.toml");
    println!("                       wovenform run presets/paper-box-tight.toml");
    println!("all the commands:      wovenform --help");
    Ok(())
}

/// `wovenform run`: solve one scene, report it, write the maps, the VTU and the summary.
fn run(args: RunArgs) -> Result<(), Failure> {
    let scene = SceneArgs {
        scene: Some(args.scene.clone()),
        set: with_accuracy(args.accuracy, &args.set),
    }
    .load()?;
    let name = args
        .scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let problem = scene.to_problem();
    let bar = stroke_bar(problem.stroke);
    let start = std::time::Instant::now();
    let result = drawing::solve(&problem, &mut |fraction| {
        bar.set_position((fraction * 1000.0).round() as u64);
        bar.set_message(format!(
            "stroke {:.2} of {} mm",
            fraction * problem.stroke,
            problem.stroke
        ));
    });
    let wall_s = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let mut summary = RunSummary::new(&name, &scene, &result, wall_s);
    let dir = args.out.unwrap_or_else(|| Path::new("out").join(&name));
    summary::write_run(&dir, &mut summary, &result, &problem.tooling).map_err(Failure::Run)?;
    if args.json {
        println!("{}", summary.to_json());
    } else {
        print!("{}", summary.to_text());
    }
    if !summary.unsound.is_empty() {
        return Err(Failure::Run(format!(
            "{}: the result cannot be trusted: {}",
            args.scene.display(),
            summary.unsound.join("; ")
        )));
    }
    if !result.converged {
        let what = if summary.verdict.starts_with("NO ANSWER") {
            "the drawing has no answer"
        } else {
            "the drawing did not converge"
        };
        return Err(Failure::Run(format!(
            "{}: {what}: {}",
            args.scene.display(),
            result
                .failure
                .as_ref()
                .map_or("no cause given".to_string(), |f| f.to_string())
        )));
    }
    Ok(())
}

/// A progress bar of `len` on stderr in the indicatif `template`; hidden when stderr is not a
/// terminal.
fn stderr_bar(len: u64, template: &str) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style);
    }
    bar
}

/// A progress bar of the punch stroke on stderr, drawn only when stderr is a terminal.
fn stroke_bar(stroke_mm: f64) -> ProgressBar {
    let bar = stderr_bar(1000, "{spinner} [{elapsed_precise}] {bar:40} {msg}");
    if bar.is_hidden() {
        return bar;
    }
    bar.set_message(format!("stroke 0.00 of {stroke_mm} mm"));
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    bar
}

impl From<SweepError> for Failure {
    fn from(e: SweepError) -> Failure {
        match e {
            SweepError::BadInput(m) => Failure::BadInput(m),
            SweepError::Run(m) => Failure::Run(m),
        }
    }
}

/// `wovenform sweep`: the grid in parallel, a progress bar, the table at the end.
fn sweep_cmd(args: SweepArgs) -> Result<(), Failure> {
    let shard = args
        .shard
        .as_deref()
        .map(|s| s.parse::<Shard>())
        .transpose()
        .map_err(Failure::BadInput)?;
    let plan = Plan::load(&args.sweep, &with_accuracy(args.accuracy, &args.set))?;
    let options = sweep::Options {
        jobs: args.jobs,
        shard,
        resume: args.resume,
        ..sweep::Options::default()
    };
    let terminal = std::io::stderr().is_terminal();
    let bar = stderr_bar(
        0,
        "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} designs, {msg}, ETA {eta}",
    );
    bar.set_message("0 feasible");
    let progress = |p: Progress| match p {
        Progress::Start {
            to_run,
            kept,
            invalid,
        } => {
            if args.resume {
                bar.suspend(|| {
                    eprintln!(
                        "resume {}: {}; {} designs to run",
                        args.out.display(),
                        kept.describe(),
                        to_run + invalid
                    )
                });
            }
            bar.set_length((to_run + invalid) as u64);
            if terminal {
                bar.enable_steady_tick(std::time::Duration::from_millis(200));
            }
        }
        Progress::Done {
            row,
            done,
            total,
            feasible,
        } => {
            bar.set_position(done as u64);
            bar.set_message(format!("{feasible} feasible"));
            if !terminal {
                let shear = row
                    .max_shear_deg
                    .map(|s| format!(", max shear {s:.1}°"))
                    .unwrap_or_default();
                eprintln!(
                    "[{done}/{total}] {} {}{shear}",
                    row.design,
                    row.verdict.word()
                );
            }
        }
        Progress::Drawing { maps } => {
            bar.set_message(format!("drawing {maps} maps and the report"));
        }
    };
    let outcome = sweep::run(&plan, &args.out, &options, &progress);
    bar.finish_and_clear();
    let outcome = outcome?;
    print_outcome(&plan, &outcome);
    let per_min = if outcome.run_wall_s > 0.0 {
        60.0 * outcome.ran as f64 / outcome.run_wall_s
    } else {
        0.0
    };
    println!(
        "{} designs run in {:.1} s on {} threads ({per_min:.1} designs/min){}; {:.1} s in all",
        outcome.ran,
        outcome.run_wall_s,
        outcome.threads,
        if outcome.kept.kept > 0 {
            format!(", {} rows kept from before", outcome.kept.kept)
        } else {
            String::new()
        },
        outcome.wall_s
    );
    Ok(())
}

/// `wovenform merge`: shards of one sweep into one results set.
fn merge_cmd(args: MergeArgs) -> Result<(), Failure> {
    let (plan, outcome) = sweep::merge(&args.dirs, &args.out, args.jobs)?;
    eprintln!(
        "merged {} folders: {}",
        args.dirs.len(),
        outcome.kept.describe()
    );
    print_outcome(&plan, &outcome);
    Ok(())
}

/// The feasibility table, the counts and the files written.
fn print_outcome(plan: &Plan, outcome: &sweep::Outcome) {
    print!("{}", sweep::table(plan, &outcome.rows));
    let c = sweep::counts(&outcome.rows);
    println!();
    println!(
        "{} of {} designs: {} feasible, {} infeasible, {} failed, {} invalid{}",
        outcome.rows.len(),
        plan.len(),
        c.feasible,
        c.infeasible,
        c.failed,
        c.invalid,
        if outcome.missing > 0 {
            format!("; {} missing", outcome.missing)
        } else {
            String::new()
        }
    );
    for f in &outcome.files {
        println!("{}", f.display());
    }
}

/// The fields printed by `wovenform law` (N, mm).
#[derive(Serialize)]
struct LawOutput {
    t11: f64,
    t22: f64,
    w1: f64,
    w2: f64,
    closure: f64,
    dt11_de1: f64,
    dt11_de2: f64,
    dt22_de1: f64,
    dt22_de2: f64,
}

fn law(args: LawArgs) -> Result<(), Failure> {
    let scene = args.scene.load()?;
    let params = scene.to_cell_params();
    if args.curves {
        let out = args
            .out
            .as_deref()
            .expect("clap requires --out with --curves");
        let written = figure6::write_figure6(params, out).map_err(Failure::Run)?;
        for path in written {
            println!("{}", path.display());
        }
        return Ok(());
    }
    let strain = |name: &str, v: Option<f64>| -> Result<f64, Failure> {
        let v = v.expect("clap requires --eps1 and --eps2 without --curves");
        if (STRAIN_RANGE[0]..=STRAIN_RANGE[1]).contains(&v) {
            Ok(v)
        } else {
            Err(Failure::BadInput(format!(
                "--{name} = {v}: expected a strain in [{:.2}, {:.2}]",
                STRAIN_RANGE[0], STRAIN_RANGE[1]
            )))
        }
    };
    let eps = [strain("eps1", args.eps1)?, strain("eps2", args.eps2)?];
    let law = CellLaw::new(params);
    let r = law.evaluate(eps, law.initial_state());
    let w = r.w(&law);
    let out = LawOutput {
        t11: r.t[0],
        t22: r.t[1],
        w1: w[0],
        w2: w[1],
        closure: r.crimp.s,
        dt11_de1: r.dt[0][0],
        dt11_de2: r.dt[0][1],
        dt22_de1: r.dt[1][0],
        dt22_de2: r.dt[1][1],
    };
    let json = serde_json::to_string(&out).map_err(|e| Failure::Run(e.to_string()))?;
    println!("{json}");
    Ok(())
}

fn fit(args: FitArgs) -> Result<(), Failure> {
    let scene = args.scene.load()?;
    let samples = fitting::read_samples(&args.data).map_err(Failure::BadInput)?;
    let options = FitOptions {
        fit_c: args.fit_c,
        ..FitOptions::default()
    };
    let start = scene.to_cell_params();
    let result = fitting::fit(&samples, start, options).map_err(Failure::BadInput)?;
    let p = result.params;
    println!("fit of {}", args.data.display());
    println!("A = {:.6} mm", p.a);
    println!("B = {:.6} 1/N", p.b);
    let c_note = if args.fit_c { "" } else { " (fixed)" };
    if p.c[0] == p.c[1] {
        println!("C = {:.1} N{c_note}", p.c[0]);
    } else {
        println!("C = [{:.1}, {:.1}] N{c_note}", p.c[0], p.c[1]);
    }
    println!("RMS residual = {:.4} N", result.rms_n);
    println!("points = {}", result.points);
    println!("iterations = {}", result.iterations);
    let dir = match &args.out {
        Some(d) => d.clone(),
        None => match args.data.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        },
    };
    let png = write_fit_png(&dir, &samples, &result, &args.data).map_err(Failure::Run)?;
    println!("{}", png.display());
    if !result.converged {
        return Err(Failure::Run(format!(
            "the fit did not converge in {} iterations; the values above are the last iterate",
            result.iterations
        )));
    }
    Ok(())
}

fn write_fit_png(
    dir: &Path,
    samples: &[fitting::Sample],
    result: &fitting::FitResult,
    data: &Path,
) -> Result<PathBuf, String> {
    std::fs::create_dir_all(dir)
        .map_err(|e| format!("{}: cannot create the folder: {e}", dir.display()))?;
    let name = data
        .file_name()
        .unwrap_or(data.as_os_str())
        .to_string_lossy();
    let title = format!(
        "Fit of {name}: A = {:.4} mm, B = {:.3} 1/N, RMS {:.2} N",
        result.params.a, result.params.b, result.rms_n
    );
    let png = dir.join("fit.png");
    fitting::fit_chart(samples, result, &title).write_png(&png)?;
    Ok(png)
}

/// `wovenform bench`: law and element throughput, one thread.
fn bench(args: BenchArgs) -> Result<(), Failure> {
    use wovenform::bench as b;
    let reps = args.repetitions.max(1);
    let note = |what: &str| {
        if !args.json {
            eprintln!("measuring {what} …");
        }
    };
    note("the law and the element");
    let rates = [b::law_rate(reps), b::element_rate(reps)];
    let box_reps = reps.min(5);
    let mut drawings = Vec::new();
    for (name, problem) in b::cases() {
        note(&format!("the {name} at standard accuracy"));
        let run =
            b::drawing_run(&problem, box_reps).map_err(|e| Failure::Run(format!("{name}: {e}")))?;
        drawings.push((name, run));
    }
    note("wall time against dofs (5, 3.5, 2.5, 1.75 mm)");
    let (ladder, exponent) = b::dof_scaling(&[5.0, 3.5, 2.5, 1.75]);
    note("sweep throughput with 1 and 2 jobs");
    let one = b::sweep_throughput(1).map_err(Failure::Run)?;
    let two = b::sweep_throughput(2).map_err(Failure::Run)?;
    let friction = if args.friction {
        note("friction resolved within the step against lagged, on the open box");
        b::friction_resolution(box_reps.min(3))
    } else {
        Vec::new()
    };
    let report = wovenform::report::bench::BenchReport {
        reps,
        box_reps,
        rates,
        drawings,
        ladder,
        exponent,
        sweep_per_min: [one, two],
        friction,
    };
    if args.json {
        println!("{}", report.to_json());
    } else {
        print!("{}", report.to_text());
    }
    Ok(())
}
