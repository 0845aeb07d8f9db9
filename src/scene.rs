//! The TOML scene: serde types, defaults, validation and `--set` overrides.
//!
//! A scene file is a set of tables — `[fabric]`, `[tools]`, `[process]`, `[mesh]`, `[blank]`,
//! `[numerics]` — each a field of [`Scene`] with its own `#[serde(default)]` type. Every table
//! rejects unknown keys by name. Missing keys take the defaults: the paper's glass fabric and
//! `DrawingProblem::paper_box(10, 15, 10)`, so an empty file (or no file at all) is the paper's
//! open square box.
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
//!
//! [tools]
//! kind = "box"          # "box" | "ellipsoid" | "hemisphere"
//! side = 60             # mm (box), or [x, y]
//! r = 10                # punch corner radius, mm (box)
//! rp = 15               # punch nose radius, mm (box)
//! rm = 10               # die entry radius, mm
//! clearance = 1.5       # mm
//! # axes = [40, 25, 20] # ellipsoid semi-axes, mm;  radius = 30  for the hemisphere
//!
//! [process]
//! friction = 0.2
//! holder_pressure = 1.0 # MPa
//! stroke = 20           # mm
//!
//! [mesh]
//! element_size = 2.5    # mm
//! symmetry = "auto"     # "auto" | "full" | "quarter"
//!
//! [blank]
//! size = 140            # mm, or [x, y]
//! ```

use std::fmt;
use std::path::Path;
use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::core::drawing::{DrawingProblem, Symmetry, Tooling};
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
        d.deserialize_any(PairVisitor {
            expecting: "a number, or a [warp, weft] pair of numbers",
            pair: "a [warp, weft] pair",
        })
        .map(PerYarn)
    }
}

/// Reads one number (used for both) or a pair of numbers.
struct PairVisitor {
    expecting: &'static str,
    pair: &'static str,
}

impl<'de> serde::de::Visitor<'de> for PairVisitor {
    type Value = [f64; 2];
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(self.expecting)
    }
    fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<[f64; 2], E> {
        Ok([v, v])
    }
    fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<[f64; 2], E> {
        Ok([v as f64; 2])
    }
    fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<[f64; 2], E> {
        Ok([v as f64; 2])
    }
    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<[f64; 2], A::Error> {
        let pair = self.pair;
        let len_err = |n| serde::de::Error::invalid_length(n, &pair);
        let a: f64 = seq.next_element()?.ok_or_else(|| len_err(0))?;
        let b: f64 = seq.next_element()?.ok_or_else(|| len_err(1))?;
        if seq.next_element::<serde::de::IgnoredAny>()?.is_some() {
            return Err(len_err(3));
        }
        Ok([a, b])
    }
}

/// Plan dimensions `[x, y]`, mm. In TOML either a 2-array or one number for both (a square).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanPair(pub [f64; 2]);

impl Serialize for PlanPair {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.0.serialize(s)
    }
}

impl<'de> Deserialize<'de> for PlanPair {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(PairVisitor {
            expecting: "a number (a square), or an [x, y] pair of numbers",
            pair: "an [x, y] pair",
        })
        .map(PlanPair)
    }
}

impl fmt::Display for PlanPair {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{}, {}]", self.0[0], self.0[1])
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

/// The tool radii `[r, rp, rm]` (mm) of the default scene: the paper's open box.
pub const DEFAULT_BOX_RADII: [f64; 3] = [10.0, 15.0, 10.0];

/// The drawing the scene defaults come from: `DrawingProblem::paper_box(10, 15, 10)`.
fn default_problem() -> DrawingProblem {
    let [r, rp, rm] = DEFAULT_BOX_RADII;
    DrawingProblem::paper_box(r, rp, rm)
}

/// The punch shape (`tools.kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ToolKind {
    /// A flat-nosed rectangular punch with rounded corners and nose (the paper's box).
    #[default]
    Box,
    /// A half-ellipsoid punch.
    Ellipsoid,
    /// A hemispherical punch.
    Hemisphere,
}

