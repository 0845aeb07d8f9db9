//! Design sweeps: the grid of designs, parallel runs, the results table, resume, shards and
//! merge.
//!
//! A sweep file is TOML: a base scene (a scene file relative to the sweep file, and/or an
//! inline `[scene]` table whose keys go over it) and a `[sweep]` table of parameters, each a
//! scene key (`tools.r`, `process.stroke`, ...) or one of the box's short names
//! `r rp rm friction holder_pressure`, with a list of values or a range:
//!
//! ```toml
//! base = "paper-box-open.toml"
//! [scene]
//! mesh.element_size = 3.5
//! [sweep]
//! r = [5.0, 7.5, 10.0]
//! rm = { start = 5.0, stop = 10.0, count = 3 }   # both ends included
//! friction = [0.15, 0.2, 0.25]
//! ```
//!
//! The grid is the Cartesian product of the parameters, in a fixed order whatever the order
//! of the file: the short names first (`r rp rm friction holder_pressure`), then the other keys
//! alphabetically; the last one varies fastest. Design `i` has the id `d007-3fa1c2`: its
//! index and a hash of its parameter values. A design that breaks a bound of the scene
//! (checked by [`Scene::from_toml_str`] with the design's values as overrides) is a row with
//! verdict `INVALID` and the reason; it is not run.
//!
//! Output folder `DIR`: `results.csv` (a row appended and flushed as each design finishes),
//! `fields/<id>.json` (each design's shear field, written before its row), `sweep.lock` (the
//! plan: base scene, grid and their hashes, written before any work), and at the end
//! `maps/<id>.png` (every map on one colour scale), `report.png` and `results.json`.
//! `--resume` keeps the rows of `results.csv` whose design is in the grid (and whose field is
//! there), refuses a folder swept with another base scene, and runs the rest. Shard `I/N` runs
//! the designs whose index is `I − 1` modulo `N`; [`merge`] puts shard folders back together.

use std::collections::{BTreeMap, HashMap, HashSet};
use std::fmt::Write as _;
use std::fs;
use std::io::Write as _;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use rayon::prelude::*;
use serde::ser::SerializeMap;
use serde::{Deserialize, Serialize, Serializer};

use crate::core::drawing;
use crate::report::maps::{self, FieldMap, MapContext, Unit};
use crate::report::mirror::{PlanQuad, mirror_quads};
use crate::report::plot::{Colour, LegendAt, LineChart, Series, Style};
use crate::report::sheet::{Sheet, Tile, TileMap, Verdict};
use crate::report::summary::RunSummary;
use crate::scene::{Override, Scene, ToolKind};

/// The box's five short names and the scene keys they stand for, in grid order.
pub const SHORT_NAMES: [(&str, &str); 5] = [
    ("r", "tools.r"),
    ("rp", "tools.rp"),
    ("rm", "tools.rm"),
    ("friction", "process.friction"),
    ("holder_pressure", "process.holder_pressure"),
];

/// The columns of `results.csv` after the parameters, in order: the contract's figures, then
/// the design's id, its verdict and why it failed or is invalid.
pub const FIGURE_COLUMNS: [&str; 10] = [
    "max_shear_deg",
    "max_tension_n",
    "punch_force_n",
    "feasible",
    "converged",
    "wall_s",
    "map",
    "design",
    "verdict",
    "failure",
];

/// At most this many maps on the report sheet (the first ones in grid order).
pub const SHEET_TILES: usize = 81;

/// Why a sweep did not go through: bad input (exit 2) or a failure while running (exit 1).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SweepError {
    BadInput(String),
    Run(String),
}

impl std::fmt::Display for SweepError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SweepError::BadInput(m) | SweepError::Run(m) => f.write_str(m),
        }
    }
}

/// One swept parameter: the scene key, its column in the results and its values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    pub key: String,
    pub column: String,
    pub values: Vec<toml::Value>,
}

/// Everything a sweep needs, read from the sweep file (and stored in `DIR/sweep.lock`, so that
/// a resume or a merge can check it and rebuild the grid without the file).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// The sweep file as given.
    pub sweep_file: String,
    /// The base scene file (relative to the current folder), if any.
    pub base_file: Option<String>,
    /// The `--set` overrides of the base, as given.
    pub set: Vec<String>,
    /// The base scene's TOML text (the base file, with the inline `[scene]` keys over it).
    pub base_text: String,
    /// What errors in the base scene are blamed on.
    pub base_origin: String,
    /// The base scene as run (every key, defaults filled in), before the swept values.
    pub base_scene: Scene,
    pub axes: Vec<Axis>,
    /// FNV-1a hashes of the base scene (as run) and of the grid.
    pub base_hash: String,
    pub sweep_hash: String,
}

/// One design of the grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Design {
    pub index: usize,
    /// `d007-3fa1c2`: the index and a hash of the parameter values.
    pub id: String,
    /// One value per axis.
    pub values: Vec<toml::Value>,
}

/// A parameter column of the results: a swept axis, or a short name held at the base value.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    pub name: String,
    pub key: String,
    pub axis: Option<usize>,
}

/// Which slice of the grid to run: designs whose index is `index − 1` modulo `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// 1-based.
    pub index: usize,
    pub count: usize,
}

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Shard, String> {
        let bad = || format!("--shard {s}: expected I/N with 1 ≤ I ≤ N, e.g. --shard 2/8");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let index: usize = i.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Shard {
    pub fn contains(&self, index: usize) -> bool {
        index % self.count == self.index - 1
    }
}

/// One row of the results: a design and what came of it.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub design: String,
    pub index: usize,
    /// (column, value) for every parameter column.
    pub params: Vec<(String, toml::Value)>,
    /// Rounded to the precision printed in `results.csv` (°: 4 decimals; N, s: 3).
    pub max_shear_deg: Option<f64>,
    pub max_tension_n: Option<f64>,
    pub punch_force_n: Option<f64>,
    pub feasible: bool,
    pub converged: bool,
    pub wall_s: Option<f64>,
    /// `maps/<id>.png`, for designs that ran.
    pub map: Option<String>,
    pub verdict: Verdict,
    pub failure: Option<String>,
}

impl Serialize for Row {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        struct Params<'a>(&'a [(String, toml::Value)]);
        impl Serialize for Params<'_> {
            fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                let mut m = s.serialize_map(Some(self.0.len()))?;
                for (k, v) in self.0 {
                    m.serialize_entry(k, v)?;
                }
                m.end()
            }
        }
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("design", &self.design)?;
        m.serialize_entry("index", &self.index)?;
        m.serialize_entry("params", &Params(&self.params))?;
        m.serialize_entry("max_shear_deg", &self.max_shear_deg)?;
        m.serialize_entry("max_tension_n", &self.max_tension_n)?;
        m.serialize_entry("punch_force_n", &self.punch_force_n)?;
        m.serialize_entry("feasible", &self.feasible)?;
        m.serialize_entry("converged", &self.converged)?;
        m.serialize_entry("wall_s", &self.wall_s)?;
        m.serialize_entry("map", &self.map)?;
        m.serialize_entry("verdict", &self.verdict)?;
        m.serialize_entry("failure", &self.failure)?;
        m.end()
    }
}

// ---------------------------------------------------------------------------------------------
// The sweep file
// ---------------------------------------------------------------------------------------------

/// 64-bit FNV-1a, as 16 hex digits: stable across platforms and Rust versions.
pub fn fnv_hex(text: &str) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// A value as written in tables and ids: `5`, `7.5`, `true`, `full`, `[5, 4]`.
pub fn show_value(v: &toml::Value) -> String {
    match v {
        toml::Value::Float(f) => format!("{f}"),
        toml::Value::Integer(i) => format!("{i}"),
        toml::Value::Boolean(b) => format!("{b}"),
        toml::Value::String(s) => s.clone(),
        toml::Value::Array(a) => {
            let parts: Vec<String> = a.iter().map(show_value).collect();
            format!("[{}]", parts.join(", "))
        }
        other => other.to_string(),
    }
}

/// The value in a TOML literal (for `--set`-style overrides).
fn toml_literal(v: &toml::Value) -> String {
    match v {
        toml::Value::Float(f) if f.fract() == 0.0 && f.abs() < 1e15 => format!("{f:.1}"),
        toml::Value::Float(f) => format!("{f}"),
        other => other.to_string(),
    }
}

fn as_number(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Float(f) => Some(*f),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// The unit written after a key's values, e.g. ` mm`.
pub fn unit_of(key: &str) -> &'static str {
    match key {
        "tools.kind" => "",
        k if k.starts_with("tools.") => " mm",
        "process.stroke" | "mesh.element_size" | "blank.size" => " mm",
        "process.holder_pressure" => " MPa",
        "fabric.locking_angle_deg" | "fabric.yarn_angle_deg" => "°",
        "fabric.break_tension_n" | "fabric.c" => " N",
        "fabric.l0" | "fabric.e0" | "fabric.a" => " mm",
        "fabric.b" => " 1/N",
        _ => "",
    }
}

fn lookup<'a>(table: &'a toml::Table, key: &str) -> Option<&'a toml::Value> {
    let mut parts = key.split('.');
    let mut v = table.get(parts.next()?)?;
    for p in parts {
        v = match v {
            toml::Value::Table(t) => t.get(p)?,
            _ => return None,
        };
    }
    Some(v)
}

