//! The command line: one thin function per subcommand.
//!
//! Exit codes: 0 success, 1 a failed run, 2 bad input (the message on stderr names the file or
//! option, the key and what was expected). Clap's own usage errors also exit with 2.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde::Serialize;

use wovenform::core::drawing;
use wovenform::core::law::{CellLaw, CellParams};
use wovenform::fit::{self as fitting, FitOptions, STRAIN_RANGE};
use wovenform::report::figure6;
use wovenform::report::summary::{self, RunSummary};
use wovenform::scene::{Override, Scene};
use wovenform::sweep::{self, Plan, Progress, Shard, SweepError};

#[derive(Parser, Debug)]
#[command(
    name = "wovenform",
    version,
    about = "Deep drawing of woven fabrics: the paper's biaxial woven-cell law and its uses"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

/// One variant per subcommand, each with its own `Args` struct and its own function in `main`.
#[derive(Subcommand, Debug)]
enum Command {
    /// Draw one scene: solve, print a summary (or one JSON object with --json) and write
    /// summary.json, shear.png, tension.png and result.vtu into --out.
    Run(RunArgs),
    /// Run a grid of designs in parallel: results.csv (a row as each design finishes),
    /// results.json, maps/<design>.png on one colour scale, report.png and a feasibility table.
    Sweep(SweepArgs),
    /// Combine the output folders of one sweep's shards into one results set and report.
    Merge(MergeArgs),
    /// Evaluate the biaxial woven-cell law at one strain pair (one JSON object), or draw the
    /// paper's Figure 6 with --curves.
    Law(LawArgs),
    /// Identify A and B (and C with --fit-c) from measured biaxial tension curves.
    Fit(FitArgs),
    /// Measure throughput on this machine (one thread; medians of several repetitions).
    Bench(BenchArgs),
    /// The terminal explorer on a sweep file (without one: the paper's square box). Also what
    /// `wovenform` alone opens in a terminal.
    Tui(TuiArgs),
}

#[derive(Args, Debug)]
struct TuiArgs {
    /// Sweep file (TOML), as for `sweep`; default: the paper's box, tight and open radii.
    #[arg(value_name = "SWEEP.toml")]
    sweep: Option<PathBuf>,
}

#[derive(Args, Debug)]
struct RunArgs {
    /// Scene file (TOML).
    #[arg(value_name = "SCENE.toml")]
    scene: PathBuf,
    /// Override one scene key; VALUE is a TOML literal, e.g. --set tools.r=7.5 or
    /// --set blank.size=[130,100]. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Output folder (default: out/<scene file stem>).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Print one JSON object instead of the text summary.
    #[arg(long)]
    json: bool,
}

#[derive(Args, Debug)]
struct SweepArgs {
    /// Sweep file (TOML): a base scene and a [sweep] table of parameters.
    #[arg(value_name = "SWEEP.toml")]
    sweep: PathBuf,
    /// Override one key of the base scene; VALUE is a TOML literal. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Output folder.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Designs run at once (default: every core).
    #[arg(long, value_name = "N")]
    jobs: Option<usize>,
    /// Run only the I-th of N slices of the grid (the designs whose index is I-1 modulo N).
    #[arg(long, value_name = "I/N")]
    shard: Option<String>,
    /// Continue a sweep in DIR: keep its rows for this base scene, run the missing designs.
    #[arg(long)]
    resume: bool,
}

#[derive(Args, Debug)]
struct MergeArgs {
    /// The output folders of the shards (of one sweep).
    #[arg(value_name = "DIR", required = true)]
    dirs: Vec<PathBuf>,
    /// Output folder for the combined results.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Maps drawn at once (default: every core).
    #[arg(long, value_name = "N")]
    jobs: Option<usize>,
}

#[derive(Args, Debug)]
struct BenchArgs {
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// Repetitions per measurement (the median is reported).
    #[arg(long, default_value_t = 7)]
    repetitions: usize,
}