impl ToolKind {
    /// The name written in the scene file.
    pub fn name(self) -> &'static str {
        match self {
            ToolKind::Box => "box",
            ToolKind::Ellipsoid => "ellipsoid",
            ToolKind::Hemisphere => "hemisphere",
        }
    }

    /// The `[tools]` keys that describe this punch only (the others are shared).
    fn own_keys(self) -> &'static [&'static str] {
        match self {
            ToolKind::Box => &["side", "r", "rp"],
            ToolKind::Ellipsoid => &["axes"],
            ToolKind::Hemisphere => &["radius"],
        }
    }
}

/// `[tools]` keys that belong to one kind of punch.
const KIND_KEYS: [&str; 5] = ["side", "r", "rp", "axes", "radius"];

/// The `[tools]` table: the punch and the die. Defaults: the paper's box with r = 10, rp = 15,
/// rm = 10 mm (side and clearance are not in the paper: see `DrawingProblem::paper_box`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Tools {
    /// `"box"`, `"ellipsoid"` or `"hemisphere"`.
    pub kind: ToolKind,
    /// Box: punch sides `[x, y]`, mm (one number: a square).
    pub side: PlanPair,
    /// Box: plan corner radius of the punch, mm.
    pub r: f64,
    /// Box: nose radius of the punch, mm.
    pub rp: f64,
    /// Die entry radius, mm.
    pub rm: f64,
    /// Gap between the punch and the die opening in plan, mm.
    pub clearance: f64,
    /// Ellipsoid: semi-axes `[ax, ay, az]`, mm (`az` is the punch's depth).
    pub axes: [f64; 3],
    /// Hemisphere: radius, mm.
    pub radius: f64,
}

impl Default for Tools {
    fn default() -> Self {
        let Tooling::Box {
            side,
            r,
            rp,
            rm,
            clearance,
        } = default_problem().tooling
        else {
            unreachable!("the paper's box is a box")
        };
        Tools {
            kind: ToolKind::Box,
            side: PlanPair(side),
            r,
            rp,
            rm,
            clearance,
            axes: [40.0, 25.0, 20.0],
            radius: 30.0,
        }
    }
}

impl Tools {
    /// The punch and die pair for the solver.
    pub fn tooling(&self) -> Tooling {
        match self.kind {
            ToolKind::Box => Tooling::Box {
                side: self.side.0,
                r: self.r,
                rp: self.rp,
                rm: self.rm,
                clearance: self.clearance,
            },
            ToolKind::Ellipsoid => Tooling::Ellipsoid {
                axes: self.axes,
                rm: self.rm,
                clearance: self.clearance,
            },
            ToolKind::Hemisphere => Tooling::Hemisphere {
                radius: self.radius,
                rm: self.rm,
                clearance: self.clearance,
            },
        }
    }

    /// The punch's depth below its widest section, mm (`None` for the box, which is extruded).
    pub fn punch_depth(&self) -> Option<f64> {
        match self.kind {
            ToolKind::Box => None,
            ToolKind::Ellipsoid => Some(self.axes[2]),
            ToolKind::Hemisphere => Some(self.radius),
        }
    }
}

/// The `[process]` table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Process {
    /// Coulomb friction coefficient between the fabric and every tool.
    pub friction: f64,
    /// Blank-holder pressure, MPa (0: no holder).
    pub holder_pressure: f64,
    /// Punch travel from touching the blank, mm.
    pub stroke: f64,
}

impl Default for Process {
    fn default() -> Self {
        let p = default_problem();
        Process {
            friction: p.friction,
            holder_pressure: p.holder_pressure,
            stroke: p.stroke,
        }
    }
}

/// `mesh.symmetry`: how much of the blank is solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SymmetryChoice {
    /// A quarter when the yarns lie along x and y (every tool here is symmetric about both).
    #[default]
    Auto,
    /// The whole blank.
    Full,
    /// A quarter (x ≥ 0, y ≥ 0), mirrored for pictures.
    Quarter,
}

impl SymmetryChoice {
    pub fn name(self) -> &'static str {
        match self {
            SymmetryChoice::Auto => "auto",
            SymmetryChoice::Full => "full",
            SymmetryChoice::Quarter => "quarter",
        }
    }
}

/// The `[mesh]` table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MeshSettings {
    /// Target element size, mm.
    pub element_size: f64,
    pub symmetry: SymmetryChoice,
}