/// Deep merge: `over`'s keys replace `base`'s, tables merged key by key.
fn merge_tables(base: &mut toml::Table, over: &toml::Table) {
    for (k, v) in over {
        match (base.get_mut(k), v) {
            (Some(toml::Value::Table(b)), toml::Value::Table(o)) => merge_tables(b, o),
            _ => {
                base.insert(k.clone(), v.clone());
            }
        }
    }
}

/// A `[sweep]` entry is a range when it is a table with any of these keys.
const RANGE_KEYS: [&str; 3] = ["start", "stop", "count"];

fn is_range(t: &toml::Table) -> bool {
    RANGE_KEYS.iter().any(|k| t.contains_key(*k))
}

/// The `[sweep]` entries with dotted keys (`[sweep] tools.r = ...` is a nested table in TOML).
fn flatten_sweep(prefix: &str, table: &toml::Table, out: &mut Vec<(String, toml::Value)>) {
    for (k, v) in table {
        let key = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            toml::Value::Table(t) if !is_range(t) => flatten_sweep(&key, t, out),
            _ => out.push((key, v.clone())),
        }
    }
}

/// Rounds a computed range value to 10 significant digits (0.30000000000000004 → 0.3).
fn tidy(v: f64) -> f64 {
    format!("{v:.10e}").parse().unwrap_or(v)
}

impl Plan {
    /// Reads a sweep file; `sets` are the `--set` overrides of the base scene. Errors name the
    /// file and the key (exit code 2).
    pub fn load(path: &Path, sets: &[String]) -> Result<Plan, SweepError> {
        let file = path.display().to_string();
        let bad = |detail: String| SweepError::BadInput(format!("{file}: {detail}"));
        let text = fs::read_to_string(path)
            .map_err(|e| bad(format!("cannot read the sweep file: {e}")))?;
        let doc: toml::Table = text.parse().map_err(|e: toml::de::Error| {
            bad(format!("not valid TOML: {}", e.to_string().trim_end()))
        })?;
        Plan::from_document(path, &doc, sets)
    }

    /// A plan from a parsed sweep document; `path` names it in errors and places a relative
    /// `base` file (the explorer builds its documents in memory).
    pub fn from_document(
        path: &Path,
        doc: &toml::Table,
        sets: &[String],
    ) -> Result<Plan, SweepError> {
        let file = path.display().to_string();
        let bad = |detail: String| SweepError::BadInput(format!("{file}: {detail}"));
        for key in doc.keys() {
            if !["base", "scene", "sweep"].contains(&key.as_str()) {
                return Err(bad(format!(
                    "{key}: unknown key; expected base = \"SCENE.toml\", a [scene] table and a [sweep] table"
                )));
            }
        }
        // The base scene: a file, an inline [scene] table over it, or both, or neither.
        let base_file = match doc.get("base") {
            None => None,
            Some(toml::Value::String(s)) => {
                let dir = path.parent().unwrap_or(Path::new(""));
                Some(dir.join(s))
            }
            Some(v) => {
                return Err(bad(format!(
                    "base = {v}: expected the path of a scene file, relative to the sweep file"
                )));
            }
        };
        let inline = match doc.get("scene") {
            None => None,
            Some(toml::Value::Table(t)) => Some(t.clone()),
            Some(v) => return Err(bad(format!("scene = {v}: expected a [scene] table"))),
        };
        let base_display = base_file.as_ref().map(|p| p.display().to_string());
        let (base_text, base_origin) = match (&base_file, &inline) {
            (None, None) => (String::new(), format!("{file} (the default scene)")),
            (Some(b), None) => {
                let t = fs::read_to_string(b).map_err(|e| {
                    bad(format!(
                        "base = {}: cannot read the scene file: {e}",
                        b.display()
                    ))
                })?;
                (t, b.display().to_string())
            }
            (None, Some(t)) => (
                toml::to_string(t).map_err(|e| bad(format!("[scene]: {e}")))?,
                format!("{file} [scene]"),
            ),
            (Some(b), Some(over)) => {
                let origin = format!("{} with {file} [scene]", b.display());
                let t = fs::read_to_string(b).map_err(|e| {
                    bad(format!(
                        "base = {}: cannot read the scene file: {e}",
                        b.display()
                    ))
                })?;
                let mut table: toml::Table = t.parse().map_err(|e: toml::de::Error| {
                    SweepError::BadInput(format!(
                        "{}: not valid TOML: {}",
                        b.display(),
                        e.to_string().trim_end()
                    ))
                })?;
                merge_tables(&mut table, over);
                (
                    toml::to_string(&table).map_err(|e| bad(format!("[scene]: {e}")))?,
                    origin,
                )
            }
        };
        let overrides = parse_sets(sets)?;
        let base_scene = Scene::from_toml_str(&base_text, &base_origin, &overrides)
            .map_err(|e| SweepError::BadInput(e.to_string()))?;
        let scene_table = toml::Table::try_from(&base_scene)
            .map_err(|e| SweepError::Run(format!("cannot tabulate the base scene: {e}")))?;

        // The parameters.
        let sweep = match doc.get("sweep") {
            Some(toml::Value::Table(t)) if !t.is_empty() => t,
            _ => {
                return Err(bad(
                    "expected a [sweep] table with at least one parameter, e.g. r = [5.0, 10.0]"
                        .into(),
                ));
            }
        };
        let mut entries = Vec::new();
        flatten_sweep("", sweep, &mut entries);
        let mut axes: Vec<Axis> = Vec::new();
        for (name, value) in entries {
            let key = SHORT_NAMES
                .iter()
                .find(|(s, _)| *s == name)
                .map(|(_, k)| k.to_string())
                .unwrap_or_else(|| name.clone());
            let base_value = match lookup(&scene_table, &key) {
                Some(toml::Value::Table(_)) | None => {
                    return Err(bad(format!(
                        "sweep.{name}: unknown key; expected a scene key (such as tools.r, process.stroke or mesh.element_size) or a short name: r, rp, rm, friction, holder_pressure"
                    )));
                }
                Some(v) => v.clone(),
            };
            if let Some(other) = axes.iter().find(|a| a.key == key) {
                return Err(bad(format!(
                    "sweep.{name}: {key} is swept twice (also as sweep.{})",
                    other.column
                )));
            }
            let values = axis_values(&name, &key, &value, &base_value).map_err(bad)?;
            let column = SHORT_NAMES
                .iter()
                .find(|(_, k)| *k == key)
                .map(|(s, _)| s.to_string())
                .unwrap_or_else(|| key.clone());
            axes.push(Axis {
                key,
                column,
                values,
            });
        }
        // The grid's order: the short names first, then the other keys alphabetically.
        axes.sort_by_key(|a| {
            let rank = SHORT_NAMES
                .iter()
                .position(|(_, k)| *k == a.key)
                .unwrap_or(SHORT_NAMES.len());
            (rank, a.key.clone())
        });
        let total = axes
            .iter()
            .try_fold(1usize, |n, a| n.checked_mul(a.values.len()))
            .unwrap_or(usize::MAX);
        if total > 1_000_000 {
            return Err(bad(format!(
                "the grid has {total} designs; expected at most 1,000,000 (split the sweep)"
            )));
        }
        let base_json = serde_json::to_string(&base_scene).expect("a scene is plain data");
        let base_hash = fnv_hex(&base_json);
        let sweep_json = serde_json::to_string(&axes).expect("the axes are plain data");
        let sweep_hash = fnv_hex(&format!("{base_hash}\n{sweep_json}"));
        Ok(Plan {
            sweep_file: file,
            base_file: base_display,
            set: sets.to_vec(),
            base_text,
            base_origin,
            base_scene,
            axes,
            base_hash,
            sweep_hash,
        })
    }

