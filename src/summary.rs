//! The summary of one drawing run: the figures a user checks, with units in their names, and
//! the verdict on them (from [`crate::verdict`]). `wovenform run --json` prints it; the sweep
//! makes a row of it; `report::summary` writes it as text, `publish` into files.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::accuracy::Accuracy;
use crate::core::drawing::{DrawingFailure, DrawingResult};
use crate::scene::Scene;
use crate::verdict::{Facts, Figures, Judged, Limits, Verdict};

/// What `run --json` prints and `summary.json` holds. Every figure carries its unit in its name.
#[derive(Clone, Debug, Serialize)]
pub struct RunSummary {
    /// The scene's name (its file stem).
    pub scene: String,
    pub converged: bool,
    /// Why the run stopped short, if it did.
    pub failure: Option<String>,
    /// The verdict is FEASIBLE: converged, sound, and the shear and the tension within their
    /// limits by more than their errors.
    pub feasible: bool,
    /// The verdict in a few words (also in the maps' titles).
    pub verdict: String,
    /// The verdict itself and the limit(s) that decide it (the rule's answer; `verdict` says
    /// it in words).
    #[serde(skip)]
    pub judged: Judged,
    /// The peak |shear angle|, degrees: the largest mean over a disc of one woven cell
    /// (`cell_mm`, the cell's mean side, as radius) around an element, in the undeformed blank;
    /// and where (final position of that element's centre, mm, in the solved part). It is what
    /// the verdict compares with the locking angle (`guide::accuracy`).
    pub max_shear_deg: f64,
    pub max_shear_at: [f64; 3],
    pub locking_angle_deg: f64,
    /// Share of the blank's initial area whose elements are sheared past the locking angle, %.
    pub area_over_limit_pct: f64,
    /// The peak yarn tension over one woven cell, as `max_shear_deg`, N.
    pub max_tension_n: f64,
    /// The radius of the peaks' disc, mm.
    pub cell_mm: f64,
    /// The same figures at the scale of one element (the largest element value): they keep
    /// moving as the mesh is refined, so no verdict uses them.
    pub max_shear_element_deg: f64,
    pub max_tension_element_n: f64,
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
    /// and that level's errors on these tools (see `crate::accuracy`: measured, and wider
    /// for radii under 5 mm).
    pub accuracy: Option<String>,
    pub max_shear_err_deg: Option<f64>,
    pub punch_force_err_pct: Option<f64>,
    pub max_tension_err_pct: Option<f64>,
    /// The largest wrinkle amplitude, mm (`core::wrinkles::amplitude`: out-of-plane waviness along the
    /// yarns that the tools do not explain), where it is, and how far it can be off (mm); all
    /// `null` for the paper's membrane, which has no bending and so no wrinkles.
    pub max_wrinkle_mm: Option<f64>,
    pub max_wrinkle_at: Option<[f64; 3]>,
    pub max_wrinkle_err_mm: Option<f64>,
    pub wrinkle_limit_mm: f64,
    pub dofs: usize,
    /// Elements of the solved part, and which part was solved ("quarter" or "full").
    pub elements: usize,
    pub solved_part: String,
    pub steps: u32,
    pub cutbacks: u32,
    pub newton_iterations: u32,
    /// Steps on which Newton stalled even at the smallest increment and that ended within ten
    /// force tolerances of balance (`RELAXED_TOLERANCE` in `core::solver`).
    pub relaxed_steps: u32,
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
    /// The files written, by kind (`summary`, `shear_map`, `tension_map`,
    /// `shear_developed_map`, `tension_developed_map`, `vtu`).
    pub files: BTreeMap<String, String>,
    /// The scene as run (every key, defaults filled in).
    pub inputs: Scene,
}

