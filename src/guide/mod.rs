//! The guide: how wovenform works and how to use it, one page per subject.
//!
//! These modules hold no code; each is a page of documentation, written in Markdown under
//! `src/guide/` and rendered by `cargo doc --open` (the examples in them run with
//! `cargo test --release --doc`).
//!
//! - [`architecture`]: what the program answers, how data flows, the code map and the rules
//!   every file keeps.
//! - [`scenes`]: the scene file, every key with its unit, default and bounds; `run`.
//! - [`explorer`]: the terminal explorer (`wovenform`, `wovenform tui`).
//! - [`sweeps`]: grids of designs, resume, shards, `merge` and Slurm.
//! - [`frontier`]: the boundary along one axis (`frontier`), in a few runs of the grid's.
//! - [`stl_tools`]: a punch and die of your own from STL files; the `tools` command.
//! - [`shear_law`]: the in-plane shear law, the bias-extension test and its fit; `fit`.
//! - [`bending`]: bending stiffness (beyond the paper) and the heavy cantilever; `cantilever`.
//! - [`accuracy`]: accuracy levels, error bands, MARGINAL, `converge` and `bench`.
//! - [`theory`]: the model — the woven-cell law, the membrane element, contact, the solver.
//! - [`verification`]: the checks with answers from outside the code.
//! - [`findings`]: what each preset gives and what each level costs, dated, each with the
//!   command that reproduces it.
//! - [`solver`]: the solver's design: each mechanism, what it does, why, and what it bought.
//! - [`solver_rejected`]: the solver's variants that were measured and rejected, and why.

#[doc = include_str!("architecture.md")]
pub mod architecture {}

#[doc = include_str!("scenes.md")]
pub mod scenes {}

#[doc = include_str!("explorer.md")]
pub mod explorer {}

#[doc = include_str!("sweeps.md")]
pub mod sweeps {}

#[doc = include_str!("frontier.md")]
pub mod frontier {}

#[doc = include_str!("stl_tools.md")]
pub mod stl_tools {}

#[doc = include_str!("shear_law.md")]
pub mod shear_law {}

#[doc = include_str!("bending.md")]
pub mod bending {}

#[doc = include_str!("accuracy.md")]
pub mod accuracy {}

#[doc = include_str!("theory.md")]
pub mod theory {}

#[doc = include_str!("verification.md")]
pub mod verification {}

#[doc = include_str!("findings.md")]
pub mod findings {}

#[doc = include_str!("solver.md")]
pub mod solver {}

#[doc = include_str!("solver_rejected.md")]
pub mod solver_rejected {}

#[cfg(test)]
mod layers;

#[cfg(test)]
mod lint;

#[cfg(test)]
mod tests {
    use std::collections::{BTreeMap, BTreeSet};
    use std::path::{Path, PathBuf};

    use crate::scene::{Scene, ToolKind};

    const ARCHITECTURE: &str = include_str!("architecture.md");
    const SCENES: &str = include_str!("scenes.md");

    /// The text of every `` `code span` `` in `text`.
    fn code_spans(text: &str) -> Vec<&str> {
        text.split('`').skip(1).step_by(2).collect()
    }

    /// Every `.rs` file under `dir`, as a path relative to `root` with `/` separators.
    pub(super) fn rust_files(root: &Path, dir: &Path, out: &mut BTreeSet<String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path: PathBuf = entry.unwrap().path();
            if path.is_dir() {
                rust_files(root, &path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let rel = path.strip_prefix(root).unwrap();
                let parts: Vec<_> = rel.iter().map(|p| p.to_string_lossy()).collect();
                out.insert(parts.join("/"));
            }
        }
    }

    #[test]
    fn architecture_names_every_source_file_and_no_other() {
        let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
        let src = manifest.join("src");
        let mut files = BTreeSet::new();
        rust_files(&src, &src, &mut files);
        // The code map names each file by its path under src/, in a code span.
        let named: BTreeSet<&str> = code_spans(ARCHITECTURE)
            .into_iter()
            .filter(|s| s.ends_with(".rs") && !s.starts_with('.') && !s.contains([' ', '*']))
            .collect();
        let missing: Vec<&String> = files
            .iter()
            .filter(|f| !named.contains(f.as_str()))
            .collect();
        // A name in the page that is no file: under src/ unless it says tests/ or src/.
        let gone: Vec<&&str> = named
            .iter()
            .filter(|n| {
                let path = if n.starts_with("tests/") || n.starts_with("src/") {
                    manifest.join(n)
                } else {
                    src.join(n)
                };
                !path.is_file()
            })
            .collect();
        assert!(
            missing.is_empty() && gone.is_empty(),
            "src/guide/architecture.md: files under src/ not in the code map: {missing:?}; \
             names in the page that are no file: {gone:?}"
        );
    }

    /// One row of the scene-key table.
    #[derive(Debug)]
    struct KeyRow {
        key: String,
        default: String,
        bounds: String,
    }

