//! The summary of one drawing run (`wovenform run`): the figures a user checks, as one JSON
//! object or as text with units, and the files written beside it.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::maps::{self, MapContext};
use super::vtu;
use crate::accuracy::Accuracy;
use crate::core::drawing::{DrawingFailure, DrawingResult, Tooling};
use crate::scene::{Scene, ToolKind};

/// What `run --json` prints and `summary.json` holds. Every figure carries its unit in its name.
#[derive(Clone, Debug, Serialize)]
pub struct RunSummary {
    /// The scene's name (its file stem).
    pub scene: String,
    pub converged: bool,
    /// Why the run stopped short, if it did.
    pub failure: Option<String>,
    /// Converged, shear within the locking angle and yarn tension within the break tension.
    pub feasible: bool,
    /// The verdict in a few words (also in the maps' titles).
    pub verdict: String,
    /// Largest |shear angle|, degrees, and where (final position of the element's centre, mm,
    /// in the solved part).
    pub max_shear_deg: f64,
    pub max_shear_at: [f64; 3],
    pub locking_angle_deg: f64,
    /// Share of the blank's initial area sheared past the locking angle, %.
    pub area_over_limit_pct: f64,
    /// Largest yarn tension, N, and the breaking tension, N.
    pub max_tension_n: f64,
    pub break_tension_n: f64,
    /// Punch force on the whole blank at the end, N.
    pub punch_force_n: f64,
    /// Stroke asked for and reached, mm.
    pub stroke_mm: f64,
    pub stroke_reached_mm: f64,
    /// Largest penetration of a node into a tool, mm.
    pub penetration_mm: f64,
    /// Largest draw-in of the blank's edge, mm.
    pub draw_in_mm: f64,
    pub wall_s: f64,
    /// The accuracy level of the scene's mesh (`coarse`, `standard`, `fine`), when it is one,
    /// and that level's measured errors (see `crate::accuracy`).
    pub accuracy: Option<String>,
    pub max_shear_err_deg: Option<f64>,
    pub punch_force_err_pct: Option<f64>,
    pub dofs: usize,
    /// Elements of the solved part, and which part was solved ("quarter" or "full").
    pub elements: usize,
    pub solved_part: String,
    pub steps: u32,
    pub cutbacks: u32,
    pub newton_iterations: u32,
    /// Work done by forces out of balance over the punch's work (dimensionless): what of the
    /// punch's work is not the paper's model. The stabilisation damps the Newton corrections
    /// only, so a converged state carries none of it.
    pub stabilisation_work_share: f64,
    /// Why a converged result cannot be trusted (empty: it can): too deep a penetration, too
    /// much work out of balance.
    pub unsound: Vec<String>,
    /// A singular tangent was met during the run (part of the blank was a mechanism).
    pub mechanism: bool,
    /// Terms the scene did not need and that were not built.
    pub left_out: Vec<String>,
    /// The files written, by kind (`summary`, `shear_map`, `tension_map`, `vtu`).
    pub files: BTreeMap<String, String>,
    /// The scene as run (every key, defaults filled in).
    pub inputs: Scene,
}

