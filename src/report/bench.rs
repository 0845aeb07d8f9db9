//! The text and JSON of `wovenform bench`: what [`crate::study::bench`] measured, with units.

use std::fmt::Write as _;

use crate::study::bench::{BoxRun, Measured, Scaling};
use crate::study::scaling::Timed;

/// The targets the ratios are judged against: bare factorizations of the open box
/// at standard, fine over standard wall time, the ladder's exponent, the long bias specimen
/// over the short one.
pub const TARGET_OPEN_BOX_FACTORIZATIONS: f64 = 190.0;
pub const TARGET_FINE_OVER_STANDARD: f64 = 6.0;
pub const TARGET_DOF_EXPONENT: f64 = 1.25;
pub const TARGET_BIAS_LONG_OVER_SHORT: f64 = 5.0;
/// The open box with bending over the same box without it, whole blank, standard.
pub const TARGET_BENDING_OVER_MEMBRANE: f64 = 2.0;

fn bending_json([without, with]: &[Timed; 2]) -> serde_json::Value {
    serde_json::json!({
        "without": timed_json(without), "with": timed_json(with),
        "bending_rigidity_nmm": crate::study::bench::BENCH_BENDING_RIGIDITY,
        "with_over_without": with.wall_s / without.wall_s,
        "target": TARGET_BENDING_OVER_MEMBRANE,
    })
}

fn write_bending([without, with]: &[Timed; 2], out: &mut String) {
    let _ = writeln!(
        out,
        "bending (open box, whole blank, standard, B = {} N·mm): {:.2} s with against {:.2} s \
         without, {:.2}× (target ≤ {TARGET_BENDING_OVER_MEMBRANE}×); Newton {} against {}{}",
        crate::study::bench::BENCH_BENDING_RIGIDITY[0],
        with.wall_s,
        without.wall_s,
        with.wall_s / without.wall_s,
        with.newton_iterations,
        without.newton_iterations,
        if with.finished && without.finished {
            ""
        } else {
            " (a run did not finish)"
        }
    );
}

fn timed_json(t: &Timed) -> serde_json::Value {
    serde_json::json!({
        "wall_s": t.wall_s, "dofs": t.dofs, "steps": t.steps,
        "newton_iterations": t.newton_iterations, "finished": t.finished, "failure": t.failure,
    })
}

fn scaling_json(s: &Scaling) -> serde_json::Value {
    let bias = match &s.bias {
        Ok([short, long]) => serde_json::json!({
            "short": timed_json(short), "long": timed_json(long),
            "long_over_short": long.wall_s / short.wall_s,
            "target": TARGET_BIAS_LONG_OVER_SHORT,
        }),
        Err(e) => serde_json::json!({"failure": e}),
    };
    let [one, assembly, all] = &s.open_fine;
    serde_json::json!({
        "deadline_s": s.deadline_s,
        "fine_over_standard": s.designs.iter().map(|d| serde_json::json!({
            "name": d.name, "standard": timed_json(&d.standard), "fine": timed_json(&d.fine),
            "wall_ratio": d.wall_ratio(), "step_ratio": d.step_ratio(),
            "target": TARGET_FINE_OVER_STANDARD,
        })).collect::<Vec<_>>(),
        "bias_long_over_short": bias,
        "open_box_fine_one_thread": timed_json(one),
        "open_box_fine_parallel_assembly": timed_json(assembly),
        "open_box_fine_parallel_assembly_and_factorization": timed_json(all),
        "threads": s.threads,
        "open_box_fine_speedup_assembly": speedup(one, assembly),
        "open_box_fine_speedup_assembly_and_factorization": speedup(one, all),
    })
}

/// One thread's wall time over `many`'s, when both runs reached the full stroke (a run stopped
/// at the deadline says nothing of the speed-up: both may have stopped there).
fn speedup(one: &Timed, many: &Timed) -> Option<f64> {
    (one.finished && many.finished).then(|| one.wall_s / many.wall_s)
}

/// [`speedup`] as text.
fn speedup_text(one: &Timed, many: &Timed) -> String {
    speedup(one, many).map_or("no speed-up: a run stopped at the deadline".into(), |v| {
        format!("speed-up {v:.2}")
    })
}

