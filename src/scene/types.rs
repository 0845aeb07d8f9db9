//! The serde types of the scene's tables, and their defaults (the paper's glass fabric and
//! open square box). Bounds are checked in `validate.rs`, the keys of each punch in `keys.rs`.

use std::fmt;

pub use crate::show::Num;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::core::drawing::{DrawingProblem, Tooling};
use crate::core::fabric::law::CellParams;

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
        write!(f, "[{}, {}]", Num(self.0[0]), Num(self.0[1]))
    }
}

impl fmt::Display for PerYarn {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{}, {}]", Num(self.0[0]), Num(self.0[1]))
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
    /// The largest wrinkle amplitude a part may have, mm (`core::wrinkles::amplitude`): judged where the
    /// fabric has bending, the paper's membrane having no wrinkles to judge.
    pub wrinkle_limit_mm: f64,
    /// Initial angle between warp and weft, degrees.
    pub yarn_angle_deg: f64,
    /// The in-plane shear moment per unit initial area `M(γ) = k1 γ + k3 γ³ + k5 γ⁵`,
    /// `[k1, k3, k5]` in N·mm/mm² (γ in radians): beyond the paper, absent by default.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shear_moment: Option<[f64; 3]>,
    /// Locking as a stiffening: past the locking angle the shear moment rises steeply
    /// (`core::fabric::shear::Locking`). Needs `shear_moment`.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub shear_locking: bool,
    /// Bending rigidity per unit width `[B1, B2]`, N·mm (warp, weft): beyond the paper, absent
    /// by default (the paper's membrane). Hinges along the yarn lines (`core::fabric::bending`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bending_rigidity: Option<[f64; 2]>,
    /// The yarns' stiffness in compression `[Cc1, Cc2]`, N per yarn (as `c` in tension): with
    /// `bending_rigidity`; absent, `DEFAULT_COMPRESSION` × `c` (1 % of it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compressive_stiffness: Option<[f64; 2]>,
    /// Areal mass, g/m²: the fabric's weight in the cantilever test (`wovenform cantilever`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub areal_mass: Option<f64>,
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
            wrinkle_limit_mm: DEFAULT_WRINKLE_LIMIT_MM,
            yarn_angle_deg: 90.0,
            shear_moment: None,
            shear_locking: false,
            bending_rigidity: None,
            compressive_stiffness: None,
            areal_mass: None,
        }
    }
}

/// The wrinkle limit of a scene that gives none, mm: a wave of about two thicknesses of a
/// glass plain weave, which shows as a fold in a moulded part.
pub const DEFAULT_WRINKLE_LIMIT_MM: f64 = 1.0;

/// The tool radii `[r, rp, rm]` (mm) of the default scene: the paper's open box.
pub const DEFAULT_BOX_RADII: [f64; 3] = [10.0, 15.0, 10.0];

/// The drawing the scene defaults come from: `DrawingProblem::paper_box(10, 15, 10)`.
pub(super) fn default_problem() -> DrawingProblem {
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
    /// A punch and a die from STL files.
    Mesh,
}

impl ToolKind {
    /// The name written in the scene file.
    pub fn name(self) -> &'static str {
        match self {
            ToolKind::Box => "box",
            ToolKind::Ellipsoid => "ellipsoid",
            ToolKind::Hemisphere => "hemisphere",
            ToolKind::Mesh => "mesh",
        }
    }
}

/// The `[tools]` table: the punch and the die. Defaults: the paper's box with r = 10, rp = 15,
/// rm = 10 mm (side and clearance are not in the paper: see `DrawingProblem::paper_box`).
#[derive(Clone, Debug, PartialEq, Deserialize)]
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
    /// Mesh: the punch's STL file (relative to the scene file).
    pub punch: String,
    /// Mesh: the die's STL file (relative to the scene file).
    pub die: String,
    /// Mesh: spacing of the lattice the tools' distance is sampled on, mm.
    pub lattice: f64,
    /// Mesh: the tools read from `punch` and `die` (filled when the scene is loaded).
    #[serde(skip)]
    pub loaded: Option<LoadedTools>,
}

/// The mesh tools of a scene, read and checked.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadedTools {
    pub punch: std::sync::Arc<crate::core::tools::mesh_tool::MeshTool>,
    pub die: std::sync::Arc<crate::core::tools::mesh_tool::MeshTool>,
    /// The smallest radius of curvature of either where the fabric can touch it, mm.
    pub smallest_radius_mm: f64,
}

/// The default spacing of a mesh tool's distance lattice, mm.
pub const DEFAULT_LATTICE_MM: f64 = 1.0;

