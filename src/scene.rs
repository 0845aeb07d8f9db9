//! The TOML scene: serde types, defaults, validation and `--set` overrides.
//!
//! A scene file is a set of tables; today only `[fabric]` exists (tools, process and mesh
//! sections join it later, each as one more field of [`Scene`] with its own `#[serde(default)]`
//! type and its own `validate`). Every table rejects unknown keys by name. Missing keys take the
//! paper's values, so an empty file (or no file at all) is the paper's glass fabric.
//!
//! Loading goes text → `toml::Table` → `--set` overrides applied to the table → typed
//! [`Scene`] → physical validation. Applying overrides to the untyped table means any key works
//! with `--set`, and an unknown one fails exactly like an unknown key in the file.
//!
//! ```toml
//! [fabric]
//! l0 = [4.76, 4.76]     # mm, or one number for both yarns
//! e0 = 0.238            # mm
//! c = 38000             # N
//! a = 0.075             # mm
//! b = 0.25              # 1/N
//! ```

use std::fmt;
use std::path::Path;
use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::core::law::CellParams;

/// What a scene error points at when there is no file.
pub const DEFAULT_ORIGIN: &str = "<default scene>";

/// A scene error: where (a file, `--set ...` or the default scene), which key, and what was
/// expected. Displays as `origin: detail`, e.g.
/// `presets/x.toml: fabric.a = -1: expected a closure saturation A ≥ 0 mm`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneError {
    /// The file, `--set KEY=VALUE`, or [`DEFAULT_ORIGIN`].
    pub origin: String,
    /// The dotted key concerned, if one is.
    pub key: Option<String>,
    /// What went wrong and what was expected (names the key when there is one).
    pub detail: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.origin, self.detail)
    }
}

impl std::error::Error for SceneError {}

/// One `--set KEY=VALUE` override; VALUE is a TOML literal.
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    /// Dotted key, e.g. `fabric.l0`.
    pub key: String,
    pub value: toml::Value,
    /// The text as given, for error messages.
    pub text: String,
}

impl FromStr for Override {
    type Err = SceneError;

    fn from_str(text: &str) -> Result<Self, SceneError> {
        let origin = format!("--set {text}");
        let err = |key: Option<String>, detail: String| SceneError {
            origin: origin.clone(),
            key,
            detail,
        };
        let Some((key, value)) = text.split_once('=') else {
            return Err(err(
                None,
                "expected KEY=VALUE with VALUE a TOML literal, e.g. fabric.a=0.05".into(),
            ));
        };
        let key = key.trim();
        let parts: Vec<&str> = key.split('.').collect();
        if parts.iter().any(|p| {
            p.is_empty()
                || !p
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        }) {
            return Err(err(
                None,
                format!("`{key}` is not a key: expected a dotted key such as fabric.a"),
            ));
        }
        let doc = format!("v = {}", value.trim());
        let value = doc
            .parse::<toml::Table>()
            .ok()
            .and_then(|mut t| t.remove("v"))
            .ok_or_else(|| {
                err(
                    Some(key.to_string()),
                    format!(
                        "{key} = {}: expected a TOML literal (a number, true/false, [a, b], or a \"quoted string\")",
                        value.trim()
                    ),
                )
            })?;
        Ok(Override {
            key: key.to_string(),
            value,
            text: text.to_string(),
        })
    }
}

/// A number for each yarn, `[warp, weft]`. In TOML either a 2-array or one number for both.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PerYarn(pub [f64; 2]);

impl Serialize for PerYarn {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.0.serialize(s)
    }
}

impl<'de> Deserialize<'de> for PerYarn {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = PerYarn;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number, or a [warp, weft] pair of numbers")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<PerYarn, E> {
                Ok(PerYarn([v, v]))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<PerYarn, E> {
                Ok(PerYarn([v as f64; 2]))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<PerYarn, E> {
                Ok(PerYarn([v as f64; 2]))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<PerYarn, A::Error> {
                let len_err = |n| serde::de::Error::invalid_length(n, &"a [warp, weft] pair");
                let w: f64 = seq.next_element()?.ok_or_else(|| len_err(0))?;
                let f: f64 = seq.next_element()?.ok_or_else(|| len_err(1))?;
                if seq.next_element::<serde::de::IgnoredAny>()?.is_some() {
                    return Err(len_err(3));
                }
                Ok(PerYarn([w, f]))
            }
        }
        d.deserialize_any(V)
    }
}

