//! `wovenform frontier SWEEP.toml --along KEY --out DIR`: for every combination of the sweep's
//! other axes, where along KEY the verdict changes, by a root search; each run a row of
//! `results.csv` in DIR as in a sweep; then `frontier.csv`, `frontier.json`, `frontier.png`
//! and the table (or the JSON with `--json`).

use std::io::IsTerminal;
use std::path::PathBuf;

use clap::Args;

use super::progress::stderr_bar;
use super::scene_args::GridArgs;
use super::{CliError, outputs};
use wovenform::accuracy::Accuracy;
use wovenform::files::Input;
use wovenform::publish;
use wovenform::report::frontier::{frontier_json, runs_line, table};
use wovenform::report::plural;
use wovenform::study::frontier::{self, Frontier, Lattice, Progress};
use wovenform::study::sweep::{Plan, Shard};

#[derive(Args, Debug)]
pub struct FrontierArgs {
    #[command(flatten)]
    pub grid: GridArgs,
    /// The number axis to search along: a short name (r, rp, rm, friction,
    /// holder_pressure) or a scene key swept in the file with two or more numbers.
    #[arg(long, value_name = "KEY")]
    pub along: String,
    /// Output folder: results.csv (a row per run, as a sweep's), the fields, frontier.*.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Runs at once (default: every core).
    #[arg(long, value_name = "N")]
    pub jobs: Option<usize>,
    /// Search only the I-th of N slices of the combinations (those numbered I-1 modulo N).
    #[arg(long, value_name = "I/N")]
    pub shard: Option<Shard>,
    /// Continue in DIR: reuse its rows (of this frontier, or of a sweep of the same base
    /// scene whose designs are on the lattice), run only what is missing.
    #[arg(long)]
    pub resume: bool,
    /// Print frontier.json on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
}

pub fn exec(args: FrontierArgs) -> Result<(), CliError> {
    let plan = args.grid.plan()?;
    let lattice = Lattice::new(&plan, &args.along)?;
    check_outputs(&plan, &args)?;
    let found = search_with_progress(&lattice, &args)?;
    let level = Accuracy::of_element_size(plan.base_scene.mesh.element_size).map(|a| a.name());
    let files = publish::write_frontier(&found, &args.out, level)
        .map_err(|e| CliError::failed(e.to_string()))?;
    if args.json {
        print!("{}", frontier_json(&found, level));
        return Ok(());
    }
    print!("{}", table(&found));
    println!("{}", runs_line(&found));
    for f in files {
        println!("{}", f.display());
    }
    Ok(())
}

/// The search, announced on stderr with a bar of its runs (a line per run off a terminal).
fn search_with_progress(lattice: &Lattice, args: &FrontierArgs) -> Result<Frontier, CliError> {
    let combos = (0..lattice.combos.len())
        .filter(|c| args.shard.is_none_or(|s| s.contains(*c)))
        .count();
    eprintln!(
        "frontier along {}: {combos} combination{} of the other axes, {} values of {} each in \
         the grid; searching on a lattice of {}",
        lattice.searched().column,
        plural(combos),
        lattice.grid_values,
        lattice.searched().column,
        lattice.len()
    );
    let bar = stderr_bar(
        2 * combos as u64,
        "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} runs, {msg}",
    );
    let terminal = std::io::stderr().is_terminal();
    if terminal {
        bar.enable_steady_tick(std::time::Duration::from_millis(200));
    }
    let progress = |p: Progress| show_progress(&bar, terminal, p);
    let options = frontier::Options {
        jobs: args.jobs,
        shard: args.shard,
        resume: args.resume,
        stop: None,
    };
    let found = frontier::search(lattice, &args.out, &options, &progress);
    bar.finish_and_clear();
    Ok(found?)
}

/// One step of the search on the bar, and as a line when stderr is no terminal.
fn show_progress(bar: &indicatif::ProgressBar, terminal: bool, p: Progress) {
    match p {
        Progress::Round {
            round,
            to_run,
            kept,
            searching,
        } => {
            bar.set_length(bar.position() + to_run as u64);
            let msg = format!(
                "round {round}: {searching} combination{} searching",
                plural(searching)
            );
            if !terminal {
                eprintln!("{msg}: {to_run} to run, {kept} found from before");
            }
            bar.set_message(msg);
        }
        Progress::Done { row, done } => {
            bar.set_position(done as u64);
            if !terminal {
                eprintln!("[{done}] {} {}", row.design, row.verdict.word());
            }
        }
    }
}

/// Refuses an output folder where the frontier's files would overwrite its inputs.
fn check_outputs(plan: &Plan, args: &FrontierArgs) -> Result<(), CliError> {
    let base = plan.base_file.as_deref().map(std::path::Path::new);
    let mut inputs = outputs::scene_inputs(base, &plan.base_scene);
    inputs.push(Input::new(&args.grid.sweep, "the sweep file"));
    let names = [&publish::SWEEP_FILES[..], &publish::FRONTIER_FILES[..]].concat();
    let files = outputs::in_dir(&args.out, &names);
    wovenform::files::check_outputs(&files, &inputs).map_err(|e| CliError::bad_input(e.to_string()))
}