    /// The sweep's name: the sweep file's stem.
    pub fn name(&self) -> String {
        Path::new(&self.sweep_file)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "sweep".into())
    }

    /// The number of designs in the grid.
    pub fn len(&self) -> usize {
        self.axes.iter().map(|a| a.values.len()).product()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Every design, in grid order (the last axis varies fastest).
    pub fn designs(&self) -> Vec<Design> {
        let total = self.len();
        let width = (total.saturating_sub(1)).to_string().len().max(3);
        (0..total)
            .map(|index| {
                let mut rest = index;
                let mut values = vec![toml::Value::Boolean(false); self.axes.len()];
                for (a, axis) in self.axes.iter().enumerate().rev() {
                    let n = axis.values.len();
                    values[a] = axis.values[rest % n].clone();
                    rest /= n;
                }
                let canonical: Vec<String> = self
                    .axes
                    .iter()
                    .zip(&values)
                    .map(|(a, v)| format!("{}={}", a.key, show_value(v)))
                    .collect();
                let hash = fnv_hex(&canonical.join(";"));
                Design {
                    index,
                    id: format!("d{index:0width$}-{}", &hash[..6]),
                    values,
                }
            })
            .collect()
    }

    /// The parameter columns: the short names that apply to the base's punch (all five for a
    /// box) or are swept, then the other swept keys.
    pub fn columns(&self) -> Vec<Column> {
        let is_box = self.base_scene.tools.kind == ToolKind::Box;
        let mut cols = Vec::new();
        for (short, key) in SHORT_NAMES {
            let axis = self.axes.iter().position(|a| a.key == key);
            let applies = is_box || !matches!(short, "r" | "rp");
            if axis.is_some() || applies {
                cols.push(Column {
                    name: short.to_string(),
                    key: key.to_string(),
                    axis,
                });
            }
        }
        for (i, a) in self.axes.iter().enumerate() {
            if !SHORT_NAMES.iter().any(|(_, k)| *k == a.key) {
                cols.push(Column {
                    name: a.column.clone(),
                    key: a.key.clone(),
                    axis: Some(i),
                });
            }
        }
        cols
    }

    /// The `--set` overrides of the base, parsed.
    fn base_overrides(&self) -> Vec<Override> {
        parse_sets(&self.set).unwrap_or_default()
    }

    /// The design's scene, or why it breaks a bound (the message starts with the key).
    pub fn design_scene(&self, design: &Design) -> Result<Scene, String> {
        let mut sets = self.base_overrides();
        for (axis, v) in self.axes.iter().zip(&design.values) {
            let literal = toml_literal(v);
            sets.push(Override {
                key: axis.key.clone(),
                value: v.clone(),
                text: format!("{}={literal}", axis.key),
            });
        }
        Scene::from_toml_str(&self.base_text, &self.base_origin, &sets).map_err(|e| e.detail)
    }

    /// The design's row parameters, in column order.
    pub fn params(&self, columns: &[Column], design: &Design) -> Vec<(String, toml::Value)> {
        let table = toml::Table::try_from(&self.base_scene).unwrap_or_default();
        columns
            .iter()
            .map(|c| {
                let v = match c.axis {
                    Some(a) => design.values[a].clone(),
                    None => lookup(&table, &c.key)
                        .cloned()
                        .unwrap_or(toml::Value::String(String::new())),
                };
                (c.name.clone(), v)
            })
            .collect()
    }

    /// The swept parameters of a design in words, a line for the radii and one for the rest:
    /// `["r 5, rp 6, rm 5 mm", "friction 0.2, holder_pressure 1 MPa"]`. Axes with a single value
    /// are left out (they are the same for every design).
    pub fn label_lines(&self, design: &Design) -> Vec<String> {
        let mut radii = Vec::new();
        let mut rest = Vec::new();
        for (a, v) in self.axes.iter().zip(&design.values) {
            if a.values.len() < 2 {
                continue;
            }
            let name = a.column.rsplit('.').next().unwrap_or(&a.column);
            if matches!(a.column.as_str(), "r" | "rp" | "rm") {
                radii.push(format!("{name} {}", show_value(v)));
            } else {
                rest.push(format!("{name} {}{}", show_value(v), unit_of(&a.key)));
            }
        }
        let mut lines = Vec::new();
        if !radii.is_empty() {
            lines.push(format!("{} mm", radii.join(", ")));
        }
        if !rest.is_empty() {
            lines.push(rest.join(", "));
        }
        lines
    }
}

fn parse_sets(sets: &[String]) -> Result<Vec<Override>, SweepError> {
    sets.iter()
        .map(|s| s.parse::<Override>())
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| SweepError::BadInput(e.to_string()))
}

/// The values of one `[sweep]` entry: a list, a range, or one value.
fn axis_values(
    name: &str,
    key: &str,
    value: &toml::Value,
    base: &toml::Value,
) -> Result<Vec<toml::Value>, String> {
    let kind_ok = |v: &toml::Value| match base {
        toml::Value::Float(_) | toml::Value::Integer(_) => as_number(v).is_some(),
        toml::Value::Boolean(_) => matches!(v, toml::Value::Boolean(_)),
        toml::Value::String(_) => matches!(v, toml::Value::String(_)),
        // [x, y] pairs: one number (both) or a pair.
        toml::Value::Array(_) => as_number(v).is_some() || matches!(v, toml::Value::Array(_)),
        _ => true,
    };
    let expected = match base {
        toml::Value::Float(_) | toml::Value::Integer(_) => "numbers",
        toml::Value::Boolean(_) => "true/false",
        toml::Value::String(_) => "\"quoted strings\"",
        toml::Value::Array(_) => "numbers or [x, y] pairs",
        _ => "values",
    };
    let values = match value {
        toml::Value::Array(list) => {
            if list.is_empty() {
                return Err(format!(
                    "sweep.{name}: an empty list; expected at least one value for {key}"
                ));
            }
            list.clone()
        }
        toml::Value::Table(t) => {
            for k in t.keys() {
                if !RANGE_KEYS.contains(&k.as_str()) {
                    return Err(format!(
                        "sweep.{name}.{k}: unknown key in a range; expected {{ start = 5.0, stop = 10.0, count = 3 }}"
                    ));
                }
            }
            let num = |k: &str| -> Result<f64, String> {
                t.get(k).and_then(as_number).filter(|v| v.is_finite()).ok_or_else(|| {
                    format!("sweep.{name}: a range needs {k} = a number; expected {{ start = 5.0, stop = 10.0, count = 3 }}")
                })
            };
            let (start, stop) = (num("start")?, num("stop")?);
            let count = match t.get("count") {
                Some(toml::Value::Integer(c)) if (1..=10_000).contains(c) => *c as usize,
                _ => {
                    return Err(format!(
                        "sweep.{name}: a range needs count = a whole number from 1 to 10000 (both ends are included)"
                    ));
                }
            };
            if as_number(base).is_none() {
                return Err(format!(
                    "sweep.{name}: a range of numbers, but {key} takes {expected}; give a list instead"
                ));
            }
            (0..count)
                .map(|i| {
                    let v = if count == 1 {
                        start
                    } else {
                        start + (stop - start) * i as f64 / (count - 1) as f64
                    };
                    toml::Value::Float(tidy(v))
                })
                .collect()
        }
        one => vec![one.clone()],
    };
    if let Some(v) = values.iter().find(|v| !kind_ok(v)) {
        return Err(format!(
            "sweep.{name} = {}: expected {expected} for {key}",
            show_value(v)
        ));
    }
    Ok(values)
}

// ---------------------------------------------------------------------------------------------
// Results: CSV rows, fields, the lock
// ---------------------------------------------------------------------------------------------

fn round_to(v: f64, decimals: i32) -> f64 {
    let s = 10f64.powi(decimals);
    (v * s).round() / s
}

fn csv_field(s: &str) -> String {
    let s = s.replace(['\n', '\r'], " ");
    if s.contains([',', '"']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s
    }
}

/// Splits one CSV line (RFC 4180 quoting, no line breaks inside fields); `None` when a quote
/// is left open.
pub fn parse_csv_line(line: &str) -> Option<Vec<String>> {
    let mut fields = Vec::new();
    let mut field = String::new();
    let mut chars = line.chars().peekable();
    let mut quoted = false;
    while let Some(c) = chars.next() {
        if quoted {
            if c == '"' {
                if chars.peek() == Some(&'"') {
                    field.push('"');
                    chars.next();
                } else {
                    quoted = false;
                }
            } else {
                field.push(c);
            }
        } else {
            match c {
                '"' => quoted = true,
                ',' => fields.push(std::mem::take(&mut field)),
                _ => field.push(c),
            }
        }
    }
    if quoted {
        return None;
    }
    fields.push(field);
    Some(fields)
}

/// The header of `results.csv`.
pub fn csv_header(columns: &[Column]) -> String {
    let mut names: Vec<&str> = columns.iter().map(|c| c.name.as_str()).collect();
    names.extend(FIGURE_COLUMNS);
    names.join(",")
}

impl Row {
    /// The row as a CSV line (with its newline).
    pub fn to_csv(&self) -> String {
        let opt = |v: Option<f64>, d: usize| v.map(|v| format!("{v:.d$}")).unwrap_or_default();
        let mut fields: Vec<String> = self.params.iter().map(|(_, v)| show_value(v)).collect();
        fields.extend([
            opt(self.max_shear_deg, 4),
            opt(self.max_tension_n, 3),
            opt(self.punch_force_n, 3),
            self.feasible.to_string(),
            self.converged.to_string(),
            opt(self.wall_s, 3),
            self.map.clone().unwrap_or_default(),
            self.design.clone(),
            self.verdict.word().to_string(),
            self.failure.clone().unwrap_or_default(),
        ]);
        let fields: Vec<String> = fields.iter().map(|f| csv_field(f)).collect();
        fields.join(",") + "\n"
    }

    fn invalid(plan: &Plan, columns: &[Column], design: &Design, reason: String) -> Row {
        Row {
            design: design.id.clone(),
            index: design.index,
            params: plan.params(columns, design),
            max_shear_deg: None,
            max_tension_n: None,
            punch_force_n: None,
            feasible: false,
            converged: false,
            wall_s: None,
            map: None,
            verdict: Verdict::Invalid,
            failure: Some(reason),
        }
    }

    fn failed(plan: &Plan, columns: &[Column], design: &Design, reason: String, wall: f64) -> Row {
        Row {
            verdict: Verdict::Failed,
            wall_s: Some(round_to(wall, 3)),
            ..Row::invalid(plan, columns, design, reason)
        }
    }

