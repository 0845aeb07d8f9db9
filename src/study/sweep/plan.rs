//! The sweep file read into a [`Plan`]: the base scene, the swept parameters (lists, ranges or
//! one value), their order and their hashes.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::SweepError;
use super::values::{as_number, fnv_hex, show_value};
use crate::scene::{Num, Override, Scene, lookup, merge_tables, unset_key_shape};

/// The box's five short names and the scene keys they stand for, in grid order.
pub const SHORT_NAMES: [(&str, &str); 5] = [
    ("r", "tools.r"),
    ("rp", "tools.rp"),
    ("rm", "tools.rm"),
    ("friction", "process.friction"),
    ("holder_pressure", "process.holder_pressure"),
];

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
    /// FNV-1a hashes of the base scene (as run, with what its tool files hold) and of the
    /// grid.
    pub base_hash: String,
    pub sweep_hash: String,
    /// A mesh scene's tool files and what they held (their surfaces' fingerprints) when the
    /// plan was made: a file written anew changes the base hash, as an edited key does.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub tool_files: Vec<ToolFile>,
}

/// A tool file of the base scene and the fingerprint of the surface it held.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ToolFile {
    pub key: String,
    pub file: String,
    pub surface: String,
}

/// The base scene's tool files as read ([`crate::core::tools::mesh_tool::MeshTool::fingerprint`]).
fn tool_files(scene: &Scene) -> Vec<ToolFile> {
    let Some(loaded) = scene.tools.loaded.as_ref() else {
        return Vec::new();
    };
    [("tools.punch", &loaded.punch), ("tools.die", &loaded.die)]
        .into_iter()
        .map(|(key, tool)| ToolFile {
            key: key.into(),
            file: tool.name.clone(),
            surface: format!("{:016x}", tool.fingerprint()),
        })
        .collect()
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
        let text = crate::files::read_text(path, crate::files::MAX_TEXT_BYTES)
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
        Plan::from_document_with(path, doc, sets, &[])
    }

    /// [`Plan::from_document`] with scene files the binary carries: a `base` named in
    /// `embedded` (name, text) is that text, not a file read from the disk.
    pub fn from_document_with(
        path: &Path,
        doc: &toml::Table,
        sets: &[String],
        embedded: &[(&str, &str)],
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
        let base = BaseText::of(path, doc, embedded)?;
        let overrides = parse_sets(sets)?;
        let base_scene = Scene::from_toml_str(&base.text, &base.origin, &overrides)?;
        let scene_table = toml::Table::try_from(&base_scene)
            .map_err(|e| SweepError::Run(format!("cannot tabulate the base scene: {e}")))?;
        let axes = axes_of(doc, &scene_table).map_err(bad)?;
        check_holder_axes(&axes, &base_scene).map_err(bad)?;
        let base_json = serde_json::to_string(&base_scene).expect("a scene is plain data");
        // The scene names its tool files; what they hold is hashed too.
        let tool_files = tool_files(&base_scene);
        let base_hash = if tool_files.is_empty() {
            fnv_hex(&base_json)
        } else {
            let tools = serde_json::to_string(&tool_files).expect("plain data");
            fnv_hex(&format!("{base_json}\n{tools}"))
        };
        let sweep_json = serde_json::to_string(&axes).expect("the axes are plain data");
        let sweep_hash = fnv_hex(&format!("{base_hash}\n{sweep_json}"));
        Ok(Plan {
            sweep_file: file,
            base_file: base.file.map(|p| p.display().to_string()),
            set: sets.to_vec(),
            base_text: base.text,
            base_origin: base.origin,
            base_scene,
            axes,
            base_hash,
            sweep_hash,
            tool_files,
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
}

/// The base scene's TOML text: a file, an inline `[scene]` table over it, or both, or neither
/// (the default scene).
struct BaseText {
    file: Option<PathBuf>,
    text: String,
    /// What errors in the base scene are blamed on.
    origin: String,
}

impl BaseText {
    fn of(
        path: &Path,
        doc: &toml::Table,
        embedded: &[(&str, &str)],
    ) -> Result<BaseText, SweepError> {
        let sweep_file = path.display().to_string();
        let bad = |detail: String| SweepError::BadInput(format!("{sweep_file}: {detail}"));
        let file = match doc.get("base") {
            None => None,
            Some(toml::Value::String(s)) if embedded.iter().any(|(name, _)| name == s) => {
                Some(PathBuf::from(s))
            }
            Some(toml::Value::String(s)) => Some(path.parent().unwrap_or(Path::new("")).join(s)),
            Some(v) => {
                return Err(bad(format!(
                    "base = {v}: expected the path of a scene file, relative to the sweep file"
                )));
            }
        };
        let twice = |key: String| {
            bad(format!(
                "\"{key}\" is given twice: as a quoted dotted key and in its table; expected one"
            ))
        };
        let inline = match doc.get("scene") {
            None => None,
            Some(toml::Value::Table(t)) => {
                // `"process.stroke" = 12.0`, as `[sweep]` spells its keys, is `[process] stroke`.
                let mut t = t.clone();
                crate::scene::expand_dotted_keys(&mut t)
                    .map_err(|k| twice(format!("scene.{k}")))?;
                Some(t)
            }
            Some(v) => return Err(bad(format!("scene = {v}: expected a [scene] table"))),
        };
        let read = |b: &Path| {
            let carried = embedded.iter().find(|(name, _)| Path::new(name) == b);
            if let Some((_, text)) = carried {
                return Ok(text.to_string());
            }
            crate::files::read_text(b, crate::files::MAX_TEXT_BYTES).map_err(|e| {
                bad(format!(
                    "base = {}: cannot read the scene file: {e}",
                    b.display()
                ))
            })
        };
        let to_text =
            |t: &toml::Table| toml::to_string(t).map_err(|e| bad(format!("[scene]: {e}")));
        let (text, origin) = match (&file, inline) {
            (None, None) => (String::new(), format!("{sweep_file} (the default scene)")),
            (Some(b), None) => (read(b)?, b.display().to_string()),
            (None, Some(t)) => (to_text(&t)?, format!("{sweep_file} [scene]")),
            (Some(b), Some(over)) => {
                let mut table: toml::Table = read(b)?.parse().map_err(|e: toml::de::Error| {
                    SweepError::BadInput(format!(
                        "{}: not valid TOML: {}",
                        b.display(),
                        e.to_string().trim_end()
                    ))
                })?;
                crate::scene::expand_dotted_keys(&mut table).map_err(|k| {
                    SweepError::BadInput(format!(
                        "{}: \"{k}\" is given twice: as a quoted dotted key and in its table; \
                         expected one",
                        b.display()
                    ))
                })?;
                merge_tables(&mut table, &over);
                let origin = format!("{} with {sweep_file} [scene]", b.display());
                (to_text(&table)?, origin)
            }
        };
        Ok(BaseText { file, text, origin })
    }
}

/// The swept parameters of the `[sweep]` table, in grid order: the short names first, then
/// the other keys alphabetically. `scene` is the base scene as a table (every key).
fn axes_of(doc: &toml::Table, scene: &toml::Table) -> Result<Vec<Axis>, String> {
    let sweep = match doc.get("sweep") {
        Some(toml::Value::Table(t)) if !t.is_empty() => t,
        _ => {
            return Err(
                "expected a [sweep] table with at least one parameter, e.g. r = [5.0, 10.0]".into(),
            );
        }
    };
    let mut entries = Vec::new();
    flatten_sweep("", sweep, &mut entries);
    let mut axes: Vec<Axis> = Vec::new();
    for (name, value) in entries {
        let axis = axis_of(&name, &value, scene)?;
        if let Some(other) = axes.iter().find(|a| a.key == axis.key) {
            return Err(format!(
                "sweep.{name}: {} is swept twice (also as sweep.{})",
                axis.key, other.column
            ));
        }
        axes.push(axis);
    }
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
        return Err(format!(
            "the grid has {total} designs; expected at most 1,000,000 (split the sweep)"
        ));
    }
    Ok(axes)
}

/// One `[sweep]` entry as an axis: its scene key, its column and its values.
fn axis_of(name: &str, value: &toml::Value, scene: &toml::Table) -> Result<Axis, String> {
    let key = SHORT_NAMES
        .iter()
        .find(|(s, _)| *s == name)
        .map_or_else(|| name.to_string(), |(_, k)| k.to_string());
    let mesh = matches!(lookup(scene, "tools.kind"), Some(toml::Value::String(k)) if k == "mesh");
    if mesh && key.starts_with("tools.") && !["tools.lattice"].contains(&key.as_str()) {
        return Err(format!(
            "sweep.{name}: {key} is not a key of tools.kind = \"mesh\" (its shape is in its STL \
             files); sweep what the files leave open: friction, holder_pressure, blank.size, \
             process.stroke, fabric.yarn_angle_deg, fabric.locking_angle_deg, tools.lattice \
             (or sweep scene files with other tools)"
        ));
    }
    // A key the base leaves unset (the shear law) is swept over the shape it takes.
    let unset = lookup(scene, &key)
        .is_none()
        .then(|| unset_key_shape(&key))
        .flatten();
    let base_value = match lookup(scene, &key).or(unset.as_ref()) {
        Some(toml::Value::Table(_)) | None => {
            return Err(format!(
                "sweep.{name}: unknown key; expected a scene key (such as tools.r, process.stroke or mesh.element_size) or a short name: r, rp, rm, friction, holder_pressure"
            ));
        }
        Some(v) => v,
    };
    let values = axis_values(name, &key, value, base_value)?;
    let column = SHORT_NAMES
        .iter()
        .find(|(_, k)| *k == key)
        .map_or_else(|| key.clone(), |(s, _)| s.to_string());
    Ok(Axis {
        key,
        column,
        values,
    })
}

/// A swept holder pressure must press the holder: with `process.holder_force` (in the base
/// scene or swept too) a plate takes the force and the pressure changes nothing.
fn check_holder_axes(axes: &[Axis], base: &Scene) -> Result<(), String> {
    let swept = |key: &str| axes.iter().find(|a| a.key == key && a.values.len() > 1);
    let Some(pressure) = swept("process.holder_pressure") else {
        return Ok(());
    };
    let force = match (base.process.holder_force, swept("process.holder_force")) {
        (_, Some(f)) => format!("sweep.{}", f.column),
        (Some(kn), None) => format!("the base scene's process.holder_force = {} kN", Num(kn)),
        (None, None) => return Ok(()),
    };
    Err(format!(
        "sweep.{}: the holder pressure is swept, but {force} presses the holder with a plate \
         instead, so every pressure would give the same answer; expected the pressure swept \
         without process.holder_force (remove it), or process.holder_force swept instead",
        pressure.column
    ))
}

pub(super) fn parse_sets(sets: &[String]) -> Result<Vec<Override>, SweepError> {
    sets.iter()
        .map(|s| s.parse::<Override>())
        .collect::<Result<Vec<_>, _>>()
        .map_err(SweepError::Scene)
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
            let values = range_values(name, t)?;
            if as_number(base).is_none() {
                return Err(format!(
                    "sweep.{name}: a range of numbers, but {key} takes {expected}; give a list instead"
                ));
            }
            values
        }
        one => vec![one.clone()],
    };
    if let Some(v) = values.iter().find(|v| !kind_ok(v)) {
        return Err(format!(
            "sweep.{name} = {}: expected {expected} for {key}",
            show_value(v)
        ));
    }
    // nan and inf are TOML numbers, and no scene key takes them.
    if let Some(v) = values.iter().find(|v| !finite(v)) {
        return Err(format!(
            "sweep.{name} = {}: expected finite {expected} for {key} (nan and inf are no \
             value of a scene)",
            show_value(v)
        ));
    }
    let same = |a: &toml::Value, b: &toml::Value| match (as_number(a), as_number(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    };
    for (i, v) in values.iter().enumerate() {
        if values[..i].iter().any(|w| same(v, w)) {
            return Err(format!(
                "sweep.{name}: {} is given twice; expected each value of {key} once (a range \
                 whose start equals its stop needs count = 1)",
                show_value(v)
            ));
        }
    }
    Ok(values)
}