impl Default for MeshSettings {
    fn default() -> Self {
        MeshSettings {
            element_size: default_problem().element_size,
            symmetry: SymmetryChoice::Auto,
        }
    }
}

/// The `[blank]` table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Blank {
    /// Blank sides `[x, y]` (the warp along x), mm, centred on the punch.
    pub size: PlanPair,
}

impl Default for Blank {
    fn default() -> Self {
        Blank {
            size: PlanPair(default_problem().blank),
        }
    }
}

/// The `[numerics]` table: knobs of the solver that a user may need to turn.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Numerics {
    /// Pseudo-transient damping κ of the Newton corrections on the slack fabric
    /// (dimensionless; 0 turns it off). It damps corrections only, not the answer.
    pub stabilisation: f64,
    /// Contact penalty, as a multiple of the cells' tensile stiffness.
    pub penalty_factor: f64,
}

impl Default for Numerics {
    fn default() -> Self {
        let p = default_problem();
        Numerics {
            stabilisation: p.solver.stabilisation,
            penalty_factor: p.penalty_factor,
        }
    }
}

/// A broken bound of the drawing: the key blamed, the keys involved (to find who set them) and
/// the message (which starts with the key).
struct Broken {
    key: String,
    involved: Vec<&'static str>,
    detail: String,
}

/// `key = value: expected what`, blaming `key` alone.
fn broken(key: &'static str, value: impl fmt::Display, what: impl fmt::Display) -> Broken {
    Broken {
        key: key.to_string(),
        involved: vec![key],
        detail: format!("{key} = {value}: expected {what}"),
    }
}

fn ok_if(ok: bool, f: impl FnOnce() -> Broken) -> Result<(), Broken> {
    if ok { Ok(()) } else { Err(f()) }
}

fn fmt3(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
}

