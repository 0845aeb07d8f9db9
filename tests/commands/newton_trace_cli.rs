//! `wovenform run --newton-trace`: a row per Newton iteration, in step with the run's own
//! counts, and a run that is the same with the trace as without it.

use std::path::Path;

use serde_json::Value;

use crate::common::{preset, text, wovenform_in};

/// The open box, coarse and shallow: a run of well under a second.
const QUICK: [&str; 6] = [
    "--set",
    "mesh.element_size=5",
    "--set",
    "process.stroke=6",
    "--set",
    "blank.size=140",
];

const COLUMNS: &str = "step,accepted,load_factor,punch_travel_mm,iteration,residual_n,active_changes,\
line_search_length,damping,largest_node,largest_x_mm,largest_y_mm,largest_z_mm,\
largest_residual_n,largest_touching,share_touching,share_on_toe";

fn run(dir: &Path, out: &Path, extra: &[&str]) -> Value {
    let open = preset("paper-box-open.toml");
    let args = [
        &[
            "run",
            open.as_str(),
            "--json",
            "--out",
            out.to_str().unwrap(),
        ][..],
        &QUICK,
        extra,
    ]
    .concat();
    let o = wovenform_in(dir, &args);
    assert_eq!(o.status.code(), Some(0), "stderr: {}", text(&o.stderr));
    serde_json::from_str(text(&o.stdout).trim()).unwrap()
}

fn field(row: &[&str], i: usize) -> f64 {
    row[i]
        .parse()
        .unwrap_or_else(|e| panic!("column {i} of {row:?}: {e}"))
}

#[test]
fn the_trace_has_a_row_per_iteration_and_leaves_the_run_alone() {
    let dir = tempfile::tempdir().unwrap();
    let (plain, traced) = (dir.path().join("plain"), dir.path().join("traced"));
    let a = run(dir.path(), &plain, &[]);
    let b = run(dir.path(), &traced, &["--newton-trace"]);
    for k in ["max_shear_deg", "max_tension_n", "punch_force_n", "steps"] {
        assert_eq!(a[k], b[k], "{k} moved with the trace");
    }
    assert_eq!(a["newton_iterations"], b["newton_iterations"]);
    assert!(
        !plain.join("newton_trace.csv").exists(),
        "a trace nobody asked for"
    );
    let csv_path = traced.join("newton_trace.csv");
    assert_eq!(b["files"]["newton_trace"], csv_path.to_str().unwrap());

    let body = std::fs::read_to_string(&csv_path).unwrap();
    let mut lines = body.lines();
    assert_eq!(lines.next(), Some(COLUMNS));
    let col = |name: &str| COLUMNS.split(',').position(|c| c == name).unwrap();
    let (length, residual, node) = (
        col("line_search_length"),
        col("residual_n"),
        col("largest_residual_n"),
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let corrections = rows.iter().filter(|r| !r[length].is_empty()).count();
    let ends: Vec<&Vec<&str>> = rows.iter().filter(|r| r[length].is_empty()).collect();
    assert_eq!(corrections as u64, b["newton_iterations"].as_u64().unwrap());
    // No cut-back on this run: every attempt converged, one per load step.
    assert_eq!(b["cutbacks"], 0);
    assert!(rows.iter().all(|r| r[col("accepted")] == "true"));
    assert_eq!(ends.len() as u64, b["steps"].as_u64().unwrap());
    // The last step ends at the full stroke.
    let last = ends.last().unwrap();
    assert!(
        (field(last, col("load_factor")) - 1.0).abs() < 1e-9,
        "{last:?}"
    );
    assert!(
        (field(last, col("punch_travel_mm")) - 6.0).abs() < 1e-6,
        "{last:?}"
    );
    for r in &rows {
        assert_eq!(r.len(), 17, "{r:?}");
        let (total, at_node) = (field(r, residual), field(r, node));
        // A node's share of the residual vector has a norm no larger than the whole's.
        assert!(at_node <= total * (1.0 + 1e-3) + 1e-12, "{r:?}");
        for name in ["share_touching", "share_on_toe"] {
            assert!((0.0..=1.0).contains(&field(r, col(name))), "{r:?}");
        }
        if !r[length].is_empty() {
            assert!((0.0..=1.0).contains(&field(r, length)), "{r:?}");
        }
    }
    // Each step ends far below where it began, or far below the run's load (the first step's
    // residual, the punch meeting the blank): Newton converged on every one. The solver's
    // tolerance is relative to the load, so a step that starts close to its balance (a few N
    // against the first step's 10⁴) may end at a thousandth of its start only; and the
    // decrement test ends a step within a thousand force tolerances (10⁻³ of the forces) once
    // its last correction releases at most 10⁻³ of the energy the step stored, which on this
    // run is up to 10⁻⁴ of the load (step 15 on 2026-12-07: 224.7 → 0.27 N, the load 2.5·10⁴ N).
    let steps: Vec<Vec<f64>> = (1..=ends.len())
        .map(|step| {
            rows.iter()
                .filter(|r| r[0] == step.to_string())
                .map(|r| field(r, residual))
                .collect()
        })
        .collect();
    let load = steps.iter().map(|of| of[0]).fold(0.0, f64::max);
    for (step, of) in steps.iter().enumerate() {
        let last = *of.last().unwrap();
        assert!(
            last < of[0] * 1e-3 || last < load * 1e-4,
            "step {}: {of:?}",
            step + 1
        );
    }

    let png = traced.join("newton_trace.png");
    assert_eq!(b["files"]["newton_trace_chart"], png.to_str().unwrap());
    let img = image::open(&png).unwrap().to_rgb8();
    assert!(img.width() >= 800 && img.height() >= 500);
}