fn run_json(name: &str, r: &BoxRun) -> serde_json::Value {
    serde_json::json!({
        "name": name, "wall_s": r.wall_s, "dofs": r.dofs, "steps": r.steps,
        "newton_iterations": r.newton_iterations,
        "newton_iterations_per_step": r.iterations_per_step(),
        "krylov_iterations": r.krylov_iterations,
        "newton_iteration_s": r.iteration_s(),
        "assembly_with_tangent_s": r.assembly_s, "contact_with_blocks_s": r.contact_s,
        "bare_factor_solve_s": r.bare_factor_solve_s, "cell_peaks_s": r.cell_peaks_s,
        "iteration_over_factor_solve": r.iteration_over_factor_solve(),
        "max_shear_deg": r.max_shear_deg, "max_tension_n": r.max_tension_n,
        "punch_force_n": r.punch_force_n,
    })
}

fn range(samples: &[f64]) -> (f64, f64) {
    let lo = samples.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = samples.iter().cloned().fold(0.0, f64::max);
    (lo, hi)
}

impl Measured {
    fn open(&self) -> &BoxRun {
        &self.drawings.open
    }

    /// One JSON object (scripts rely on `open_box_standard_wall_s`,
    /// `iteration_over_factor_solve`, `open_box_newton_iterations`, `open_box_steps`).
    pub fn to_json(&self) -> serde_json::Value {
        let open = self.open();
        let [one, two] = self.sweep_per_min;
        serde_json::json!({
            "law_evals_per_s": self.rates[0].per_second,
            "element_evals_per_s": self.rates[1].per_second,
            "open_box_standard_wall_s": open.wall_s,
            "open_box_dofs": open.dofs,
            "open_box_steps": open.steps,
            "open_box_newton_iterations": open.newton_iterations,
            "open_box_krylov_iterations": open.krylov_iterations,
            "newton_iteration_s": open.iteration_s(),
            "bare_factor_solve_s": open.bare_factor_solve_s,
            "open_box_bare_factorizations": open.wall_in_factorizations,
            "open_box_bare_factorizations_target": TARGET_OPEN_BOX_FACTORIZATIONS,
            "wall_dof_exponent_target": TARGET_DOF_EXPONENT,
            "scaling": self.scaling.as_ref().map(scaling_json),
            "bending": self.bending.as_ref().map(bending_json),
            "iteration_over_factor_solve": open.iteration_over_factor_solve(),
            "tight_box_standard_wall_s": self.drawings.tight.wall_s,
            "open_box_friction_0_05_wall_s": self.drawings.open_low_friction.wall_s,
            "drawings": self.drawings.named().iter().map(|(n, r)| run_json(n, r)).collect::<Vec<_>>(),
            "friction_resolution": self.friction.iter().map(|(n, r)| match r {
                Ok(r) => run_json(n, r),
                Err(e) => serde_json::json!({"name": n, "failure": e}),
            }).collect::<Vec<_>>(),
            "mesh_tools": self.mesh.iter().map(|r| match r {
                Ok(r) => serde_json::json!({
                    "name": r.name, "punch_triangles": r.triangles[0], "die_triangles": r.triangles[1],
                    "analytic_wall_s": r.analytic_s, "stl_wall_s": r.mesh_s, "stl_read_s": r.read_s,
                    "stl_over_analytic": r.mesh_s / r.analytic_s,
                    "max_shear_departure_deg": r.departures[0],
                    "punch_force_departure_pct": 100.0 * r.departures[1],
                    "draw_in_departure_mm": r.departures[2],
                }),
                Err(e) => serde_json::json!({"failure": e}),
            }).collect::<Vec<_>>(),
            "dof_ladder": self.ladder.iter().map(|(d, w)| serde_json::json!({"dofs": d, "wall_s": w})).collect::<Vec<_>>(),
            "wall_dof_exponent": self.exponent,
            "sweep_designs_per_min": {"jobs_1": one, "jobs_2": two},
            "repetitions": self.reps,
        })
    }

