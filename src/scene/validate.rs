//! The physical bounds of a typed scene, checked in the order of the file's tables.
//!
//! Every check has one form: `ok_if(condition, || broken(key, value, what))`, which reads
//! `key = value: expected what`, or, for a bound that involves other keys too,
//! `ok_if(condition, || broken_with(&[key, others…], message))`. The keys involved find who set
//! them (the file or a `--set`); the first one is the key the error names.

use std::fmt;

use super::types::{Num, PerYarn, PlanPair, SymmetryChoice, ToolKind};
use super::{Scene, SceneError};

/// The shortest punch stroke, mm.
pub const MIN_STROKE_MM: f64 = 0.01;
/// The stiffest bending rigidity a scene takes, N·mm per unit width: a steel sheet 1.7 mm
/// thick (`E t³ / 12(1 − ν²)`); woven fabrics measure 0.01 to 100.
pub const MAX_BENDING_NMM: f64 = 1e5;

/// A broken bound: the key blamed, the keys involved (to find who set them) and the message
/// (which starts with the key).
struct Broken {
    key: String,
    involved: Vec<&'static str>,
    detail: String,
}

/// `key = value: expected what`, blaming `key` alone.
fn broken(key: &'static str, value: impl fmt::Display, what: impl fmt::Display) -> Broken {
    broken_with(&[key], format!("{key} = {value}: expected {what}"))
}

