//! Running a sweep: the designs of the grid (of the shard) without a row yet, in parallel,
//! each solved on one thread; a row appended to `results.csv` and a field file written as
//! each finishes, so that an interrupted sweep keeps what it did.

use std::collections::HashSet;
use std::fs;
use std::io::Write as _;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use rayon::prelude::*;

use super::SweepError;
use super::field::StoredField;
use super::folder_lock::FolderLock;
use super::grid::{Column, Design};
use super::plan::Plan;
use super::rows::Row;
use super::shard::Shard;
use super::store::{self, ReadReport};
use crate::core::drawing;
use crate::scene::Scene;
use crate::summary::RunSummary;
use crate::verdict::Verdict;

/// How to run a sweep.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Designs run at once (threads); `None`: every core.
    pub jobs: Option<usize>,
    pub shard: Option<Shard>,
    pub resume: bool,
    /// Set from another thread to stop: designs not started are left, running ones end at
    /// their next load step (their rows are not written, so a resume runs them again).
    pub stop: Option<Arc<AtomicBool>>,
    /// Run only these designs (by id), e.g. the marginal ones again at a finer level.
    pub only: Option<HashSet<String>>,
}

/// What a sweep reports while it runs.
#[derive(Debug)]
pub enum Progress<'a> {
    /// Before the first design: designs to run, rows kept from an earlier run, invalid designs.
    Start {
        to_run: usize,
        kept: &'a ReadReport,
        invalid: usize,
        /// A lock left by a sweep that no longer runs, taken over.
        note: Option<&'a str>,
    },
    /// A design finished (or was found invalid); counts over this run.
    Done {
        row: &'a Row,
        done: usize,
        total: usize,
        feasible: usize,
    },
}

/// What a sweep (or a merge) came to.
#[derive(Debug)]
pub struct Outcome {
    /// Every row of the folder, in grid order.
    pub rows: Vec<Row>,
    /// Designs of the grid (of this shard) without a row.
    pub missing: usize,
    /// Designs run now, and rows kept from before.
    pub ran: usize,
    pub kept: ReadReport,
    pub threads: usize,
    /// Wall time of the designs' runs (from the first start to the last finish), s.
    pub run_wall_s: f64,
    /// Wall time of the whole call, s.
    pub wall_s: f64,
    /// The files written.
    pub files: Vec<PathBuf>,
    /// Stopped on request before every design had run.
    pub stopped: bool,
    /// The output folder's lock: held while the outcome lives (the maps and the report are
    /// drawn into the folder after the run), let go when it is dropped.
    pub lock: Option<FolderLock>,
}

/// The cores of this machine (1 when it cannot be told).
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The designs run at once for `jobs` asked: no more than the designs or the cores (more
/// would only start idle or competing threads); 0 stays 0, which [`pool`] refuses.
pub fn workers_for(jobs: usize, designs: usize) -> usize {
    jobs.min(designs.max(1)).min(cores().max(1))
}

/// The threads that run designs (or draw maps) at once; `None`: every core.
pub fn pool(jobs: Option<usize>) -> Result<rayon::ThreadPool, SweepError> {
    if jobs == Some(0) {
        return Err(SweepError::BadInput(
            "--jobs 0: expected at least one design at a time".into(),
        ));
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.unwrap_or(0))
        .thread_name(|i| format!("sweep-{i}"))
        .build()
        .map_err(|e| SweepError::Run(format!("cannot start the worker threads: {e}")))
}

/// The rows writer: one line per design, written whole and flushed, under a mutex.
struct Sink<'a> {
    state: Mutex<SinkState>,
    progress: &'a (dyn Fn(Progress) + Sync),
    total: usize,
}

struct SinkState {
    file: fs::File,
    rows: Vec<Row>,
    feasible: usize,
    error: Option<String>,
    path: PathBuf,
}

