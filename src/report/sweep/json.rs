//! `results.json`: the sweep's plan, counts, error level and every row, as one JSON document.

use crate::accuracy::Accuracy;
use crate::study::sweep::{Plan, Row, Shard, column_names, counts};

/// The text of `results.json`; `top` is the common colour scale's top, degrees.
pub fn results_json(plan: &Plan, rows: &[Row], shard: Option<Shard>, top: f64) -> String {
    let c = counts(rows);
    let level = Accuracy::of_element_size(plan.base_scene.mesh.element_size);
    let obj = serde_json::json!({
        "program": "wovenform",
        "version": env!("CARGO_PKG_VERSION"),
        "sweep_file": plan.sweep_file,
        "base_file": plan.base_file,
        "set": plan.set,
        "base_scene": plan.base_scene,
        "base_hash": plan.base_hash,
        "sweep_hash": plan.sweep_hash,
        "sweep": plan.axes,
        "designs": plan.len(),
        "shard": shard.map(|s| s.to_string()),
        "shard_rule": "design index modulo N (shard I/N runs the indices i with i % N == I - 1)",
        "columns": column_names(&plan.columns()),
        "counts": {
            "feasible": c.feasible,
            "marginal": c.marginal,
            "infeasible": c.infeasible,
            "failed": c.failed,
            "invalid": c.invalid,
            "rows": rows.len(),
        },
        "locking_angle_deg": plan.base_scene.fabric.locking_angle_deg,
        "break_tension_n": plan.base_scene.fabric.break_tension_n,
        "accuracy": level.map(|a| a.name()),
        "max_shear_err_deg": level.map(|a| a.error().max_shear_deg),
        "punch_force_err_pct": level.map(|a| a.error().punch_force_pct),
        "max_tension_err_pct": level.map(|a| a.error().max_tension_pct),
        "shear_scale_max_deg": top,
        "rows": rows,
    });
    serde_json::to_string_pretty(&obj).expect("plain data") + "\n"
}