/// Only the keys of the scene's kind of punch (and the shared ones), so that a written scene
/// (`summary.json`'s `inputs`, `results.json`'s `base_scene`) reads back as a scene.
impl Serialize for Tools {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let own = self.kind.own_keys();
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("kind", &self.kind)?;
        if own.contains(&"side") {
            m.serialize_entry("side", &self.side)?;
            m.serialize_entry("r", &self.r)?;
            m.serialize_entry("rp", &self.rp)?;
        }
        if own.contains(&"axes") {
            m.serialize_entry("axes", &self.axes)?;
        }
        if own.contains(&"radius") {
            m.serialize_entry("radius", &self.radius)?;
        }
        if self.kind == ToolKind::Mesh {
            m.serialize_entry("punch", &self.punch)?;
            m.serialize_entry("die", &self.die)?;
            m.serialize_entry("lattice", &self.lattice)?;
        } else {
            m.serialize_entry("rm", &self.rm)?;
            m.serialize_entry("clearance", &self.clearance)?;
        }
        m.end()
    }
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
            punch: String::new(),
            die: String::new(),
            lattice: DEFAULT_LATTICE_MM,
            loaded: None,
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
            ToolKind::Mesh => {
                let loaded = self
                    .loaded
                    .as_ref()
                    .expect("a mesh scene's tools are read when it is loaded");
                Tooling::Mesh {
                    punch: loaded.punch.clone(),
                    die: loaded.die.clone(),
                }
            }
        }
    }

    /// The last part of a tool file's path, for titles.
    pub fn file_name<'a>(&self, path: &'a str) -> &'a str {
        path.rsplit(['/', '\\']).next().unwrap_or(path)
    }

    /// The smallest radius of curvature the fabric is drawn over, mm: for the box its corner,
    /// nose and die entry radii; for the ellipsoid the die entry and the punch's tightest
    /// curvature (c²/a for semi-axes a ≥ b ≥ c); for the hemisphere its radius and the die
    /// entry. The accuracy levels' errors were measured down to 5 mm (`crate::accuracy`).
    pub fn smallest_radius_mm(&self) -> f64 {
        match self.kind {
            ToolKind::Box => self.r.min(self.rp).min(self.rm),
            ToolKind::Ellipsoid => {
                let mut a = self.axes;
                a.sort_by(f64::total_cmp);
                (a[0] * a[0] / a[2]).min(self.rm)
            }
            ToolKind::Hemisphere => self.radius.min(self.rm),
            ToolKind::Mesh => self.loaded.as_ref().map_or(0.0, |l| l.smallest_radius_mm),
        }
    }

    /// The punch's depth below its widest section, mm (`None` for the box, which is extruded).
    pub fn punch_depth(&self) -> Option<f64> {
        match self.kind {
            ToolKind::Box | ToolKind::Mesh => None,
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
    /// A rigid holder plate pressed with this total force, kN, in place of the pressure on
    /// each node (`core::contact::holder`): absent by default.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub holder_force: Option<f64>,
    /// Punch travel from touching the blank, mm.
    pub stroke: f64,
}

impl Default for Process {
    fn default() -> Self {
        let p = default_problem();
        Process {
            friction: p.friction,
            holder_pressure: p.holder_pressure_mpa,
            holder_force: None,
            stroke: p.stroke_mm,
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
            element_size: default_problem().element_size_mm,
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
            size: PlanPair(default_problem().blank_mm),
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
    /// With bending: the root-mean-square of the seeded out-of-plane pressure that lets a flat
    /// blank buckle (`core::wrinkles::trigger`), Pa.
    pub trigger_pa: f64,
    /// With bending: the seed of the trigger's pattern.
    pub trigger_seed: u64,
}

impl Default for Numerics {
    fn default() -> Self {
        let p = default_problem();
        Numerics {
            stabilisation: p.solver.stabilisation,
            penalty_factor: p.penalty_factor,
            trigger_pa: crate::core::wrinkles::trigger::DEFAULT_TRIGGER_MPA * 1e6,
            trigger_seed: 1,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::parse;

    #[test]
    fn per_yarn_accepts_one_number_or_a_pair_and_integers() {
        let s = parse("[fabric]\nl0 = 5\ne0 = [0.2, 0.3]\nc = 30000\n", &[]).unwrap();
        assert_eq!(s.fabric.l0.0, [5.0, 5.0]);
        assert_eq!(s.fabric.e0.0, [0.2, 0.3]);
        assert_eq!(s.fabric.c.0, [30000.0, 30000.0]);
        let e = parse("[fabric]\nl0 = [1.0, 2.0, 3.0]\n", &[]).unwrap_err();
        assert!(e.detail.starts_with("fabric.l0"), "{e}");
    }
}
