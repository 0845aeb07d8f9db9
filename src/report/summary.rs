//! The summary of one drawing run (`wovenform run`) as text with units, and the files written
//! beside it.

use super::{fixed, plural};
use std::fmt::Write as _;

use crate::scene::ToolKind;
use crate::show::Num;
use crate::summary::RunSummary;

impl RunSummary {
    /// The summary as text with units, for a person.
    pub fn to_text(&self) -> String {
        let mut out = String::new();
        self.write_inputs(&mut out);
        let _ = writeln!(out);
        let _ = writeln!(out, "verdict      {}", self.verdict);
        if let Some(f) = &self.failure {
            let _ = writeln!(out, "failure      {f}");
        }
        if self.converged || self.steps > 0 {
            self.write_figures(&mut out);
        }
        // Else nothing was solved: no figures to show.
        self.write_footer(&mut out);
        out
    }

    /// The scene as run: tools, process, blank and mesh.
    fn write_inputs(&self, out: &mut String) {
        let s = &self.inputs;
        let t = &s.tools;
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
            ToolKind::Mesh => format!(
                "punch {}, die {} (STL; distance lattice {} mm)",
                t.punch, t.die, t.lattice
            ),
        };
        let mut law = if s.fabric.undulation {
            "woven law (undulation)".to_string()
        } else {
            "linear yarn law".to_string()
        };
        if let Some(k) = s.fabric.shear_moment {
            law.push_str(&format!(
                ", shear law [{}, {}, {}] N·mm/mm²{}",
                k[0],
                k[1],
                k[2],
                if s.fabric.shear_locking {
                    ", stiffening past locking"
                } else {
                    ""
                }
            ));
        }
        let _ = writeln!(out, "scene        {}", self.scene);
        let _ = writeln!(out, "tools        {tools}");
        let holder = match s.process.holder_force {
            Some(kn) => format!("holder plate pressed with {kn} kN"),
            None if s.fabric.bending_rigidity.is_some() => format!(
                "holder plate pressed with {} MPa over the flange",
                s.process.holder_pressure
            ),
            None => format!("holder pressure {} MPa", s.process.holder_pressure),
        };
        let _ = writeln!(
            out,
            "process      friction {}, {holder}, stroke {} mm",
            s.process.friction, s.process.stroke
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
    }

    /// The figures of the run with their units, limits and errors.
    fn write_figures(&self, out: &mut String) {
        let [x, y, z] = self.max_shear_at;
        let _ = writeln!(
            out,
            "max shear    {:.1}° over one woven cell, around ({x:.1}, {y:.1}, {z:.1}) mm; locking angle {}°; {:.2} % of the blank over it",
            self.max_shear_deg,
            Num(self.locking_angle_deg),
            self.area_over_limit_pct
        );
        let _ = writeln!(
            out,
            "max tension  {} N per yarn over one woven cell; break tension {} N ({:.0} %)",
            fixed(self.max_tension_n, 1),
            Num(self.break_tension_n),
            100.0 * self.max_tension_n / self.break_tension_n
        );
        self.write_wrinkles(out);
        let _ = writeln!(
            out,
            "one element  {:.1}° of shear, {:.1} N of tension at the most loaded element (the figures above are means over a disc of {:.2} mm radius)",
            self.max_shear_element_deg, self.max_tension_element_n, self.cell_mm
        );
        let _ = writeln!(
            out,
            "punch force  {} N at stroke {:.2} of {} mm",
            fixed(self.punch_force_n, 1),
            self.stroke_reached_mm,
            self.stroke_mm
        );
        let _ = writeln!(
            out,
            "draw-in      {:.2} mm at the blank's edge; largest penetration {:.4} mm",
            self.draw_in_mm, self.penetration_mm
        );
        self.write_solver(out);
        self.write_accuracy(out);
    }

    /// The wrinkle amplitude with its place, error and limit, or why there is none.
    fn write_wrinkles(&self, out: &mut String) {
        let Some(w) = self.max_wrinkle_mm else {
            let _ = writeln!(
                out,
                "wrinkles     not modelled: the paper's membrane has no bending (give \
                 fabric.bending_rigidity)"
            );
            return;
        };
        let [x, y, z] = self.max_wrinkle_at.unwrap_or([0.0; 3]);
        let err = self
            .max_wrinkle_err_mm
            .map(|e| format!(" ± {e:.2}"))
            .unwrap_or_default();
        let _ = writeln!(
            out,
            "wrinkles     {w:.2}{err} mm peak to valley along a yarn off the tools, around \
             ({x:.1}, {y:.1}, {z:.1}) mm; wrinkle limit {} mm",
            Num(self.wrinkle_limit_mm)
        );
    }

    /// How the solver went: its steps, cut-backs, iterations and time, the work out of
    /// balance.
    fn write_solver(&self, out: &mut String) {
        let _ = writeln!(
            out,
            "solver       {} step{}, {} cut-back{}, {} Newton iteration{}, {:.2} s; forces out of balance did {}{}{}",
            self.steps,
            plural(self.steps as usize),
            self.cutbacks,
            plural(self.cutbacks as usize),
            self.newton_iterations,
            plural(self.newton_iterations as usize),
            self.wall_s,
            share_text(self.stabilisation_work_share),
            if self.mechanism {
                "; a singular tangent was met (part of the blank was a mechanism)"
            } else {
                ""
            },
            if self.relaxed_steps > 0 {
                format!(
                    "; {} step{} stalled and ended within ten force tolerances",
                    self.relaxed_steps,
                    plural(self.relaxed_steps as usize)
                )
            } else {
                String::new()
            }
        );
    }

    /// The accuracy level of the mesh and its errors, or that there is none.
    fn write_accuracy(&self, out: &mut String) {
        let _ = match (
            &self.accuracy,
            self.max_shear_err_deg,
            self.punch_force_err_pct,
            self.max_tension_err_pct,
        ) {
            (Some(level), Some(shear), Some(force), Some(tension)) => writeln!(
                out,
                "accuracy     {level} ({} mm elements): max shear ±{shear:.1}°, max tension ±{tension:.0} %, punch force ±{force:.1} % ({})",
                self.inputs.mesh.element_size,
                if self.inputs.tools.smallest_radius_mm() < crate::accuracy::MEASURED_RADIUS_MM {
                    format!(
                        "the level's measured error, grown for the {:.1} mm radius",
                        self.inputs.tools.smallest_radius_mm()
                    )
                } else {
                    "measured over the paper's grid of tools and the presets".to_string()
                }
            ),
            _ => writeln!(
                out,
                "accuracy     no level ({} mm elements): --accuracy coarse|standard|fine gives an error estimate",
                self.inputs.mesh.element_size
            ),
        };
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

/// A small share as a percentage (`2.1e-5 %`); one over 1 as a multiple (`4.0e9 times`), a
/// percentage of which no one reads.
fn share_text(share: f64) -> String {
    if share > 1.0 {
        format!("{share:.1e} times the punch's work")
    } else {
        format!("{:.1e} % of the punch's work", 100.0 * share)
    }
}
