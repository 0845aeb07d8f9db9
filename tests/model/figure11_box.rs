//! Benchmark: the paper's square box (Boisse et al. 1997, Figure 11), the presets
//! `paper-box-tight.toml` and `paper-box-open.toml` drawn in full at their standard mesh.
//!
//! The outside answers are the paper's: friction 0.2, holder pressure 1 MPa, a locking angle
//! "close to 60°"; the tight tools (r/rp/rm = 5/6/5 mm) lead to shear angles "greater than
//! 80°", impossible for the fabric, the open tools (10/15/10 mm) to "smaller than 60°", a
//! feasible drawing; the shear concentrates "near the corners of the box". And the
//! verification note's: a rounded box corner carries the total Gaussian curvature π/2 whatever
//! its radii, so the radii only spread or concentrate the shear, which stays below 90°. (This
//! model leaves the tight box at 78°, not over 80°: `wovenform::guide::findings`, "The presets".)
//!
//! ```text
//!   plan of a quarter (the solved part)          y
//!                                                ↑   punch side 60, corner radius r
//!   the shear peaks near (30, 30), on the        │ ╭─╮ die opening 63, entry radius rm
//!   diagonal, between the corner arc's centre    │ │ │
//!   (30 − r) and the die's edge (31.5 + rm)      └─┴─┴──→ x
//! ```

use crate::analytic;

use std::path::{Path, PathBuf};

use wovenform::core::drawing::{self, DrawingResult};
use wovenform::scene::Scene;

fn preset_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("presets")
        .join(name)
}

fn preset(name: &str) -> Scene {
    Scene::load(Some(&preset_path(name)), &[]).expect("the preset loads")
}

/// The paper's two designs: the preset and its tools r, rp, rm (mm).
const DESIGNS: [(&str, [f64; 3]); 2] = [
    ("paper-box-tight.toml", [5.0, 6.0, 5.0]),
    ("paper-box-open.toml", [10.0, 15.0, 10.0]),
];

#[test]
fn the_presets_are_the_papers_process_and_tools() {
    for (name, radii) in DESIGNS {
        let s = preset(name);
        assert_eq!([s.tools.r, s.tools.rp, s.tools.rm], radii, "{name}");
        assert_eq!(s.process.friction, 0.2, "{name}");
        assert_eq!(s.process.holder_pressure, 1.0, "{name}");
        assert_eq!(s.fabric.locking_angle_deg, 60.0, "{name}");
        // The paper's first example: "only dependent on the yarn tensile behaviour".
        assert!(!s.fabric.undulation, "{name}");
    }
}

/// A drawn preset: the scene as loaded and the result.
struct Drawn {
    scene: Scene,
    result: DrawingResult,
}

fn draw(name: &str) -> Drawn {
    let scene = preset(name);
    let result = drawing::solve(&scene.to_problem(), &mut |_| {});
    assert!(result.converged, "{name}: {:?}", result.failure);
    assert!(
        result.unsound().is_empty(),
        "{name}: {:?}",
        result.unsound()
    );
    assert!(
        (result.stroke_reached_mm - scene.process.stroke).abs() < 1e-9,
        "{name}: stroke {} mm",
        result.stroke_reached_mm
    );
    Drawn { scene, result }
}

impl Drawn {
    fn max_shear_deg(&self) -> f64 {
        self.result.max_shear().1
    }

    fn feasible(&self) -> bool {
        let fabric = &self.scene.fabric;
        analytic::feasible(
            self.max_shear_deg(),
            fabric.locking_angle_deg,
            self.result.max_tension_n(),
            fabric.break_tension_n,
        )
    }

    /// Checks that the largest shear sits at a corner of the box: in plan on the diagonal
    /// (within an element) and, on both axes, between the centre of the punch's corner arc and
    /// the die's edge.
    fn assert_peak_at_a_corner(&self, name: &str) {
        let t = &self.scene.tools;
        let half_side = t.side.0.map(|s| 0.5 * s);
        let at = self.result.element_centre(self.result.max_shear().0);
        let (x, y) = (at[0].abs(), at[1].abs());
        let h = self.scene.mesh.element_size;
        println!(
            "{name}: max shear at ({:.2}, {:.2}, {:.2}) mm",
            at[0], at[1], at[2]
        );
        assert!((x - y).abs() < h, "{name}: off the diagonal at {at:?}");
        for (c, half) in [x, y].into_iter().zip(half_side) {
            assert!(
                c > half - t.r - h && c < half + t.clearance + t.rm,
                "{name}: not at a corner: {at:?}"
            );
        }
    }
}

#[test]
fn the_open_box_is_feasible_and_the_tight_box_is_not() {
    let [tight, open] = DESIGNS.map(|(name, _)| draw(name));
    let (s_tight, s_open) = (tight.max_shear_deg(), open.max_shear_deg());
    println!(
        "Figure 11: tight box max shear {s_tight:.2}° (paper: over 80°), open box {s_open:.2}° \
         (paper: under 60°); max tension {:.1} N and {:.1} N",
        tight.result.max_tension_n(),
        open.result.max_tension_n()
    );
    // The paper's verdicts.
    assert!(s_open < 60.0, "open box: {s_open}°");
    assert!(open.feasible(), "open box infeasible");
    assert!(s_tight > 60.0, "tight box: {s_tight}°");
    assert!(!tight.feasible(), "tight box feasible");
    // The tight radii concentrate the corner's shear; neither reaches 90°.
    assert!(s_open < s_tight && s_tight < 90.0);
    tight.assert_peak_at_a_corner("tight box");
    open.assert_peak_at_a_corner("open box");
}

#[test]
fn the_preset_sweep_holds_both_paper_designs() {
    let plan =
        wovenform::study::sweep::Plan::load(&preset_path("paper-box-sweep.toml"), &[]).unwrap();
    let designs = plan.designs();
    let columns: Vec<&str> = plan.axes.iter().map(|a| a.column.as_str()).collect();
    assert_eq!(columns, ["r", "rp", "rm", "friction", "holder_pressure"]);
    for want in [[5.0, 6.0, 5.0, 0.2, 1.0], [10.0, 15.0, 10.0, 0.2, 1.0]] {
        let found = designs.iter().any(|d| {
            d.values
                .iter()
                .zip(want)
                .all(|(v, w)| v.as_float() == Some(w))
        });
        assert!(found, "{want:?} is not in the grid");
    }
    assert!(designs.iter().all(|d| plan.design_scene(d).is_ok()));
}
