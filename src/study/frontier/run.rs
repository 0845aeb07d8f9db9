//! Running a frontier: rounds of runs, each round every unfinished combination's next runs in
//! parallel through the sweep machinery (rows appended to `results.csv` as they finish), until
//! every search has its answer.

use std::collections::{HashMap, HashSet};
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use super::search::{self, Search};
use super::{Boundary, Found, Frontier, Lattice, Line, RunPoint, answer_of};
use crate::study::sweep::{self, Row, Shard, SweepError};
use crate::verdict::Limits;

/// How to run a frontier.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Runs at once (threads); `None`: every core.
    pub jobs: Option<usize>,
    /// Only the combinations whose number is `I − 1` modulo `N`.
    pub shard: Option<Shard>,
    pub resume: bool,
    pub stop: Option<Arc<AtomicBool>>,
}

/// What a frontier reports while it runs.
#[derive(Debug)]
pub enum Progress<'a> {
    /// A round begins: its runs to do and the rows found from before.
    Round {
        round: usize,
        to_run: usize,
        kept: usize,
        searching: usize,
    },
    /// A run finished (`done` over the whole frontier).
    Done { row: &'a Row, done: usize },
}

/// Searches every combination (of the shard) of `lattice` into `dir`.
pub fn search(
    lattice: &Lattice,
    dir: &Path,
    options: &Options,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<Frontier, SweepError> {
    let start = Instant::now();
    let mine: Vec<usize> = (0..lattice.combos.len())
        .filter(|c| options.shard.is_none_or(|s| s.contains(*c)))
        .collect();
    let budget = lattice.grid_values.max(3);
    let mut searches: Vec<Search> = (mine.iter())
        .map(|_| Search::new(lattice.len(), super::lattice::PER_STEP, budget))
        .collect();
    let mut limits: HashMap<String, Limits> = HashMap::new();
    let (mut ran, mut kept, mut rows) = (0, 0, Vec::new());
    let done = AtomicUsize::new(0);
    if mine.is_empty() {
        rows = empty_shard(lattice, dir, options.resume)?;
    }
    let mut resume = options.resume;
    let mut stopped = false;
    for round in 1.. {
        let wanted: Vec<(usize, usize)> = (searches.iter().enumerate())
            .flat_map(|(s, search)| search.next().into_iter().map(move |j| (s, j)))
            .collect();
        if wanted.is_empty() {
            break;
        }
        let ids: HashSet<String> = (wanted.iter())
            .map(|&(s, j)| lattice.design(mine[s], j).id.clone())
            .collect();
        let searching = wanted.iter().map(|w| w.0).collect::<HashSet<_>>().len();
        let round = Round {
            number: round,
            ids: &ids,
            searching,
            resume,
        };
        let (outcome, written) = run_round(lattice, dir, options, &round, &done, progress)?;
        resume = true;
        ran += outcome.ran;
        let by_id: HashMap<&str, &Row> = (outcome.rows.iter())
            .map(|r| (r.design.as_str(), r))
            .collect();
        let present = ids.iter().filter(|id| by_id.contains_key(id.as_str()));
        kept += present.count().saturating_sub(written);
        for &(s, j) in &wanted {
            let design = lattice.design(mine[s], j);
            let Some(row) = by_id.get(design.id.as_str()) else {
                stopped = true;
                continue;
            };
            let limits = *limits.entry(design.id.clone()).or_insert_with(|| {
                (lattice.plan.design_scene(design).ok())
                    .map_or_else(|| Limits::of(&lattice.plan.base_scene), |s| Limits::of(&s))
            });
            searches[s].add(j, answer_of(row, limits));
        }
        rows = outcome.rows;
        if stopped || outcome.stopped {
            stopped = true;
            break;
        }
    }
    let by_id: HashMap<&str, &Row> = rows.iter().map(|r| (r.design.as_str(), r)).collect();
    let lines = (mine.iter().zip(&searches))
        .map(|(&c, s)| line_of(lattice, c, s, &by_id, stopped))
        .collect();
    let mut found = frontier_of(lattice, lines, rows);
    (found.ran, found.kept, found.wall_s) = (ran, kept, start.elapsed().as_secs_f64());
    Ok(found)
}

/// The frontier of `lattice` with its lines and the folder's rows (no runs counted yet).
fn frontier_of(lattice: &Lattice, lines: Vec<Line>, rows: Vec<Row>) -> Frontier {
    Frontier {
        column: lattice.searched().column.clone(),
        key: lattice.searched().key.clone(),
        range: [lattice.lo, lattice.hi],
        grid_values: lattice.grid_values,
        log: lattice.log,
        limits: Limits::of(&lattice.plan.base_scene),
        lines,
        ran: 0,
        kept: 0,
        rows,
        wall_s: 0.0,
    }
}

/// A shard with no combination still leaves a folder a merge can read: its lock and an
/// empty `results.csv` (or the rows already there).
fn empty_shard(lattice: &Lattice, dir: &Path, resume: bool) -> Result<Vec<Row>, SweepError> {
    let none = sweep::Options {
        only: Some(HashSet::new()),
        resume,
        ..sweep::Options::default()
    };
    Ok(sweep::run(&lattice.plan, dir, &none, &|_| {})?.rows)
}

/// One round: its number, the designs it runs, the combinations searching, and whether the
/// folder's rows are kept.
struct Round<'a> {
    number: usize,
    ids: &'a HashSet<String>,
    searching: usize,
    resume: bool,
}

