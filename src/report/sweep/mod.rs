//! What a sweep draws and prints, from plain data (the plan, the rows, the stored fields): each
//! design's map on one colour scale, the report sheet, the feasibility table and
//! `results.json`. Nothing here reads or writes a file; [`crate::publish`] does.

mod chart;
mod json;
mod sheet;
mod table;
mod window;

pub use json::results_json;
pub use sheet::{SHEET_TILES, sheet};
pub use table::{aligned, ranked, table};

use super::maps::{FieldMap, Outline, Unit};
use super::mirror::{PlanQuad, mirror_quads};
use crate::study::sweep::{Design, Plan, Row, StoredField};

/// The top of the common colour scale: a little past the locking angle, or the largest max
/// shear of the designs that converged.
pub fn shared_scale_max(plan: &Plan, rows: &[Row]) -> f64 {
    let locking = plan.base_scene.fabric.locking_angle_deg;
    rows.iter()
        .filter(|r| r.converged)
        .filter_map(|r| r.max_shear_deg)
        .fold(1.1 * locking, f64::max)
}

/// A design's label: its id and swept parameters, e.g. `d007 (r 5, rp 6, rm 5 mm; friction 0.2)`.
pub fn design_label(plan: &Plan, design: &Design) -> String {
    let lines = plan.label_lines(design);
    if lines.is_empty() {
        design.id.clone()
    } else {
        format!("{} ({})", design.id, lines.join("; "))
    }
}

/// The full blank's plan quads and shear values (mirrored when a quarter was solved).
pub fn full_blank(field: &StoredField) -> (Vec<PlanQuad>, Vec<f64>) {
    full_blank_of(field, &field.shear_deg)
}

/// The full blank's plan quads and `values`, one per element of the field (mirrored when a
/// quarter was solved; missing values read 0).
pub fn full_blank_of(field: &StoredField, values: &[f64]) -> (Vec<PlanQuad>, Vec<f64>) {
    let quads: Vec<PlanQuad> = field
        .quads
        .iter()
        .map(|q| q.map(|n| field.nodes.get(n as usize).copied().unwrap_or([0.0; 2])))
        .collect();
    let mut values = values.to_vec();
    values.resize(quads.len(), 0.0);
    if field.quarter {
        mirror_quads(&quads, &values)
    } else {
        (quads, values)
    }
}

/// The map of one design of a sweep, on the sweep's common colour scale.
pub fn field_map(field: &StoredField, label: &str, scale_max: f64) -> FieldMap {
    let (quads, values) = full_blank(field);
    let title = format!(
        "{label}: max shear {} over a woven cell (locking {}) — {}",
        Unit::Degrees.show(field.max_shear_deg),
        Unit::Degrees.show(field.locking_angle_deg),
        field.verdict
    );
    let subtitle = format!("{}; one colour scale for the whole sweep", field.subtitle);
    FieldMap {
        max_at: field.max_at,
        peak: Some(field.max_shear_deg),
        outlines: vec![Outline::dashed(field.die_opening.clone())],
        scale_max: Some(scale_max),
        ..FieldMap::shear(title, subtitle, quads, values, field.locking_angle_deg)
    }
}