impl RunSummary {
    /// The summary of `result`, which took `wall_s` seconds.
    pub fn new(name: &str, scene: &Scene, result: &DrawingResult, wall_s: f64) -> RunSummary {
        let locking = scene.fabric.locking_angle_deg;
        let breaking = scene.fabric.break_tension_n;
        let (e, max_shear_deg) = result.max_shear();
        let max_tension_n = result.max_tension_n();
        let shear_over = max_shear_deg > locking;
        let tension_over = max_tension_n > breaking;
        let unsound: Vec<String> = if result.converged {
            result.unsound().iter().map(|u| u.to_string()).collect()
        } else {
            Vec::new()
        };
        let feasible = result.converged && unsound.is_empty() && !shear_over && !tension_over;
        let no_answer = matches!(result.failure, Some(DrawingFailure::NoUniqueShape(_)));
        let verdict = if no_answer {
            "NO ANSWER: the model has no unique shape for this scene".to_string()
        } else if !result.converged {
            format!(
                "RUN FAILED at stroke {:.1} of {:.1} mm",
                result.stroke_reached_mm, scene.process.stroke
            )
        } else if !unsound.is_empty() {
            format!("NOT SOUND: {}", unsound.join("; "))
        } else {
            match (shear_over, tension_over) {
                (false, false) => "FEASIBLE".to_string(),
                (true, false) => "INFEASIBLE: shear over the locking angle".to_string(),
                (false, true) => "INFEASIBLE: yarn tension over the break".to_string(),
                (true, true) => {
                    "INFEASIBLE: shear over the locking angle, yarn tension over the break"
                        .to_string()
                }
            }
        };
        let level = Accuracy::of_element_size(scene.mesh.element_size);
        let max_shear_at = if result.shear_deg.is_empty() {
            [0.0; 3]
        } else {
            result.element_centre(e)
        };
        RunSummary {
            scene: name.to_string(),
            converged: result.converged,
            failure: result.failure.as_ref().map(|f| f.to_string()),
            feasible,
            verdict,
            max_shear_deg,
            max_shear_at,
            locking_angle_deg: locking,
            area_over_limit_pct: result.area_over_limit_pct(locking),
            max_tension_n,
            break_tension_n: breaking,
            punch_force_n: result.punch_force_n,
            stroke_mm: scene.process.stroke,
            stroke_reached_mm: result.stroke_reached_mm,
            penetration_mm: result.penetration_mm,
            draw_in_mm: result.draw_in_mm,
            wall_s,
            accuracy: level.map(|a| a.name().to_string()),
            max_shear_err_deg: level.map(|a| a.error().max_shear_deg),
            punch_force_err_pct: level.map(|a| a.error().punch_force_pct),
            dofs: result.dofs,
            elements: result.mesh.quads.len(),
            solved_part: if result.quarter { "quarter" } else { "full" }.to_string(),
            steps: result.stats.steps,
            cutbacks: result.stats.cutbacks,
            newton_iterations: result.stats.newton_iterations,
            stabilisation_work_share: result.unbalanced_work_share,
            unsound,
            mechanism: result.stats.mechanism,
            left_out: result.left_out.iter().map(|l| l.to_string()).collect(),
            files: BTreeMap::new(),
            inputs: scene.clone(),
        }
    }

