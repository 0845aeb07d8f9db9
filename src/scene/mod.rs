//! The TOML scene: what a scene file holds, how it is loaded, and the drawing it describes.
//!
//! A scene file describes one drawing: the fabric, the punch and die, the process, the blank,
//! the mesh and the solver's knobs, in units of mm, N and MPa. It is a set of tables —
//! `[fabric]`, `[tools]`, `[process]`, `[mesh]`, `[blank]`, `[numerics]` — each a field of
//! [`Scene`] with its own `#[serde(default)]` type. Every table rejects unknown keys by name.
//! Missing keys take the defaults: the paper's glass fabric and
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
//! kind = "box"          # "box" | "ellipsoid" | "hemisphere" | "mesh" (punch, die: STL files)
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
//!
//! The parts: `types.rs` (the tables and their defaults), `overrides.rs` (`--set` and the
//! errors of typing the table), `keys.rs` (dotted-key lookup, [`lookup`], and the keys of each
//! punch) and `validate.rs` (the physical bounds).

mod keys;
mod mesh_tools;
mod overrides;
pub mod specimen;
mod types;
mod validate;

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::core::drawing::{DrawingProblem, Symmetry};
use crate::core::fabric::law::CellParams;

pub use keys::{differences, lookup, unset_key_shape};
pub use mesh_tools::forget_mesh_tools;
pub use overrides::{Override, blame, expand_dotted_keys, merge_tables};
pub use types::{
    Blank, DEFAULT_BOX_RADII, Fabric, MeshSettings, Num, Numerics, PerYarn, PlanPair, Process,
    SymmetryChoice, ToolKind, Tools,
};

use overrides::{apply_override, structural_error};
use types::default_problem;

/// What a scene error points at when there is no file.
pub const DEFAULT_ORIGIN: &str = "<default scene>";

/// A scene error: where (a file, `--set ...` or the default scene), which key, and what was
/// expected. Displays as `origin: detail`, e.g.
/// `presets/x.toml: fabric.a = -1: expected a closure saturation A ≥ 0 mm`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{origin}: {detail}")]
pub struct SceneError {
    /// The file, `--set KEY=VALUE`, or [`DEFAULT_ORIGIN`].
    pub origin: String,
    /// The dotted key concerned, if one is.
    pub key: Option<String>,
    /// What went wrong and what was expected (names the key when there is one).
    pub detail: String,
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
                let text =
                    crate::files::read_text(path, crate::files::MAX_TEXT_BYTES).map_err(|e| {
                        SceneError {
                            origin: origin.clone(),
                            key: None,
                            detail: format!("cannot read the scene file: {e}"),
                        }
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
        expand_dotted_keys(&mut table).map_err(|key| SceneError {
            origin: origin.to_string(),
            detail: format!(
                "\"{key}\" is given twice: as a quoted dotted key and in its table; expected one"
            ),
            key: Some(key),
        })?;
        for o in overrides {
            apply_override(&mut table, o)?;
        }
        // Whose fault is a bad key: the last override that set it, else the file.
        let origin_of = |key: &str| blame(overrides, origin, &[key]);
        let mut scene: Scene = serde_path_to_error::deserialize(toml::Value::Table(table.clone()))
            .map_err(|e| {
                let path = e.path().to_string();
                let message = e.inner().message().to_string();
                structural_error(&path, &message, &table, &origin_of)
            })?;
        let kind_set = (overrides.iter().rev())
            .find(|o| o.key == "tools.kind" || o.key == "tools")
            .map(|o| o.text.as_str());
        scene.check_kind_keys(&table, kind_set, origin, &origin_of)?;
        scene.validate_with(&|keys: &[&str]| blame(overrides, origin, keys))?;
        if scene.tools.kind == ToolKind::Mesh {
            scene.read_mesh_tools(origin, &|keys: &[&str]| blame(overrides, origin, keys))?;
            scene.validate_with(&|keys: &[&str]| blame(overrides, origin, keys))?;
        }
        Ok(scene)
    }

    /// The drawing this scene describes, for [`crate::core::drawing::solve`]. Solver settings
    /// the scene does not expose keep the defaults of `DrawingProblem::paper_box`.
    pub fn to_problem(&self) -> DrawingProblem {
        let mut p = default_problem();
        p.fabric = self.to_cell_params();
        p.shear = self.fabric.shear_moment.map(|k| {
            let law = crate::core::fabric::shear::ShearLaw::new(k);
            if self.fabric.shear_locking {
                law.with_locking(self.fabric.locking_angle_deg)
            } else {
                law
            }
        });
        p.yarn_angle_deg = self.fabric.yarn_angle_deg;
        p.bending = self.bending();
        p.tooling = self.tools.tooling();
        p.blank_mm = self.blank.size.0;
        p.friction = self.process.friction;
        p.holder_pressure_mpa = self.process.holder_pressure;
        p.holder_force_n = self.process.holder_force.map(|kn| 1000.0 * kn);
        p.stroke_mm = self.process.stroke;
        p.element_size_mm = self.mesh.element_size;
        p.symmetry = match self.mesh.symmetry {
            SymmetryChoice::Auto => Symmetry::Auto,
            SymmetryChoice::Full => Symmetry::Full,
            SymmetryChoice::Quarter => Symmetry::Quarter,
        };
        p.solver.stabilisation = self.numerics.stabilisation;
        p.penalty_factor = self.numerics.penalty_factor;
        p
    }

    /// The fabric's bending, with its yarns' compressive stiffness as fractions of `c` (the
    /// default fraction when the scene gives none).
    pub fn bending(&self) -> Option<crate::core::drawing::Bending> {
        let f = &self.fabric;
        let c = f.c.0;
        f.bending_rigidity
            .map(|rigidity| crate::core::drawing::Bending {
                rigidity,
                compression: f
                    .compressive_stiffness
                    .map_or([crate::core::drawing::DEFAULT_COMPRESSION; 2], |cc| {
                        [cc[0] / c[0], cc[1] / c[1]]
                    }),
                trigger: crate::core::wrinkles::trigger::Trigger {
                    pressure_mpa: self.numerics.trigger_pa * 1e-6,
                    seed: self.numerics.trigger_seed,
                },
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

/// Parses `text` as `x.toml` with the `--set` texts `sets`: the tests' way in.
#[cfg(test)]
fn parse(text: &str, sets: &[&str]) -> Result<Scene, SceneError> {
    let sets: Vec<Override> = sets.iter().map(|s| s.parse().unwrap()).collect();
    Scene::from_toml_str(text, "x.toml", &sets)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::drawing::Tooling;

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
            ("process.holder_pressure=0", |p| {
                p.holder_pressure_mpa == 0.0
            }),
            ("process.stroke=12.5", |p| p.stroke_mm == 12.5),
            ("mesh.element_size=5", |p| p.element_size_mm == 5.0),
            ("mesh.symmetry=\"full\"", |p| p.symmetry == Symmetry::Full),
            ("blank.size=[150,120]", |p| p.blank_mm == [150.0, 120.0]),
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
                got.blank_mm,
                got.friction,
                got.holder_pressure_mpa
            ),
            (
                want.fabric,
                want.tooling,
                want.blank_mm,
                want.friction,
                want.holder_pressure_mpa
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