    fn from_summary(plan: &Plan, columns: &[Column], design: &Design, s: &RunSummary) -> Row {
        let verdict = if !s.converged || !s.unsound.is_empty() {
            Verdict::Failed
        } else if s.feasible {
            Verdict::Feasible
        } else {
            Verdict::Infeasible
        };
        Row {
            design: design.id.clone(),
            index: design.index,
            params: plan.params(columns, design),
            max_shear_deg: Some(round_to(s.max_shear_deg, 4)),
            max_tension_n: Some(round_to(s.max_tension_n, 3)),
            punch_force_n: Some(round_to(s.punch_force_n, 3)),
            feasible: s.feasible,
            converged: s.converged,
            wall_s: Some(round_to(s.wall_s, 3)),
            map: Some(format!("maps/{}.png", design.id)),
            verdict,
            failure: s.failure.clone().or_else(|| {
                (!s.unsound.is_empty()).then(|| format!("not sound: {}", s.unsound.join("; ")))
            }),
        }
    }

    /// Reads a row from its CSV fields; the design must be in the grid. `None` if anything is
    /// off (a row half-written, from another grid, or with a figure that does not parse).
    fn from_csv(
        header: &HashMap<&str, usize>,
        fields: &[String],
        plan: &Plan,
        columns: &[Column],
        grid: &HashMap<&str, &Design>,
    ) -> Option<Row> {
        let get = |name: &str| header.get(name).and_then(|&i| fields.get(i));
        let design = *grid.get(get("design")?.as_str())?;
        let num = |name: &str| -> Option<Option<f64>> {
            let s = get(name)?;
            if s.is_empty() {
                Some(None)
            } else {
                s.parse::<f64>().ok().filter(|v| v.is_finite()).map(Some)
            }
        };
        let boolean = |name: &str| match get(name)?.as_str() {
            "true" => Some(true),
            "false" => Some(false),
            _ => None,
        };
        let text = |name: &str| get(name).filter(|s| !s.is_empty()).cloned();
        let verdict = Verdict::parse(get("verdict")?)?;
        let row = Row {
            design: design.id.clone(),
            index: design.index,
            params: plan.params(columns, design),
            max_shear_deg: num("max_shear_deg")?,
            max_tension_n: num("max_tension_n")?,
            punch_force_n: num("punch_force_n")?,
            feasible: boolean("feasible")?,
            converged: boolean("converged")?,
            wall_s: num("wall_s")?,
            map: text("map"),
            verdict,
            failure: text("failure"),
        };
        // The parameters written must be the design's (the id's hash says so too).
        for (name, v) in &row.params {
            if let Some(s) = get(name)
                && *s != show_value(v)
            {
                return None;
            }
        }
        Some(row)
    }
}

/// What `sweep.lock` holds.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Lock {
    program: String,
    version: String,
    base_hash: String,
    sweep_hash: String,
    shard: Option<String>,
    plan: Plan,
}

fn read_lock(dir: &Path) -> Result<Lock, String> {
    let path = dir.join("sweep.lock");
    let text = fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    serde_json::from_str(&text)
        .map_err(|e| format!("{}: not a sweep lock file: {e}", path.display()))
}

/// Writes `text` to `path` through a temporary file and a rename (never half a file).
fn write_atomic(path: &Path, text: &str) -> Result<(), String> {
    let tmp = path.with_extension(format!(
        "{}.tmp",
        path.extension().and_then(|e| e.to_str()).unwrap_or("")
    ));
    fs::write(&tmp, text).map_err(|e| format!("{}: cannot write: {e}", tmp.display()))?;
    fs::rename(&tmp, path).map_err(|e| format!("{}: cannot write: {e}", path.display()))
}

/// What the rows of an existing `results.csv` came to.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ReadReport {
    /// Rows kept.
    pub kept: usize,
    /// A last line without its newline (the program was stopped while writing it).
    pub truncated: usize,
    /// Rows whose design is not in this grid, or that do not parse.
    pub foreign: usize,
    /// Rows of a design already read.
    pub duplicates: usize,
    /// Rows whose field file is missing (they are run again).
    pub no_field: usize,
}

impl ReadReport {
    pub fn dropped(&self) -> usize {
        self.truncated + self.foreign + self.duplicates + self.no_field
    }

    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        if self.truncated > 0 {
            parts.push(format!("{} half-written last line", self.truncated));
        }
        if self.foreign > 0 {
            parts.push(format!("{} not of this grid", self.foreign));
        }
        if self.duplicates > 0 {
            parts.push(format!("{} duplicate", self.duplicates));
        }
        if self.no_field > 0 {
            parts.push(format!("{} without their field file", self.no_field));
        }
        if parts.is_empty() {
            format!("kept {} rows", self.kept)
        } else {
            format!("kept {} rows, dropped {}", self.kept, parts.join(", "))
        }
    }
}

/// Reads the rows of `dir/results.csv` that belong to the plan's grid (first of each design).
fn read_rows(dir: &Path, plan: &Plan) -> Result<(Vec<Row>, ReadReport), String> {
    let path = dir.join("results.csv");
    let text = match fs::read(&path) {
        Ok(b) => String::from_utf8_lossy(&b).into_owned(),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Default::default()),
        Err(e) => return Err(format!("{}: cannot read: {e}", path.display())),
    };
    let mut report = ReadReport::default();
    let mut lines: Vec<&str> = text.split_inclusive('\n').collect();
    if lines.last().is_some_and(|l| !l.ends_with('\n')) {
        lines.pop();
        report.truncated = 1;
    }
    let mut lines = lines.into_iter().map(|l| l.trim_end_matches(['\n', '\r']));
    let Some(header_line) = lines.next() else {
        return Ok((Vec::new(), report));
    };
    let header_fields = parse_csv_line(header_line).unwrap_or_default();
    let header: HashMap<&str, usize> = header_fields
        .iter()
        .enumerate()
        .map(|(i, h)| (h.as_str(), i))
        .collect();
    let columns = plan.columns();
    let designs = plan.designs();
    let grid: HashMap<&str, &Design> = designs.iter().map(|d| (d.id.as_str(), d)).collect();
    let mut seen = HashSet::new();
    let mut rows = Vec::new();
    for line in lines {
        if line.is_empty() {
            continue;
        }
        let row = parse_csv_line(line)
            .filter(|f| f.len() == header_fields.len())
            .and_then(|f| Row::from_csv(&header, &f, plan, &columns, &grid));
        let Some(row) = row else {
            report.foreign += 1;
            continue;
        };
        if !seen.insert(row.design.clone()) {
            report.duplicates += 1;
            continue;
        }
        if row.map.is_some() && StoredField::read(dir, &row.design).is_err() {
            report.no_field += 1;
            continue;
        }
        rows.push(row);
    }
    report.kept = rows.len();
    Ok((rows, report))
}

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
}

impl StoredField {
    fn path(dir: &Path, id: &str) -> PathBuf {
        dir.join("fields").join(format!("{id}.json"))
    }

