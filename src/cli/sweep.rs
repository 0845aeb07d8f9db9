//! `wovenform sweep SWEEP.toml --out DIR`: the grid in parallel with a progress bar, then the
//! maps, the report sheet, `results.json` and the feasibility table.

use std::io::IsTerminal;
use std::path::PathBuf;

use clap::Args;
use indicatif::ProgressBar;

use super::progress::stderr_bar;
use super::scene_args::GridArgs;
use super::{CliError, outputs};
use wovenform::files::Input;
use wovenform::publish;
use wovenform::report::plural;
use wovenform::report::sweep::table;
use wovenform::study::sweep::{self, Outcome, Plan, Progress, Shard, counts};

#[derive(Args, Debug)]
pub struct SweepArgs {
    #[command(flatten)]
    pub grid: GridArgs,
    /// Output folder.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Designs run at once (default: every core).
    #[arg(long, value_name = "N")]
    pub jobs: Option<usize>,
    /// Run only the I-th of N slices of the grid (the designs whose index is I-1 modulo N).
    #[arg(long, value_name = "I/N")]
    pub shard: Option<Shard>,
    /// Continue a sweep in DIR: keep its rows for this base scene, run the missing designs.
    #[arg(long)]
    pub resume: bool,
}

pub fn exec(args: SweepArgs) -> Result<(), CliError> {
    let plan = args.grid.plan()?;
    check_outputs(&plan, &args)?;
    let jobs = workers(&plan, args.jobs);
    let options = sweep::Options {
        jobs,
        shard: args.shard,
        resume: args.resume,
        ..sweep::Options::default()
    };
    let start = std::time::Instant::now();
    let bar = stderr_bar(
        0,
        "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} designs, {msg}, ETA {eta}",
    );
    bar.set_message("0 feasible");
    let per_design_s = wovenform::study::estimate::run_seconds(&plan.base_scene);
    let workers = jobs.unwrap_or_else(sweep::cores);
    let progress = |p: Progress| show_progress(&bar, &args, p, per_design_s, workers);
    let outcome = sweep::run(&plan, &args.out, &options, &progress);
    let mut outcome = outcome.inspect_err(|_| bar.finish_and_clear())?;
    let maps = outcome.rows.iter().filter(|r| r.map.is_some()).count();
    bar.set_message(format!("drawing {maps} maps and the report"));
    let pool = sweep::pool(jobs)?;
    let drawn = publish::sweep_report(&plan, &args.out, &outcome.rows, args.shard, &pool);
    bar.finish_and_clear();
    outcome.files = drawn?;
    outcome.wall_s = start.elapsed().as_secs_f64();
    print_outcome(&plan, &outcome);
    println!("{}", ran_line(&outcome));
    Ok(())
}

/// The workers for `--jobs`: no more than designs or cores (more would only start idle or
/// competing threads), said when fewer than asked.
fn workers(plan: &Plan, asked: Option<usize>) -> Option<usize> {
    let cores = sweep::cores();
    let used = asked.map(|j| sweep::workers_for(j, plan.len()));
    if let (Some(asked), Some(used)) = (asked, used)
        && used < asked
    {
        eprintln!(
            "--jobs {asked}: {} design{} on {cores} core{}, so {used} worker{}",
            plan.len(),
            plural(plan.len()),
            plural(cores),
            plural(used)
        );
    }
    used
}

/// How many designs ran, how fast, and the whole call's time.
fn ran_line(outcome: &Outcome) -> String {
    let per_min = if outcome.run_wall_s > 0.0 {
        60.0 * outcome.ran as f64 / outcome.run_wall_s
    } else {
        0.0
    };
    let kept = if outcome.kept.kept > 0 {
        format!(", {} rows kept from before", outcome.kept.kept)
    } else {
        String::new()
    };
    format!(
        "{} design{} run in {:.1} s on {} thread{} ({per_min:.1} designs/min){kept}; {:.1} s in all",
        outcome.ran,
        plural(outcome.ran),
        outcome.run_wall_s,
        outcome.threads,
        plural(outcome.threads),
        outcome.wall_s
    )
}

/// The progress of a sweep on the bar (on a terminal) or a line per design (in a log).
fn show_progress(
    bar: &ProgressBar,
    args: &SweepArgs,
    p: Progress,
    per_design_s: f64,
    workers: usize,
) {
    let terminal = std::io::stderr().is_terminal();
    match p {
        Progress::Start {
            to_run,
            kept,
            invalid,
            note,
        } => {
            if let Some(note) = note {
                bar.suspend(|| eprintln!("{note}"));
            }
            let n = to_run + invalid;
            if args.resume {
                bar.suspend(|| {
                    eprintln!(
                        "resume {}: {}; {n} designs to run",
                        args.out.display(),
                        kept.describe(),
                    )
                });
            }
            let threads = workers.min(to_run.max(1));
            let estimate = per_design_s * to_run as f64 / threads as f64;
            bar.suspend(|| {
                eprintln!(
                    "{n} design{} to run, roughly {} on {threads} worker{} (about \
                     {per_design_s:.1} s a design at this mesh)",
                    plural(n),
                    duration(estimate),
                    plural(threads),
                )
            });
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
    }
}

/// The feasibility table, the counts and the files written.
pub fn print_outcome(plan: &Plan, outcome: &Outcome) {
    print!("{}", table(plan, &outcome.rows));
    let c = counts(&outcome.rows);
    println!();
    println!(
        "{} of {} designs: {} feasible, {} marginal, {} infeasible, {} failed, {} invalid{}",
        outcome.rows.len(),
        plan.len(),
        c.feasible,
        c.marginal,
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

/// A duration for people: seconds, minutes or hours.
fn duration(s: f64) -> String {
    if s < 1.0 {
        "under a second".to_string()
    } else if s < 90.0 {
        format!("{s:.0} s")
    } else if s < 5400.0 {
        format!("{:.0} min", s / 60.0)
    } else {
        format!("{:.1} h", s / 3600.0)
    }
}

/// Refuses an output folder where the sweep's files would overwrite its sweep file, its base
/// scene or its tools (the folder itself is checked by the sweep: another sweep's is refused).
fn check_outputs(plan: &Plan, args: &SweepArgs) -> Result<(), CliError> {
    let base = plan.base_file.as_deref().map(std::path::Path::new);
    let mut inputs = outputs::scene_inputs(base, &plan.base_scene);
    inputs.push(Input::new(&args.grid.sweep, "the sweep file"));
    let files = outputs::in_dir(&args.out, &wovenform::publish::SWEEP_FILES);
    wovenform::files::check_outputs(&files, &inputs).map_err(|e| CliError::bad_input(e.to_string()))
}
