//! The shear field of each design, kept in `fields/<id>.json` as its run finishes: what its
//! map and its tile on the report sheet are drawn from at the end, on the sweep's common
//! scale (and after a resume or a merge).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::folder_error::{StoreError, write_atomic};
use super::grid::Design;
use super::rows::round_to;
use crate::core::drawing::{DrawingResult, Tooling};
use crate::summary::{RunSummary, shear_subtitle};

/// The shear field of one design, kept so that its map and its tile on the sheet can be
/// drawn at the end on the sweep's common scale (and after a resume or a merge). The solved
/// part only (mirrored when drawn); positions to 0.001 mm, angles to 0.001°.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StoredField {
    pub design: String,
    /// The run's verdict in words (e.g. "INFEASIBLE: shear over the locking angle").
    pub verdict: String,
    pub max_shear_deg: f64,
    pub locking_angle_deg: f64,
    /// What the map shows (the blank, the stroke reached).
    pub subtitle: String,
    pub quarter: bool,
    /// Final plan positions of the solved part's nodes, mm.
    pub nodes: Vec<[f64; 2]>,
    pub quads: Vec<[u32; 4]>,
    /// |shear| of each element, degrees.
    pub shear_deg: Vec<f64>,
    pub max_at: Option<[f64; 2]>,
    pub die_opening: Vec<[f64; 2]>,
    /// The larger yarn tension of each element, N (to 0.1 N); empty in fields written before
    /// it was kept.
    #[serde(default)]
    pub tension_n: Vec<f64>,
    /// The figures the detail shows beside the map: the yarns' break tension and the peak
    /// over a cell (N), how far the blank's edge drew in (mm), and the share of the blank
    /// over the locking angle (%).
    #[serde(default)]
    pub break_tension_n: f64,
    #[serde(default)]
    pub max_tension_n: f64,
    #[serde(default)]
    pub draw_in_mm: f64,
    #[serde(default)]
    pub area_over_limit_pct: f64,
    /// The wrinkle amplitude of each element (the largest of its nodes', mm, to 0.001 mm), the
    /// largest and the limit: empty and `None` for the paper's membrane (no bending) and in
    /// fields written before wrinkles were kept.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub wrinkle_mm: Vec<f64>,
    #[serde(default)]
    pub max_wrinkle_mm: Option<f64>,
    #[serde(default)]
    pub wrinkle_limit_mm: f64,
}

impl StoredField {
    /// `dir/fields/<id>.json`.
    pub fn path(dir: &Path, id: &str) -> PathBuf {
        dir.join("fields").join(format!("{id}.json"))
    }

    pub fn read(dir: &Path, id: &str) -> Result<StoredField, StoreError> {
        let path = Self::path(dir, id);
        let field = |source: Box<dyn std::error::Error + Send + Sync>| StoreError::Field {
            path: path.clone(),
            source,
        };
        // A design's fields: a few values per element of a mesh that fits in memory.
        let text = crate::files::read_text(&path, 4_000_000_000).map_err(|e| field(e.into()))?;
        serde_json::from_str(&text).map_err(|e| field(e.into()))
    }

    pub(super) fn write(&self, dir: &Path) -> Result<(), StoreError> {
        let text = serde_json::to_string(self).expect("a field is plain data");
        write_atomic(&Self::path(dir, &self.design), &text)
    }

    /// The field of a run: its shear, the place of its largest shear, the die opening.
    pub(super) fn of_run(
        design: &Design,
        summary: &RunSummary,
        result: &DrawingResult,
        tooling: &Tooling,
    ) -> StoredField {
        let r3 = |v: f64| round_to(v, 3);
        // Where the summary found the peak (no second neighbour search).
        let [x, y, _] = summary.max_shear_at;
        let max_at = (!result.shear_deg.is_empty()).then_some([x, y]);
        StoredField {
            design: design.id.clone(),
            verdict: summary.verdict.clone(),
            max_shear_deg: summary.max_shear_deg,
            locking_angle_deg: summary.locking_angle_deg,
            subtitle: shear_subtitle(result, summary.stroke_mm),
            quarter: result.quarter,
            nodes: result
                .positions
                .iter()
                .map(|p| [r3(p[0]), r3(p[1])])
                .collect(),
            quads: result
                .mesh
                .quads
                .iter()
                .map(|q| q.map(|n| n as u32))
                .collect(),
            shear_deg: result.shear_deg.iter().map(|s| r3(s.abs())).collect(),
            max_at: max_at.map(|p| [r3(p[0]), r3(p[1])]),
            die_opening: tooling
                .die_opening_outline()
                .iter()
                .map(|p| [r3(p[0]), r3(p[1])])
                .collect(),
            tension_n: result
                .tension_max_n
                .iter()
                .map(|t| round_to(*t, 1))
                .collect(),
            break_tension_n: summary.break_tension_n,
            max_tension_n: r3(summary.max_tension_n),
            draw_in_mm: r3(summary.draw_in_mm),
            area_over_limit_pct: r3(summary.area_over_limit_pct),
            wrinkle_mm: result
                .wrinkle_mm
                .as_ref()
                .map(|w| {
                    let quads = &result.mesh.quads;
                    quads
                        .iter()
                        .map(|q| r3(q.iter().map(|&n| w[n]).fold(0.0, f64::max)))
                        .collect()
                })
                .unwrap_or_default(),
            max_wrinkle_mm: summary.max_wrinkle_mm.map(r3),
            wrinkle_limit_mm: summary.wrinkle_limit_mm,
        }
    }
}