    pub fn read(dir: &Path, id: &str) -> Result<StoredField, String> {
        let path = Self::path(dir, id);
        let text = fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    fn write(&self, dir: &Path) -> Result<(), String> {
        let text = serde_json::to_string(self).expect("a field is plain data");
        write_atomic(&Self::path(dir, &self.design), &text)
    }

    fn of_run(
        design: &Design,
        summary: &RunSummary,
        result: &drawing::DrawingResult,
        map: &FieldMap,
    ) -> StoredField {
        let r3 = |v: f64| round_to(v, 3);
        StoredField {
            design: design.id.clone(),
            verdict: summary.verdict.clone(),
            max_shear_deg: summary.max_shear_deg,
            locking_angle_deg: summary.locking_angle_deg,
            subtitle: map.subtitle.clone(),
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
            max_at: map.max_at.map(|p| [r3(p[0]), r3(p[1])]),
            die_opening: map
                .die_opening
                .iter()
                .map(|p| [r3(p[0]), r3(p[1])])
                .collect(),
        }
    }

    /// The full blank's plan quads and values (mirrored when a quarter was solved).
    pub fn full_blank(&self) -> (Vec<PlanQuad>, Vec<f64>) {
        let quads: Vec<PlanQuad> = self
            .quads
            .iter()
            .map(|q| q.map(|n| self.nodes.get(n as usize).copied().unwrap_or([0.0; 2])))
            .collect();
        let mut values = self.shear_deg.clone();
        values.resize(quads.len(), 0.0);
        if self.quarter {
            mirror_quads(&quads, &values)
        } else {
            (quads, values)
        }
    }

    fn field_map(&self, label: &str, scale_max: f64) -> FieldMap {
        let (quads, values) = self.full_blank();
        FieldMap {
            title: format!(
                "{label}: max shear {} (locking {}) — {}",
                Unit::Degrees.show(self.max_shear_deg),
                Unit::Degrees.show(self.locking_angle_deg),
                self.verdict
            ),
            subtitle: format!("{}; one colour scale for the whole sweep", self.subtitle),
            quads,
            values,
            limit: self.locking_angle_deg,
            limit_name: "locking angle".into(),
            bar_caption: "shear (°)".into(),
            unit: Unit::Degrees,
            max_at: self.max_at,
            die_opening: self.die_opening.clone(),
            size: (1100, 900),
            scale_max: Some(scale_max),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Running
// ---------------------------------------------------------------------------------------------

/// How to run a sweep.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Designs run at once (threads); `None`: every core.
    pub jobs: Option<usize>,
    pub shard: Option<Shard>,
    pub resume: bool,
    /// Set from another thread to stop: designs not started are left, running ones end at
    /// their next load step (their rows are not written, so a resume runs them again).
    pub stop: Option<Arc<AtomicBool>>,
    /// Leave out the maps, the report sheet and `results.json` at the end (the explorer
    /// draws them on export).
    pub skip_report: bool,
}

/// What a sweep reports while it runs.
#[derive(Debug)]
pub enum Progress<'a> {
    /// Before the first design: designs to run, rows kept from an earlier run, invalid designs.
    Start {
        to_run: usize,
        kept: &'a ReadReport,
        invalid: usize,
    },
    /// A design finished (or was found invalid); counts over this run.
    Done {
        row: &'a Row,
        done: usize,
        total: usize,
        feasible: usize,
    },
    /// The designs are done; the maps and the report are being drawn.
    Drawing { maps: usize },
}

/// What a sweep (or a merge) came to.
#[derive(Debug)]
pub struct Outcome {
    /// Every row of the folder, in grid order.
    pub rows: Vec<Row>,
    /// Designs of the grid (of this shard) without a row.
    pub missing: usize,
    /// Designs run now, and rows kept from before.
    pub ran: usize,
    pub kept: ReadReport,
    pub threads: usize,
    /// Wall time of the designs' runs (from the first start to the last finish), s.
    pub run_wall_s: f64,
    /// Wall time of the whole command, s.
    pub wall_s: f64,
    /// The files written at the end.
    pub files: Vec<PathBuf>,
    /// Stopped on request before every design had run.
    pub stopped: bool,
}

fn pool(jobs: Option<usize>) -> Result<rayon::ThreadPool, SweepError> {
    if jobs == Some(0) {
        return Err(SweepError::BadInput(
            "--jobs 0: expected at least one design at a time".into(),
        ));
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.unwrap_or(0))
        .thread_name(|i| format!("sweep-{i}"))
        .build()
        .map_err(|e| SweepError::Run(format!("cannot start the worker threads: {e}")))
}

/// Creates `dir`, `dir/maps` and `dir/fields` and writes `dir/sweep.lock`; an error here is
/// bad input (exit 2), found before any work.
fn prepare_dir(dir: &Path, plan: &Plan, shard: Option<Shard>) -> Result<(), SweepError> {
    let cannot = |p: &Path, e: &dyn std::fmt::Display| {
        SweepError::BadInput(format!(
            "{}: cannot write the output folder: {e}",
            p.display()
        ))
    };
    for d in [dir.to_path_buf(), dir.join("maps"), dir.join("fields")] {
        fs::create_dir_all(&d).map_err(|e| cannot(&d, &e))?;
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
    write_atomic(&dir.join("sweep.lock"), &(text + "\n")).map_err(|e| cannot(dir, &e))
}

/// The rows writer: one line per design, written whole and flushed, under a mutex.
struct Sink<'a> {
    state: Mutex<SinkState>,
    progress: &'a (dyn Fn(Progress) + Sync),
    total: usize,
}

struct SinkState {
    file: fs::File,
    rows: Vec<Row>,
    feasible: usize,
    error: Option<String>,
    path: PathBuf,
}

impl Sink<'_> {
    fn push(&self, row: Row) {
        let mut s = self.state.lock().unwrap_or_else(|e| e.into_inner());
        let line = row.to_csv();
        if let Err(e) = s
            .file
            .write_all(line.as_bytes())
            .and_then(|_| s.file.flush())
        {
            let msg = format!("{}: cannot write a row: {e}", s.path.display());
            s.error.get_or_insert(msg);
        }
        if row.verdict == Verdict::Feasible {
            s.feasible += 1;
        }
        s.rows.push(row);
        let (done, feasible) = (s.rows.len(), s.feasible);
        (self.progress)(Progress::Done {
            row: s.rows.last().expect("just pushed"),
            done,
            total: self.total,
            feasible,
        });
    }
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        s.to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "no message".into()
    }
}

/// Runs one valid design: solve (single-threaded), its field file, its row; `None` when
/// stopped on request before the end.
fn run_design(
    plan: &Plan,
    columns: &[Column],
    design: &Design,
    scene: &Scene,
    dir: &Path,
    stop: Option<&AtomicBool>,
) -> Option<Row> {
    let mut problem = scene.to_problem();
    problem.solver.parallel = false;
    let stopped = || stop.is_some_and(|s| s.load(Ordering::Relaxed));
    let start = std::time::Instant::now();
    let result = drawing::solve_until(&problem, &mut |_| {
        if stopped() {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    if stopped() {
        return None;
    }
    let summary = RunSummary::new(&design.id, scene, &result, start.elapsed().as_secs_f64());
    let ctx = MapContext {
        scene: &design.id,
        verdict: &summary.verdict,
        tooling: problem.tooling,
        stroke_mm: scene.process.stroke,
    };
    let map = maps::shear_map(&result, &ctx, summary.locking_angle_deg);
    let mut row = Row::from_summary(plan, columns, design, &summary);
    if let Err(e) = StoredField::of_run(design, &summary, &result, &map).write(dir) {
        row.map = None;
        let note = format!("the field was not saved: {e}");
        row.failure = Some(match row.failure.take() {
            Some(f) => format!("{f}; {note}"),
            None => note,
        });
    }
    Some(row)
}

/// Runs a sweep into `dir`: the designs of the grid (of the shard) without a row yet, in
/// parallel; then the maps, the report sheet and `results.json`.
pub fn run(
    plan: &Plan,
    dir: &Path,
    options: &Options,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<Outcome, SweepError> {
    let start = Instant::now();
    let pool = pool(options.jobs)?;
    let csv_path = dir.join("results.csv");
    let columns = plan.columns();
    let designs = plan.designs();
    // Before any work: the folder, the earlier rows, the lock.
    let (kept_rows, kept) = if options.resume && csv_path.exists() {
        let lock = read_lock(dir).map_err(|e| {
            SweepError::BadInput(format!(
                "--resume: {e}; cannot tell which sweep {} belongs to (remove the folder, or use another --out)",
                csv_path.display()
            ))
        })?;
        if lock.base_hash != plan.base_hash {
            return Err(SweepError::BadInput(format!(
                "--resume: {} was swept with another base scene ({} with {}; now {} with {}): its rows cannot be reused; use another --out, or remove the folder to start again",
                dir.display(),
                lock.plan.sweep_file,
                lock.plan.base_file.as_deref().unwrap_or("the inline scene"),
                plan.sweep_file,
                plan.base_file.as_deref().unwrap_or("the inline scene"),
            )));
        }
        read_rows(dir, plan).map_err(SweepError::Run)?
    } else if csv_path.exists() {
        return Err(SweepError::BadInput(format!(
            "{} exists: add --resume to continue that sweep, or choose another --out",
            csv_path.display()
        )));
    } else {
        (Vec::new(), ReadReport::default())
    };
    prepare_dir(dir, plan, options.shard)?;
    // The CSV, rewritten with the rows kept (a half-written line or a duplicate goes).
    let mut text = csv_header(&columns) + "\n";
    for r in &kept_rows {
        text.push_str(&r.to_csv());
    }
    write_atomic(&csv_path, &text).map_err(|e| {
        SweepError::BadInput(format!(
            "{}: cannot write the output folder: {e}",
            dir.display()
        ))
    })?;
    let file = fs::OpenOptions::new()
        .append(true)
        .open(&csv_path)
        .map_err(|e| SweepError::BadInput(format!("{}: cannot write: {e}", csv_path.display())))?;

    let have: HashSet<&str> = kept_rows.iter().map(|r| r.design.as_str()).collect();
    let pending: Vec<&Design> = designs
        .iter()
        .filter(|d| options.shard.is_none_or(|s| s.contains(d.index)))
        .filter(|d| !have.contains(d.id.as_str()))
        .collect();
    let mut valid = Vec::new();
    let mut invalid = Vec::new();
    for d in pending {
        match plan.design_scene(d) {
            Ok(scene) => valid.push((d, scene)),
            Err(reason) => invalid.push(Row::invalid(plan, &columns, d, reason)),
        }
    }
    progress(Progress::Start {
        to_run: valid.len(),
        kept: &kept,
        invalid: invalid.len(),
    });
    let sink = Sink {
        state: Mutex::new(SinkState {
            file,
            rows: Vec::new(),
            feasible: 0,
            error: None,
            path: csv_path.clone(),
        }),
        progress,
        total: valid.len() + invalid.len(),
    };
    for row in invalid {
        sink.push(row);
    }
    let run_start = Instant::now();
    let stop = options.stop.as_deref();
    pool.install(|| {
        valid.par_iter().with_max_len(1).for_each(|(d, scene)| {
            if stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
                return;
            }
            let t = Instant::now();
            let row = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                run_design(plan, &columns, d, scene, dir, stop)
            }))
            .unwrap_or_else(|payload| {
                let reason = format!(
                    "the program failed on this design: {}",
                    panic_message(&*payload)
                );
                Some(Row::failed(
                    plan,
                    &columns,
                    d,
                    reason,
                    t.elapsed().as_secs_f64(),
                ))
            });
            if let Some(row) = row {
                sink.push(row);
            }
        });
    });
    let stopped = stop.is_some_and(|s| s.load(Ordering::Relaxed));
    let run_wall_s = run_start.elapsed().as_secs_f64();
    let state = sink.state.into_inner().unwrap_or_else(|e| e.into_inner());
    if let Some(e) = state.error {
        return Err(SweepError::Run(e));
    }
    let ran = state
        .rows
        .iter()
        .filter(|r| r.verdict != Verdict::Invalid)
        .count();
    let mut rows = kept_rows;
    rows.extend(state.rows);
    rows.sort_by_key(|r| r.index);
    let mine = designs
        .iter()
        .filter(|d| options.shard.is_none_or(|s| s.contains(d.index)))
        .count();
    let present = rows
        .iter()
        .filter(|r| options.shard.is_none_or(|s| s.contains(r.index)))
        .count();
    let files = if options.skip_report {
        vec![csv_path]
    } else {
        progress(Progress::Drawing {
            maps: rows.iter().filter(|r| r.map.is_some()).count(),
        });
        finalize(plan, dir, &rows, options.shard, &pool).map_err(SweepError::Run)?
    };
    Ok(Outcome {
        missing: mine.saturating_sub(present),
        rows,
        ran,
        kept,
        threads: pool.current_num_threads(),
        run_wall_s,
        wall_s: start.elapsed().as_secs_f64(),
        files,
        stopped,
    })
}

