//! The output folder of a sweep: `sweep.lock` (the plan, written before any work),
//! `results.csv` (a row appended as each design finishes) and `fields/` (see [`super::field`]);
//! reading them back for a resume (and refusing a folder of another sweep) or a merge.

use std::collections::{HashMap, HashSet};
use std::fs;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::SweepError;
use super::field::StoredField;
use super::folder_error::{StoreError, write_atomic};
use super::grid::Design;
use super::plan::Plan;
use super::rows::{LATER_COLUMNS, Row, column_names, csv_header, csv_line, round_to};
use super::shard::Shard;
use crate::verdict::Verdict;

/// What `sweep.lock` holds.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Lock {
    pub program: String,
    pub version: String,
    pub base_hash: String,
    pub sweep_hash: String,
    pub shard: Option<String>,
    pub plan: Plan,
}

/// Reads `dir/sweep.lock`.
pub fn read_lock(dir: &Path) -> Result<Lock, StoreError> {
    let path = dir.join("sweep.lock");
    let text = crate::files::read_text(&path, crate::files::MAX_TEXT_BYTES).map_err(|source| {
        StoreError::NoLock {
            path: path.clone(),
            source,
        }
    })?;
    serde_json::from_str(&text).map_err(|source| StoreError::BadLock { path, source })
}

/// Creates `dir`, `dir/maps` and `dir/fields` and writes `dir/sweep.lock`.
pub fn prepare_dir(dir: &Path, plan: &Plan, shard: Option<Shard>) -> Result<(), StoreError> {
    for d in [dir.to_path_buf(), dir.join("maps"), dir.join("fields")] {
        fs::create_dir_all(&d).map_err(StoreError::io(&d, "write the output folder"))?;
    }
    let lock = Lock {
        program: "wovenform".into(),
        version: env!("CARGO_PKG_VERSION").into(),
        base_hash: plan.base_hash.clone(),
        sweep_hash: plan.sweep_hash.clone(),
        shard: shard.map(|s| s.to_string()),
        plan: plan.clone(),
    };
    let text = serde_json::to_string_pretty(&lock).expect("the lock is plain data");
    write_atomic(&dir.join("sweep.lock"), &(text + "\n"))
}

/// Writes `results.csv` whole: the header, `rows`, then `others` (rows of other grids the
/// folder held, as they were: see [`ReadReport::others`]).
pub fn write_rows(
    dir: &Path,
    plan: &Plan,
    rows: &[Row],
    others: &[Vec<String>],
) -> Result<PathBuf, StoreError> {
    let path = dir.join("results.csv");
    let mut text = csv_header(&plan.columns()) + "\n";
    for r in rows {
        text.push_str(&r.to_csv());
    }
    for fields in others {
        text.push_str(&csv_line(fields));
    }
    write_atomic(&path, &text)?;
    Ok(path)
}

/// What the rows of an existing `results.csv` came to.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ReadReport {
    /// Rows kept.
    pub kept: usize,
    /// A last line without its newline (the program was stopped while writing it).
    pub truncated: usize,
    /// Rows whose design is not in this grid, or that do not parse: not this sweep's, but
    /// kept in `results.csv` as they are (a frontier's runs between the grid's values, a
    /// grid's values since removed), never dropped.
    pub foreign: usize,
    /// Rows of a design already read.
    pub duplicates: usize,
    /// Rows whose field file is missing (they are run again).
    pub no_field: usize,
    /// Rows that disagree with their field file (a figure or the verdict edited by hand):
    /// run again.
    pub edited: usize,
    /// Rows of a scene with bending written before the wrinkle columns: judged without
    /// wrinkles, so run again.
    pub no_wrinkles: usize,
    /// Rows of designs whose values are in the grid under another number (the grid grew or
    /// shrank, or a frontier's lattice holds the grid): kept, their files copied to the new
    /// id (the old ones stay, for what refers to them).
    pub renumbered: usize,
    /// The fields of the [`ReadReport::foreign`] rows, laid out under this sweep's header.
    pub others: Vec<Vec<String>>,
}

