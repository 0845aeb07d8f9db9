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

use wovenform::accuracy::Accuracy;
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
    /// Solve a scene on a ladder of mesh sizes and of load-step counts: each rung's error
    /// against a Richardson extrapolation, next to its run time (converge.csv, converge.png).
    Converge(ConvergeArgs),
    /// The terminal explorer on a sweep file (without one: the paper's square box). Also what
    /// `wovenform` alone opens in a terminal.
    Tui(TuiArgs),
}

#[derive(Args, Debug)]
struct ConvergeArgs {
    /// Scene file (TOML).
    #[arg(value_name = "SCENE.toml")]
    scene: PathBuf,
    /// Override one scene key; VALUE is a TOML literal. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Output folder.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Element sizes of the mesh ladder, mm, coarse to fine (default: the scene's size times
    /// 2, √2, 1, 1/√2, 1/2).
    #[arg(long, value_delimiter = ',', value_name = "MM,MM,...")]
    sizes: Vec<f64>,
    /// Least load-step counts of the step ladder, few to many (default 4,8,16,32,64).
    #[arg(long, value_delimiter = ',', value_name = "N,N,...")]
    steps: Vec<u32>,
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
    /// Accuracy level: coarse (5 mm elements), standard (2.5 mm) or fine (1.25 mm); sets
    /// mesh.element_size (a --set of it wins) and reports the level's measured error.
    #[arg(long, value_name = "LEVEL", value_parser = parse_accuracy)]
    accuracy: Option<Accuracy>,
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
    /// Accuracy level: coarse (5 mm elements), standard (2.5 mm) or fine (1.25 mm); sets
    /// mesh.element_size (a --set of it wins) and reports the level's measured error.
    #[arg(long, value_name = "LEVEL", value_parser = parse_accuracy)]
    accuracy: Option<Accuracy>,
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
    /// Also compare ways of resolving friction within a load step (implicit with the exact or
    /// the symmetric Jacobian, lagged, lagged to a fixed point) on the open box.
    #[arg(long)]
    friction: bool,
}

fn parse_accuracy(text: &str) -> Result<Accuracy, String> {
    Accuracy::parse(text)
}