/// A bound between several keys: `involved[0]` is the key named, `detail` the whole message.
fn broken_with(involved: &[&'static str], detail: String) -> Broken {
    Broken {
        key: involved[0].to_string(),
        involved: involved.to_vec(),
        detail,
    }
}

fn ok_if(ok: bool, f: impl FnOnce() -> Broken) -> Result<(), Broken> {
    if ok { Ok(()) } else { Err(f()) }
}

/// Finite and > 0.
fn pos(v: f64) -> bool {
    v.is_finite() && v > 0.0
}

/// Finite and ≥ 0.
fn non_neg(v: f64) -> bool {
    v.is_finite() && v >= 0.0
}

/// Finite and in `[lo, hi]`.
fn within(v: f64, lo: f64, hi: f64) -> bool {
    v.is_finite() && (lo..=hi).contains(&v)
}

/// Finite and strictly between `lo` and `hi`.
fn strictly_between(v: f64, lo: f64, hi: f64) -> bool {
    v.is_finite() && v > lo && v < hi
}

fn fmt3(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", Num(v[0]), Num(v[1]), Num(v[2]))
}

impl Scene {
    /// Checks the physical bounds; `origin` names the scene in the error.
    pub fn validate(&self, origin: &str) -> Result<(), SceneError> {
        self.validate_with(&|_| origin.to_string())
    }

    /// `origin_of(keys)` names who set the keys involved in a broken bound.
    pub(super) fn validate_with(
        &self,
        origin_of: &dyn Fn(&[&str]) -> String,
    ) -> Result<(), SceneError> {
        self.check_bounds().map_err(|b| SceneError {
            origin: origin_of(&b.involved),
            detail: b.detail,
            key: Some(b.key),
        })
    }

    /// The first broken bound, table by table.
    fn check_bounds(&self) -> Result<(), Broken> {
        self.check_fabric()?;
        self.check_tools()?;
        self.check_process()?;
        self.check_blank()?;
        self.check_mesh()?;
        self.check_numerics()
    }

    fn check_fabric(&self) -> Result<(), Broken> {
        let f = &self.fabric;
        let [l0, e0] = [f.l0.0, f.e0.0];
        ok_if(l0.iter().all(|&v| pos(v)), || {
            broken("fabric.l0", f.l0, "a cell length L0 > 0 mm for each yarn")
        })?;
        let half = PerYarn([0.5 * l0[0], 0.5 * l0[1]]);
        ok_if((0..2).all(|i| non_neg(e0[i]) && e0[i] < half.0[i]), || {
            let what = format!("a crown height 0 ≤ e0 < L0/2 mm for each yarn (L0/2 = {half})");
            broken("fabric.e0", f.e0, what)
        })?;
        ok_if(f.c.0.iter().all(|&v| pos(v)), || {
            broken("fabric.c", f.c, "a yarn stiffness C > 0 N for each yarn")
        })?;
        ok_if(non_neg(f.a), || {
            broken("fabric.a", Num(f.a), "a closure saturation A ≥ 0 mm")
        })?;
        let h = e0[0] + e0[1];
        ok_if(f.a < h, || {
            let what = format!(
                "a closure saturation A < e01 + e02 = {h} mm (the yarns cannot flatten past each other)"
            );
            broken("fabric.a", Num(f.a), what)
        })?;
        ok_if(pos(f.b), || {
            broken(
                "fabric.b",
                Num(f.b),
                "a transverse compliance rate B > 0 1/N",
            )
        })?;
        ok_if(strictly_between(f.locking_angle_deg, 0.0, 90.0), || {
            let what = "a shear locking angle strictly between 0 and 90 degrees";
            broken("fabric.locking_angle_deg", Num(f.locking_angle_deg), what)
        })?;
        ok_if(pos(f.break_tension_n), || {
            let what = "a yarn breaking tension > 0 N";
            broken("fabric.break_tension_n", Num(f.break_tension_n), what)
        })?;
        ok_if(pos(f.wrinkle_limit_mm), || {
            let what = "a wrinkle limit > 0 mm";
            broken("fabric.wrinkle_limit_mm", Num(f.wrinkle_limit_mm), what)
        })?;
        if let Some(k) = f.shear_moment {
            ok_if(crate::core::fabric::shear::ShearLaw::new(k).rises(), || {
                broken(
                    "fabric.shear_moment",
                    format!("[{}, {}, {}]", Num(k[0]), Num(k[1]), Num(k[2])),
                    "[k1, k3, k5] in N·mm/mm², finite, with k1 ≥ 0 and the moment k1 γ + k3 γ³ + \
                     k5 γ⁵ rising from γ = 0 to 90° (a softening law has no unique answer)",
                )
            })?;
        }
        ok_if(!f.shear_locking || f.shear_moment.is_some(), || {
            broken(
                "fabric.shear_locking",
                "true",
                "a shear law to stiffen: fabric.shear_moment = [k1, k3, k5] with it",
            )
        })?;
        self.check_bending()?;
        // An initial angle further from 90° than the locking angle is a fabric locked before
        // it is formed.
        let (lo, hi) = (90.0 - f.locking_angle_deg, 90.0 + f.locking_angle_deg);
        ok_if(strictly_between(f.yarn_angle_deg, lo, hi), || {
            broken_with(
                &["fabric.yarn_angle_deg", "fabric.locking_angle_deg"],
                format!(
                    "fabric.yarn_angle_deg = {}: expected an initial angle between the yarns \
                     strictly between 90° ± the locking angle, {} and {} degrees (further from \
                     90° the fabric is sheared past locking before it is formed)",
                    Num(f.yarn_angle_deg),
                    Num(lo),
                    Num(hi)
                ),
            )
        })
    }

    /// Bending and what goes with it: rigidities ≥ 0 with one > 0, compressive stiffnesses
    /// ≥ 0 and below `c`, an areal mass > 0. Either yarn law and any yarn angle take bending
    /// (off 90° the hinges run along the mesh's lines with the yarns' rigidities projected on
    /// them: `core::membrane::hinges::rigidity_along_lines`).
    fn check_bending(&self) -> Result<(), Broken> {
        let f = &self.fabric;
        if let Some(b) = f.bending_rigidity {
            ok_if(
                b.iter().all(|&v| non_neg(v) && v <= MAX_BENDING_NMM) && b.iter().any(|&v| pos(v)),
                || {
                    let what = "[B1, B2] in N·mm per unit width, each ≥ 0 and one > 0, at most \
                                1e5 (a steel sheet 1.7 mm thick; fabrics are 0.01 to 100)";
                    broken("fabric.bending_rigidity", PerYarn(b), what)
                },
            )?;
        }
        if f.bending_rigidity.is_some() {
            ok_if(self.mesh.symmetry != SymmetryChoice::Quarter, || {
                broken_with(
                    &["mesh.symmetry", "fabric.bending_rigidity"],
                    "mesh.symmetry = \"quarter\" with fabric.bending_rigidity: expected \"auto\" \
                     or \"full\" (wrinkles are not symmetric, and a quarter's yarn lines end at \
                     the symmetry planes without the slope condition there)"
                        .to_string(),
                )
            })?;
        }
        if let Some(cc) = f.compressive_stiffness {
            ok_if((0..2).all(|i| non_neg(cc[i]) && cc[i] < f.c.0[i]), || {
                let what = format!("[Cc1, Cc2] in N per yarn, each ≥ 0 and below c = {}", f.c);
                broken("fabric.compressive_stiffness", PerYarn(cc), what)
            })?;
            ok_if(f.bending_rigidity.is_some(), || {
                let what = "fabric.bending_rigidity with it (a compressive stiffness alone \
                            shortens the membrane without wrinkling it)";
                broken("fabric.compressive_stiffness", PerYarn(cc), what)
            })?;
        }
        if let Some(m) = f.areal_mass {
            ok_if(pos(m) && m < 1e5, || {
                broken(
                    "fabric.areal_mass",
                    Num(m),
                    "an areal mass > 0 and < 100,000 g/m²",
                )
            })?;
        }
        Ok(())
    }

    fn check_tools(&self) -> Result<(), Broken> {
        let t = &self.tools;
        ok_if(pos(t.rm), || {
            broken("tools.rm", Num(t.rm), "a die entry radius rm > 0 mm")
        })?;
        ok_if(non_neg(t.clearance), || {
            broken(
                "tools.clearance",
                t.clearance,
                "a punch–die clearance ≥ 0 mm",
            )
        })?;
        match t.kind {
            ToolKind::Box => self.check_box(),
            ToolKind::Ellipsoid => ok_if(t.axes.iter().all(|&v| pos(v)), || {
                let what = "punch semi-axes [ax, ay, az] > 0 mm";
                broken("tools.axes", fmt3(t.axes), what)
            }),
            ToolKind::Hemisphere => ok_if(pos(t.radius), || {
                broken("tools.radius", Num(t.radius), "a punch radius > 0 mm")
            }),
            ToolKind::Mesh => self.check_mesh_tools(),
        }
    }

    /// Mesh tools: both files named, a lattice fine enough for a tool's radii and coarse
    /// enough to sample (the files themselves are read and checked by `mesh_tools.rs`).
    fn check_mesh_tools(&self) -> Result<(), Broken> {
        let t = &self.tools;
        for (key, path) in [("tools.punch", &t.punch), ("tools.die", &t.die)] {
            ok_if(!path.trim().is_empty(), || {
                broken(
                    key,
                    "\"\"",
                    "the path of an STL file (relative to the scene file)",
                )
            })?;
        }
        ok_if((0.05..=5.0).contains(&t.lattice), || {
            broken(
                "tools.lattice",
                Num(t.lattice),
                "a distance lattice spacing of 0.05 to 5 mm (a tenth of the smallest tool radius or finer)",
            )
        })
    }

    /// The box punch: its sides, and its radii within them.
    fn check_box(&self) -> Result<(), Broken> {
        let t = &self.tools;
        ok_if(t.side.0.iter().all(|&v| pos(v)), || {
            broken("tools.side", t.side, "punch sides > 0 mm")
        })?;
        let half = 0.5 * t.side.0[0].min(t.side.0[1]);
        ok_if(pos(t.r), || {
            broken("tools.r", Num(t.r), "a punch corner radius r > 0 mm")
        })?;
        ok_if(t.r < half, || {
            broken_with(
                &["tools.r", "tools.side"],
                format!(
                    "tools.r = {}: r larger than the punch allows: expected a corner radius r < side/2 = {} mm",
                    Num(t.r),
                    Num(half)
                ),
            )
        })?;
        ok_if(pos(t.rp), || {
            broken("tools.rp", Num(t.rp), "a punch nose radius rp > 0 mm")
        })?;
        ok_if(t.rp < half, || {
            broken_with(
                &["tools.rp", "tools.side"],
                format!(
                    "tools.rp = {}: rp larger than the punch allows: expected a nose radius rp < side/2 = {} mm",
                    Num(t.rp),
                    Num(half)
                ),
            )
        })
    }

    fn check_process(&self) -> Result<(), Broken> {
        let p = &self.process;
        ok_if(within(p.friction, 0.0, 1.0), || {
            let what = "a friction coefficient μ in [0, 1]";
            broken("process.friction", Num(p.friction), what)
        })?;
        ok_if(within(p.holder_pressure, 0.0, 50.0), || {
            let what = "a blank-holder pressure in [0, 50] MPa";
            broken("process.holder_pressure", Num(p.holder_pressure), what)
        })?;
        if let Some(f) = p.holder_force {
            ok_if(f > 0.0 && f <= 10_000.0, || {
                let what = "a holder force in (0, 10000] kN (a rigid plate pressed with it)";
                broken("process.holder_force", Num(f), what)
            })?;
        }
        ok_if(p.stroke >= MIN_STROKE_MM && p.stroke.is_finite(), || {
            let what = "a punch stroke of at least 0.01 mm (10 µm: less draws nothing a press \
                        could set, and its work is within the solver's tolerance)";
            broken("process.stroke", Num(p.stroke), what)
        })?;
        // Deeper than the blank is long, no part could be drawn from it.
        let longest = self.blank.size.0[0].max(self.blank.size.0[1]);
        ok_if(p.stroke <= longest, || {
            broken_with(
                &["process.stroke", "blank.size"],
                format!(
                    "process.stroke = {}: expected a stroke at most the blank's longest side, \
                     {} mm (a deeper part cannot be drawn from this blank)",
                    Num(p.stroke),
                    Num(longest)
                ),
            )
        })?;
        let t = &self.tools;
        let Some(depth) = t.punch_depth() else {
            return Ok(());
        };
        let axis = if t.kind == ToolKind::Ellipsoid {
            "the semi-axis az"
        } else {
            "its radius"
        };
        ok_if(p.stroke <= depth, || {
            broken_with(
                &["process.stroke", "tools.axes", "tools.radius"],
                format!(
                    "process.stroke = {}: expected a stroke ≤ the punch's depth, {axis} = {} mm (the punch is the lower half of the {})",
                    Num(p.stroke),
                    Num(depth),
                    t.kind.name()
                ),
            )
        })
    }

    fn check_blank(&self) -> Result<(), Broken> {
        let (t, size) = (&self.tools, self.blank.size);
        let b = size.0;
        ok_if(b.iter().all(|&v| pos(v)), || {
            broken("blank.size", size, "blank sides > 0 mm")
        })?;
        if t.kind == ToolKind::Mesh {
            // Where the blank rests is checked against the die's face when it is read.
            return Ok(());
        }
        let half = t.tooling().opening_half();
        let need = [2.0 * (half[0] + t.rm), 2.0 * (half[1] + t.rm)];
        ok_if(b[0] > need[0] && b[1] > need[1], || {
            broken_with(
                &[
                    "blank.size",
                    "tools.side",
                    "tools.clearance",
                    "tools.rm",
                    "tools.axes",
                    "tools.radius",
                ],
                format!(
                    "blank.size = {size}: blank barely larger than the die opening: expected sides > the opening plus 2·rm = {} mm, so that the blank's edge rests on the die face",
                    PlanPair(need)
                ),
            )
        })
    }

    fn check_mesh(&self) -> Result<(), Broken> {
        let m = &self.mesh;
        let b = self.blank.size.0;
        let quarter_of_blank = 0.25 * b[0].min(b[1]);
        ok_if(
            pos(m.element_size) && m.element_size <= quarter_of_blank,
            || {
                broken_with(
                    &["mesh.element_size", "blank.size"],
                    format!(
                        "mesh.element_size = {}: expected an element size > 0 and ≤ blank/4 = {} mm",
                        Num(m.element_size),
                        Num(quarter_of_blank)
                    ),
                )
            },
        )?;
        self.check_size()?;
        let yarn_angle = self.fabric.yarn_angle_deg;
        let yarns_on_axes = (yarn_angle - 90.0).abs() < 1e-9;
        ok_if(
            m.symmetry != SymmetryChoice::Quarter || yarns_on_axes,
            || {
                broken_with(
                    &["mesh.symmetry", "fabric.yarn_angle_deg"],
                    format!(
                        "mesh.symmetry = \"quarter\": expected \"auto\" or \"full\" when the yarns are not along x and y (fabric.yarn_angle_deg = {})",
                        Num(yarn_angle)
                    ),
                )
            },
        )
    }

    /// The mesh fits in the machine's memory budget, checked before anything is allocated.
    fn check_size(&self) -> Result<(), Broken> {
        if self.tools.kind == ToolKind::Mesh && self.tools.loaded.is_none() {
            // Checked again once the tools are read (the blank is solved whole).
            return Ok(());
        }
        let budget = crate::machine::memory_budget_bytes();
        crate::machine::check_fits(&self.to_problem(), budget)
            .map_err(|e| broken_with(&["mesh.element_size", "blank.size"], e.to_string()))
    }

    fn check_numerics(&self) -> Result<(), Broken> {
        let n = &self.numerics;
        ok_if(non_neg(n.stabilisation), || {
            let what = "a damping κ ≥ 0 of the Newton corrections (0 turns it off)";
            broken("numerics.stabilisation", Num(n.stabilisation), what)
        })?;
        ok_if(pos(n.penalty_factor), || {
            let what = "a contact penalty factor > 0";
            broken("numerics.penalty_factor", Num(n.penalty_factor), what)
        })?;
        // A trigger above a kilopascal is a load, not an imperfection.
        ok_if(n.trigger_pa >= 0.0 && n.trigger_pa <= 1000.0, || {
            let what = "a trigger pressure from 0 to 1000 Pa (a seeded imperfection, far \
                        below what the tools press with)";
            broken("numerics.trigger_pa", Num(n.trigger_pa), what)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::parse;

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
            ("numerics.trigger_pa=-1", "numerics.trigger_pa"),
            ("numerics.trigger_pa=5000", "numerics.trigger_pa"),
            ("fabric.wrinkle_limit_mm=0", "fabric.wrinkle_limit_mm"),
            ("process.holder_force=0", "process.holder_force"),
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
}