impl ReadReport {
    pub fn dropped(&self) -> usize {
        self.truncated + self.duplicates + self.no_field + self.edited + self.no_wrinkles
    }

    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        if self.truncated > 0 {
            parts.push(format!("{} half-written last line", self.truncated));
        }
        if self.duplicates > 0 {
            parts.push(format!("{} duplicate", self.duplicates));
        }
        if self.no_field > 0 {
            parts.push(format!("{} without their field file", self.no_field));
        }
        if self.edited > 0 {
            parts.push(format!(
                "{} that disagree with their field file (max shear or verdict edited; run again)",
                self.edited
            ));
        }
        if self.no_wrinkles > 0 {
            parts.push(format!(
                "{} of a scene with bending written without the wrinkle columns (run again)",
                self.no_wrinkles
            ));
        }
        let kept = if self.renumbered > 0 {
            format!(
                "kept {} rows ({} renumbered: same values, the grid changed around them)",
                self.kept, self.renumbered
            )
        } else {
            format!("kept {} rows", self.kept)
        };
        let kept = if self.foreign > 0 {
            format!(
                "{kept} ({} more of another grid left in results.csv as they are)",
                self.foreign
            )
        } else {
            kept
        };
        if parts.is_empty() {
            kept
        } else {
            format!("{kept}, dropped {}", parts.join(", "))
        }
    }
}

/// Reads the rows of `dir/results.csv` that belong to the plan's grid (first of each design).
pub fn read_rows(dir: &Path, plan: &Plan) -> Result<(Vec<Row>, ReadReport), StoreError> {
    let path = dir.join("results.csv");
    let Some((text, truncated)) = read_text(&path)? else {
        return Ok(Default::default());
    };
    let mut report = ReadReport {
        truncated,
        ..Default::default()
    };
    let mut reader = csv::ReaderBuilder::new()
        .flexible(true)
        .from_reader(text.as_bytes());
    let Ok(header_fields) = reader.headers().cloned() else {
        return Ok((Vec::new(), report));
    };
    check_header(&path, dir, plan, &header_fields)?;
    let expected = column_names(&plan.columns());
    let header: HashMap<&str, usize> = header_fields
        .iter()
        .enumerate()
        .map(|(i, h)| (h, i))
        .collect();
    let columns = plan.columns();
    let designs = plan.designs();
    let grid: HashMap<&str, &Design> = designs.iter().map(|d| (d.id.as_str(), d)).collect();
    // A design is its values: the id's hash part finds it when its number changed.
    let by_values: HashMap<&str, &Design> = designs
        .iter()
        .filter_map(|d| Some((Design::values_hash(&d.id)?, d)))
        .collect();
    let mut seen = HashSet::new();
    let mut rows = Vec::new();
    for record in reader.records() {
        let Ok(record) = record else {
            report.truncated += 1;
            continue;
        };
        let whole = record.len() == header_fields.len();
        let record = if whole {
            renumbered(dir, &header, record, &grid, &by_values, &mut report)
        } else {
            record
        };
        let row = Some(&record)
            .filter(|_| whole)
            .and_then(|f| Row::from_csv(&header, f, plan, &columns, &grid));
        let Some(row) = row else {
            report.foreign += 1;
            report
                .others
                .push(laid_out(&record, &header_fields, &expected));
            continue;
        };
        if !seen.insert(row.design.clone()) {
            report.duplicates += 1;
            continue;
        }
        if !header.contains_key("max_wrinkle_mm") && judged_with_wrinkles(plan, &row, &grid) {
            report.no_wrinkles += 1;
            continue;
        }
        match agrees_with_field(dir, &row) {
            Some(true) => rows.push(row),
            Some(false) => report.edited += 1,
            None => report.no_field += 1,
        }
    }
    report.kept = rows.len();
    keepable(path, &report, &header_fields, &expected)?;
    Ok((rows, report))
}