impl fmt::Display for PerYarn {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{}, {}]", self.0[0], self.0[1])
    }
}

/// The `[fabric]` table: the woven cell of eqs 1–7 and the fabric's limits.
/// Defaults are the paper's plain-weave glass fabric (eqs 6–7).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Fabric {
    /// `L0α`: cell length (wavelength) along [warp, weft], mm.
    pub l0: PerYarn,
    /// `e0α`: initial crown height of each yarn, mm.
    pub e0: PerYarn,
    /// `Cα`: tensile stiffness of each yarn, N.
    pub c: PerYarn,
    /// `A`: saturation of the closure, mm.
    pub a: f64,
    /// `B`: transverse compliance rate, 1/N.
    pub b: f64,
    /// The woven (undulation) law, or the linear yarn law `T = C max(ε, 0)` when false.
    pub undulation: bool,
    /// Shear locking angle, degrees: the design limit on the change of angle between the yarns.
    pub locking_angle_deg: f64,
    /// Yarn breaking tension, N. An assumption: the paper gives no value for its glass fabric;
    /// 1500 N is a round figure for a glass roving of that stiffness.
    pub break_tension_n: f64,
    /// Initial angle between warp and weft, degrees.
    pub yarn_angle_deg: f64,
}

impl Default for Fabric {
    fn default() -> Self {
        let p = CellParams::PAPER_GLASS;
        Fabric {
            l0: PerYarn(p.l0),
            e0: PerYarn(p.e0),
            c: PerYarn(p.c),
            a: p.a,
            b: p.b,
            undulation: p.undulation,
            locking_angle_deg: 60.0,
            break_tension_n: 1500.0,
            yarn_angle_deg: 90.0,
        }
    }
}

impl Fabric {
    /// The physical bounds; `Err((key, value shown, expectation))` for the first one broken.
    fn check(&self) -> Result<(), (&'static str, String, String)> {
        let per = |key: &'static str, v: PerYarn, ok: &dyn Fn(f64, usize) -> bool, what: String| {
            if (0..2).all(|i| v.0[i].is_finite() && ok(v.0[i], i)) {
                Ok(())
            } else {
                Err((key, v.to_string(), what))
            }
        };
        let one = |key: &'static str, v: f64, ok: bool, what: &str| {
            if v.is_finite() && ok {
                Ok(())
            } else {
                Err((key, v.to_string(), what.to_string()))
            }
        };
        per(
            "l0",
            self.l0,
            &|v, _| v > 0.0,
            "a cell length L0 > 0 mm for each yarn".into(),
        )?;
        let l0 = self.l0.0;
        per(
            "e0",
            self.e0,
            &|v, i| v >= 0.0 && v < 0.5 * l0[i],
            format!(
                "a crown height 0 ≤ e0 < L0/2 mm for each yarn (L0/2 = {})",
                PerYarn([0.5 * l0[0], 0.5 * l0[1]])
            ),
        )?;
        per(
            "c",
            self.c,
            &|v, _| v > 0.0,
            "a yarn stiffness C > 0 N for each yarn".into(),
        )?;
        let h = self.e0.0[0] + self.e0.0[1];
        one("a", self.a, self.a >= 0.0, "a closure saturation A ≥ 0 mm")?;
        one(
            "a",
            self.a,
            self.a < h,
            &format!(
                "a closure saturation A < e01 + e02 = {h} mm (the yarns cannot flatten past each other)"
            ),
        )?;
        one(
            "b",
            self.b,
            self.b > 0.0,
            "a transverse compliance rate B > 0 1/N",
        )?;
        one(
            "locking_angle_deg",
            self.locking_angle_deg,
            self.locking_angle_deg > 0.0 && self.locking_angle_deg < 90.0,
            "a shear locking angle strictly between 0 and 90 degrees",
        )?;
        one(
            "break_tension_n",
            self.break_tension_n,
            self.break_tension_n > 0.0,
            "a yarn breaking tension > 0 N",
        )?;
        one(
            "yarn_angle_deg",
            self.yarn_angle_deg,
            self.yarn_angle_deg > 0.0 && self.yarn_angle_deg < 180.0,
            "an initial angle between the yarns strictly between 0 and 180 degrees",
        )?;
        Ok(())
    }
}

/// A whole scene. Each section is a table of the TOML file.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    #[serde(default)]
    pub fabric: Fabric,
}

