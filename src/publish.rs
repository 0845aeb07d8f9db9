//! Writes what `report` draws and formats into files: a run's maps, VTU and `summary.json`;
//! a sweep folder's maps on the sweep's common colour scale (`maps/<id>.png`), report sheet
//! (`report.png`) and `results.json`; the paper's Figure 6; the convergence study's CSV and
//! chart; the fit's chart. The studies leave their results
//! (and a sweep its rows and fields) as plain data or in their folder; this reads and writes.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::core::drawing::{DrawingResult, Tooling};
use crate::core::fabric::law::CellParams;
use crate::core::solver::SolveStats;
use crate::files::write_atomic;
use crate::report::converge;
use crate::report::error::DrawError;
use crate::report::figure6::{figure6_chart, figure6_csv, figure6_table};
use crate::report::fit::fit_chart;
use crate::report::maps::{self, MapContext};
use crate::report::newton_trace;
use crate::report::sweep::{design_label, field_map, results_json, shared_scale_max, sheet};
use crate::report::vtu::vtu_string;
use crate::study::converge::Ladder;
use crate::study::fit::{FitResult, Sample};
use crate::study::sweep::{Plan, Row, Shard, StoreError, StoredField};
use crate::summary::RunSummary;

/// Why a file could not be written.
#[derive(Debug, thiserror::Error)]
pub enum PublishError {
    #[error(transparent)]
    Draw(#[from] DrawError),
    #[error(transparent)]
    Store(#[from] StoreError),
    /// The folder is not wovenform's to write into.
    #[error(transparent)]
    Folder(#[from] crate::files::OverwriteError),
}

fn io(path: &Path, action: &'static str) -> impl FnOnce(std::io::Error) -> PublishError {
    let to_store = StoreError::io(path, action);
    move |source| PublishError::Store(to_store(source))
}

/// Draws the maps (on `pool`), the sheet and `results.json` of the sweep folder `dir` whose
/// rows are `rows`; returns the files of the folder a user opens.
pub fn sweep_report(
    plan: &Plan,
    dir: &Path,
    rows: &[Row],
    shard: Option<Shard>,
    pool: &rayon::ThreadPool,
) -> Result<Vec<PathBuf>, PublishError> {
    let designs = plan.designs();
    let top = shared_scale_max(plan, rows);
    let read = |r: &Row| StoredField::read(dir, &r.design).map_err(PublishError::from);
    // Every map on the common scale.
    let drawn: Vec<Result<(), PublishError>> = pool.install(|| {
        rows.par_iter()
            .with_max_len(1)
            .filter(|r| r.map.is_some())
            .map(|r| {
                let label = design_label(plan, &designs[r.index]);
                let png = dir.join("maps").join(format!("{}.png", r.design));
                Ok(field_map(&read(r)?, &label, top).write_png(&png)?)
            })
            .collect()
    });
    drawn.into_iter().collect::<Result<Vec<()>, _>>()?;
    let report = dir.join("report.png");
    sheet(plan, rows, &designs, top, &read)?.write_png(&report)?;
    let json = dir.join("results.json");
    crate::study::sweep::write_atomic(&json, &results_json(plan, rows, shard, top))?;
    Ok(vec![
        dir.join("results.csv"),
        json,
        report,
        dir.join("maps"),
    ])
}

/// The files [`write_run`] writes into its folder (the last only where the fabric bends).
pub const RUN_FILES: [&str; 8] = [
    "summary.json",
    "shear.png",
    "tension.png",
    "shear_developed.png",
    "tension_developed.png",
    "form.png",
    "result.vtu",
    "wrinkles.png",
];

/// The files a sweep (and a frontier, a merge) writes at the top of its folder, besides the
/// folders `maps/` and `fields/`.
pub const SWEEP_FILES: [&str; 5] = [
    "results.csv",
    "results.json",
    "report.png",
    "sweep.lock",
    crate::study::sweep::LOCK_FILE,
];

/// The files [`write_frontier`] writes.
pub const FRONTIER_FILES: [&str; 3] = ["frontier.csv", "frontier.json", "frontier.png"];

/// Writes `shear.png`, `tension.png`, their developed views (`shear_developed.png`,
/// `tension_developed.png`: on the flat blank), `form.png` (the formed blank in 3-D),
/// `result.vtu`, `summary.json` and, where the
/// fabric has bending, `wrinkles.png` into `dir`
/// (claimed: see [`crate::files::claim_folder`]), records them in `summary.files`, and returns their paths. Errors name the file.
pub fn write_run(
    dir: &Path,
    summary: &mut RunSummary,
    result: &DrawingResult,
    tooling: &Tooling,
) -> Result<Vec<PathBuf>, PublishError> {
    crate::files::claim_folder(dir)?;
    let design = summary.design_line();
    let ctx = MapContext {
        design: &design,
        scene: &summary.scene,
        verdict: &summary.verdict,
        tooling: tooling.clone(),
        stroke_mm: summary.stroke_mm,
    };
    let shear = dir.join("shear.png");
    maps::shear_map(result, &ctx, summary.locking_angle_deg).write_png(&shear)?;
    let tension = dir.join("tension.png");
    maps::tension_map(result, &ctx, summary.break_tension_n).write_png(&tension)?;
    let shear_flat = dir.join("shear_developed.png");
    maps::shear_developed(result, &ctx, summary.locking_angle_deg).write_png(&shear_flat)?;
    let tension_flat = dir.join("tension_developed.png");
    maps::tension_developed(result, &ctx, summary.break_tension_n).write_png(&tension_flat)?;
    let form = dir.join("form.png");
    maps::form_view(result, &ctx, summary.locking_angle_deg).write_png(&form)?;
    let vtu_path = dir.join("result.vtu");
    write_atomic(&vtu_path, vtu_string(result).as_bytes())
        .map_err(io(&vtu_path, "write the VTU file"))?;
    let json = dir.join("summary.json");
    let written = vec![
        json.clone(),
        shear,
        tension,
        shear_flat,
        tension_flat,
        form,
        vtu_path,
    ];
    let kinds = [
        "summary",
        "shear_map",
        "tension_map",
        "shear_developed_map",
        "tension_developed_map",
        "form_map",
        "vtu",
    ];
    for (kind, path) in kinds.iter().zip(&written) {
        summary
            .files
            .insert(kind.to_string(), path.display().to_string());
    }
    // With bending: the wrinkle map too.
    let mut written = written;
    if let Some(map) = maps::wrinkle_map(result, &ctx, summary.wrinkle_limit_mm) {
        let path = dir.join("wrinkles.png");
        map.write_png(&path)?;
        summary
            .files
            .insert("wrinkle_map".to_string(), path.display().to_string());
        written.push(path);
    }
    let text = serde_json::to_string_pretty(&*summary).expect("the summary is plain data");
    write_atomic(&json, (text + "\n").as_bytes()).map_err(io(&json, "write the summary"))?;
    Ok(written)
}

/// Writes `dir/newton_trace.csv` and `dir/newton_trace.png` (`dir` exists): the run's Newton
/// iterations as recorded in `stats` ([`crate::report::newton_trace`]); records them in
/// `summary.files` (`newton_trace`, `newton_trace_chart`) and returns their paths.
pub fn write_newton_trace(
    dir: &Path,
    summary: &mut RunSummary,
    stats: &SolveStats,
    stroke_mm: f64,
    title: &str,
) -> Result<[PathBuf; 2], PublishError> {
    let csv = dir.join(NEWTON_TRACE_FILES[0]);
    write_atomic(&csv, newton_trace::csv(stats, stroke_mm).as_bytes())
        .map_err(io(&csv, "write"))?;
    let png = dir.join(NEWTON_TRACE_FILES[1]);
    newton_trace::chart(stats, title).write_png(&png)?;
    for (kind, path) in ["newton_trace", "newton_trace_chart"]
        .iter()
        .zip([&csv, &png])
    {
        (summary.files).insert(kind.to_string(), path.display().to_string());
    }
    Ok([csv, png])
}

/// The files [`write_newton_trace`] writes.
pub const NEWTON_TRACE_FILES: [&str; 2] = ["newton_trace.csv", "newton_trace.png"];

/// Writes `dir/figure6.csv` and `dir/figure6.png` (creating `dir`); returns the paths written.
pub fn write_figure6(params: CellParams, dir: &Path) -> Result<Vec<PathBuf>, PublishError> {
    crate::files::claim_folder(dir)?;
    let rows = figure6_table(params, 121);
    let csv = dir.join("figure6.csv");
    write_atomic(&csv, figure6_csv(&rows).as_bytes()).map_err(io(&csv, "write"))?;
    let png = dir.join("figure6.png");
    figure6_chart(&rows).write_png(&png)?;
    Ok(vec![csv, png])
}

/// Writes `dir/converge.csv` and `dir/converge.png` (`dir` exists); returns their paths.
pub fn write_converge(
    dir: &Path,
    mesh: &Ladder,
    steps: &Ladder,
) -> Result<[PathBuf; 2], PublishError> {
    let csv = dir.join("converge.csv");
    write_atomic(&csv, converge::csv(mesh, steps).as_bytes()).map_err(io(&csv, "write"))?;
    let png = dir.join("converge.png");
    converge::chart(mesh, steps).write_png(&png)?;
    Ok([csv, png])
}

/// Writes `dir/fit.png` (creating `dir`): the data named `data_name` against the fitted law.
pub fn write_fit(
    dir: &Path,
    samples: &[Sample],
    result: &FitResult,
    data_name: &str,
) -> Result<PathBuf, PublishError> {
    crate::files::claim_folder(dir)?;
    let title = format!(
        "Fit of {data_name}: A = {:.4} mm, B = {:.3} 1/N, RMS {:.2} N",
        result.params.a, result.params.b, result.rms_n
    );
    let png = dir.join("fit.png");
    fit_chart(samples, result, &title).write_png(&png)?;
    Ok(png)
}

/// Writes a bias-extension test's `bias.csv` (`displacement_mm,force_n,shear_centre_deg`),
/// `bias.png` (its force against the ideal kinematics', and `measured` points when given) and
/// `shear.png` into `dir` (created); returns their paths.
pub fn write_bias(
    dir: &Path,
    problem: &crate::core::specimens::bias::BiasProblem,
    result: &crate::core::specimens::bias::BiasResult,
    locking_angle_deg: f64,
    measured: Option<&[(f64, f64)]>,
) -> Result<Vec<PathBuf>, PublishError> {
    use crate::report::bias;
    crate::files::claim_folder(dir)?;
    let csv_path = dir.join("bias.csv");
    let mut w = csv::Writer::from_writer(Vec::new());
    let row_error = |e: csv::Error| io(&csv_path, "write")(std::io::Error::other(e.to_string()));
    w.write_record(["displacement_mm", "force_n", "shear_centre_deg"])
        .map_err(row_error)?;
    for i in 0..result.displacement_mm.len() {
        w.write_record([
            format!("{:.4}", result.displacement_mm[i]),
            format!("{:.6}", result.force_n[i]),
            format!("{:.4}", result.shear_centre_deg[i]),
        ])
        .map_err(|e| io(&csv_path, "write")(std::io::Error::other(e.to_string())))?;
    }
    let text = w
        .into_inner()
        .map_err(|e| io(&csv_path, "write")(std::io::Error::other(e.to_string())))?;
    crate::study::sweep::write_atomic(&csv_path, &String::from_utf8_lossy(&text))?;
    let png = dir.join("bias.png");
    bias::force_chart(problem, result, measured).write_png(&png)?;
    let map = dir.join("shear.png");
    bias::shear_map(problem, result, locking_angle_deg).write_png(&map)?;
    Ok(vec![csv_path, png, map])
}

/// Writes `text` whole into `path`; returns the path.
pub fn write_text(path: &Path, text: &str) -> Result<PathBuf, PublishError> {
    write_atomic(path, text.as_bytes()).map_err(io(path, "write"))?;
    Ok(path.to_path_buf())
}

/// Writes a frontier's `frontier.csv`, `frontier.json` and `frontier.png` into `dir`; returns
/// them. `accuracy` names the level the runs were made at.
pub fn write_frontier(
    frontier: &crate::study::frontier::Frontier,
    dir: &Path,
    accuracy: Option<&str>,
) -> Result<Vec<PathBuf>, PublishError> {
    use crate::report::frontier::{chart, frontier_csv, frontier_json};
    let [csv, json, png] = FRONTIER_FILES.map(|f| dir.join(f));
    let csv = write_text(&csv, &frontier_csv(frontier))?;
    let json = write_text(&json, &frontier_json(frontier, accuracy))?;
    crate::report::canvas::write_png(&png, chart::SIZE, "chart", |area| {
        chart::draw(frontier, area)
    })?;
    Ok(vec![csv, json, png])
}