    /// The cells of a Markdown table row (`\|` is a `|` inside a cell).
    fn table_cells(line: &str) -> Vec<String> {
        let inner = line.trim().strip_prefix('|').unwrap_or(line);
        let inner = inner.strip_suffix('|').unwrap_or(inner);
        let mut cells = vec![String::new()];
        let mut chars = inner.chars().peekable();
        while let Some(c) = chars.next() {
            match c {
                '\\' if chars.peek() == Some(&'|') => {
                    cells.last_mut().unwrap().push('|');
                    chars.next();
                }
                '|' => cells.push(String::new()),
                c => cells.last_mut().unwrap().push(c),
            }
        }
        cells.iter().map(|c| c.trim().to_string()).collect()
    }

    /// The rows of the table whose header is `| key | unit | default | bounds |`.
    fn key_rows(page: &str) -> Vec<KeyRow> {
        let mut lines = page
            .lines()
            .skip_while(|l| !l.replace(' ', "").starts_with("|key|unit|default|bounds|"));
        assert!(
            lines.next().is_some(),
            "scenes.md: no key | unit | default | bounds table"
        );
        lines
            .skip(1)
            .take_while(|l| l.trim_start().starts_with('|'))
            .map(|l| {
                let cells = table_cells(l);
                assert_eq!(cells.len(), 4, "scenes.md: a row of four cells: {l}");
                let first = |c: &String| code_spans(c).first().map(|s| s.to_string());
                KeyRow {
                    key: first(&cells[0]).unwrap_or_else(|| panic!("no `key` in: {l}")),
                    default: first(&cells[2]).unwrap_or_default(),
                    bounds: cells[3].clone(),
                }
            })
            .collect()
    }

    /// `prefix.key = value` for every leaf of `table`.
    fn flatten(prefix: &str, table: &toml::Table, out: &mut BTreeMap<String, toml::Value>) {
        for (k, v) in table {
            let key = if prefix.is_empty() {
                k.clone()
            } else {
                format!("{prefix}.{k}")
            };
            match v {
                toml::Value::Table(t) => flatten(&key, t, out),
                v => {
                    out.insert(key, v.clone());
                }
            }
        }
    }

    /// Each key the scene reader takes, with its serialised default and the punch it needs:
    /// the default scene for each kind of punch, and the keys a scene may leave unset.
    fn scene_keys() -> BTreeMap<String, (Option<toml::Value>, ToolKind)> {
        let mut keys = BTreeMap::new();
        for kind in [
            ToolKind::Box,
            ToolKind::Ellipsoid,
            ToolKind::Hemisphere,
            ToolKind::Mesh,
        ] {
            let mut scene = Scene::default();
            scene.tools.kind = kind;
            let mut flat = BTreeMap::new();
            flatten("", &toml::Table::try_from(&scene).unwrap(), &mut flat);
            for (k, v) in flat {
                keys.entry(k).or_insert((Some(v), kind));
            }
        }
        // Keys without a serialised default: written only when set.
        let mut full = Scene::default();
        full.fabric.shear_moment = Some([0.0; 3]);
        full.fabric.shear_locking = true;
        full.fabric.bending_rigidity = Some([0.0; 2]);
        full.fabric.compressive_stiffness = Some([0.0; 2]);
        full.fabric.areal_mass = Some(0.0);
        full.process.holder_force = Some(0.0);
        let mut flat = BTreeMap::new();
        flatten("", &toml::Table::try_from(&full).unwrap(), &mut flat);
        for k in flat.into_keys() {
            keys.entry(k).or_insert((None, ToolKind::Box));
        }
        keys
    }

    /// Two TOML values equal as numbers (an integer and a float alike); one number documents
    /// a pair of equal numbers (`fabric.l0`, `blank.size` take either).
    fn same(doc: &toml::Value, real: &toml::Value) -> bool {
        use toml::Value as V;
        let num = |v: &V| match v {
            V::Integer(i) => Some(*i as f64),
            V::Float(f) => Some(*f),
            _ => None,
        };
        match (doc, real) {
            (V::Array(a), V::Array(b)) => {
                a.len() == b.len() && a.iter().zip(b).all(|(x, y)| same(x, y))
            }
            (d, V::Array(b)) if num(d).is_some() => b.iter().all(|y| same(d, y)),
            _ => match (num(doc), num(real)) {
                (Some(x), Some(y)) => x == y,
                _ => doc == real,
            },
        }
    }

    fn literal(text: &str) -> toml::Value {
        let t: toml::Table = format!("v = {text}")
            .parse()
            .unwrap_or_else(|e| panic!("`{text}` is not a TOML literal: {e}"));
        t["v"].clone()
    }

    /// A simple bound at the start of a bounds cell: `> x`, `≥ x`, `[lo, hi]` or `(lo, hi)`.
    #[derive(Debug, Clone, Copy)]
    enum Bound {
        Above(f64),
        AtLeast(f64),
        Closed(f64, f64),
        Open(f64, f64),
    }

