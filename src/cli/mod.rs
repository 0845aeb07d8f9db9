//! The command line that scripts rely on: one file per subcommand, each with its options (a
//! clap `Args` struct) and its `exec`; what they share (the scene options, the accuracy
//! level, progress bars) and the one error type that carries the exit code.
//!
//! Exit codes: 0 success, 1 a failed run, 2 bad input (the message on stderr names the file or
//! option, the key and what was expected). Clap's own usage errors also exit with 2.

mod bench;
mod bias;
mod cantilever;
mod converge;
mod error;
mod fit;
mod fit_bias;
mod frontier;
mod law;
mod merge;
mod outputs;
mod progress;
mod run;
mod scene_args;
mod slurm;
mod sweep;
mod tools;
mod tui;

use clap::{Parser, Subcommand};

pub use error::CliError;

#[derive(Parser, Debug)]
#[command(
    name = "wovenform",
    version,
    about = "Deep drawing of woven fabrics: the paper's biaxial woven-cell law and its uses"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// One variant per subcommand, each with its own `Args` struct and `exec` in its own file.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Draw one scene: solve, print a summary (or one JSON object with --json) and write
    /// summary.json, shear.png, tension.png (seen from above), shear_developed.png and
    /// tension_developed.png (on the flat blank) and result.vtu into --out.
    Run(run::RunArgs),
    /// Run a grid of designs in parallel: results.csv (a row as each design finishes),
    /// results.json, maps/<design>.png on one colour scale, report.png and a feasibility table.
    Sweep(sweep::SweepArgs),
    /// For every combination of a sweep's other axes, where along one number axis (--along r)
    /// the verdict changes, by a root search on the governing figure minus its limit: each
    /// boundary with its interval (the MARGINAL zone and the search's tolerance), in a few
    /// runs of the grid's; writes frontier.csv, frontier.json, frontier.png and each run as a
    /// row of results.csv (so --resume, --shard and merge work as for a sweep).
    Frontier(frontier::FrontierArgs),
    /// Combine the output folders of one sweep's shards into one results set and report.
    Merge(merge::MergeArgs),
    /// Evaluate the biaxial woven-cell law at one strain pair (one JSON object), or draw the
    /// paper's Figure 6 with --curves.
    Law(law::LawArgs),
    /// Identify A and B (and C with --fit-c) from measured biaxial tension curves, or the
    /// shear law from a bias-extension curve (--bias HxW).
    Fit(fit::FitArgs),
    /// The bias-extension test of a scene's fabric (with `fabric.shear_moment`; the scene's
    /// numerics are used too): an H × W specimen, yarns at ±45°, pulled by D mm; writes
    /// bias.csv, bias.png and the shear map.
    Bias(bias::BiasArgs),
    /// The heavy cantilever of a scene's fabric (with `fabric.bending_rigidity` and
    /// `fabric.areal_mass`): a strip bent by its own weight (Peirce; ASTM D1388); the tip's
    /// deflection and angles and the rigidity Peirce's formula reads from them.
    Cantilever(cantilever::CantileverArgs),
    /// Measure throughput on this machine (one thread; medians of several repetitions).
    Bench(bench::BenchArgs),
    /// Solve a scene on a ladder of mesh sizes and of load-step counts: each rung's error
    /// against a Richardson extrapolation, next to its run time (converge.csv, converge.png).
    Converge(converge::ConvergeArgs),
    /// Write the scene's punch and die as closed triangle surfaces: punch.stl and die.stl
    /// (binary STL, mm) in --out, tessellated on a grid of --spacing mm.
    Tools(tools::ToolsArgs),
    /// A sweep as a Slurm job array (a resumable shard per task) and a merge job after it.
    Slurm(slurm::SlurmArgs),
    /// The terminal explorer on a sweep file (without one: the paper's square box). Also what
    /// `wovenform` alone opens in a terminal.
    Tui(tui::TuiArgs),
}

/// Runs the command line (no subcommand: the explorer in a terminal, else an overview).
pub fn exec(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        None => tui::exec_default(),
        Some(Command::Tui(args)) => tui::exec(args),
        Some(Command::Converge(args)) => converge::exec(args),
        Some(Command::Run(args)) => run::exec(args),
        Some(Command::Sweep(args)) => sweep::exec(args),
        Some(Command::Frontier(args)) => frontier::exec(args),
        Some(Command::Merge(args)) => merge::exec(args),
        Some(Command::Law(args)) => law::exec(args),
        Some(Command::Fit(args)) => fit::exec(args),
        Some(Command::Bias(args)) => bias::exec(args),
        Some(Command::Cantilever(args)) => cantilever::exec(args),
        Some(Command::Bench(args)) => bench::exec(args),
        Some(Command::Tools(args)) => tools::exec(args),
        Some(Command::Slurm(args)) => slurm::exec(args),
    }
}
