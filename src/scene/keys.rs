//! Dotted keys: finding `a.b.c` in a TOML table, and which `[tools]` keys each punch takes.
//!
//! The keys of every table are those of its serde type (`types.rs`), each table rejecting
//! unknown ones by name; the `[tools]` table holds the keys of all three punches, so the keys
//! of a punch other than `tools.kind` are rejected here.

use super::types::ToolKind;
use super::{Scene, SceneError};

/// The value at a dotted key such as `tools.r` or `fabric`: each part but the last names a
/// table. `None` when a part is missing or names a value that is not a table.
pub fn lookup<'a>(table: &'a toml::Table, key: &str) -> Option<&'a toml::Value> {
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

/// A value of the shape of `key` when it is a key a scene may leave unset (it has no default:
/// `fabric.shear_moment`, `fabric.bending_rigidity`, `fabric.compressive_stiffness`,
/// `fabric.areal_mass`, `process.holder_force`); `None` for every other key.
pub fn unset_key_shape(key: &str) -> Option<toml::Value> {
    let mut full = Scene::default();
    full.fabric.shear_moment = Some([0.0; 3]);
    full.fabric.bending_rigidity = Some([0.0; 2]);
    full.fabric.compressive_stiffness = Some([0.0; 2]);
    full.fabric.areal_mass = Some(0.0);
    full.process.holder_force = Some(0.0);
    let table = toml::Table::try_from(&full).ok()?;
    let empty = toml::Table::try_from(Scene::default()).ok()?;
    lookup(&empty, key)
        .is_none()
        .then(|| lookup(&table, key).cloned())?
}

/// Whether `key` is written as a dotted key: parts of ASCII letters, digits, `_` and `-`,
/// joined by dots (TOML's bare keys).
pub(super) fn is_dotted_key(key: &str) -> bool {
    key.split('.').all(|p| {
        !p.is_empty()
            && p.chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    })
}

/// `[tools]` keys that every punch takes.
const SHARED_TOOL_KEYS: [&str; 2] = ["rm", "clearance"];

impl ToolKind {
    /// Every kind of punch.
    const ALL: [ToolKind; 4] = [
        ToolKind::Box,
        ToolKind::Ellipsoid,
        ToolKind::Hemisphere,
        ToolKind::Mesh,
    ];

    /// The `[tools]` keys that describe this punch only (the others are shared).
    pub(super) fn own_keys(self) -> &'static [&'static str] {
        match self {
            ToolKind::Box => &["side", "r", "rp"],
            ToolKind::Ellipsoid => &["axes"],
            ToolKind::Hemisphere => &["radius"],
            ToolKind::Mesh => &["punch", "die", "lattice"],
        }
    }

    /// The punch that `tools.{name}` belongs to alone, if it belongs to one.
    fn owner_of(name: &str) -> Option<ToolKind> {
        ToolKind::ALL
            .into_iter()
            .find(|k| k.own_keys().contains(&name))
    }
}

impl Scene {
    /// Rejects `[tools]` keys of another kind of punch (they would be silently ignored). When
    /// `tools.kind` itself comes from `--set`, the file's keys for the old kind are blamed on
    /// that `--set` (`kind_set`, its `KEY=VALUE`): switching a box scene to a hemisphere would
    /// drop its r, rp and side.
    pub(super) fn check_kind_keys(
        &self,
        table: &toml::Table,
        kind_set: Option<&str>,
        origin: &str,
        origin_of: &dyn Fn(&str) -> String,
    ) -> Result<(), SceneError> {
        let Some(toml::Value::Table(tools)) = table.get("tools") else {
            return Ok(());
        };
        let kind = self.tools.kind;
        for name in tools.keys() {
            if kind == ToolKind::Mesh && SHARED_TOOL_KEYS.contains(&name.as_str()) {
                let key = format!("tools.{name}");
                return Err(SceneError {
                    origin: origin_of(&key),
                    detail: format!(
                        "{key}: not for tools.kind = \"mesh\" (the die's entry radius and the \
                         clearance are in its STL); expected one of: {}",
                        ToolKind::Mesh.own_keys().join(", ")
                    ),
                    key: Some(key),
                });
            }
            let Some(owner) = ToolKind::owner_of(name).filter(|&k| k != kind) else {
                continue;
            };
            let key = format!("tools.{name}");
            let blamed = origin_of(&key);
            if let Some(set) = kind_set.filter(|_| blamed == origin) {
                return Err(SceneError {
                    origin: format!("--set {set}"),
                    detail: format!(
                        "tools.kind = \"{}\" would drop the scene file's {key} (a \"{}\" key): \
                         start from a scene of that kind (presets/hemisphere.toml, \
                         presets/paper-ellipsoid.toml) or remove {key} from the file",
                        kind.name(),
                        owner.name()
                    ),
                    key: Some("tools.kind".into()),
                });
            }
            let mut keys: Vec<&str> = kind.own_keys().to_vec();
            keys.extend(SHARED_TOOL_KEYS);
            return Err(SceneError {
                origin: blamed,
                detail: format!(
                    "{key}: only for tools.kind = \"{}\"; expected, for tools.kind = \"{}\", one of: {}",
                    owner.name(),
                    kind.name(),
                    keys.join(", ")
                ),
                key: Some(key),
            });
        }
        Ok(())
    }
}