/// Whether every number in `v` (a number, or the numbers of an array) is finite.
fn finite(v: &toml::Value) -> bool {
    match v {
        toml::Value::Float(f) => f.is_finite(),
        toml::Value::Array(list) => list.iter().all(finite),
        _ => true,
    }
}

/// The values of a range `{ start, stop, count }` (both ends included, count from 1 to
/// 10,000), named `sweep.{name}` in errors.
fn range_values(name: &str, t: &toml::Table) -> Result<Vec<toml::Value>, String> {
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
    Ok((0..count)
        .map(|i| {
            let v = if count == 1 {
                start
            } else {
                start + (stop - start) * i as f64 / (count - 1) as f64
            };
            toml::Value::Float(tidy(v))
        })
        .collect())
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    pub(in crate::study::sweep) fn plan_of(text: &str) -> Result<Plan, SweepError> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.toml");
        std::fs::write(&path, text).unwrap();
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
    fn a_value_given_twice_is_refused() {
        for sweep in [
            "r = [5.0, 5]",
            "r = { start = 5.0, stop = 5.0, count = 3 }",
            "\"mesh.symmetry\" = [\"full\", \"full\"]",
        ] {
            let e = plan_of(&format!("[sweep]\n{sweep}\n"))
                .unwrap_err()
                .to_string();
            assert!(e.contains("is given twice"), "{sweep}: {e}");
        }
        assert!(plan_of("[sweep]\nr = { start = 5.0, stop = 5.0, count = 1 }\n").is_ok());
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
            assert!(e.is_bad_input(), "{text}");
            assert!(e.to_string().contains(must), "{text}: {e}");
            assert!(e.to_string().contains("s.toml"), "{text}: {e}");
        }
    }
}