/// A whole scene. Each section is a table of the TOML file.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    #[serde(default)]
    pub fabric: Fabric,
    #[serde(default)]
    pub tools: Tools,
    #[serde(default)]
    pub process: Process,
    #[serde(default)]
    pub mesh: MeshSettings,
    #[serde(default)]
    pub blank: Blank,
    #[serde(default)]
    pub numerics: Numerics,
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
        scene.check_kind_keys(&table, overrides, origin, &origin_of)?;
        scene.validate_with(&|keys: &[&str]| {
            // The last override that touched any of the keys, else the file.
            overrides
                .iter()
                .rev()
                .find(|o| {
                    keys.iter()
                        .any(|k| o.key == *k || k.starts_with(&format!("{}.", o.key)))
                })
                .map(|o| format!("--set {}", o.text))
                .unwrap_or_else(|| origin.to_string())
        })?;
        Ok(scene)
    }

    /// Rejects `[tools]` keys of another kind of punch (they would be silently ignored). When
    /// `tools.kind` itself comes from `--set`, the file's keys for the old kind are let pass.
    fn check_kind_keys(
        &self,
        table: &toml::Table,
        overrides: &[Override],
        origin: &str,
        origin_of: &dyn Fn(&str) -> String,
    ) -> Result<(), SceneError> {
        let Some(toml::Value::Table(tools)) = table.get("tools") else {
            return Ok(());
        };
        let kind = self.tools.kind;
        let kind_overridden = overrides
            .iter()
            .any(|o| o.key == "tools.kind" || o.key == "tools");
        for name in tools.keys() {
            if !KIND_KEYS.contains(&name.as_str()) || kind.own_keys().contains(&name.as_str()) {
                continue;
            }
            let key = format!("tools.{name}");
            let blamed = origin_of(&key);
            if kind_overridden && blamed == origin {
                continue;
            }
            let owner = [ToolKind::Box, ToolKind::Ellipsoid, ToolKind::Hemisphere]
                .into_iter()
                .find(|k| k.own_keys().contains(&name.as_str()))
                .expect("every kind key has an owner");
            let mut keys: Vec<&str> = kind.own_keys().to_vec();
            keys.extend(["rm", "clearance"]);
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

    /// Checks the physical bounds; `origin` names the scene in the error.
    pub fn validate(&self, origin: &str) -> Result<(), SceneError> {
        self.validate_with(&|_| origin.to_string())
    }

    /// `origin_of(keys)` names who set the keys involved in a broken bound.
    fn validate_with(&self, origin_of: &dyn Fn(&[&str]) -> String) -> Result<(), SceneError> {
        self.fabric.check().map_err(|(key, value, what)| {
            let key = format!("fabric.{key}");
            SceneError {
                origin: origin_of(&[&key]),
                detail: format!("{key} = {value}: expected {what}"),
                key: Some(key),
            }
        })?;
        self.check_drawing().map_err(|b| SceneError {
            origin: origin_of(&b.involved),
            detail: b.detail,
            key: Some(b.key),
        })
    }

    /// The physical bounds of the tools, process, blank, mesh and numerics.
    fn check_drawing(&self) -> Result<(), Broken> {
        let t = &self.tools;
        let pos = |v: f64| v.is_finite() && v > 0.0;
        ok_if(pos(t.rm), || {
            broken("tools.rm", t.rm, "a die entry radius rm > 0 mm")
        })?;
        ok_if(t.clearance.is_finite() && t.clearance >= 0.0, || {
            broken(
                "tools.clearance",
                t.clearance,
                "a punch–die clearance ≥ 0 mm",
            )
        })?;
        match t.kind {
            ToolKind::Box => {
                ok_if(t.side.0.iter().all(|&v| pos(v)), || {
                    broken("tools.side", t.side, "punch sides > 0 mm")
                })?;
                let half = 0.5 * t.side.0[0].min(t.side.0[1]);
                ok_if(pos(t.r), || {
                    broken("tools.r", t.r, "a punch corner radius r > 0 mm")
                })?;
                ok_if(t.r < half, || Broken {
                    key: "tools.r".into(),
                    involved: vec!["tools.r", "tools.side"],
                    detail: format!(
                        "tools.r = {}: r larger than the punch allows: expected a corner radius r < side/2 = {half} mm",
                        t.r
                    ),
                })?;
                ok_if(pos(t.rp), || {
                    broken("tools.rp", t.rp, "a punch nose radius rp > 0 mm")
                })?;
                ok_if(t.rp < half, || Broken {
                    key: "tools.rp".into(),
                    involved: vec!["tools.rp", "tools.side"],
                    detail: format!(
                        "tools.rp = {}: rp larger than the punch allows: expected a nose radius rp < side/2 = {half} mm",
                        t.rp
                    ),
                })?;
            }
            ToolKind::Ellipsoid => {
                ok_if(t.axes.iter().all(|&v| pos(v)), || {
                    broken(
                        "tools.axes",
                        fmt3(t.axes),
                        "punch semi-axes [ax, ay, az] > 0 mm",
                    )
                })?;
            }
            ToolKind::Hemisphere => {
                ok_if(pos(t.radius), || {
                    broken("tools.radius", t.radius, "a punch radius > 0 mm")
                })?;
            }
        }
        let p = &self.process;
        ok_if(
            p.friction.is_finite() && (0.0..=1.0).contains(&p.friction),
            || {
                broken(
                    "process.friction",
                    p.friction,
                    "a friction coefficient μ in [0, 1]",
                )
            },
        )?;
        ok_if(
            p.holder_pressure.is_finite() && (0.0..=50.0).contains(&p.holder_pressure),
            || {
                broken(
                    "process.holder_pressure",
                    p.holder_pressure,
                    "a blank-holder pressure in [0, 50] MPa",
                )
            },
        )?;
        ok_if(pos(p.stroke), || {
            broken("process.stroke", p.stroke, "a punch stroke > 0 mm")
        })?;
        if let Some(depth) = t.punch_depth() {
            let axis = if t.kind == ToolKind::Ellipsoid {
                "the semi-axis az"
            } else {
                "its radius"
            };
            ok_if(p.stroke <= depth, || Broken {
                key: "process.stroke".into(),
                involved: vec!["process.stroke", "tools.axes", "tools.radius"],
                detail: format!(
                    "process.stroke = {}: expected a stroke ≤ the punch's depth, {axis} = {depth} mm (the punch is the lower half of the {})",
                    p.stroke,
                    t.kind.name()
                ),
            })?;
        }
        let b = self.blank.size.0;
        ok_if(b.iter().all(|&v| pos(v)), || {
            broken("blank.size", self.blank.size, "blank sides > 0 mm")
        })?;
        let half = t.tooling().opening_half();
        let need = [2.0 * (half[0] + t.rm), 2.0 * (half[1] + t.rm)];
        ok_if(b[0] > need[0] && b[1] > need[1], || Broken {
            key: "blank.size".into(),
            involved: vec![
                "blank.size",
                "tools.side",
                "tools.clearance",
                "tools.rm",
                "tools.axes",
                "tools.radius",
            ],
            detail: format!(
                "blank.size = {}: blank barely larger than the die opening: expected sides > the opening plus 2·rm = {} mm, so that the blank's edge rests on the die face",
                self.blank.size,
                PlanPair(need)
            ),
        })?;
        let m = &self.mesh;
        let quarter_of_blank = 0.25 * b[0].min(b[1]);
        ok_if(
            pos(m.element_size) && m.element_size <= quarter_of_blank,
            || Broken {
                key: "mesh.element_size".into(),
                involved: vec!["mesh.element_size", "blank.size"],
                detail: format!(
                    "mesh.element_size = {}: expected an element size > 0 and ≤ blank/4 = {quarter_of_blank} mm",
                    m.element_size
                ),
            },
        )?;
        self.check_size()?;
        let yarns_on_axes = (self.fabric.yarn_angle_deg - 90.0).abs() < 1e-9;
        ok_if(
            m.symmetry != SymmetryChoice::Quarter || yarns_on_axes,
            || Broken {
                key: "mesh.symmetry".into(),
                involved: vec!["mesh.symmetry", "fabric.yarn_angle_deg"],
                detail: format!(
                    "mesh.symmetry = \"quarter\": expected \"auto\" or \"full\" when the yarns are not along x and y (fabric.yarn_angle_deg = {})",
                    self.fabric.yarn_angle_deg
                ),
            },
        )?;
        let n = &self.numerics;
        ok_if(
            n.stabilisation.is_finite() && n.stabilisation >= 0.0,
            || {
                broken(
                    "numerics.stabilisation",
                    n.stabilisation,
                    "a damping κ ≥ 0 of the Newton corrections (0 turns it off)",
                )
            },
        )?;
        ok_if(pos(n.penalty_factor), || {
            broken(
                "numerics.penalty_factor",
                n.penalty_factor,
                "a contact penalty factor > 0",
            )
        })?;
        Ok(())
    }

    /// The mesh fits in the machine's memory budget, checked before anything is allocated.
    fn check_size(&self) -> Result<(), Broken> {
        let budget = crate::machine::memory_budget_bytes();
        crate::machine::check_fits(&self.to_problem(), budget).map_err(|detail| Broken {
            key: "mesh.element_size".into(),
            involved: vec!["mesh.element_size", "blank.size"],
            detail,
        })
    }

    /// The drawing this scene describes, for [`crate::core::drawing::solve`]. Solver settings
    /// the scene does not expose keep the defaults of `DrawingProblem::paper_box`.
    pub fn to_problem(&self) -> DrawingProblem {
        let mut p = default_problem();
        p.fabric = self.to_cell_params();
        p.yarn_angle_deg = self.fabric.yarn_angle_deg;
        p.tooling = self.tools.tooling();
        p.blank = self.blank.size.0;
        p.friction = self.process.friction;
        p.holder_pressure = self.process.holder_pressure;
        p.stroke = self.process.stroke;
        p.element_size = self.mesh.element_size;
        p.symmetry = match self.mesh.symmetry {
            SymmetryChoice::Auto => Symmetry::Auto,
            SymmetryChoice::Full => Symmetry::Full,
            SymmetryChoice::Quarter => Symmetry::Quarter,
        };
        p.solver.stabilisation = self.numerics.stabilisation;
        p.penalty_factor = self.numerics.penalty_factor;
        p
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

    #[test]
    fn empty_scene_is_the_paper_open_box() {
        let s = parse("", &[]).unwrap();
        assert_eq!(s.to_problem(), DrawingProblem::paper_box(10.0, 15.0, 10.0));
    }

    #[test]
    fn every_drawing_key_works_with_set() {
        // (override, what it must change in the problem)
        type Check = fn(&DrawingProblem) -> bool;
        let cases: [(&str, Check); 16] = [
            (
                "tools.r=7.5",
                |p| matches!(p.tooling, Tooling::Box { r, .. } if r == 7.5),
            ),
            (
                "tools.rp=6",
                |p| matches!(p.tooling, Tooling::Box { rp, .. } if rp == 6.0),
            ),
            (
                "tools.rm=4",
                |p| matches!(p.tooling, Tooling::Box { rm, .. } if rm == 4.0),
            ),
            (
                "tools.side=[50,40]",
                |p| matches!(p.tooling, Tooling::Box { side, .. } if side == [50.0, 40.0]),
            ),
            (
                "tools.clearance=0",
                |p| matches!(p.tooling, Tooling::Box { clearance, .. } if clearance == 0.0),
            ),
            ("process.friction=0.1", |p| p.friction == 0.1),
            ("process.holder_pressure=0", |p| p.holder_pressure == 0.0),
            ("process.stroke=12.5", |p| p.stroke == 12.5),
            ("mesh.element_size=5", |p| p.element_size == 5.0),
            ("mesh.symmetry=\"full\"", |p| p.symmetry == Symmetry::Full),
            ("blank.size=[150,120]", |p| p.blank == [150.0, 120.0]),
            ("numerics.stabilisation=0", |p| {
                p.solver.stabilisation == 0.0
            }),
            ("numerics.penalty_factor=20", |p| p.penalty_factor == 20.0),
            ("fabric.undulation=false", |p| !p.fabric.undulation),
            ("fabric.yarn_angle_deg=80", |p| p.yarn_angle_deg == 80.0),
            ("fabric.c=30000", |p| p.fabric.c == [30000.0; 2]),
        ];
        for (set, check) in cases {
            let p = parse("", &[set])
                .unwrap_or_else(|e| panic!("{set}: {e}"))
                .to_problem();
            assert!(check(&p), "--set {set} did not reach the problem: {p:?}");
        }
        let p = parse(
            "",
            &[
                "tools.kind=\"ellipsoid\"",
                "tools.axes=[30,20,10]",
                "process.stroke=10",
            ],
        )
        .unwrap()
        .to_problem();
        assert_eq!(
            p.tooling,
            Tooling::Ellipsoid {
                axes: [30.0, 20.0, 10.0],
                rm: 10.0,
                clearance: 1.5
            }
        );
        let p = parse(
            "[tools]\nkind = \"hemisphere\"\nradius = 25\n",
            &["tools.radius=28"],
        )
        .unwrap()
        .to_problem();
        assert!(matches!(p.tooling, Tooling::Hemisphere { radius, .. } if radius == 28.0));
    }

    #[test]
    fn drawing_bounds_name_key_and_expectation() {
        let e = parse("[tools]\nr = -1\n", &[]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "x.toml: tools.r = -1: expected a punch corner radius r > 0 mm"
        );
        let e = parse("", &["tools.rp=31"]).unwrap_err();
        assert_eq!(e.origin, "--set tools.rp=31");
        assert!(e.detail.contains("rp larger than the punch allows"), "{e}");
        assert!(e.detail.contains("side/2 = 30 mm"), "{e}");
        // A smaller side makes the file's rp too large: the override that did it is named.
        let e = parse("[tools]\nrp = 15\n", &["tools.side=28"]).unwrap_err();
        assert_eq!(e.origin, "--set tools.side=28", "{e}");
        assert_eq!(e.key.as_deref(), Some("tools.rp"), "{e}");
        let e = parse("", &["blank.size=80"]).unwrap_err();
        assert!(
            e.detail
                .starts_with("blank.size = [80, 80]: blank barely larger than the die opening"),
            "{e}"
        );
        assert!(e.detail.contains("[83, 83] mm"), "{e}");
        for (set, key) in [
            ("process.friction=-0.1", "process.friction"),
            ("process.friction=1.5", "process.friction"),
            ("process.holder_pressure=51", "process.holder_pressure"),
            ("process.stroke=0", "process.stroke"),
            ("mesh.element_size=50", "mesh.element_size"),
            ("mesh.element_size=0", "mesh.element_size"),
            ("tools.clearance=-1", "tools.clearance"),
            ("tools.rm=0", "tools.rm"),
            ("numerics.penalty_factor=0", "numerics.penalty_factor"),
            ("numerics.stabilisation=-1", "numerics.stabilisation"),
        ] {
            let e = parse("", &[set]).unwrap_err();
            assert_eq!(e.key.as_deref(), Some(key), "{set}: {e}");
            assert!(e.detail.contains("expected"), "{set}: {e}");
        }
        let e = parse("[tools]\nkind = \"hemisphere\"\n", &["process.stroke=31"]).unwrap_err();
        assert!(e.detail.contains("punch's depth"), "{e}");
        let e = parse(
            "",
            &["mesh.symmetry=\"quarter\"", "fabric.yarn_angle_deg=45"],
        )
        .unwrap_err();
        assert_eq!(e.key.as_deref(), Some("mesh.symmetry"), "{e}");
        let e = parse("[tools]\nkind = \"cone\"\n", &[]).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("tools.kind"), "{e}");
        assert!(e.detail.contains("hemisphere"), "{e}");
        let e = parse("[blank]\nsize = [1, 2, 3]\n", &[]).unwrap_err();
        assert!(e.detail.starts_with("blank.size"), "{e}");
    }

    #[test]
    fn keys_of_another_punch_are_rejected() {
        let e = parse("[tools]\nkind = \"ellipsoid\"\nr = 5\n", &[]).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("tools.r"), "{e}");
        assert!(e.detail.contains("only for tools.kind = \"box\""), "{e}");
        let e = parse("", &["tools.axes=[30,20,10]"]).unwrap_err();
        assert_eq!(e.origin, "--set tools.axes=[30,20,10]");
        // Switching the kind with --set lets the file's box keys pass.
        let s = parse(
            "[tools]\nr = 5\nrp = 6\n",
            &[
                "tools.kind=\"hemisphere\"",
                "tools.radius=20",
                "process.stroke=15",
            ],
        )
        .unwrap();
        assert_eq!(s.tools.kind, ToolKind::Hemisphere);
    }

    #[test]
    fn the_presets_load_and_the_boxes_differ_only_in_the_radii() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("presets");
        let load = |name: &str| Scene::load(Some(&dir.join(name)), &[]).unwrap();
        let tight = load("paper-box-tight.toml");
        let open = load("paper-box-open.toml");
        let radii = |s: &Scene| [s.tools.r, s.tools.rp, s.tools.rm];
        assert_eq!(radii(&tight), [5.0, 6.0, 5.0]);
        assert_eq!(radii(&open), [10.0, 15.0, 10.0]);
        let mut same = tight.clone();
        same.tools = Tools {
            r: 10.0,
            rp: 15.0,
            rm: 10.0,
            ..tight.tools.clone()
        };
        assert_eq!(same, open);
        // The open box is the default drawing, with the linear yarn law (the paper's first
        // example); the stroke and the mesh may be tuned in the preset.
        let mut want = DrawingProblem::paper_box(10.0, 15.0, 10.0);
        want.fabric.undulation = false;
        let got = open.to_problem();
        assert_eq!(
            (
                got.fabric,
                got.tooling,
                got.blank,
                got.friction,
                got.holder_pressure
            ),
            (
                want.fabric,
                want.tooling,
                want.blank,
                want.friction,
                want.holder_pressure
            )
        );
        assert_eq!(open.fabric.locking_angle_deg, 60.0);
        for name in ["paper-ellipsoid.toml", "hemisphere.toml"] {
            let s = load(name);
            assert!(s.fabric.undulation, "{name}");
        }
        assert_eq!(load("paper-ellipsoid.toml").tools.kind, ToolKind::Ellipsoid);
        assert_eq!(load("hemisphere.toml").tools.kind, ToolKind::Hemisphere);
        let sets: Vec<Override> = vec!["fabric.undulation=false".parse().unwrap()];
        Scene::load(Some(&dir.join("paper-ellipsoid.toml")), &sets).unwrap();
    }
}