    /// The table a person reads: one figure a line, with its unit and what it was measured on.
    pub fn to_text(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "one thread unless stated; medians of {} repetitions (the drawings, the dof ladder and what a finer answer costs: of {}, interleaved)",
            self.reps, self.box_reps
        );
        for r in &self.rates {
            let (lo, hi) = range(&r.samples);
            let _ = writeln!(
                out,
                "{:<48} {:>12.3e} /s  (range {lo:.2e} to {hi:.2e})",
                r.name, r.per_second
            );
        }
        for (name, run) in self.drawings.named() {
            let (lo, hi) = range(&run.samples);
            let _ = writeln!(
                out,
                "{:<48} {:>12.3} s   (standard, 2.5 mm: {} dofs, {} steps, {} Newton iterations, {:.1} a step; range {lo:.2} to {hi:.2} s)",
                format!("{name}, whole run"),
                run.wall_s,
                run.dofs,
                run.steps,
                run.newton_iterations,
                run.iterations_per_step(),
            );
        }
        self.write_iteration(&mut out);
        self.write_friction(&mut out);
        self.write_mesh(&mut out);
        if let Some(s) = &self.scaling {
            write_scaling(s, &mut out);
        }
        if let Some(b) = &self.bending {
            write_bending(b, &mut out);
        }
        out
    }

    /// Where an iteration's time goes, how the time grows with the dofs, sweep throughput.
    fn write_iteration(&self, out: &mut String) {
        let open = self.open();
        let ms = |s: f64| s * 1e3;
        let _ = writeln!(
            out,
            "{:<48} {:>12.3} ms  (the open box's run over its iterations; on its final state: an assembly with the tangent {:.3} ms, of it the contact {:.3} ms; {} GMRES iterations in the run)",
            "one Newton iteration",
            ms(open.iteration_s()),
            ms(open.assembly_s),
            ms(open.contact_s),
            open.krylov_iterations
        );
        let _ = writeln!(
            out,
            "{:<48} {:>12.2}   (bare factorization + solve of the last tangent: {:.3} ms)",
            "Newton iteration / bare factorization + solve",
            open.iteration_over_factor_solve(),
            ms(open.bare_factor_solve_s)
        );
        let _ = writeln!(
            out,
            "{:<48} {:>12.0}   (each run over the bare factorization + solve timed right after it, median; target ≤ {TARGET_OPEN_BOX_FACTORIZATIONS:.0})",
            "open box at standard, in bare factorizations", open.wall_in_factorizations
        );
        let _ = writeln!(
            out,
            "{:<48} {:>12.3} ms  (shear and tension over one woven cell, on the final state; {:.2} % of the run)",
            "peaks over a cell",
            ms(open.cell_peaks_s),
            100.0 * open.cell_peaks_s / open.wall_s
        );
        let pts: Vec<String> = self
            .ladder
            .iter()
            .map(|(d, w)| format!("{d} dofs {w:.2} s"))
            .collect();
        let _ = writeln!(
            out,
            "{:<48} {:>12.2}   (target ≤ {TARGET_DOF_EXPONENT}; {})",
            "wall time ∝ dofs^k, k =",
            self.exponent,
            pts.join(", ")
        );
        let [one, two] = self.sweep_per_min;
        let _ = writeln!(
            out,
            "{:<48} {:>12.1} /min with 1 job, {:.1} /min with 2 jobs (speed-up {:.2})",
            "sweep throughput (8 box designs, coarse)",
            one,
            two,
            two / one
        );
    }

    /// STL tools against analytic ones, when measured.
    fn write_mesh(&self, out: &mut String) {
        if self.mesh.is_empty() {
            return;
        }
        let _ = writeln!(
            out,
            "\ntools from STL against the same analytic tools, whole blank, standard (medians of {}):",
            self.box_reps.min(3)
        );
        let _ = writeln!(
            out,
            "  {:<11} {:>17} {:>10} {:>9} {:>9} {:>7} {:>13} {:>9} {:>9} {:>9}",
            "tools",
            "triangles",
            "analytic s",
            "STL s",
            "of it read",
            "ratio",
            "steps/Newton",
            "shear °",
            "force %",
            "draw-in mm"
        );
        for run in &self.mesh {
            let _ = match run {
                Ok(r) => writeln!(
                    out,
                    "  {:<11} {:>8} + {:<7} {:>10.2} {:>9.2} {:>9.2} {:>7.2} {:>6}/{:<6} {:>+9.3} {:>+9.2} {:>+9.3}",
                    r.name,
                    r.triangles[0],
                    r.triangles[1],
                    r.analytic_s,
                    r.mesh_s,
                    r.read_s,
                    r.mesh_s / r.analytic_s,
                    format!("{}/{}", r.steps[0], r.newton_iterations[0]),
                    format!("{}/{}", r.steps[1], r.newton_iterations[1]),
                    r.departures[0],
                    100.0 * r.departures[1],
                    r.departures[2]
                ),
                Err(e) => writeln!(out, "  failed: {e}"),
            };
        }
    }

    /// The comparison of how friction is resolved in a step, when it was measured.
    fn write_friction(&self, out: &mut String) {
        if self.friction.is_empty() {
            return;
        }
        let _ = writeln!(
            out,
            "\nfriction's normal force and direction, open box at standard (medians of {}):",
            self.box_reps.min(3)
        );
        let _ = writeln!(
            out,
            "  {:<36} {:>7} {:>6} {:>7} {:>9} {:>10} {:>9} {:>9}",
            "resolved", "wall s", "steps", "Newton", "GMRES", "force N", "tension N", "shear °"
        );
        for (name, run) in &self.friction {
            let _ = match run {
                Ok(r) => writeln!(
                    out,
                    "  {name:<36} {:>7.2} {:>6} {:>7} {:>9} {:>10.1} {:>9.1} {:>9.2}",
                    r.wall_s,
                    r.steps,
                    r.newton_iterations,
                    r.krylov_iterations,
                    r.punch_force_n,
                    r.max_tension_n,
                    r.max_shear_deg
                ),
                Err(e) => writeln!(out, "  {name:<36} failed: {e}"),
            };
        }
    }
}