impl Scene {
    /// Loads `path` (or the embedded default when `None`), applies the overrides in order, and
    /// validates. Errors name the file (or `--set ...`), the key and what was expected.
    pub fn load(path: Option<&Path>, overrides: &[Override]) -> Result<Scene, SceneError> {
        match path {
            None => Scene::from_toml_str("", DEFAULT_ORIGIN, overrides),
            Some(path) => {
                let origin = path.display().to_string();
                let text = std::fs::read_to_string(path).map_err(|e| SceneError {
                    origin: origin.clone(),
                    key: None,
                    detail: format!("cannot read the scene file: {e}"),
                })?;
                Scene::from_toml_str(&text, &origin, overrides)
            }
        }
    }

    /// Parses scene text; `origin` names it in errors (a path, or [`DEFAULT_ORIGIN`]).
    pub fn from_toml_str(
        text: &str,
        origin: &str,
        overrides: &[Override],
    ) -> Result<Scene, SceneError> {
        let mut table: toml::Table = text.parse().map_err(|e: toml::de::Error| SceneError {
            origin: origin.to_string(),
            key: None,
            detail: format!("not valid TOML: {}", e.to_string().trim_end()),
        })?;
        for o in overrides {
            apply_override(&mut table, o)?;
        }
        // Whose fault is a bad key: the last override that set it, else the file.
        let origin_of = |key: &str| -> String {
            overrides
                .iter()
                .rev()
                .find(|o| o.key == key || key.starts_with(&format!("{}.", o.key)))
                .map(|o| format!("--set {}", o.text))
                .unwrap_or_else(|| origin.to_string())
        };
        let scene: Scene = serde_path_to_error::deserialize(toml::Value::Table(table.clone()))
            .map_err(|e| {
                let path = e.path().to_string();
                let message = e.inner().message().to_string();
                structural_error(&path, &message, &table, &origin_of)
            })?;
        scene.validate_with(&origin_of)?;
        Ok(scene)
    }

    /// Checks the physical bounds; `origin` names the scene in the error.
    pub fn validate(&self, origin: &str) -> Result<(), SceneError> {
        self.validate_with(&|_| origin.to_string())
    }

    fn validate_with(&self, origin_of: &dyn Fn(&str) -> String) -> Result<(), SceneError> {
        self.fabric.check().map_err(|(key, value, what)| {
            let key = format!("fabric.{key}");
            SceneError {
                origin: origin_of(&key),
                detail: format!("{key} = {value}: expected {what}"),
                key: Some(key),
            }
        })
    }

    /// The law's parameters for this scene's fabric.
    pub fn to_cell_params(&self) -> CellParams {
        let f = &self.fabric;
        CellParams {
            l0: f.l0.0,
            e0: f.e0.0,
            c: f.c.0,
            a: f.a,
            b: f.b,
            undulation: f.undulation,
        }
    }
}