    /// One JSON object on one line.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("the summary is plain data")
    }

    /// The summary as text with units, for a person.
    pub fn to_text(&self) -> String {
        let s = &self.inputs;
        let t = &s.tools;
        let mut out = String::new();
        let tools = match t.kind {
            ToolKind::Box => format!(
                "box punch {} × {} mm, r = {} mm, rp = {} mm; die rm = {} mm, clearance {} mm",
                t.side.0[0], t.side.0[1], t.r, t.rp, t.rm, t.clearance
            ),
            ToolKind::Ellipsoid => format!(
                "ellipsoid punch, semi-axes {} × {} × {} mm; die rm = {} mm, clearance {} mm",
                t.axes[0], t.axes[1], t.axes[2], t.rm, t.clearance
            ),
            ToolKind::Hemisphere => format!(
                "hemisphere punch, radius {} mm; die rm = {} mm, clearance {} mm",
                t.radius, t.rm, t.clearance
            ),
        };
        let law = if s.fabric.undulation {
            "woven law (undulation)"
        } else {
            "linear yarn law"
        };
        let _ = writeln!(out, "scene        {}", self.scene);
        let _ = writeln!(out, "tools        {tools}");
        let _ = writeln!(
            out,
            "process      friction {}, holder pressure {} MPa, stroke {} mm",
            s.process.friction, s.process.holder_pressure, s.process.stroke
        );
        let _ = writeln!(
            out,
            "blank        {} × {} mm, {law}, element {} mm, {} solved ({} elements, {} dofs)",
            s.blank.size.0[0],
            s.blank.size.0[1],
            s.mesh.element_size,
            self.solved_part,
            self.elements,
            self.dofs
        );
        let _ = writeln!(out);
        let _ = writeln!(out, "verdict      {}", self.verdict);
        if let Some(f) = &self.failure {
            let _ = writeln!(out, "failure      {f}");
        }
        if !self.converged && self.steps == 0 {
            // Nothing was solved: no figures to show.
            self.write_footer(&mut out);
            return out;
        }
        let [x, y, z] = self.max_shear_at;
        let _ = writeln!(
            out,
            "max shear    {:.1}° at ({x:.1}, {y:.1}, {z:.1}) mm; locking angle {}°; {:.2} % of the blank over it",
            self.max_shear_deg, self.locking_angle_deg, self.area_over_limit_pct
        );
        let _ = writeln!(
            out,
            "max tension  {:.1} N per yarn; break tension {} N ({:.0} %)",
            self.max_tension_n,
            self.break_tension_n,
            100.0 * self.max_tension_n / self.break_tension_n
        );
        let _ = writeln!(
            out,
            "punch force  {:.1} N at stroke {:.2} of {} mm",
            self.punch_force_n, self.stroke_reached_mm, self.stroke_mm
        );
        let _ = writeln!(
            out,
            "draw-in      {:.2} mm at the blank's edge; largest penetration {:.4} mm",
            self.draw_in_mm, self.penetration_mm
        );
        let _ = writeln!(
            out,
            "solver       {} steps, {} cut-backs, {} Newton iterations, {:.2} s; forces out of balance did {:.1e} % of the punch's work{}",
            self.steps,
            self.cutbacks,
            self.newton_iterations,
            self.wall_s,
            100.0 * self.stabilisation_work_share,
            if self.mechanism {
                "; a singular tangent was met (part of the blank was a mechanism)"
            } else {
                ""
            }
        );
        let _ = match (
            &self.accuracy,
            self.max_shear_err_deg,
            self.punch_force_err_pct,
        ) {
            (Some(level), Some(shear), Some(force)) => writeln!(
                out,
                "accuracy     {level} ({} mm elements): max shear ±{shear}°, punch force ±{force} % (measured on the paper's box)",
                self.inputs.mesh.element_size
            ),
            _ => writeln!(
                out,
                "accuracy     no level ({} mm elements): --accuracy coarse|standard|fine gives an error estimate",
                self.inputs.mesh.element_size
            ),
        };
        self.write_footer(&mut out);
        out
    }

    /// The terms left out and the files written.
    fn write_footer(&self, out: &mut String) {
        if !self.left_out.is_empty() {
            let _ = writeln!(out, "left out     {}", self.left_out.join("; "));
        }
        if !self.files.is_empty() {
            let _ = writeln!(out);
            for path in self.files.values() {
                let _ = writeln!(out, "{path}");
            }
        }
    }
}

/// Writes `shear.png`, `tension.png`, `result.vtu` and `summary.json` into `dir` (created if
/// needed), records them in `summary.files`, and returns their paths. Errors name the file.
pub fn write_run(
    dir: &Path,
    summary: &mut RunSummary,
    result: &DrawingResult,
    tooling: &Tooling,
) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir)
        .map_err(|e| format!("{}: cannot create the folder: {e}", dir.display()))?;
    let ctx = MapContext {
        scene: &summary.scene,
        verdict: &summary.verdict,
        tooling: *tooling,
        stroke_mm: summary.stroke_mm,
    };
    let shear = dir.join("shear.png");
    maps::shear_map(result, &ctx, summary.locking_angle_deg).write_png(&shear)?;
    let tension = dir.join("tension.png");
    maps::tension_map(result, &ctx, summary.break_tension_n).write_png(&tension)?;
    let vtu_path = dir.join("result.vtu");
    vtu::write_vtu(result, &vtu_path)?;
    let json = dir.join("summary.json");
    let written = vec![json.clone(), shear, tension, vtu_path];
    for (kind, path) in ["summary", "shear_map", "tension_map", "vtu"]
        .iter()
        .zip(&written)
    {
        summary
            .files
            .insert(kind.to_string(), path.display().to_string());
    }
    let text = serde_json::to_string_pretty(&*summary).expect("the summary is plain data");
    std::fs::write(&json, text + "\n")
        .map_err(|e| format!("{}: cannot write the summary: {e}", json.display()))?;
    Ok(written)
}