/// The keys whose values differ between two scenes, as `key: old → new` (TOML literals), in
/// key order: what a person needs to see when two runs are not of the same scene.
pub fn differences(old: &Scene, new: &Scene) -> Vec<String> {
    fn flatten(prefix: &str, v: &toml::Value, out: &mut Vec<(String, String)>) {
        match v {
            toml::Value::Table(t) => {
                for (k, v) in t {
                    let key = if prefix.is_empty() {
                        k.clone()
                    } else {
                        format!("{prefix}.{k}")
                    };
                    flatten(&key, v, out);
                }
            }
            other => out.push((prefix.to_string(), other.to_string())),
        }
    }
    let flat = |s: &Scene| {
        let mut out = Vec::new();
        if let Ok(v) = toml::Value::try_from(s) {
            flatten("", &v, &mut out);
        }
        out.into_iter()
            .collect::<std::collections::BTreeMap<_, _>>()
    };
    let (a, b) = (flat(old), flat(new));
    let keys: std::collections::BTreeSet<&String> = a.keys().chain(b.keys()).collect();
    keys.into_iter()
        .filter(|k| a.get(*k) != b.get(*k))
        .map(|k| {
            let show = |m: &std::collections::BTreeMap<String, String>| {
                m.get(k).cloned().unwrap_or_else(|| "(none)".into())
            };
            format!("{k}: {} → {}", show(&a), show(&b))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::parse;
    use super::*;

    #[test]
    fn lookup_follows_tables_only() {
        let t: toml::Table = "a = 1\n[b]\nc = [1, 2]\n[b.d]\ne = \"x\"\n"
            .parse()
            .unwrap();
        assert_eq!(lookup(&t, "a"), Some(&toml::Value::Integer(1)));
        assert_eq!(lookup(&t, "b.d.e"), Some(&toml::Value::String("x".into())));
        assert!(matches!(lookup(&t, "b.d"), Some(toml::Value::Table(_))));
        assert!(matches!(lookup(&t, "b.c"), Some(toml::Value::Array(_))));
        for missing in ["", "z", "b.z", "a.x", "b.c.0", "b.c[0]", "b..d"] {
            assert_eq!(lookup(&t, missing), None, "{missing}");
        }
    }

    #[test]
    fn dotted_keys_are_bare_toml_keys() {
        for ok in ["a", "fabric.l0", "tools.side-x", "a_b.c9"] {
            assert!(is_dotted_key(ok), "{ok}");
        }
        for bad in ["", ".a", "a.", "a..b", "a b", "a.\"b\"", "é"] {
            assert!(!is_dotted_key(bad), "{bad}");
        }
    }

    #[test]
    fn every_kind_key_has_one_owner() {
        for kind in ToolKind::ALL {
            for name in kind.own_keys() {
                assert_eq!(ToolKind::owner_of(name), Some(kind), "{name}");
            }
        }
        for name in SHARED_TOOL_KEYS.into_iter().chain(["kind", "nose"]) {
            assert_eq!(ToolKind::owner_of(name), None, "{name}");
        }
    }

    #[test]
    fn keys_of_another_punch_are_rejected() {
        let e = parse("[tools]\nkind = \"ellipsoid\"\nr = 5\n", &[]).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("tools.r"), "{e}");
        assert!(e.detail.contains("only for tools.kind = \"box\""), "{e}");
        let e = parse("", &["tools.axes=[30,20,10]"]).unwrap_err();
        assert_eq!(e.origin, "--set tools.axes=[30,20,10]");
        // Switching the kind with --set would drop the file's box keys: refused, blamed on the
        // --set, naming the key it would drop.
        let sets = [
            "tools.kind=\"hemisphere\"",
            "tools.radius=20",
            "process.stroke=15",
        ];
        let e = parse("[tools]\nr = 5\nrp = 6\n", &sets).unwrap_err();
        assert_eq!(e.origin, "--set tools.kind=\"hemisphere\"");
        assert_eq!(e.key.as_deref(), Some("tools.kind"), "{e}");
        assert!(e.detail.contains("drop the scene file's tools.r"), "{e}");
        // A file without box keys switches.
        let s = parse("[tools]\nrm = 6\n", &sets).unwrap();
        assert_eq!(s.tools.kind, ToolKind::Hemisphere);
    }

    #[test]
    fn differences_name_the_keys_and_both_values() {
        let a = parse("", &[]).unwrap();
        let b = parse("", &["mesh.element_size=5.0", "process.friction=0.25"]).unwrap();
        assert_eq!(
            differences(&a, &b),
            [
                "mesh.element_size: 2.5 → 5.0",
                "process.friction: 0.2 → 0.25"
            ]
        );
        assert!(differences(&a, &a).is_empty());
    }
}