/// A timed run as `12.3 s (steps/Newton)`, or what stopped it.
fn timed_text(t: &Timed) -> String {
    let base = format!("{:.1} s ({}/{})", t.wall_s, t.steps, t.newton_iterations);
    match (&t.failure, t.finished) {
        (_, true) => base,
        (Some(f), false) => format!("{base}, not finished: {f}"),
        (None, false) => format!("{base}, not finished"),
    }
}

/// What a finer answer costs, when measured.
fn write_scaling(s: &Scaling, out: &mut String) {
    let _ = writeln!(
        out,
        "\nwhat a finer answer costs (one thread; a run stopped at {:.0} s gives a lower bound, ≥):",
        s.deadline_s
    );
    let _ = writeln!(
        out,
        "  {:<24} {:>26} {:>34} {:>8} {:>8}",
        "design (r/rp/rm)",
        "standard s (steps/Newton)",
        "fine s (steps/Newton)",
        "wall ×",
        "steps ×"
    );
    for d in &s.designs {
        let bound = if d.fine.finished { "" } else { "≥" };
        let _ = writeln!(
            out,
            "  {:<24} {:>26} {:>34} {:>8} {:>8.2}",
            d.name,
            timed_text(&d.standard),
            timed_text(&d.fine),
            format!("{bound}{:.1}", d.wall_ratio()),
            d.step_ratio()
        );
    }
    let _ = writeln!(
        out,
        "  (target: fine ≤ {TARGET_FINE_OVER_STANDARD}× standard's wall time)"
    );
    match &s.bias {
        Ok([short, _]) if !short.finished => {
            let _ = writeln!(
                out,
                "  bias extension: the 300 × 150 mm specimen did not finish within the deadline ({}): no ratio",
                timed_text(short)
            );
        }
        Ok([short, long]) => {
            let bound = if long.finished { "" } else { "≥" };
            let _ = writeln!(
                out,
                "  bias extension, 450 × 150 mm to 105 mm over 300 × 150 mm to 55 mm: {bound}{:.1}× ({} against {}, points/Newton; target ≤ {TARGET_BIAS_LONG_OVER_SHORT}×)",
                long.wall_s / short.wall_s,
                timed_text(long),
                timed_text(short)
            );
        }
        Err(e) => {
            let _ = writeln!(out, "  bias extension: {e}");
        }
    }
    let [one, assembly, all] = &s.open_fine;
    let _ = writeln!(
        out,
        "  open box at fine: {} on one thread; on {} threads, {} assembling ({}), {} assembling and factorizing ({})",
        timed_text(one),
        s.threads,
        timed_text(assembly),
        speedup_text(one, assembly),
        timed_text(all),
        speedup_text(one, all)
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    fn timed(wall_s: f64, finished: bool) -> Timed {
        Timed {
            wall_s,
            dofs: 14_145,
            steps: 20,
            newton_iterations: 150,
            finished,
            failure: (!finished).then(|| "stopped on request".into()),
        }
    }

    #[test]
    fn a_speed_up_needs_both_runs_to_reach_the_full_stroke() {
        let one = timed(4.0, true);
        assert_eq!(speedup(&one, &timed(3.2, true)), Some(1.25));
        // Both stopped at the same deadline: their times say nothing of the speed-up.
        assert_eq!(speedup(&timed(2.0, false), &timed(2.0, false)), None);
        assert_eq!(speedup(&one, &timed(2.0, false)), None);
        assert!(speedup_text(&one, &timed(2.0, false)).starts_with("no speed-up"));
        assert_eq!(speedup_text(&one, &timed(3.2, true)), "speed-up 1.25");
    }
}