/// Refuses a file whose rows of another grid could not be written back under the sweep's
/// header (its columns differ): they would be lost.
fn keepable(
    path: PathBuf,
    report: &ReadReport,
    found: &csv::StringRecord,
    expected: &[String],
) -> Result<(), StoreError> {
    if report.foreign == 0 || same_layout(found, expected) {
        return Ok(());
    }
    Err(StoreError::Header {
        path,
        problem: format!(
            "{} rows of another grid, whose columns are not this sweep's (they would be lost \
             under its header)",
            report.foreign
        ),
        expected: expected.join(","),
    })
}

/// Whether the row's design has bending, so its verdict needs the wrinkle figure (a row
/// solved before the wrinkle columns were written lacks it).
fn judged_with_wrinkles(plan: &Plan, row: &Row, grid: &HashMap<&str, &Design>) -> bool {
    row.verdict != Verdict::Invalid
        && grid
            .get(row.design.as_str())
            .and_then(|d| plan.design_scene(d).ok())
            .is_some_and(|scene| scene.bending().is_some())
}

/// The text of `results.csv` without a byte-order mark and without a last line cut short
/// (1 when there was one); `None` when there is no such file.
fn read_text(path: &Path) -> Result<Option<(String, usize)>, StoreError> {
    // A sweep's rows are small (a few hundred bytes a design): 4 GB is millions of designs.
    let mut text = match crate::files::read_regular(path, 4_000_000_000) {
        Ok(b) => String::from_utf8_lossy(&b).into_owned(),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(StoreError::io(path, "read")(e)),
    };
    // A byte-order mark (a spreadsheet saved the file) is not part of the header.
    if text.starts_with('\u{feff}') {
        text.drain(..'\u{feff}'.len_utf8());
    }
    // A last line without its newline was being written when the program stopped.
    let mut truncated = 0;
    if !text.is_empty() && !text.ends_with('\n') {
        let cut = text.rfind('\n').map_or(0, |i| i + 1);
        text.truncate(cut);
        truncated = 1;
    }
    Ok(Some((text, truncated)))
}

/// Whether rows under `found` can be written under `expected`: the same columns, or the same
/// with later columns missing at the end (see [`LATER_COLUMNS`]).
fn same_layout(found: &csv::StringRecord, expected: &[String]) -> bool {
    found.len() <= expected.len() && found.iter().zip(expected).all(|(a, b)| a == b)
}

/// A record of another grid as it is written back under `expected`: padded with empty fields
/// for the later columns its header lacked.
fn laid_out(
    record: &csv::StringRecord,
    found: &csv::StringRecord,
    expected: &[String],
) -> Vec<String> {
    let mut fields: Vec<String> = record.iter().map(String::from).collect();
    if record.len() == found.len() && same_layout(found, expected) {
        fields.resize(expected.len(), String::new());
    }
    fields
}

/// The record of a design whose values are in the grid under another id (its number moved
/// when values were added to or removed from a range): the id and map path changed to the
/// new id, and its field and map files renamed. Any other record unchanged.
fn renumbered(
    dir: &Path,
    header: &HashMap<&str, usize>,
    record: csv::StringRecord,
    grid: &HashMap<&str, &Design>,
    by_values: &HashMap<&str, &Design>,
    report: &mut ReadReport,
) -> csv::StringRecord {
    let Some(&at) = header.get("design") else {
        return record;
    };
    let old = record.get(at).unwrap_or_default().to_string();
    if grid.contains_key(old.as_str()) {
        return record;
    }
    let Some(design) = Design::values_hash(&old).and_then(|h| by_values.get(h)) else {
        return record;
    };
    let new = design.id.as_str();
    // Copied, not moved: a frontier's files (and the explorer's table) name the old id.
    let moved_field = StoredField::read(dir, &old).ok().is_some_and(|mut field| {
        field.design = new.to_string();
        field.write(dir).is_ok()
    });
    let (old_map, new_map) = (format!("maps/{old}.png"), format!("maps/{new}.png"));
    if dir.join(&old_map).exists() {
        let _ = fs::copy(dir.join(&old_map), dir.join(&new_map));
    }
    if moved_field {
        report.renumbered += 1;
    }
    record
        .iter()
        .map(|f| {
            if f == old {
                new.to_string()
            } else if f == old_map {
                new_map.clone()
            } else {
                f.to_string()
            }
        })
        .collect()
}

