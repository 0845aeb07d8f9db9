//! The command-line contract that scripts rely on: subcommands, options, their help.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

use wovenform::accuracy::Accuracy;

#[derive(Parser, Debug)]
#[command(
    name = "wovenform",
    version,
    about = "Deep drawing of woven fabrics: the paper's biaxial woven-cell law and its uses"
)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Option<Command>,
}

/// One variant per subcommand, each with its own `Args` struct and its own function in `main`.
#[derive(Subcommand, Debug)]
pub(crate) enum Command {
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
pub(crate) struct ConvergeArgs {
    /// Scene file (TOML).
    #[arg(value_name = "SCENE.toml")]
    pub(crate) scene: PathBuf,
    /// Override one scene key; VALUE is a TOML literal. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub(crate) set: Vec<String>,
    /// Output folder.
    #[arg(long, value_name = "DIR")]
    pub(crate) out: PathBuf,
    /// Element sizes of the mesh ladder, mm, coarse to fine (default: the scene's size times
    /// 2, √2, 1, 1/√2, 1/2).
    #[arg(long, value_delimiter = ',', value_name = "MM,MM,...")]
    pub(crate) sizes: Vec<f64>,
    /// Least load-step counts of the step ladder, few to many (default 4,8,16,32,64).
    #[arg(long, value_delimiter = ',', value_name = "N,N,...")]
    pub(crate) steps: Vec<u32>,
}

#[derive(Args, Debug)]
pub(crate) struct TuiArgs {
    /// Sweep file (TOML), as for `sweep`; default: the paper's box, tight and open radii.
    #[arg(value_name = "SWEEP.toml")]
    pub(crate) sweep: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub(crate) struct RunArgs {
    /// Scene file (TOML).
    #[arg(value_name = "SCENE.toml")]
    pub(crate) scene: PathBuf,
    /// Override one scene key; VALUE is a TOML literal, e.g. --set tools.r=7.5 or
    /// --set blank.size=[130,100]. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub(crate) set: Vec<String>,
    /// Output folder (default: out/<scene file stem>).
    #[arg(long, value_name = "DIR")]
    pub(crate) out: Option<PathBuf>,
    /// Print one JSON object instead of the text summary.
    #[arg(long)]
    pub(crate) json: bool,
    /// Accuracy level: coarse (5 mm elements), standard (2.5 mm) or fine (1.25 mm); sets
    /// mesh.element_size (a --set of it wins) and reports the level's measured error.
    #[arg(long, value_name = "LEVEL", value_parser = parse_accuracy)]
    pub(crate) accuracy: Option<Accuracy>,
}

#[derive(Args, Debug)]
pub(crate) struct SweepArgs {
    /// Sweep file (TOML): a base scene and a [sweep] table of parameters.
    #[arg(value_name = "SWEEP.toml")]
    pub(crate) sweep: PathBuf,
    /// Override one key of the base scene; VALUE is a TOML literal. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub(crate) set: Vec<String>,
    /// Output folder.
    #[arg(long, value_name = "DIR")]
    pub(crate) out: PathBuf,
    /// Designs run at once (default: every core).
    #[arg(long, value_name = "N")]
    pub(crate) jobs: Option<usize>,
    /// Run only the I-th of N slices of the grid (the designs whose index is I-1 modulo N).
    #[arg(long, value_name = "I/N")]
    pub(crate) shard: Option<String>,
    /// Continue a sweep in DIR: keep its rows for this base scene, run the missing designs.
    #[arg(long)]
    pub(crate) resume: bool,
    /// Accuracy level: coarse (5 mm elements), standard (2.5 mm) or fine (1.25 mm); sets
    /// mesh.element_size (a --set of it wins) and reports the level's measured error.
    #[arg(long, value_name = "LEVEL", value_parser = parse_accuracy)]
    pub(crate) accuracy: Option<Accuracy>,
}

#[derive(Args, Debug)]
pub(crate) struct MergeArgs {
    /// The output folders of the shards (of one sweep).
    #[arg(value_name = "DIR", required = true)]
    pub(crate) dirs: Vec<PathBuf>,
    /// Output folder for the combined results.
    #[arg(long, value_name = "DIR")]
    pub(crate) out: PathBuf,
    /// Maps drawn at once (default: every core).
    #[arg(long, value_name = "N")]
    pub(crate) jobs: Option<usize>,
}

#[derive(Args, Debug)]
pub(crate) struct BenchArgs {
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub(crate) json: bool,
    /// Repetitions per measurement (the median is reported).
    #[arg(long, default_value_t = 7)]
    pub(crate) repetitions: usize,
    /// Also compare ways of resolving friction within a load step (implicit with the exact or
    /// the symmetric Jacobian, lagged, lagged to a fixed point) on the open box.
    #[arg(long)]
    pub(crate) friction: bool,
}

pub(crate) fn parse_accuracy(text: &str) -> Result<Accuracy, String> {
    Accuracy::parse(text)
}

/// The overrides of an accuracy level, before the user's own (which win).
pub(crate) fn with_accuracy(level: Option<Accuracy>, set: &[String]) -> Vec<String> {
    let mut all = level.map(|a| a.overrides()).unwrap_or_default();
    all.extend_from_slice(set);
    all
}

/// The scene options shared by the subcommands that read a scene.
#[derive(Args, Debug, Clone, Default)]
pub(crate) struct SceneArgs {
    /// Scene file (TOML); without it, the embedded default (the paper's glass fabric).
    #[arg(long, value_name = "SCENE.toml")]
    pub(crate) scene: Option<PathBuf>,
    /// Override one scene key; VALUE is a TOML literal, e.g. --set fabric.a=0.05 or
    /// --set fabric.l0=[5.0,4.0]. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub(crate) set: Vec<String>,
}

#[derive(Args, Debug)]
pub(crate) struct LawArgs {
    /// Warp strain ε11 (in [-0.05, 0.10]).
    #[arg(
        long,
        allow_negative_numbers = true,
        required_unless_present = "curves"
    )]
    pub(crate) eps1: Option<f64>,
    /// Weft strain ε22 (in [-0.05, 0.10]).
    #[arg(
        long,
        allow_negative_numbers = true,
        required_unless_present = "curves"
    )]
    pub(crate) eps2: Option<f64>,
    /// Write the paper's Figure 6 (figure6.csv, figure6.png) into --out instead.
    #[arg(long, conflicts_with_all = ["eps1", "eps2"], requires = "out")]
    pub(crate) curves: bool,
    /// Output folder for --curves.
    #[arg(long, value_name = "DIR")]
    pub(crate) out: Option<PathBuf>,
    #[command(flatten)]
    pub(crate) scene: SceneArgs,
}

#[derive(Args, Debug)]
pub(crate) struct FitArgs {
    /// Measured curves: CSV with header eps1,eps2,t11,t22 (strains, tensions per yarn in N).
    #[arg(value_name = "DATA.csv")]
    pub(crate) data: PathBuf,
    /// Also identify the yarn stiffness C (one value for both yarns).
    #[arg(long)]
    pub(crate) fit_c: bool,
    /// Folder for fit.png (default: the folder of DATA.csv).
    #[arg(long, value_name = "DIR")]
    pub(crate) out: Option<PathBuf>,
    #[command(flatten)]
    pub(crate) scene: SceneArgs,
}