/// The overrides of an accuracy level, before the user's own (which win).
fn with_accuracy(level: Option<Accuracy>, set: &[String]) -> Vec<String> {
    let mut all = level.map(|a| a.overrides()).unwrap_or_default();
    all.extend_from_slice(set);
    all
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
    use wovenform::converge::{self as study, FIGURES};
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

    let mut csv = String::from(
        "ladder,element_size_mm,max_step,dofs,steps,newton_iterations,wall_s,converged,max_shear_deg,punch_force_n,draw_in_mm,max_tension_n,err_max_shear_deg,err_punch_force_pct,err_draw_in_mm,err_max_tension_pct\n",
    );
    println!(
        "{:<6} {:>7} {:>6} {:>6} {:>5} {:>6} {:>8}  {:>9} {:>8} {:>8} {:>8}   errors: {:>7} {:>7} {:>7} {:>7}",
        "ladder",
        "h mm",
        "Δλ",
        "dofs",
        "steps",
        "Newton",
        "wall s",
        "shear °",
        "force N",
        "draw mm",
        "T N",
        "shear °",
        "force %",
        "draw mm",
        "T %"
    );
    for ladder in [&mesh, &steps] {
        for (i, r) in ladder.rungs.iter().enumerate() {
            let e: Vec<f64> = (0..FIGURES.len()).map(|k| ladder.error(i, k)).collect();
            let f = r.figures;
            csv.push_str(&format!(
                "{},{},{},{},{},{},{:.3},{},{:.4},{:.2},{:.4},{:.2},{:.4},{:.3},{:.4},{:.3}\n",
                r.ladder,
                r.element_size_mm,
                r.max_step,
                r.dofs,
                r.steps,
                r.newton_iterations,
                r.wall_s,
                r.converged,
                f[0],
                f[1],
                f[2],
                f[3],
                e[0],
                e[1],
                e[2],
                e[3]
            ));
            println!(
                "{:<6} {:>7} {:>6.4} {:>6} {:>5} {:>6} {:>8.2}  {:>9.3} {:>8.1} {:>8.3} {:>8.1}           {:>7.3} {:>7.2} {:>7.3} {:>7.2}{}",
                r.ladder,
                r.element_size_mm,
                r.max_step,
                r.dofs,
                r.steps,
                r.newton_iterations,
                r.wall_s,
                f[0],
                f[1],
                f[2],
                f[3],
                e[0],
                e[1],
                e[2],
                e[3],
                if r.converged {
                    ""
                } else {
                    "  (did not converge)"
                }
            );
        }
        let refs: Vec<String> = FIGURES
            .iter()
            .zip(&ladder.reference)
            .map(|(name, r)| match r.order {
                Some(p) => format!("{name} {:.4} (Richardson, order {p:.2})", r.value),
                None => format!("{name} {:.4} (the finest rung)", r.value),
            })
            .collect();
        println!(
            "reference of the {} ladder: {}",
            ladder.rungs[0].ladder,
            refs.join("; ")
        );
    }
    // The accuracy levels, where the mesh ladder has their element sizes.
    for level in wovenform::accuracy::Accuracy::ALL {
        if let Some(i) = mesh
            .rungs
            .iter()
            .position(|r| (r.element_size_mm - level.element_size_mm()).abs() < 1e-9)
        {
            println!(
                "{level} ({} mm): max shear error {:.2}°, punch force error {:.2} %, {:.2} s on one core",
                level.element_size_mm(),
                mesh.error(i, 0),
                mesh.error(i, 1),
                mesh.rungs[i].wall_s
            );
        }
    }
    println!(
        "\nerror against wall time (S, F: the mesh ladder's max shear in °, punch force in %; \
         s, f: the step ladder's)\n{}",
        wovenform::report::converge::text_chart(&mesh, &steps, 60, 14)
    );
    let csv_path = args.out.join("converge.csv");
    std::fs::write(&csv_path, csv)
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
    let open = &drawings[0].1;
    if args.json {
        let run_json = |name: &str, r: &b::BoxRun| {
            serde_json::json!({
                "name": name, "wall_s": r.wall_s, "dofs": r.dofs, "steps": r.steps,
                "newton_iterations": r.newton_iterations,
                "newton_iterations_per_step": r.iterations_per_step(),
                "krylov_iterations": r.krylov_iterations,
                "newton_iteration_s": r.iteration_s(),
                "assembly_with_tangent_s": r.assembly_s, "contact_with_blocks_s": r.contact_s,
                "bare_factor_solve_s": r.bare_factor_solve_s,
                "iteration_over_factor_solve": r.iteration_over_factor_solve(),
                "max_shear_deg": r.max_shear_deg, "max_tension_n": r.max_tension_n,
                "punch_force_n": r.punch_force_n,
            })
        };
        let obj = serde_json::json!({
            "law_evals_per_s": rates[0].per_second,
            "element_evals_per_s": rates[1].per_second,
            "open_box_standard_wall_s": open.wall_s,
            "open_box_dofs": open.dofs,
            "open_box_steps": open.steps,
            "open_box_newton_iterations": open.newton_iterations,
            "open_box_krylov_iterations": open.krylov_iterations,
            "newton_iteration_s": open.iteration_s(),
            "bare_factor_solve_s": open.bare_factor_solve_s,
            "iteration_over_factor_solve": open.iteration_over_factor_solve(),
            "tight_box_standard_wall_s": drawings[1].1.wall_s,
            "open_box_friction_0_05_wall_s": drawings[2].1.wall_s,
            "drawings": drawings.iter().map(|(n, r)| run_json(n, r)).collect::<Vec<_>>(),
            "friction_resolution": friction.iter().map(|(n, r)| match r {
                Ok(r) => run_json(n, r),
                Err(e) => serde_json::json!({"name": n, "failure": e}),
            }).collect::<Vec<_>>(),
            "dof_ladder": ladder.iter().map(|(d, w)| serde_json::json!({"dofs": d, "wall_s": w})).collect::<Vec<_>>(),
            "wall_dof_exponent": exponent,
            "sweep_designs_per_min": {"jobs_1": one, "jobs_2": two},
            "repetitions": reps,
        });
        println!("{obj}");
        return Ok(());
    }
    println!(
        "one thread unless stated; medians of {reps} repetitions (the drawings: of {box_reps})"
    );
    for r in &rates {
        let lo = r.samples.iter().cloned().fold(f64::INFINITY, f64::min);
        let hi = r.samples.iter().cloned().fold(0.0, f64::max);
        println!(
            "{:<48} {:>12.3e} /s  (range {lo:.2e} to {hi:.2e})",
            r.name, r.per_second
        );
    }
    let ms = |s: f64| s * 1e3;
    for (name, run) in &drawings {
        println!(
            "{:<48} {:>12.3} s   (standard, 2.5 mm: {} dofs, {} steps, {} Newton iterations, {:.1} a step; range {:.2} to {:.2} s)",
            format!("{name}, whole run"),
            run.wall_s,
            run.dofs,
            run.steps,
            run.newton_iterations,
            run.iterations_per_step(),
            run.samples.iter().cloned().fold(f64::INFINITY, f64::min),
            run.samples.iter().cloned().fold(0.0, f64::max)
        );
    }
    println!(
        "{:<48} {:>12.3} ms  (the open box's run over its iterations; on its final state: an assembly with the tangent {:.3} ms, of it the contact {:.3} ms; {} GMRES iterations in the run)",
        "one Newton iteration",
        ms(open.iteration_s()),
        ms(open.assembly_s),
        ms(open.contact_s),
        open.krylov_iterations
    );
    println!(
        "{:<48} {:>12.2}   (bare factorization + solve of the last tangent: {:.3} ms)",
        "Newton iteration / bare factorization + solve",
        open.iteration_over_factor_solve(),
        ms(open.bare_factor_solve_s)
    );
    let pts: Vec<String> = ladder
        .iter()
        .map(|(d, w)| format!("{d} dofs {w:.2} s"))
        .collect();
    println!(
        "{:<48} {:>12.2}   ({})",
        "wall time ∝ dofs^k, k =",
        exponent,
        pts.join(", ")
    );
    println!(
        "{:<48} {:>12.1} /min with 1 job, {:.1} /min with 2 jobs (speed-up {:.2})",
        "sweep throughput (8 box designs, coarse)",
        one,
        two,
        two / one
    );
    if !friction.is_empty() {
        println!(
            "\nfriction's normal force and direction, open box at standard (medians of {}):",
            box_reps.min(3)
        );
        println!(
            "  {:<36} {:>7} {:>6} {:>7} {:>9} {:>10} {:>9} {:>9}",
            "resolved", "wall s", "steps", "Newton", "GMRES", "force N", "tension N", "shear °"
        );
        for (name, run) in &friction {
            match run {
                Ok(r) => println!(
                    "  {name:<36} {:>7.2} {:>6} {:>7} {:>9} {:>10.1} {:>9.1} {:>9.2}",
                    r.wall_s,
                    r.steps,
                    r.newton_iterations,
                    r.krylov_iterations,
                    r.punch_force_n,
                    r.max_tension_n,
                    r.max_shear_deg
                ),
                Err(e) => println!("  {name:<36} failed: {e}"),
            }
        }
    }
    Ok(())
}