/// Combines sweep folders (shards) of one sweep into `out`: the rows (the first of each
/// design), the fields, then the maps, the sheet and `results.json` as for a sweep.
/// Returns the sweep's plan (read from the folders' `sweep.lock`) with the outcome.
pub fn merge(
    inputs: &[PathBuf],
    out: &Path,
    jobs: Option<usize>,
) -> Result<(Plan, Outcome), SweepError> {
    let start = Instant::now();
    let pool = pool(jobs)?;
    if inputs.is_empty() {
        return Err(SweepError::BadInput(
            "merge: expected at least one sweep folder".into(),
        ));
    }
    // Never overwrite rows: an existing results set in `out` must be one of the inputs.
    if out.join("results.csv").exists() {
        let same = |a: &Path| match (fs::canonicalize(a), fs::canonicalize(out)) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        };
        if !inputs.iter().any(|d| same(d)) {
            return Err(SweepError::BadInput(format!(
                "merge: {} already holds a results.csv; list it among the folders to merge into it, or choose another --out",
                out.display()
            )));
        }
    }
    let mut plan: Option<(Plan, PathBuf)> = None;
    let mut rows: Vec<Row> = Vec::new();
    let mut sources: HashMap<String, PathBuf> = HashMap::new();
    let mut report = ReadReport::default();
    for dir in inputs {
        let lock = read_lock(dir).map_err(|e| {
            SweepError::BadInput(format!("{e}: {} is not a sweep folder", dir.display()))
        })?;
        if !dir.join("results.csv").exists() {
            return Err(SweepError::BadInput(format!(
                "{}: no results.csv: not a sweep folder",
                dir.display()
            )));
        }
        if let Some((p, first)) = &plan {
            if lock.base_hash != p.base_hash || lock.sweep_hash != p.sweep_hash {
                let what = if lock.base_hash != p.base_hash {
                    "base scene"
                } else {
                    "grid"
                };
                return Err(SweepError::BadInput(format!(
                    "merge: {} and {} come from different sweeps (their {what} differs: {} and {}); merge only the shards of one sweep",
                    first.display(),
                    dir.display(),
                    p.sweep_file,
                    lock.plan.sweep_file
                )));
            }
        } else {
            plan = Some((lock.plan.clone(), dir.clone()));
        }
        let (p, _) = plan.as_ref().expect("set above");
        let (found, r) = read_rows(dir, p).map_err(SweepError::Run)?;
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
    let (plan, _) = plan.expect("at least one input");
    report.kept = rows.len();
    rows.sort_by_key(|r| r.index);
    prepare_dir(out, &plan, None)?;
    for row in rows.iter().filter(|r| r.map.is_some()) {
        let from = StoredField::path(&sources[&row.design], &row.design);
        let to = StoredField::path(out, &row.design);
        let same = match (fs::canonicalize(&from), fs::canonicalize(&to)) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        };
        if !same {
            fs::copy(&from, &to).map_err(|e| {
                SweepError::Run(format!(
                    "cannot copy {} to {}: {e}",
                    from.display(),
                    to.display()
                ))
            })?;
        }
    }
    let columns = plan.columns();
    let mut text = csv_header(&columns) + "\n";
    for r in &rows {
        text.push_str(&r.to_csv());
    }
    write_atomic(&out.join("results.csv"), &text).map_err(SweepError::Run)?;
    let files = finalize(&plan, out, &rows, None, &pool).map_err(SweepError::Run)?;
    let outcome = Outcome {
        missing: plan.len().saturating_sub(rows.len()),
        rows,
        ran: 0,
        kept: report,
        threads: pool.current_num_threads(),
        run_wall_s: 0.0,
        wall_s: start.elapsed().as_secs_f64(),
        files,
        stopped: false,
    };
    Ok((plan, outcome))
}

// ---------------------------------------------------------------------------------------------
// The end: maps, sheet, results.json, the table
// ---------------------------------------------------------------------------------------------

/// Counts of the verdicts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Counts {
    pub feasible: usize,
    pub infeasible: usize,
    pub failed: usize,
    pub invalid: usize,
}

pub fn counts(rows: &[Row]) -> Counts {
    let mut c = Counts::default();
    for r in rows {
        match r.verdict {
            Verdict::Feasible => c.feasible += 1,
            Verdict::Infeasible => c.infeasible += 1,
            Verdict::Failed => c.failed += 1,
            Verdict::Invalid => c.invalid += 1,
        }
    }
    c
}

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
fn design_label(plan: &Plan, design: &Design) -> String {
    let lines = plan.label_lines(design);
    if lines.is_empty() {
        design.id.clone()
    } else {
        format!("{} ({})", design.id, lines.join("; "))
    }
}

fn finalize(
    plan: &Plan,
    dir: &Path,
    rows: &[Row],
    shard: Option<Shard>,
    pool: &rayon::ThreadPool,
) -> Result<Vec<PathBuf>, String> {
    let designs = plan.designs();
    let top = shared_scale_max(plan, rows);
    // Every map on the common scale.
    let drawn: Vec<Result<(), String>> = pool.install(|| {
        rows.par_iter()
            .with_max_len(1)
            .filter(|r| r.map.is_some())
            .map(|r| {
                let field = StoredField::read(dir, &r.design)?;
                let label = design_label(plan, &designs[r.index]);
                field
                    .field_map(&label, top)
                    .write_png(&dir.join("maps").join(format!("{}.png", r.design)))
            })
            .collect()
    });
    drawn.into_iter().collect::<Result<Vec<()>, String>>()?;
    let report = dir.join("report.png");
    sheet(plan, dir, rows, &designs, top)?.write_png(&report)?;
    let json = dir.join("results.json");
    write_atomic(&json, &results_json(plan, rows, shard, top))?;
    Ok(vec![
        dir.join("results.csv"),
        json,
        report,
        dir.join("maps"),
    ])
}

fn results_json(plan: &Plan, rows: &[Row], shard: Option<Shard>, top: f64) -> String {
    let c = counts(rows);
    let level = crate::accuracy::Accuracy::of_element_size(plan.base_scene.mesh.element_size);
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
        "columns": csv_header(&plan.columns()).split(',').collect::<Vec<_>>(),
        "counts": {
            "feasible": c.feasible,
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
        "shear_scale_max_deg": top,
        "rows": rows,
    });
    serde_json::to_string_pretty(&obj).expect("plain data") + "\n"
}

/// Values of a numeric axis, sorted and distinct.
fn numeric_values(axis: &Axis) -> Option<Vec<f64>> {
    let mut v: Vec<f64> = axis.values.iter().map(as_number).collect::<Option<_>>()?;
    v.sort_by(|a, b| a.total_cmp(b));
    v.dedup();
    Some(v)
}

