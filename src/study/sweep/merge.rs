//! Merging: the folders of one sweep's shards put back together into one sweep folder.

use std::collections::HashMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::SweepError;
use super::field::StoredField;
use super::folder_lock::FolderLock;
use super::plan::Plan;
use super::rows::Row;
use super::run::Outcome;
use super::store::{self, ReadReport};

/// Combines sweep folders (shards) of one sweep into `out`: the rows (the first of each
/// design), their fields and the lock, as one sweep folder. An `out` that already holds this
/// sweep (an earlier merge, or one stopped half-way) keeps its rows and gets those of the
/// designs it lacks: merging again is safe and finishes what is missing. An `out` of another
/// sweep is refused.
/// Returns the sweep's plan (read from the folders' `sweep.lock`) with the outcome.
pub fn merge(inputs: &[PathBuf], out: &Path) -> Result<(Plan, Outcome), SweepError> {
    let start = Instant::now();
    if inputs.is_empty() {
        return Err(SweepError::BadInput(
            "merge: expected at least one sweep folder".into(),
        ));
    }
    let shards = gather(inputs)?;
    // Held before `out` is read: two merges into one folder never interleave.
    let (lock, _) = FolderLock::take(out)?;
    let Gathered {
        plan,
        mut rows,
        sources,
        mut report,
    } = with_earlier_merge(shards, inputs, out)?;
    report.kept = rows.len();
    rows.sort_by_key(|r| r.index);
    store::prepare_dir(out, &plan, None).map_err(SweepError::Folder)?;
    for row in rows.iter().filter(|r| r.map.is_some()) {
        let from = StoredField::path(&sources[&row.design], &row.design);
        let to = StoredField::path(out, &row.design);
        if !same_folder(&from, &to) {
            fs::copy(&from, &to).map_err(|e| {
                SweepError::Run(format!(
                    "cannot copy {} to {}: {e}",
                    from.display(),
                    to.display()
                ))
            })?;
        }
    }
    let csv = store::write_rows(out, &plan, &rows, &report.others).map_err(SweepError::Store)?;
    let outcome = Outcome {
        missing: plan.len().saturating_sub(rows.len()),
        rows,
        ran: 0,
        kept: report,
        threads: 1,
        run_wall_s: 0.0,
        wall_s: start.elapsed().as_secs_f64(),
        files: vec![csv],
        stopped: false,
        lock: Some(lock),
    };
    Ok((plan, outcome))
}

/// The rows already in `out` when it holds this sweep and is not among the inputs (an
/// earlier merge), then the shards' rows of the designs it lacks. Refused: an `out` of
/// another sweep, or with rows that cannot be told to be this sweep's (nothing is
/// overwritten).
fn with_earlier_merge(
    shards: Gathered,
    inputs: &[PathBuf],
    out: &Path,
) -> Result<Gathered, SweepError> {
    if inputs.iter().any(|d| same_folder(d, out)) {
        return Ok(shards);
    }
    let holds = store::holds_this_sweep(out, &shards.plan).map_err(|e| {
        SweepError::BadInput(format!(
            "merge: --out {}: {e}; choose another --out",
            out.display()
        ))
    })?;
    if !holds {
        return Ok(shards);
    }
    let (earlier, r) = store::read_rows(out, &shards.plan).map_err(store::rows_error)?;
    let mut report = shards.report;
    report.truncated += r.truncated;
    report.foreign += r.foreign;
    report.no_field += r.no_field;
    report.duplicates += r.duplicates;
    report.edited += r.edited;
    // The rows of other grids the folder held stay in it.
    report.others = r.others;
    let mut sources: HashMap<String, PathBuf> = earlier
        .iter()
        .map(|row| (row.design.clone(), out.to_path_buf()))
        .collect();
    let mut rows = earlier;
    for row in shards.rows {
        if !sources.contains_key(&row.design) {
            sources.insert(row.design.clone(), shards.sources[&row.design].clone());
            rows.push(row);
        }
    }
    Ok(Gathered {
        plan: shards.plan,
        rows,
        sources,
        report,
    })
}

/// Two paths name the same file or folder.
fn same_folder(a: &Path, b: &Path) -> bool {
    match (fs::canonicalize(a), fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// The rows of the input folders (the first of each design) and where each came from.
struct Gathered {
    plan: Plan,
    rows: Vec<Row>,
    sources: HashMap<String, PathBuf>,
    report: ReadReport,
}

/// Reads the input folders, which must be sweep folders of one sweep (the same base scene and
/// grid in their locks).
fn gather(inputs: &[PathBuf]) -> Result<Gathered, SweepError> {
    let mut first: Option<(Plan, PathBuf)> = None;
    let mut rows: Vec<Row> = Vec::new();
    let mut sources: HashMap<String, PathBuf> = HashMap::new();
    let mut report = ReadReport::default();
    for dir in inputs {
        let lock = store::read_lock(dir).map_err(|e| {
            SweepError::BadInput(format!("{e}: {} is not a sweep folder", dir.display()))
        })?;
        if !dir.join("results.csv").exists() {
            return Err(SweepError::BadInput(format!(
                "{}: no results.csv: not a sweep folder",
                dir.display()
            )));
        }
        let (plan, first_dir) = first.get_or_insert_with(|| (lock.plan.clone(), dir.clone()));
        if lock.base_hash != plan.base_hash || lock.sweep_hash != plan.sweep_hash {
            let what = if lock.base_hash != plan.base_hash {
                "base scene"
            } else {
                "grid"
            };
            return Err(SweepError::BadInput(format!(
                "merge: {} and {} come from different sweeps (their {what} differs: {} and {}); merge only the shards of one sweep",
                first_dir.display(),
                dir.display(),
                plan.sweep_file,
                lock.plan.sweep_file
            )));
        }
        let (found, r) = store::read_rows(dir, plan).map_err(store::rows_error)?;
        // A shard's rows of other grids stay in the shard's folder.
        report.truncated += r.truncated;
        report.foreign += r.foreign;
        report.no_field += r.no_field;
        report.duplicates += r.duplicates;
        for row in found {
            if sources.contains_key(&row.design) {
                report.duplicates += 1;
                continue;
            }
            sources.insert(row.design.clone(), dir.clone());
            rows.push(row);
        }
    }
    let (plan, _) = first.expect("at least one input");
    Ok(Gathered {
        plan,
        rows,
        sources,
        report,
    })
}