/// Refuses a header that is not the one this sweep (or the folder's own, from its
/// `sweep.lock`) writes: a renamed or unknown column would otherwise drop every row.
fn check_header(
    path: &Path,
    dir: &Path,
    plan: &Plan,
    found: &csv::StringRecord,
) -> Result<(), StoreError> {
    let expected = column_names(&plan.columns());
    let folder = read_lock(dir).ok().map(|l| column_names(&l.plan.columns()));
    let found: Vec<&str> = found.iter().collect();
    // A file written before some of the later columns (`LATER_COLUMNS`, each group added at
    // the end) lacks them: its rows read with those figures empty, and the file is written
    // again whole with them.
    let same = |names: &[String]| {
        let n = found.len();
        n <= names.len()
            && names[..n].iter().zip(&found).all(|(a, b)| a == b)
            && names[n..]
                .iter()
                .all(|m| LATER_COLUMNS.contains(&m.as_str()))
    };
    if same(&expected) || folder.as_deref().is_some_and(same) {
        return Ok(());
    }
    let known = folder.as_ref().unwrap_or(&expected);
    let problem = match found.iter().find(|f| !known.iter().any(|k| k == *f)) {
        Some(unknown) => format!("a column `{unknown}`"),
        None => match known.iter().find(|k| !found.contains(&k.as_str())) {
            Some(missing) => format!("no column `{missing}`"),
            None => format!("the columns in another order ({})", found.join(",")),
        },
    };
    Err(StoreError::Header {
        path: path.to_path_buf(),
        problem,
        expected: known.join(","),
    })
}

/// Whether a row read back agrees with its field file (the max shear to the printed
/// precision, the verdict); a row without a map must be one that did not run (INVALID, or
/// FAILED without figures). `None`: its field file is missing or unreadable (or was never
/// saved: figures without a map).
fn agrees_with_field(dir: &Path, row: &Row) -> Option<bool> {
    if row.map.is_none() {
        if row.max_shear_deg.is_some() {
            return None;
        }
        let did_not_run = matches!(row.verdict, Verdict::Invalid | Verdict::Failed);
        return Some(did_not_run && !row.feasible);
    }
    let field = StoredField::read(dir, &row.design).ok()?;
    let shear_agrees = row
        .max_shear_deg
        .is_some_and(|s| (s - round_to(field.max_shear_deg, 4)).abs() < 1e-6);
    Some(shear_agrees && Verdict::of_sentence(&field.verdict) == row.verdict)
}

/// Why a folder cannot take a sweep, naming the folder.
#[derive(Debug, thiserror::Error)]
pub enum OtherSweep {
    #[error(
        "{} holds a results.csv without a sweep.lock: cannot tell which sweep it belongs to",
        dir.display()
    )]
    RowsWithoutLock { dir: PathBuf },
    #[error("{lock}: cannot tell which sweep {} belongs to", dir.display())]
    UnreadableLock {
        dir: PathBuf,
        #[source]
        lock: StoreError,
    },
    #[error(
        "{} holds another sweep ({its_file}, whose {differs} differs from {this_file}'s)",
        dir.display()
    )]
    Another {
        dir: PathBuf,
        /// The sweep file of the folder's lock, and of the sweep asking.
        its_file: String,
        this_file: String,
        /// `base scene` or `grid`: what differs (the base scene first).
        differs: &'static str,
    },
}