impl<'a> Sink<'a> {
    /// A sink that appends rows to `file` (at `path`) and tells `progress`, of `total` rows.
    fn new(
        file: fs::File,
        path: PathBuf,
        progress: &'a (dyn Fn(Progress) + Sync),
        total: usize,
    ) -> Sink<'a> {
        Sink {
            state: Mutex::new(SinkState {
                file,
                rows: Vec::new(),
                feasible: 0,
                error: None,
                path,
            }),
            progress,
            total,
        }
    }

    /// Appends `row` and reports it; a row that cannot be written (a full disk) is not
    /// reported: the first such error is kept, and `failed` set so that the sweep stops.
    fn push(&self, row: Row, failed: &AtomicBool) {
        let mut s = self.state.lock().unwrap_or_else(|e| e.into_inner());
        if s.error.is_some() {
            return;
        }
        let line = row.to_csv();
        if let Err(e) = s
            .file
            .write_all(line.as_bytes())
            .and_then(|_| s.file.flush())
        {
            let msg = format!(
                "{}: cannot write the row of {}: {e}",
                s.path.display(),
                row.design
            );
            s.error = Some(msg);
            failed.store(true, Ordering::Relaxed);
            return;
        }
        if row.verdict == Verdict::Feasible {
            s.feasible += 1;
        }
        s.rows.push(row);
        let (done, feasible) = (s.rows.len(), s.feasible);
        (self.progress)(Progress::Done {
            row: s.rows.last().expect("just pushed"),
            done,
            total: self.total,
            feasible,
        });
    }
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        s.to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "no message".into()
    }
}

/// What every design of a run shares.
struct Job<'a> {
    plan: &'a Plan,
    columns: &'a [Column],
    /// The output folder.
    dir: &'a Path,
    stop: Option<&'a AtomicBool>,
    /// Set when a design's row or field could not be written (a full disk): the designs
    /// not started are left, the running ones stop, and the sweep ends with the error.
    failed: AtomicBool,
    /// Why a field could not be written, the first time.
    field_error: Mutex<Option<String>>,
}

impl<'a> Job<'a> {
    fn new(plan: &'a Plan, columns: &'a [Column], dir: &'a Path, options: &'a Options) -> Self {
        Job {
            plan,
            columns,
            dir,
            stop: options.stop.as_deref(),
            failed: AtomicBool::new(false),
            field_error: Mutex::new(None),
        }
    }

    fn stopped(&self) -> bool {
        self.failed.load(Ordering::Relaxed) || self.stop.is_some_and(|s| s.load(Ordering::Relaxed))
    }
}

