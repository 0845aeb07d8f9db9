//! The stiff and extreme cases of `verification.md`: each either converges or stops with a
//! structured reason — never a panic, a NaN or Inf in any output, or a hang (each case is
//! bounded by a coarse mesh and a shallow stroke; the wall time is checked).

use wovenform::core::drawing::{self, DrawingProblem, DrawingResult, Tooling};

/// The open box on a coarse mesh and a shallow stroke: the base of every case.
fn base() -> DrawingProblem {
    let mut p = DrawingProblem::paper_box(10.0, 15.0, 10.0);
    p.fabric.undulation = false;
    p.element_size = 5.0;
    p.stroke = 10.0;
    p
}

/// Runs a case and checks the outcome is well formed; returns it for case-specific checks.
fn run(name: &str, p: &DrawingProblem) -> DrawingResult {
    let start = std::time::Instant::now();
    let r = drawing::solve(p, &mut |_| {});
    let wall_s = start.elapsed().as_secs_f64();
    let finite = r.shear_deg.iter().all(|v| v.is_finite())
        && r.tension_max_n.iter().all(|v| v.is_finite())
        && r.t11_n.iter().chain(&r.t22_n).all(|v| v.is_finite())
        && r.positions.iter().flatten().all(|v| v.is_finite())
        && r.punch_force_n.is_finite()
        && r.penetration_mm.is_finite()
        && r.draw_in_mm.is_finite();
    println!(
        "{name:<44} {:<10} stroke {:>5.1}/{:<4} mm  shear {:>5.1}°  tension {:>8.1} N  {:>4} steps {:>5} Newton  {:>6.2} s  {}",
        if r.converged { "converged" } else { "stopped" },
        r.stroke_reached_mm,
        p.stroke,
        r.max_shear().1,
        r.max_tension_n(),
        r.stats.steps,
        r.stats.newton_iterations,
        wall_s,
        r.failure.as_ref().map(|f| f.to_string()).unwrap_or_default()
    );
    assert!(finite, "{name}: a non-finite value in the output");
    assert!(
        r.converged || r.failure.as_ref().is_some_and(|f| !f.to_string().is_empty()),
        "{name}: stopped without a reason"
    );
    assert!(wall_s < 120.0, "{name}: {wall_s} s");
    r
}

#[test]
fn yarn_stiffness_from_1e2_to_1e8() {
    for c in [1e2, 1e4, 1e6, 1e8] {
        for undulation in [false, true] {
            let mut p = base();
            p.fabric.c = [c, c];
            p.fabric.undulation = undulation;
            run(&format!("C = {c:.0e} N, undulation {undulation}"), &p);
        }
    }
}

#[test]
fn friction_from_0_to_1() {
    for mu in [0.0, 0.5, 1.0] {
        let mut p = base();
        p.friction = mu;
        run(&format!("friction {mu}"), &p);
    }
}

#[test]
fn holder_pressure_from_0_to_20_mpa() {
    for pressure in [0.0, 5.0, 20.0] {
        let mut p = base();
        p.holder_pressure = pressure;
        run(&format!("holder pressure {pressure} MPa"), &p);
    }
}

#[test]
fn radii_from_half_a_millimetre_to_50_mm() {
    for (r, rp, rm) in [(0.5, 0.5, 0.5), (0.5, 15.0, 10.0), (25.0, 25.0, 50.0)] {
        let mut p = base();
        p.tooling = Tooling::Box {
            side: [60.0, 60.0],
            r,
            rp,
            rm,
            clearance: 1.5,
        };
        if rm > 20.0 {
            p.blank = [300.0, 300.0];
            p.element_size = 8.0;
        }
        run(&format!("radii r {r} rp {rp} rm {rm} mm"), &p);
    }
}

#[test]
fn zero_die_clearance() {
    let mut p = base();
    if let Tooling::Box { clearance, .. } = &mut p.tooling {
        *clearance = 0.0;
    }
    run("zero clearance", &p);
}

#[test]
fn a_stroke_deeper_than_the_blank_can_follow() {
    // 50 mm into the die with a 120 mm blank and a 60 mm punch: the blank is pulled off the
    // flange and out from under the holder, and hangs in the die.
    let mut p = base();
    p.blank = [120.0, 120.0];
    p.element_size = 6.0;
    p.stroke = 50.0;
    let r = run("stroke 50 mm, blank 120 mm", &p);
    assert!(r.converged);
}

#[test]
fn elements_much_smaller_and_much_larger_than_a_woven_cell() {
    // A cell is 4.76 mm: elements of 1 mm (on a small blank) and of 20 mm.
    let mut p = base();
    p.element_size = 1.0;
    p.blank = [100.0, 100.0];
    p.stroke = 4.0;
    run("elements of 1 mm", &p);
    let mut p = base();
    p.element_size = 20.0;
    run("elements of 20 mm", &p);
}

#[test]
fn a_blank_barely_larger_than_the_die_opening() {
    // The opening is 63 mm with entry radii of 10 mm: a 90 mm blank barely reaches the flange.
    let mut p = base();
    p.blank = [90.0, 90.0];
    p.element_size = 3.0;
    run("blank 90 mm", &p);
}

#[test]
fn no_stabilisation_reports_instead_of_failing_silently() {
    let mut p = base();
    p.solver.stabilisation = 0.0;
    let r = run("no stabilisation", &p);
    assert!(r.converged || r.stats.mechanism || r.failure.is_some());
}