/// Whether `dir` can take `plan`'s sweep: `Ok(false)` when it holds no sweep, `Ok(true)` when
/// it holds this one (the same base scene and grid in its `sweep.lock`). Refused, with why:
/// a folder of another sweep, or rows or a lock that cannot be told to be this sweep's.
pub fn holds_this_sweep(dir: &Path, plan: &Plan) -> Result<bool, OtherSweep> {
    let rows = dir.join("results.csv");
    let lock = match read_lock(dir) {
        Ok(lock) => lock,
        Err(StoreError::NoLock { source, .. }) if source.kind() == std::io::ErrorKind::NotFound => {
            if !rows.exists() {
                return Ok(false);
            }
            return Err(OtherSweep::RowsWithoutLock {
                dir: dir.to_path_buf(),
            });
        }
        Err(lock) => {
            return Err(OtherSweep::UnreadableLock {
                dir: dir.to_path_buf(),
                lock,
            });
        }
    };
    if lock.base_hash == plan.base_hash && lock.sweep_hash == plan.sweep_hash {
        return Ok(true);
    }
    let differs = if lock.base_hash != plan.base_hash {
        "base scene"
    } else {
        "grid"
    };
    Err(OtherSweep::Another {
        dir: dir.to_path_buf(),
        its_file: lock.plan.sweep_file,
        this_file: plan.sweep_file.clone(),
        differs,
    })
}

/// The rows of an earlier run of this sweep in `dir` (with `--resume`); refuses a folder that
/// holds rows without `--resume`, or rows of another base scene.
pub fn earlier_rows(
    plan: &Plan,
    dir: &Path,
    resume: bool,
) -> Result<(Vec<Row>, ReadReport), SweepError> {
    let csv_path = dir.join("results.csv");
    if !csv_path.exists() {
        return Ok((Vec::new(), ReadReport::default()));
    }
    if !resume {
        return Err(SweepError::BadInput(format!(
            "{} exists: add --resume to continue that sweep, or choose another --out",
            csv_path.display()
        )));
    }
    let lock = read_lock(dir).map_err(|e| {
        SweepError::BadInput(format!(
            "--resume: {e}; cannot tell which sweep {} belongs to (remove the folder, or use another --out)",
            csv_path.display()
        ))
    })?;
    if lock.base_hash != plan.base_hash {
        let mut changed = crate::scene::differences(&lock.plan.base_scene, &plan.base_scene);
        for new in &plan.tool_files {
            let old = lock.plan.tool_files.iter().find(|o| o.key == new.key);
            if old.is_some_and(|o| o.file == new.file && o.surface != new.surface) {
                changed.push(format!(
                    "{} = \"{}\": the file holds another surface than when the sweep began \
                     (it was written anew)",
                    new.key, new.file
                ));
            }
        }
        if changed.is_empty() {
            changed.push(format!(
                "{} with {}, now {} with {}",
                lock.plan.sweep_file,
                lock.plan.base_file.as_deref().unwrap_or("the inline scene"),
                plan.sweep_file,
                plan.base_file.as_deref().unwrap_or("the inline scene"),
            ));
        }
        return Err(SweepError::BadInput(format!(
            "--resume: {} was swept with another base scene ({}): its rows cannot be reused; use another --out, or remove the folder to start again",
            dir.display(),
            changed.join("; "),
        )));
    }
    read_rows(dir, plan).map_err(rows_error)
}

/// An error reading the rows: an edited header is bad input (exit 2), the rest a failure.
pub(super) fn rows_error(e: StoreError) -> SweepError {
    match e {
        StoreError::Header { .. } => SweepError::Folder(e),
        other => SweepError::Store(other),
    }
}

/// Prepares the folder and writes `results.csv` anew with the rows kept and those of other
/// grids (a half-written line or a duplicate goes); returns it open for appending.
pub fn open_rows(
    plan: &Plan,
    dir: &Path,
    shard: Option<Shard>,
    kept: &[Row],
    others: &[Vec<String>],
) -> Result<fs::File, SweepError> {
    prepare_dir(dir, plan, shard).map_err(SweepError::Folder)?;
    let path = write_rows(dir, plan, kept, others).map_err(|e| {
        SweepError::BadInput(format!(
            "{}: cannot write the output folder: {e}",
            dir.display()
        ))
    })?;
    fs::OpenOptions::new()
        .append(true)
        .open(&path)
        .map_err(|e| SweepError::BadInput(format!("{}: cannot write: {e}", path.display())))
}