/// Max shear against a swept radius (or the first numeric swept parameter), one line per
/// combination of the other swept parameters, the locking angle as a dashed line.
fn shear_chart(plan: &Plan, rows: &[Row], designs: &[Design]) -> (Option<LineChart>, Vec<String>) {
    let swept: Vec<usize> = (0..plan.axes.len())
        .filter(|&a| plan.axes[a].values.len() > 1)
        .collect();
    let numeric = |a: usize| numeric_values(&plan.axes[a]).filter(|v| v.len() > 1);
    let x_axis = swept
        .iter()
        .copied()
        .find(|&a| {
            matches!(plan.axes[a].column.as_str(), "r" | "rp" | "rm") && numeric(a).is_some()
        })
        .or_else(|| swept.iter().copied().find(|&a| numeric(a).is_some()));
    let Some(xa) = x_axis else {
        return (
            None,
            vec!["(no chart: no numeric parameter takes more than one value)".into()],
        );
    };
    let xs = numeric(xa).expect("numeric");
    let spacing = xs
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    let others: Vec<usize> = swept.iter().copied().filter(|&a| a != xa).collect();
    let xname = plan.axes[xa].column.clone();
    let xunit = unit_of(&plan.axes[xa].key).trim().to_string();
    let locking = plan.base_scene.fabric.locking_angle_deg;
    // Groups: the designs sharing the values of the other swept axes.
    let mut groups: BTreeMap<Vec<String>, Vec<&Row>> = BTreeMap::new();
    let mut order: Vec<Vec<String>> = Vec::new();
    for r in rows {
        let d = &designs[r.index];
        let key: Vec<String> = others.iter().map(|&a| show_value(&d.values[a])).collect();
        if !groups.contains_key(&key) {
            order.push(key.clone());
        }
        groups.entry(key).or_default().push(r);
    }
    // Only the groups with a point to plot (a converged run) take a place in the dodge.
    let plotted = |r: &Row| r.converged && r.max_shear_deg.is_some();
    order.retain(|k| groups[k].iter().any(|r| plotted(r)));
    let ng = order.len().max(1);
    let left_out = rows.iter().filter(|r| !plotted(r)).count();
    // Lines coloured by the first other axis when it has few values.
    let colour_axis = others
        .first()
        .copied()
        .filter(|&a| plan.axes[a].values.len() <= 7);
    let mut chart = LineChart::new(
        format!(
            "Max shear against {xname}{}",
            if xunit.is_empty() {
                String::new()
            } else {
                format!(" ({xunit})")
            }
        ),
        if xunit.is_empty() {
            xname.clone()
        } else {
            format!("{xname} ({xunit})")
        },
        "max shear (°)",
    );
    let mut feasible_pts = Vec::new();
    let mut infeasible_pts = Vec::new();
    let mut named: HashSet<String> = HashSet::new();
    for (gi, key) in order.iter().enumerate() {
        let dodge = if ng > 1 && spacing.is_finite() {
            ((gi as f64 + 0.5) / ng as f64 - 0.5) * 0.25 * spacing
        } else {
            0.0
        };
        let mut pts: Vec<(f64, f64)> = Vec::new();
        for r in &groups[key] {
            let d = &designs[r.index];
            let (Some(x), Some(y)) = (as_number(&d.values[xa]), r.max_shear_deg) else {
                continue;
            };
            if !r.converged {
                continue;
            }
            let p = (x + dodge, y);
            pts.push(p);
            if r.verdict == Verdict::Feasible {
                feasible_pts.push(p);
            } else {
                infeasible_pts.push(p);
            }
        }
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        if pts.is_empty() {
            continue;
        }
        let (name, colour) = match colour_axis {
            Some(ca) => {
                let v = &designs[groups[key][0].index].values[ca];
                let vi = plan.axes[ca]
                    .values
                    .iter()
                    .position(|x| x == v)
                    .unwrap_or(0);
                let label = format!(
                    "{} = {}{}",
                    plan.axes[ca].column,
                    show_value(v),
                    unit_of(&plan.axes[ca].key)
                );
                let name = if named.insert(label.clone()) {
                    label
                } else {
                    String::new()
                };
                (name, Colour::nth(vi))
            }
            None => (String::new(), Colour::nth(gi)),
        };
        chart.push(Series::new(name, pts, Style::Line, colour));
    }
    let pad = if spacing.is_finite() {
        0.45 * spacing
    } else {
        1.0
    };
    let (x0, x1) = (xs[0] - pad, xs[xs.len() - 1] + pad);
    chart.push(Series::dashed(
        format!(
            "locking angle {}°",
            crate::report::plot::tick_label(locking)
        ),
        vec![(x0, locking), (x1, locking)],
        Colour::BLACK,
    ));
    chart.x_range = Some((x0, x1));
    // The y axis spans the designs and the locking angle (the boundary stays in view).
    let ys = feasible_pts.iter().chain(&infeasible_pts).map(|p| p.1);
    let (lo, hi) = ys.fold((locking, locking), |(lo, hi), y| (lo.min(y), hi.max(y)));
    let pad = 0.12 * (hi - lo) + 1.0;
    chart.y_range = Some(((lo - pad).max(0.0), hi + pad));
    chart.push(Series::markers(
        "✓ feasible",
        feasible_pts,
        Colour(0, 150, 100),
    ));
    chart.push(Series::crosses(
        "✗ infeasible",
        infeasible_pts,
        Colour(213, 70, 0),
    ));
    chart.legend_at = LegendAt::LowerLeft;
    let mut note = Vec::new();
    if !others.is_empty() {
        let names: Vec<&str> = others
            .iter()
            .map(|&a| plan.axes[a].column.as_str())
            .collect();
        note.push(format!(
            "Each line: one combination of {}; points nudged sideways to keep them apart.",
            names.join(", ")
        ));
    }
    note.push(format!(
        "Above the dashed line the fabric shears past its locking angle ({}°): infeasible.",
        crate::report::plot::tick_label(locking)
    ));
    if left_out > 0 {
        note.push(format!(
            "{left_out} design(s) without a converged run are not plotted."
        ));
    }
    (Some(chart), note)
}

fn sheet(
    plan: &Plan,
    dir: &Path,
    rows: &[Row],
    designs: &[Design],
    top: f64,
) -> Result<Sheet, String> {
    let base = &plan.base_scene;
    let c = counts(rows);
    let mut tally = vec![
        format!("{} ✓ feasible", c.feasible),
        format!("{} ✗ infeasible", c.infeasible),
    ];
    if c.failed > 0 {
        tally.push(format!("{} failed", c.failed));
    }
    if c.invalid > 0 {
        tally.push(format!("{} invalid", c.invalid));
    }
    let missing = plan.len().saturating_sub(rows.len());
    if missing > 0 {
        tally.push(format!("{missing} not computed"));
    }
    let title = format!(
        "Sweep {}: {} designs — {}",
        plan.name(),
        plan.len(),
        tally.join(", ")
    );
    let t = &base.tools;
    let tools = match t.kind {
        ToolKind::Box => format!("box punch {} × {} mm", t.side.0[0], t.side.0[1]),
        ToolKind::Ellipsoid => format!(
            "ellipsoid punch {} × {} × {} mm",
            t.axes[0], t.axes[1], t.axes[2]
        ),
        ToolKind::Hemisphere => format!("hemisphere punch, radius {} mm", t.radius),
    };
    let law = if base.fabric.undulation {
        "woven law"
    } else {
        "linear yarn law"
    };
    let swept: Vec<String> = plan
        .axes
        .iter()
        .filter(|a| a.values.len() > 1)
        .map(|a| {
            let vals: Vec<String> = a.values.iter().map(show_value).collect();
            format!("{} ∈ {{{}}}{}", a.column, vals.join(", "), unit_of(&a.key))
        })
        .collect();
    let fixed: Vec<String> = plan
        .columns()
        .iter()
        .filter(|col| col.axis.is_none_or(|a| plan.axes[a].values.len() < 2))
        .map(|col| {
            let v = plan.params(std::slice::from_ref(col), &designs[0]);
            format!("{} {}{}", col.name, show_value(&v[0].1), unit_of(&col.key))
        })
        .collect();
    let subtitle = vec![
        format!(
            "Base scene: {} — {tools}, clearance {} mm, stroke {} mm, blank {} × {} mm, {law}, mesh {} mm; locking angle {}°, break tension {} N",
            plan.base_file.as_deref().unwrap_or(&plan.base_origin),
            t.clearance,
            base.process.stroke,
            base.blank.size.0[0],
            base.blank.size.0[1],
            base.mesh.element_size,
            base.fabric.locking_angle_deg,
            base.fabric.break_tension_n
        ),
        format!(
            "Swept: {}{}",
            swept.join("; "),
            if fixed.is_empty() {
                String::new()
            } else {
                format!(" — fixed: {}", fixed.join(", "))
            }
        ),
        "Feasible = converged, max shear ≤ locking angle and max yarn tension ≤ break tension. Every design's map: maps/<design>.png; every row: results.csv.".into(),
    ];
    let shown: Vec<&Row> = rows.iter().take(SHEET_TILES).collect();
    let tiles_note = if rows.len() > shown.len() || missing > 0 {
        Some(format!(
            "Showing the first {} of {} designs (grid order){}",
            shown.len(),
            plan.len(),
            if missing > 0 {
                format!("; {missing} designs have no result yet")
            } else {
                String::new()
            }
        ))
    } else {
        None
    };
    let mut tiles = Vec::new();
    for r in shown {
        let map = match &r.map {
            Some(_) => {
                let f = StoredField::read(dir, &r.design)?;
                let (quads, values) = f.full_blank();
                Some(TileMap {
                    quads,
                    values,
                    limit: f.locking_angle_deg,
                    die_opening: f.die_opening.clone(),
                })
            }
            None => None,
        };
        tiles.push(Tile {
            id: r.design.clone(),
            lines: plan.label_lines(&designs[r.index]),
            verdict: r.verdict,
            max_shear_deg: if r.converged { r.max_shear_deg } else { None },
            reason: r.failure.clone(),
            map,
        });
    }
    let (chart, chart_note) = shear_chart(plan, rows, designs);
    let ranked = ranked(rows);
    let mut ranking = vec![(
        None,
        if ranked.len() > RANKED_ON_SHEET {
            format!(
                "The {RANKED_ON_SHEET} best of {} designs (feasible first, then by max shear):",
                rows.len()
            )
        } else {
            "The designs, feasible first, then by max shear:".to_string()
        },
    )];
    for r in ranked.iter().take(RANKED_ON_SHEET) {
        let mut text = format!(
            "{} {}",
            r.verdict.mark(),
            r.design.split('-').next().unwrap_or("")
        );
        let label = plan.label_lines(&designs[r.index]).join("; ");
        if !label.is_empty() {
            text.push_str(&format!("  {label}"));
        }
        match (r.converged, r.max_shear_deg, r.max_tension_n) {
            (true, Some(s), Some(t)) => text.push_str(&format!(" — {s:.1}°, {t:.0} N")),
            _ => text.push_str(&format!(" — {}", r.verdict.word())),
        }
        ranking.push((Some(r.verdict), text));
    }
    Ok(Sheet {
        title,
        subtitle,
        tiles,
        tiles_note,
        scale_max: top,
        limit: base.fabric.locking_angle_deg,
        chart,
        chart_note,
        ranking,
    })
}