    fn parse_bound(cell: &str) -> Option<Bound> {
        let span = *code_spans(cell).first()?;
        let num = |s: &str| s.trim().parse::<f64>().ok();
        if let Some(x) = span.strip_prefix('>') {
            return num(x).map(Bound::Above);
        }
        if let Some(x) = span.strip_prefix('≥') {
            return num(x).map(Bound::AtLeast);
        }
        let pair = |s: &str| {
            let (a, b) = s.split_once(',')?;
            Some((num(a)?, num(b)?))
        };
        if let Some(r) = span.strip_prefix('[').and_then(|s| s.strip_suffix(']')) {
            return pair(r).map(|(a, b)| Bound::Closed(a, b));
        }
        if let Some(r) = span.strip_prefix('(').and_then(|s| s.strip_suffix(')')) {
            return pair(r).map(|(a, b)| Bound::Open(a, b));
        }
        None
    }

    /// Values just outside and just inside a bound.
    fn probes(b: Bound) -> (Vec<f64>, Vec<f64>) {
        let d = |x: f64| 1e-9 * x.abs().max(1.0);
        match b {
            Bound::Above(x) => (vec![x], vec![x + d(x)]),
            Bound::AtLeast(x) => (vec![x - d(x)], vec![x]),
            Bound::Closed(lo, hi) => (vec![lo - d(lo), hi + d(hi)], vec![lo, hi]),
            Bound::Open(lo, hi) => (vec![lo, hi], vec![lo + d(lo), hi - d(hi)]),
        }
    }

    /// The scene's text with `key` set to `v` (each number of an array default, for a pair or
    /// a triple), for a punch of kind `kind`.
    fn scene_with(key: &str, v: f64, default: &toml::Value, kind: ToolKind) -> String {
        let value = match default {
            toml::Value::Array(a) => format!("[{}]", vec![format!("{v:?}"); a.len()].join(", ")),
            _ => format!("{v:?}"),
        };
        let mut text = format!("tools.kind = \"{}\"\n", kind.name());
        if kind == ToolKind::Mesh {
            text += "tools.punch = \"punch.stl\"\ntools.die = \"die.stl\"\n";
        }
        text + &format!("{key} = {value}\n")
    }

    #[test]
    fn scene_key_table_matches_the_scene_reader() {
        let rows = key_rows(SCENES);
        let keys = scene_keys();
        let documented: BTreeSet<&str> = rows.iter().map(|r| r.key.as_str()).collect();
        let known: BTreeSet<&str> = keys.keys().map(String::as_str).collect();
        let undocumented: Vec<_> = known.difference(&documented).collect();
        let unknown: Vec<_> = documented.difference(&known).collect();
        assert!(
            undocumented.is_empty() && unknown.is_empty(),
            "src/guide/scenes.md: keys the scene reader takes but the table lacks: \
             {undocumented:?}; keys in the table it does not take: {unknown:?}"
        );
        assert_eq!(rows.len(), documented.len(), "a key documented twice");

        let mut checked = 0;
        for row in &rows {
            let (default, kind) = &keys[&row.key];
            match default {
                Some(real) => {
                    let doc = literal(&row.default);
                    assert!(
                        same(&doc, real),
                        "scenes.md: {} documents the default `{}`, the scene's is {real}",
                        row.key,
                        row.default
                    );
                }
                None => {
                    // Unset by default: documented as absent, or as the value that changes
                    // nothing when written.
                    if row.default != "absent" {
                        let text = format!("{} = {}\n", row.key, row.default);
                        let set = Scene::from_toml_str(&text, "x.toml", &[]).unwrap();
                        assert_eq!(set, Scene::default(), "scenes.md: {}'s default", row.key);
                    }
                }
            }
            let Some(bound) = parse_bound(&row.bounds) else {
                continue;
            };
            let default = default.clone().unwrap_or(toml::Value::Float(0.0));
            // A bound that also depends on other keys: only its own side is checked.
            let loose = row.bounds.contains("depends on");
            let (outside, inside) = probes(bound);
            for v in outside {
                let text = scene_with(&row.key, v, &default, *kind);
                let e = Scene::from_toml_str(&text, "x.toml", &[])
                    .expect_err(&format!("scenes.md: {} = {v:?} accepted", row.key));
                assert_eq!(e.key.as_deref(), Some(row.key.as_str()), "{text}: {e}");
                assert!(e.detail.contains(&row.key), "{text}: {e}");
                checked += 1;
            }
            if loose {
                continue;
            }
            for v in inside {
                let text = scene_with(&row.key, v, &default, *kind);
                if let Err(e) = Scene::from_toml_str(&text, "x.toml", &[]) {
                    panic!("scenes.md: {} = {v:?} refused: {e}", row.key);
                }
                checked += 1;
            }
        }
        assert!(checked >= 30, "only {checked} bounds checked");
    }
}