/// Runs one valid design: solve (single-threaded), its field file, its row; `None` when
/// stopped on request before the end.
fn run_design(job: &Job, design: &Design, scene: &Scene) -> Option<Row> {
    let mut problem = scene.to_problem();
    problem.solver.parallel = false;
    let start = std::time::Instant::now();
    let result = drawing::solve_until(&problem, &mut |_| {
        if job.stopped() {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    if job.stopped() {
        return None;
    }
    let summary = RunSummary::new(&design.id, scene, &result, start.elapsed().as_secs_f64());
    let row = Row::from_summary(job.plan, job.columns, design, &summary);
    let field = StoredField::of_run(design, &summary, &result, &problem.tooling);
    // Without its field the row would be run again on a resume: the folder cannot take the
    // sweep's results (a full disk), so the sweep stops and says so.
    if let Err(e) = field.write(job.dir) {
        let mut first = job.field_error.lock().unwrap_or_else(|e| e.into_inner());
        first.get_or_insert(format!("the field of {}: {e}", design.id));
        job.failed.store(true, Ordering::Relaxed);
        return None;
    }
    Some(row)
}

/// Runs a sweep into `dir`: the designs of the grid (of the shard) without a row yet, in
/// parallel. The maps, the report sheet and `results.json` are drawn after, from the rows and
/// the fields (see [`crate::publish`]).
pub fn run(
    plan: &Plan,
    dir: &Path,
    options: &Options,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<Outcome, SweepError> {
    let start = Instant::now();
    let pool = pool(options.jobs)?;
    let columns = plan.columns();
    let designs = plan.designs();
    // Before any work: the folder's lock (held to the end), the earlier rows, the plan.
    let (lock, note) = FolderLock::take(dir)?;
    let (kept_rows, kept) = store::earlier_rows(plan, dir, options.resume)?;
    let file = store::open_rows(plan, dir, options.shard, &kept_rows, &kept.others)?;
    let have: HashSet<&str> = kept_rows.iter().map(|r| r.design.as_str()).collect();
    let kept_count = kept_rows.len();
    let wanted = |d: &Design| options.only.as_ref().is_none_or(|o| o.contains(&d.id));
    let mine = |index: usize| options.shard.is_none_or(|s| s.contains(index));
    let todo = designs
        .iter()
        .filter(|d| mine(d.index) && wanted(d) && !have.contains(d.id.as_str()));
    let (valid, invalid) = sort_valid(plan, &columns, todo, pool.current_num_threads());
    progress(Progress::Start {
        to_run: valid.len(),
        kept: &kept,
        invalid: invalid.len(),
        note: note.as_deref(),
    });
    let sink = Sink::new(
        file,
        dir.join("results.csv"),
        progress,
        valid.len() + invalid.len(),
    );
    let job = Job::new(plan, &columns, dir, options);
    for row in invalid {
        sink.push(row, &job.failed);
    }
    let run_start = Instant::now();
    pool.install(|| {
        valid.par_iter().with_max_len(1).for_each(|(d, scene)| {
            if let Some(row) = run_guarded(&job, d, scene) {
                sink.push(row, &job.failed);
            }
        });
    });
    let stopped = job.stopped();
    let run_wall_s = run_start.elapsed().as_secs_f64();
    let state = sink.state.into_inner().unwrap_or_else(|e| e.into_inner());
    let field_error = job
        .field_error
        .into_inner()
        .unwrap_or_else(|e| e.into_inner());
    let written = kept_count + state.rows.len();
    write_failure(state.error.or(field_error), written, dir)?;
    let ran = (state.rows.iter())
        .filter(|r| r.verdict != Verdict::Invalid)
        .count();
    let mut rows = kept_rows;
    rows.extend(state.rows);
    rows.sort_by_key(|r| r.index);
    let present = rows.iter().filter(|r| mine(r.index)).count();
    Ok(Outcome {
        missing: designs
            .iter()
            .filter(|d| mine(d.index) && wanted(d))
            .count()
            .saturating_sub(present),
        rows,
        ran,
        kept,
        threads: pool.current_num_threads(),
        run_wall_s,
        wall_s: start.elapsed().as_secs_f64(),
        files: vec![dir.join("results.csv")],
        stopped,
        lock: Some(lock),
    })
}

/// The error that stopped the sweep (a row or a field that could not be written), with what
/// was kept: `written` rows in `dir/results.csv`.
fn write_failure(error: Option<String>, written: usize, dir: &Path) -> Result<(), SweepError> {
    match error {
        None => Ok(()),
        Some(e) => Err(SweepError::Run(format!(
            "{e}; the sweep stopped there: the {written} rows written before are kept in {}, \
             and --resume runs the rest once the folder can be written",
            dir.join("results.csv").display()
        ))),
    }
}

/// The designs to run with their scenes, and the rows of those that break a bound of the
/// scene, or that would not fit in their share of the memory with `threads` designs at once.
fn sort_valid<'d>(
    plan: &Plan,
    columns: &[Column],
    todo: impl Iterator<Item = &'d Design>,
    threads: usize,
) -> (Vec<(&'d Design, Scene)>, Vec<Row>) {
    let mut valid = Vec::new();
    let mut invalid = Vec::new();
    for d in todo {
        match plan.design_scene(d) {
            Ok(scene) => valid.push((d, scene)),
            Err(e) => invalid.push(Row::invalid(plan, columns, d, e.detail)),
        }
    }
    let runs = threads.min(valid.len());
    if runs > 1 {
        let budget = crate::machine::memory_budget_bytes();
        valid.retain(|(d, scene)| {
            let fits = crate::machine::check_fits_among(&scene.to_problem(), budget, runs);
            if let Err(why) = &fits {
                invalid.push(Row::invalid(plan, columns, d, why.to_string()));
            }
            fits.is_ok()
        });
    }
    (valid, invalid)
}

/// Runs one design unless stopped; a panic in the program becomes a FAILED row that says so.
fn run_guarded(job: &Job, design: &Design, scene: &Scene) -> Option<Row> {
    if job.stopped() {
        return None;
    }
    let t = Instant::now();
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        run_design(job, design, scene)
    }))
    .unwrap_or_else(|payload| {
        let reason = format!(
            "the program failed on this design: {}",
            panic_message(&*payload)
        );
        let wall = t.elapsed().as_secs_f64();
        Some(Row::failed(job.plan, job.columns, design, reason, wall))
    })
}