/// Rows on the sheet's ranking.
const RANKED_ON_SHEET: usize = 30;

/// Feasible first, then infeasible, failed, invalid; by max shear within each.
fn ranked(rows: &[Row]) -> Vec<&Row> {
    let rank = |v: Verdict| match v {
        Verdict::Feasible => 0,
        Verdict::Infeasible => 1,
        Verdict::Failed => 2,
        Verdict::Invalid => 3,
    };
    let mut sorted: Vec<&Row> = rows.iter().collect();
    sorted.sort_by(|a, b| {
        rank(a.verdict)
            .cmp(&rank(b.verdict))
            .then(
                a.max_shear_deg
                    .unwrap_or(f64::INFINITY)
                    .total_cmp(&b.max_shear_deg.unwrap_or(f64::INFINITY)),
            )
            .then(a.index.cmp(&b.index))
    });
    sorted
}

/// The feasibility table printed at the end: feasible designs first, then by max shear;
/// verdicts marked, units in the header.
pub fn table(plan: &Plan, rows: &[Row]) -> String {
    let columns = plan.columns();
    let sorted = ranked(rows);
    let mut head: Vec<(String, String)> =
        vec![("".into(), "".into()), ("design".into(), "".into())];
    for c in &columns {
        head.push((c.name.clone(), unit_of(&c.key).trim().to_string()));
    }
    for (n, u) in [
        ("max shear", "°"),
        ("max tension", "N"),
        ("punch force", "N"),
        ("wall", "s"),
        ("verdict", ""),
    ] {
        head.push((n.into(), u.into()));
    }
    let mut body: Vec<Vec<String>> = Vec::new();
    for r in &sorted {
        let f = |v: Option<f64>, d: usize| v.map(|v| format!("{v:.d$}")).unwrap_or("–".into());
        let mut line = vec![r.verdict.mark().to_string(), r.design.clone()];
        line.extend(r.params.iter().map(|(_, v)| show_value(v)));
        line.push(f(r.max_shear_deg, 1));
        line.push(f(r.max_tension_n, 0));
        line.push(f(r.punch_force_n, 0));
        line.push(f(r.wall_s, 1));
        let mut verdict = r.verdict.word().to_string();
        if let Some(why) = &r.failure {
            let short: String = why.chars().take(90).collect();
            let dots = if why.chars().count() > 90 { "…" } else { "" };
            verdict = format!("{verdict}: {short}{dots}");
        }
        line.push(verdict);
        body.push(line);
    }
    let n = head.len();
    let width: Vec<usize> = (0..n)
        .map(|i| {
            let h = head[i].0.chars().count().max(head[i].1.chars().count());
            if i == n - 1 {
                return h;
            }
            body.iter()
                .map(|l| l[i].chars().count())
                .fold(h, usize::max)
        })
        .collect();
    let numeric_from = 2; // right-align the parameters and figures
    let fmt_line = |cells: Vec<&str>| -> String {
        let mut s = String::new();
        for (i, cell) in cells.iter().enumerate() {
            let pad = width[i].saturating_sub(cell.chars().count());
            if i == n - 1 {
                s.push_str(cell);
            } else if i >= numeric_from {
                s.push_str(&" ".repeat(pad));
                s.push_str(cell);
                s.push_str("  ");
            } else {
                s.push_str(cell);
                s.push_str(&" ".repeat(pad));
                s.push_str("  ");
            }
        }
        s.trim_end().to_string()
    };
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{}",
        fmt_line(head.iter().map(|h| h.0.as_str()).collect())
    );
    let _ = writeln!(
        out,
        "{}",
        fmt_line(head.iter().map(|h| h.1.as_str()).collect())
    );
    for line in &body {
        let _ = writeln!(
            out,
            "{}",
            fmt_line(line.iter().map(|s| s.as_str()).collect())
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan_of(text: &str) -> Result<Plan, SweepError> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.toml");
        fs::write(&path, text).unwrap();
        Plan::load(&path, &[])
    }

    #[test]
    fn lists_ranges_and_short_names_make_the_grid() {
        let p = plan_of(
            "[sweep]\nfriction = [0.1, 0.2]\nr = { start = 5, stop = 10, count = 3 }\ntools.clearance = 1.0\n",
        )
        .unwrap();
        let keys: Vec<&str> = p.axes.iter().map(|a| a.key.as_str()).collect();
        assert_eq!(keys, ["tools.r", "process.friction", "tools.clearance"]);
        assert_eq!(p.axes[0].values, vec![5.0.into(), 7.5.into(), 10.0.into()]);
        let d = p.designs();
        assert_eq!(d.len(), 6);
        assert_eq!(d[1].values[1], toml::Value::Float(0.2));
        assert!(d[5].id.starts_with("d005-"), "{}", d[5].id);
        // Stable ids: the same values give the same id.
        assert_eq!(p.designs()[3].id, d[3].id);
        let names: Vec<String> = p.columns().iter().map(|c| c.name.clone()).collect();
        assert_eq!(
            names,
            [
                "r",
                "rp",
                "rm",
                "friction",
                "holder_pressure",
                "tools.clearance"
            ]
        );
        let range =
            plan_of("[sweep]\nfriction = { start = 0.1, stop = 0.3, count = 3 }\n").unwrap();
        assert_eq!(range.axes[0].values[1], toml::Value::Float(0.2));
    }

    #[test]
    fn unknown_keys_and_bad_values_name_the_key() {
        for (text, must) in [
            ("[sweep]\nradius_x = [1.0]\n", "sweep.radius_x: unknown key"),
            ("[sweep]\ntools.q = [1.0]\n", "sweep.tools.q: unknown key"),
            ("[sweep]\nr = []\n", "sweep.r: an empty list"),
            (
                "[sweep]\nr = { start = 1, stop = 2, cnt = 3 }\n",
                "sweep.r.cnt",
            ),
            ("[sweep]\nr = [\"a\"]\n", "sweep.r = a: expected numbers"),
            ("[sweep]\nr = [5.0]\ntools.r = [6.0]\n", "swept twice"),
            ("bse = \"x.toml\"\n[sweep]\nr = [5.0]\n", "bse: unknown key"),
            ("[scene]\n", "expected a [sweep] table"),
        ] {
            let e = plan_of(text).unwrap_err();
            assert!(matches!(e, SweepError::BadInput(_)), "{text}");
            assert!(e.to_string().contains(must), "{text}: {e}");
            assert!(e.to_string().contains("s.toml"), "{text}: {e}");
        }
    }

    #[test]
    fn designs_out_of_bounds_are_invalid_with_the_reason() {
        let p = plan_of("[sweep]\nr = [5.0, 40.0]\n").unwrap();
        let d = p.designs();
        assert!(p.design_scene(&d[0]).is_ok());
        let why = p.design_scene(&d[1]).unwrap_err();
        assert!(why.starts_with("tools.r = 40"), "{why}");
    }

    #[test]
    fn csv_rows_round_trip() {
        let p = plan_of("[sweep]\nr = [5.0, 7.5]\n").unwrap();
        let cols = p.columns();
        let d = p.designs();
        let mut row = Row::invalid(&p, &cols, &d[1], "a, \"quoted\" reason".into());
        row.max_shear_deg = Some(12.3456);
        let line = row.to_csv();
        let fields = parse_csv_line(line.trim_end()).unwrap();
        let header_line = csv_header(&cols);
        let names: Vec<&str> = header_line.split(',').collect();
        assert_eq!(fields.len(), names.len());
        let header: HashMap<&str, usize> = names.iter().enumerate().map(|(i, h)| (*h, i)).collect();
        let grid: HashMap<&str, &Design> = d.iter().map(|d| (d.id.as_str(), d)).collect();
        let back = Row::from_csv(&header, &fields, &p, &cols, &grid).unwrap();
        assert_eq!(back, row);
        assert_eq!(parse_csv_line("a,\"b"), None);
    }

    #[test]
    fn shards_split_the_grid() {
        let s: Shard = "2/3".parse().unwrap();
        let mine: Vec<usize> = (0..7).filter(|&i| s.contains(i)).collect();
        assert_eq!(mine, [1, 4]);
        assert!("0/3".parse::<Shard>().is_err());
        assert!("4/3".parse::<Shard>().is_err());
        assert!("x".parse::<Shard>().is_err());
    }
}