impl RunSummary {
    /// The summary of `result`, which took `wall_s` seconds.
    pub fn new(name: &str, scene: &Scene, result: &DrawingResult, wall_s: f64) -> RunSummary {
        let limits = Limits::of(scene);
        let [(e, max_shear_deg), (_, max_tension_n)] = result.cell_peaks();
        let unsound = unsound_words(result);
        let level = Accuracy::of_element_size(scene.mesh.element_size);
        let error = level.map(|a| a.error_for(scene.tools.smallest_radius_mm()));
        let wrinkle = result.max_wrinkle();
        let wrinkle_err_mm = wrinkle.zip(error).map(|((w, _), e)| e.wrinkle_mm(w));
        let facts = Facts {
            converged: result.converged,
            no_answer: matches!(result.failure, Some(DrawingFailure::NoUniqueShape { .. })),
            unsound: &unsound,
            figures: Figures {
                max_shear_deg,
                max_tension_n,
                max_shear_err_deg: error.map_or(0.0, |e| e.max_shear_deg),
                max_tension_err_pct: error.map_or(0.0, |e| e.max_tension_pct),
                max_wrinkle_mm: wrinkle.map(|w| w.0),
                max_wrinkle_err_mm: wrinkle_err_mm.unwrap_or(0.0),
            },
            limits,
            stroke_reached_mm: result.stroke_reached_mm,
            stroke_mm: scene.process.stroke,
        };
        let judged = facts.judge();
        let feasible = judged.verdict == Verdict::Feasible;
        let verdict = facts.sentence();
        let max_shear_at = centre_or_origin(result, e);
        RunSummary {
            scene: name.to_string(),
            converged: result.converged,
            failure: result.failure.as_ref().map(|f| f.to_string()),
            feasible,
            verdict,
            judged,
            max_shear_deg,
            max_shear_at,
            locking_angle_deg: limits.locking_angle_deg,
            area_over_limit_pct: result.area_over_limit_pct(limits.locking_angle_deg),
            max_tension_n,
            cell_mm: result.cell_mm,
            max_shear_element_deg: result.max_shear_element().1,
            max_tension_element_n: result.max_tension_element_n(),
            break_tension_n: limits.break_tension_n,
            punch_force_n: result.punch_force_n,
            stroke_mm: scene.process.stroke,
            stroke_reached_mm: result.stroke_reached_mm,
            penetration_mm: result.penetration_mm,
            draw_in_mm: result.draw_in_mm,
            wall_s,
            accuracy: level.map(|a| a.name().to_string()),
            max_shear_err_deg: error.map(|e| e.max_shear_deg),
            punch_force_err_pct: error.map(|e| e.punch_force_pct),
            max_tension_err_pct: error.map(|e| e.max_tension_pct),
            max_wrinkle_mm: wrinkle.map(|w| w.0),
            max_wrinkle_at: wrinkle.map(|w| w.1),
            max_wrinkle_err_mm: wrinkle_err_mm,
            wrinkle_limit_mm: limits.wrinkle_limit_mm,
            dofs: result.dofs,
            elements: result.mesh.quads.len(),
            solved_part: if result.quarter { "quarter" } else { "full" }.to_string(),
            steps: result.stats.steps,
            cutbacks: result.stats.cutbacks,
            newton_iterations: result.stats.newton_iterations,
            relaxed_steps: result.stats.relaxed_steps,
            stabilisation_work_share: result.unbalanced_work_share,
            unsound,
            mechanism: result.stats.mechanism,
            left_out: result.left_out.iter().map(|l| l.to_string()).collect(),
            files: BTreeMap::new(),
            inputs: scene.clone(),
        }
    }

    /// The design in one line, for the maps: the tools, the friction, the holder pressure and
    /// the mesh, with units.
    pub fn design_line(&self) -> String {
        use crate::scene::{Num, ToolKind};
        let s = &self.inputs;
        let t = &s.tools;
        let tools = match t.kind {
            ToolKind::Box => format!(
                "box r {} · rp {} · rm {} mm",
                Num(t.r),
                Num(t.rp),
                Num(t.rm)
            ),
            ToolKind::Hemisphere => {
                format!("hemisphere radius {} · rm {} mm", Num(t.radius), Num(t.rm))
            }
            ToolKind::Ellipsoid => format!(
                "ellipsoid {} × {} × {} · rm {} mm",
                Num(t.axes[0]),
                Num(t.axes[1]),
                Num(t.axes[2]),
                Num(t.rm)
            ),
            ToolKind::Mesh => format!(
                "punch {} · die {}",
                t.file_name(&t.punch),
                t.file_name(&t.die)
            ),
        };
        let level = self
            .accuracy
            .as_ref()
            .map(|a| format!(" ({a})"))
            .unwrap_or_default();
        let holder = match s.process.holder_force {
            Some(kn) => format!("holder plate {} kN", Num(kn)),
            None if s.fabric.bending_rigidity.is_some() => {
                format!("holder plate {} MPa", Num(s.process.holder_pressure))
            }
            None => format!("holder {} MPa", Num(s.process.holder_pressure)),
        };
        format!(
            "{tools} · friction {} · {holder} · {} mm elements{level}",
            Num(s.process.friction),
            Num(s.mesh.element_size)
        )
    }

    /// One JSON object on one line.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("the summary is plain data")
    }
}

/// Why a converged result cannot be trusted, in words (empty when it can, or did not converge).
fn unsound_words(result: &DrawingResult) -> Vec<String> {
    if result.converged {
        result.unsound().iter().map(|u| u.to_string()).collect()
    } else {
        Vec::new()
    }
}

/// The final centre of element `e`, or the origin for a run with no field.
fn centre_or_origin(result: &DrawingResult, e: usize) -> [f64; 3] {
    if result.shear_deg.is_empty() {
        [0.0; 3]
    } else {
        result.element_centre(e)
    }
}

/// What a map of the run shows: the part of the blank and the stroke reached.
pub fn what_is_drawn(result: &DrawingResult, stroke_mm: f64) -> String {
    let part = if result.quarter {
        "full blank (the solved quarter mirrored)"
    } else {
        "full blank"
    };
    let stroke = stroke_reached(result, stroke_mm);
    format!("deformed blank seen from above, {part}, {stroke}; dashed: die opening")
}

/// The stroke a map shows: "stroke 28.0 mm", or where the run stopped short of `stroke_mm`.
pub fn stroke_reached(result: &DrawingResult, stroke_mm: f64) -> String {
    if result.converged {
        format!("stroke {:.1} mm", result.stroke_reached_mm)
    } else {
        format!(
            "stopped at stroke {:.1} of {:.1} mm",
            result.stroke_reached_mm, stroke_mm
        )
    }
}

/// The subtitle of a shear map of the run.
pub fn shear_subtitle(result: &DrawingResult, stroke_mm: f64) -> String {
    format!(
        "Shear angle of the yarns: {}",
        what_is_drawn(result, stroke_mm)
    )
}