/// Runs a round's designs through the sweep engine (those with a row already are kept);
/// the outcome and the rows written in it.
fn run_round(
    lattice: &Lattice,
    dir: &Path,
    options: &Options,
    round: &Round,
    done: &AtomicUsize,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<(sweep::Outcome, usize), SweepError> {
    let adapter = |p: sweep::Progress| match p {
        sweep::Progress::Start { to_run, kept, .. } => progress(Progress::Round {
            round: round.number,
            to_run,
            kept: kept.kept.min(round.ids.len()),
            searching: round.searching,
        }),
        sweep::Progress::Done { row, .. } => {
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            progress(Progress::Done { row, done: n });
        }
    };
    let sweep_options = sweep::Options {
        jobs: options.jobs,
        shard: None,
        resume: round.resume,
        stop: options.stop.clone(),
        only: Some(round.ids.clone()),
    };
    let before = done.load(Ordering::Relaxed);
    let outcome = sweep::run(&lattice.plan, dir, &sweep_options, &adapter)?;
    let written = done.load(Ordering::Relaxed) - before;
    Ok((outcome, written))
}

/// A combination's line: its values, what its search found (in the axis's unit) and its runs.
fn line_of(
    lattice: &Lattice,
    c: usize,
    s: &Search,
    by_id: &HashMap<&str, &Row>,
    stopped: bool,
) -> Line {
    let runs = (0..lattice.len())
        .filter_map(|j| {
            let d = lattice.design(c, j);
            let row = by_id.get(d.id.as_str())?;
            s.has(j).then(|| RunPoint {
                value: lattice.x(j as f64),
                design: d.id.clone(),
                verdict: row.verdict,
            })
        })
        .collect();
    let last = (lattice.len() - 1) as f64;
    let found = match s.found() {
        _ if stopped && !s.next().is_empty() => Found::Stopped,
        search::Found::Boundaries(roots) => Found::Boundaries(
            roots
                .iter()
                .map(|r| Boundary {
                    governing: r.governing,
                    value: lattice.x(r.at),
                    search: r.search.map(|j| lattice.x(j)),
                    interval: [
                        lattice.x(r.search[0].min(r.zone[0]).max(0.0)),
                        lattice.x(r.search[1].max(r.zone[1]).min(last)),
                    ],
                    feasible_above: r.under_above,
                })
                .collect(),
        ),
        search::Found::Whole { over, range } => Found::Whole {
            over,
            range: range.map(|j| lattice.x(j as f64)),
        },
        search::Found::NoAnswer(why) => Found::NoAnswer(why),
    };
    let unanswered = (s.failures().into_iter())
        .map(|(j, why)| (lattice.x(j as f64), why))
        .collect();
    Line {
        values: lattice.combo_values(c),
        found,
        runs,
        unanswered,
    }
}
