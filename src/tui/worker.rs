//! Work off the interface thread: a sweep on worker threads and an export, reporting over a
//! channel.

use std::collections::HashSet;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::sync::mpsc::Sender;
use std::thread;

use crate::study::sweep::{self, Plan, Progress, Row};

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
    Exported(Result<Vec<PathBuf>, String>),
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
            let finished = match sweep::run(&plan, &dir, &options, &progress) {
                Ok(o) => Message::Finished {
                    stopped: o.stopped,
                    wall_s: o.run_wall_s,
                    error: None,
                },
                Err(e) => Message::Finished {
                    stopped: false,
                    wall_s: 0.0,
                    error: Some(e.to_string()),
                },
            };
            let _ = tx.send(finished);
        })
        .expect("a thread can be started");
    stop
}

/// Writes the results of the sweep folder `from` into `to` as the headless sweep does: the
/// CSV, `results.json`, the maps on one scale and the report sheet.
pub fn start_export(from: PathBuf, to: PathBuf, tx: Sender<Message>) {
    thread::Builder::new()
        .name("explorer-export".into())
        .spawn(move || {
            let result = sweep::merge(&[from], &to)
                .map_err(|e| e.to_string())
                .and_then(|(plan, outcome)| {
                    let pool = sweep::pool(None).map_err(|e| e.to_string())?;
                    crate::publish::sweep_report(&plan, &to, &outcome.rows, None, &pool)
                        .map_err(|e| e.to_string())
                });
            let _ = tx.send(Message::Exported(result));
        })
        .expect("a thread can be started");
}