/// Sets `o.key` in the table, creating intermediate tables as needed.
fn apply_override(table: &mut toml::Table, o: &Override) -> Result<(), SceneError> {
    let parts: Vec<&str> = o.key.split('.').collect();
    let (last, parents) = parts.split_last().expect("a key has at least one part");
    let mut t = table;
    for (i, p) in parents.iter().enumerate() {
        let entry = t
            .entry(p.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        t = match entry {
            toml::Value::Table(inner) => inner,
            _ => {
                let at = parts[..=i].join(".");
                return Err(SceneError {
                    origin: format!("--set {}", o.text),
                    key: Some(o.key.clone()),
                    detail: format!("{at} is a value, not a table, so it has no key {}", o.key),
                });
            }
        };
    }
    t.insert(last.to_string(), o.value.clone());
    Ok(())
}

/// Turns a serde error at `path` into a message naming the key and the expectation.
fn structural_error(
    path: &str,
    message: &str,
    table: &toml::Table,
    origin_of: &dyn Fn(&str) -> String,
) -> SceneError {
    // serde: "unknown field `x`, expected one of `a`, `b`" (path = the table, or the key itself).
    if let Some(rest) = message.strip_prefix("unknown field `") {
        let (name, expected) = rest.split_once('`').unwrap_or((rest, ""));
        let key = if path == "." || path.is_empty() {
            name.to_string()
        } else if path.ends_with(name) {
            path.to_string()
        } else {
            format!("{path}.{name}")
        };
        let expected = expected
            .trim_start_matches(", ")
            .replace("expected one of", "expected one of:")
            .replace("expected nothing", "expected no keys here")
            .replace('`', "");
        let section = if key.contains('.') { "key" } else { "section" };
        return SceneError {
            origin: origin_of(&key),
            detail: format!("{key}: unknown {section}; {expected}"),
            key: Some(key),
        };
    }
    let shown = lookup(table, path)
        .map(|v| format!(" = {v}"))
        .unwrap_or_default();
    SceneError {
        origin: origin_of(path),
        detail: format!("{path}{shown}: {message}"),
        key: Some(path.to_string()),
    }
}

fn lookup<'a>(table: &'a toml::Table, path: &str) -> Option<&'a toml::Value> {
    let mut parts = path.split('.');
    let mut v = table.get(parts.next()?)?;
    for p in parts {
        v = match v {
            toml::Value::Table(t) => t.get(p)?,
            toml::Value::Array(a) => a.get(p.parse::<usize>().ok()?)?,
            _ => return None,
        };
    }
    Some(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str, sets: &[&str]) -> Result<Scene, SceneError> {
        let sets: Vec<Override> = sets.iter().map(|s| s.parse().unwrap()).collect();
        Scene::from_toml_str(text, "x.toml", &sets)
    }

    #[test]
    fn empty_scene_is_the_paper_fabric() {
        let s = parse("", &[]).unwrap();
        assert_eq!(s.to_cell_params(), CellParams::PAPER_GLASS);
        assert_eq!(s.fabric.locking_angle_deg, 60.0);
        assert_eq!(s.fabric.yarn_angle_deg, 90.0);
    }

    #[test]
    fn the_paper_preset_is_the_default() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/paper_glass_fabric.toml");
        assert_eq!(Scene::load(Some(&path), &[]).unwrap(), Scene::default());
    }

    #[test]
    fn per_yarn_accepts_one_number_or_a_pair_and_integers() {
        let s = parse("[fabric]\nl0 = 5\ne0 = [0.2, 0.3]\nc = 30000\n", &[]).unwrap();
        assert_eq!(s.fabric.l0.0, [5.0, 5.0]);
        assert_eq!(s.fabric.e0.0, [0.2, 0.3]);
        assert_eq!(s.fabric.c.0, [30000.0, 30000.0]);
        let e = parse("[fabric]\nl0 = [1.0, 2.0, 3.0]\n", &[]).unwrap_err();
        assert!(e.detail.starts_with("fabric.l0"), "{e}");
    }

    #[test]
    fn unknown_keys_are_named() {
        let e = parse("[fabric]\nfoo = 1\n", &[]).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("fabric.foo"), "{e}");
        assert!(
            e.to_string().starts_with("x.toml: fabric.foo: unknown key"),
            "{e}"
        );
        let e = parse("[tooling]\nr = 1\n", &[]).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("tooling"), "{e}");
        let e = parse("", &["fabric.bar=2"]).unwrap_err();
        assert_eq!(e.origin, "--set fabric.bar=2");
        assert!(e.detail.contains("fabric.bar"), "{e}");
    }

    #[test]
    fn bounds_name_file_key_and_expectation() {
        let e = parse("[fabric]\na = -1\n", &[]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "x.toml: fabric.a = -1: expected a closure saturation A ≥ 0 mm"
        );
        let e = parse("", &["fabric.l0=[5.0,-4.0]"]).unwrap_err();
        assert_eq!(e.origin, "--set fabric.l0=[5.0,-4.0]");
        assert!(e.detail.starts_with("fabric.l0 = [5, -4]: expected"), "{e}");
        let e = parse("[fabric]\nb = nan\n", &[]).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("fabric.b"));
    }

    #[test]
    fn overrides_apply_in_order() {
        let s = parse(
            "[fabric]\na = 0.05\n",
            &["fabric.a=0.06", "fabric.l0=[5.0,4.0]"],
        )
        .unwrap();
        assert_eq!(s.fabric.a, 0.06);
        assert_eq!(s.fabric.l0.0, [5.0, 4.0]);
        assert!("fabric.a".parse::<Override>().is_err());
        assert!("fabric.a=abc".parse::<Override>().is_err());
        let e = parse("[fabric]\na = 0.05\n", &["fabric.a.x=1"]).unwrap_err();
        assert!(e.detail.contains("not a table"), "{e}");
    }

    #[test]
    fn wrong_types_are_named() {
        let e = parse("[fabric]\nundulation = 3\n", &[]).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("fabric.undulation"), "{e}");
        assert!(e.detail.contains("= 3"), "{e}");
    }
}
