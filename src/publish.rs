//! Writes a sweep folder's report files: each design's map on the sweep's common colour scale
//! (`maps/<id>.png`), the report sheet (`report.png`) and `results.json`. The study left the
//! rows and the fields in the folder; `report::sweep` draws them; this reads and writes.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::report::sweep::{design_label, field_map, results_json, shared_scale_max, sheet};
use crate::study::sweep::{Plan, Row, Shard, StoredField, write_atomic};

/// Draws the maps (on `pool`), the sheet and `results.json` of the sweep folder `dir` whose
/// rows are `rows`; returns the files of the folder a user opens.
pub fn sweep_report(
    plan: &Plan,
    dir: &Path,
    rows: &[Row],
    shard: Option<Shard>,
    pool: &rayon::ThreadPool,
) -> Result<Vec<PathBuf>, String> {
    let designs = plan.designs();
    let top = shared_scale_max(plan, rows);
    let read = |r: &Row| StoredField::read(dir, &r.design).map_err(|e| e.to_string());
    // Every map on the common scale.
    let drawn: Vec<Result<(), String>> = pool.install(|| {
        rows.par_iter()
            .with_max_len(1)
            .filter(|r| r.map.is_some())
            .map(|r| {
                let label = design_label(plan, &designs[r.index]);
                field_map(&read(r)?, &label, top)
                    .write_png(&dir.join("maps").join(format!("{}.png", r.design)))
            })
            .collect()
    });
    drawn.into_iter().collect::<Result<Vec<()>, String>>()?;
    let report = dir.join("report.png");
    sheet(plan, rows, &designs, top, &read)?.write_png(&report)?;
    let json = dir.join("results.json");
    write_atomic(&json, &results_json(plan, rows, shard, top)).map_err(|e| e.to_string())?;
    Ok(vec![
        dir.join("results.csv"),
        json,
        report,
        dir.join("maps"),
    ])
}