/// The scene options shared by the subcommands that read a scene.
#[derive(Args, Debug, Clone, Default)]
struct SceneArgs {
    /// Scene file (TOML); without it, the embedded default (the paper's glass fabric).
    #[arg(long, value_name = "SCENE.toml")]
    scene: Option<PathBuf>,
    /// Override one scene key; VALUE is a TOML literal, e.g. --set fabric.a=0.05 or
    /// --set fabric.l0=[5.0,4.0]. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

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

#[derive(Args, Debug)]
struct LawArgs {
    /// Warp strain ε11 (in [-0.05, 0.10]).
    #[arg(
        long,
        allow_negative_numbers = true,
        required_unless_present = "curves"
    )]
    eps1: Option<f64>,
    /// Weft strain ε22 (in [-0.05, 0.10]).
    #[arg(
        long,
        allow_negative_numbers = true,
        required_unless_present = "curves"
    )]
    eps2: Option<f64>,
    /// Write the paper's Figure 6 (figure6.csv, figure6.png) into --out instead.
    #[arg(long, conflicts_with_all = ["eps1", "eps2"], requires = "out")]
    curves: bool,
    /// Output folder for --curves.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    #[command(flatten)]
    scene: SceneArgs,
}

#[derive(Args, Debug)]
struct FitArgs {
    /// Measured curves: CSV with header eps1,eps2,t11,t22 (strains, tensions per yarn in N).
    #[arg(value_name = "DATA.csv")]
    data: PathBuf,
    /// Also identify the yarn stiffness C (one value for both yarns).
    #[arg(long)]
    fit_c: bool,
    /// Folder for fit.png (default: the folder of DATA.csv).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    #[command(flatten)]
    scene: SceneArgs,
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
        set: args.set.clone(),
    }
    .load()?;
    let name = args
        .scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let problem = scene.to_problem();
    let bar = stroke_bar(problem.stroke);
    let result = drawing::solve(&problem, &mut |fraction| {
        bar.set_position((fraction * 1000.0).round() as u64);
        bar.set_message(format!(
            "stroke {:.2} of {} mm",
            fraction * problem.stroke,
            problem.stroke
        ));
    });
    bar.finish_and_clear();
    let mut summary = RunSummary::new(&name, &scene, &result);
    let dir = args.out.unwrap_or_else(|| Path::new("out").join(&name));
    summary::write_run(&dir, &mut summary, &result, &problem.tooling).map_err(Failure::Run)?;
    if args.json {
        println!("{}", summary.to_json());
    } else {
        print!("{}", summary.to_text());
    }
    if !result.converged {
        return Err(Failure::Run(format!(
            "{}: the drawing did not converge: {}",
            args.scene.display(),
            result.failure.as_deref().unwrap_or("no cause given")
        )));
    }
    Ok(())
}

/// A progress bar of the punch stroke on stderr, drawn only when stderr is a terminal.
fn stroke_bar(stroke_mm: f64) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(1000), ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template("{spinner} [{elapsed_precise}] {bar:40} {msg}")
    {
        bar.set_style(style);
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
    let plan = Plan::load(&args.sweep, &args.set)?;
    let options = sweep::Options {
        jobs: args.jobs,
        shard,
        resume: args.resume,
        ..sweep::Options::default()
    };
    let terminal = std::io::stderr().is_terminal();
    let bar = if terminal {
        let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} designs, {msg}, ETA {eta}",
        ) {
            bar.set_style(style);
        }
        bar.set_message("0 feasible");
        bar
    } else {
        ProgressBar::hidden()
    };
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
    let reps = args.repetitions.max(1);
    let rates = [
        wovenform::bench::law_rate(reps),
        wovenform::bench::element_rate(reps),
    ];
    if args.json {
        let obj = serde_json::json!({
            "law_evals_per_s": rates[0].per_second,
            "element_evals_per_s": rates[1].per_second,
            "repetitions": reps,
        });
        println!("{obj}");
    } else {
        for r in &rates {
            let lo = r.samples.iter().cloned().fold(f64::INFINITY, f64::min);
            let hi = r.samples.iter().cloned().fold(0.0, f64::max);
            println!(
                "{:<48} {:>12.3e} /s  (median of {reps}; range {lo:.2e} to {hi:.2e})",
                r.name, r.per_second
            );
        }
    }
    Ok(())
}
