//! Writes what `report` draws and formats into files: a run's maps, VTU and `summary.json`;
//! a sweep folder's maps on the sweep's common colour scale (`maps/<id>.png`), report sheet
//! (`report.png`) and `results.json`; the paper's Figure 6. The studies leave their results
//! (and a sweep its rows and fields) as plain data or in their folder; this reads and writes.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::core::drawing::{DrawingResult, Tooling};
use crate::core::law::CellParams;
use crate::report::figure6::{figure6_chart, figure6_csv, figure6_table};
use crate::report::maps::{self, MapContext};
use crate::report::sweep::{design_label, field_map, results_json, shared_scale_max, sheet};
use crate::report::vtu;
use crate::study::sweep::{Plan, Row, Shard, StoredField, write_atomic};
use crate::summary::RunSummary;

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

/// Writes `shear.png`, `tension.png`, `result.vtu` and `summary.json` into `dir` (created if
/// needed), records them in `summary.files`, and returns their paths. Errors name the file.
pub fn write_run(
    dir: &Path,
    summary: &mut RunSummary,
    result: &DrawingResult,
    tooling: &Tooling,
) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir)
        .map_err(|e| format!("{}: cannot create the folder: {e}", dir.display()))?;
    let ctx = MapContext {
        scene: &summary.scene,
        verdict: &summary.verdict,
        tooling: *tooling,
        stroke_mm: summary.stroke_mm,
    };
    let shear = dir.join("shear.png");
    maps::shear_map(result, &ctx, summary.locking_angle_deg).write_png(&shear)?;
    let tension = dir.join("tension.png");
    maps::tension_map(result, &ctx, summary.break_tension_n).write_png(&tension)?;
    let vtu_path = dir.join("result.vtu");
    vtu::write_vtu(result, &vtu_path)?;
    let json = dir.join("summary.json");
    let written = vec![json.clone(), shear, tension, vtu_path];
    for (kind, path) in ["summary", "shear_map", "tension_map", "vtu"]
        .iter()
        .zip(&written)
    {
        summary
            .files
            .insert(kind.to_string(), path.display().to_string());
    }
    let text = serde_json::to_string_pretty(&*summary).expect("the summary is plain data");
    std::fs::write(&json, text + "\n")
        .map_err(|e| format!("{}: cannot write the summary: {e}", json.display()))?;
    Ok(written)
}

/// Writes `dir/figure6.csv` and `dir/figure6.png` (creating `dir`); returns the paths written.
pub fn write_figure6(params: CellParams, dir: &Path) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir)
        .map_err(|e| format!("{}: cannot create the folder: {e}", dir.display()))?;
    let rows = figure6_table(params, 121);
    let csv = dir.join("figure6.csv");
    std::fs::write(&csv, figure6_csv(&rows))
        .map_err(|e| format!("{}: cannot write: {e}", csv.display()))?;
    let png = dir.join("figure6.png");
    figure6_chart(&rows).write_png(&png)?;
    Ok(vec![csv, png])
}
