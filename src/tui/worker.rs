//! Work off the interface thread: a sweep on worker threads and an export, reporting over a
//! channel.

use std::collections::HashSet;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::sync::mpsc::Sender;
use std::thread;

use crate::study::sweep::{self, Plan, Progress, Row};

use super::error::WorkError;

/// What the workers tell the interface.
#[derive(Debug)]
pub enum Message {
    /// The sweep starts: designs to run, rows kept from a stopped run of the same grid.
    Started { to_run: usize, kept: usize },
    /// A design finished (or was found invalid).
    Row(Box<Row>),
    /// The sweep ended: stopped on request or not; an error that ended it early.
    Finished {
        stopped: bool,
        wall_s: f64,
        error: Option<String>,
    },
    /// An export ended: the files written, or why not.
    Exported(Result<Vec<PathBuf>, WorkError>),
    /// A frontier's round starts: its runs to do.
    Round { to_run: usize },
    /// A frontier found its boundaries.
    Frontier(Box<crate::study::frontier::Frontier>),
    /// A design's own files (maps, VTU, summary) are written, or why not.
    Written {
        design: String,
        result: Result<Vec<PathBuf>, WorkError>,
    },
}

/// Starts `plan` into `dir` (resuming the rows already there); returns the stop flag.
pub fn start_sweep(
    plan: Plan,
    dir: PathBuf,
    resume: bool,
    only: Option<HashSet<String>>,
    tx: Sender<Message>,
) -> Arc<AtomicBool> {
    let stop = Arc::new(AtomicBool::new(false));
    let options = sweep::Options {
        jobs: None,
        shard: None,
        resume,
        stop: Some(stop.clone()),
        only,
    };
    thread::Builder::new()
        .name("explorer-sweep".into())
        .spawn(move || {
            let progress = |p: Progress| {
                let m = match p {
                    Progress::Start { to_run, kept, .. } => Message::Started {
                        to_run,
                        kept: kept.kept,
                    },
                    Progress::Done { row, .. } => Message::Row(Box::new(row.clone())),
                };
                let _ = tx.send(m);
            };
            let outcome = sweep::run(&plan, &dir, &options, &progress);
            let _ = tx.send(finished(outcome.map(|o| (o.stopped, o.run_wall_s))));
        })
        .expect("a thread can be started");
    stop
}

/// The end of a run: stopped on request or not and its wall time, or the error that ended it.
fn finished(outcome: Result<(bool, f64), sweep::SweepError>) -> Message {
    match outcome {
        Ok((stopped, wall_s)) => Message::Finished {
            stopped,
            wall_s,
            error: None,
        },
        Err(e) => Message::Finished {
            stopped: false,
            wall_s: 0.0,
            error: Some(e.to_string()),
        },
    }
}

/// Finds the boundary along `lattice`'s axis into `dir`: its runs reported as rows, each
/// round's count, then what it found; returns the stop flag.
pub fn start_frontier(
    lattice: crate::study::frontier::Lattice,
    dir: PathBuf,
    resume: bool,
    tx: Sender<Message>,
) -> Arc<AtomicBool> {
    use crate::study::frontier;
    let stop = Arc::new(AtomicBool::new(false));
    let options = frontier::Options {
        jobs: None,
        shard: None,
        resume,
        stop: Some(stop.clone()),
    };
    thread::Builder::new()
        .name("explorer-frontier".into())
        .spawn(move || {
            let progress = |p: frontier::Progress| {
                let m = match p {
                    frontier::Progress::Round { to_run, .. } => Message::Round { to_run },
                    frontier::Progress::Done { row, .. } => Message::Row(Box::new(row.clone())),
                };
                let _ = tx.send(m);
            };
            let start = std::time::Instant::now();
            let outcome = frontier::search(&lattice, &dir, &options, &progress).map(|found| {
                let stopped = (found.lines.iter()).any(|l| l.found == frontier::Found::Stopped);
                let _ = tx.send(Message::Frontier(Box::new(found)));
                (stopped, start.elapsed().as_secs_f64())
            });
            let _ = tx.send(finished(outcome));
        })
        .expect("a thread can be started");
    stop
}

/// Writes the results of the run folders `from` as the headless sweep does (the CSV,
/// `results.json`, the maps on one scale and the report sheet): the first into `to`, each
/// other (designs re-run finer, a scene of their own) into `to/<its folder name>`.
pub fn start_export(from: Vec<PathBuf>, to: PathBuf, tx: Sender<Message>) {
    thread::Builder::new()
        .name("explorer-export".into())
        .spawn(move || {
            let one = |from: &PathBuf, to: &PathBuf| -> Result<Vec<PathBuf>, WorkError> {
                let (plan, outcome) = sweep::merge(std::slice::from_ref(from), to)?;
                let pool = sweep::pool(None)?;
                Ok(crate::publish::sweep_report(
                    &plan,
                    to,
                    &outcome.rows,
                    None,
                    &pool,
                )?)
            };
            let mut written = Vec::new();
            let mut result = Ok(());
            for (k, dir) in from.iter().enumerate() {
                let target = match (k, dir.file_name()) {
                    (0, _) | (_, None) => to.clone(),
                    (_, Some(name)) => to.join(name),
                };
                match one(dir, &target) {
                    Ok(files) => written.extend(files),
                    Err(e) => {
                        result = Err(e);
                        break;
                    }
                }
            }
            let _ = tx.send(Message::Exported(result.map(|()| written)));
        })
        .expect("a thread can be started");
}

/// Solves one design again as `wovenform run` does and writes its files into `dir`:
/// `shear.png`, `tension.png`, `result.vtu` and `summary.json`.
pub fn start_design_files(
    design: String,
    scene: crate::scene::Scene,
    dir: PathBuf,
    tx: Sender<Message>,
) {
    thread::Builder::new()
        .name("explorer-design-files".into())
        .spawn(move || {
            let mut drawn =
                crate::machine::on_pool(|| crate::study::draw::draw(&design, &scene, &mut |_| {}));
            let tooling = &drawn.problem.tooling;
            let written =
                crate::publish::write_run(&dir, &mut drawn.summary, &drawn.result, tooling)
                    .map_err(WorkError::from);
            let _ = tx.send(Message::Written {
                design,
                result: written,
            });
        })
        .expect("a thread can be started");
}
