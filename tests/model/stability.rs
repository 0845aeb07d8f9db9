//! The stiff and extreme cases of `src/guide/verification.md`: each converges, or stops with the
//! structured reason the physics calls for — never a panic, a NaN or Inf in any output, or a
//! hang (each case is bounded by a coarse mesh and a shallow stroke, and the solver by its step
//! and iteration budgets).

use wovenform::core::drawing::{self, DrawingFailure, DrawingProblem, DrawingResult, Tooling};

/// The open box on a coarse mesh and a shallow stroke: the base of every case.
fn base() -> DrawingProblem {
    let mut p = DrawingProblem::paper_box(10.0, 15.0, 10.0);
    p.fabric.undulation = false;
    p.element_size_mm = 5.0;
    p.stroke_mm = 10.0;
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
        p.stroke_mm,
        r.max_shear().1,
        r.max_tension_n(),
        r.stats.steps,
        r.stats.newton_iterations,
        wall_s,
        r.failure
            .as_ref()
            .map(|f| f.to_string())
            .unwrap_or_default()
    );
    assert!(finite, "{name}: a non-finite value in the output");
    r
}

/// A case that must reach the full stroke with a sound result.
fn converges(name: &str, p: &DrawingProblem) -> DrawingResult {
    let r = run(name, p);
    assert!(r.converged, "{name}: {:?}", r.failure);
    assert!((r.stroke_reached_mm - p.stroke_mm).abs() < 1e-9);
    assert!(r.unsound().is_empty(), "{name}: {:?}", r.unsound());
    r
}

#[test]
fn yarn_stiffness_from_1e2_to_1e8() {
    for c in [1e2, 1e4, 1e6, 1e8] {
        for undulation in [false, true] {
            let mut p = base();
            p.fabric.c = [c, c];
            p.fabric.undulation = undulation;
            converges(&format!("C = {c:.0e} N, undulation {undulation}"), &p);
        }
    }
}

#[test]
fn friction_from_0_to_1() {
    // μ = 0: nothing holds the flange back; the fabric has no shear or bending stiffness, so
    // the model has no unique answer, and says so without a single iteration.
    let mut p = base();
    p.friction = 0.0;
    let r = run("friction 0", &p);
    assert!(matches!(
        r.failure,
        Some(DrawingFailure::NoUniqueShape { .. })
    ));
    assert_eq!(r.stats.newton_iterations, 0);
    for mu in [0.01, 0.05, 0.5, 1.0] {
        let mut p = base();
        p.friction = mu;
        converges(&format!("friction {mu}"), &p);
    }
}

#[test]
fn holder_pressure_from_0_to_20_mpa() {
    let mut p = base();
    p.holder_pressure_mpa = 0.0;
    let r = run("holder pressure 0 MPa", &p);
    assert!(matches!(
        r.failure,
        Some(DrawingFailure::NoUniqueShape { .. })
    ));
    for pressure in [0.01, 5.0, 20.0] {
        let mut p = base();
        p.holder_pressure_mpa = pressure;
        converges(&format!("holder pressure {pressure} MPa"), &p);
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
            p.blank_mm = [300.0, 300.0];
            p.element_size_mm = 8.0;
        }
        converges(&format!("radii r {r} rp {rp} rm {rm} mm"), &p);
    }
}

#[test]
fn zero_die_clearance() {
    let mut p = base();
    if let Tooling::Box { clearance, .. } = &mut p.tooling {
        *clearance = 0.0;
    }
    converges("zero clearance", &p);
}

#[test]
fn a_stroke_deeper_than_the_blank_can_follow() {
    // 50 mm into the die with a 120 mm blank and a 60 mm punch: the blank is pulled off the
    // flange and out from under the holder, and hangs in the die.
    let mut p = base();
    p.blank_mm = [120.0, 120.0];
    p.element_size_mm = 6.0;
    p.stroke_mm = 50.0;
    let r = converges("stroke 50 mm, blank 120 mm", &p);
    assert!(
        r.draw_in_mm > 20.0,
        "the blank was not pulled in: {}",
        r.draw_in_mm
    );
}

#[test]
fn elements_much_smaller_and_much_larger_than_a_woven_cell() {
    // A cell is 4.76 mm: elements of 1 mm (on a small blank) and of 20 mm.
    let mut p = base();
    p.element_size_mm = 1.0;
    p.blank_mm = [100.0, 100.0];
    p.stroke_mm = 4.0;
    converges("elements of 1 mm", &p);
    let mut p = base();
    p.element_size_mm = 20.0;
    converges("elements of 20 mm", &p);
}

#[test]
fn a_blank_barely_larger_than_the_die_opening() {
    // The opening is 63 mm with entry radii of 10 mm: a 90 mm blank barely reaches the flange.
    let mut p = base();
    p.blank_mm = [90.0, 90.0];
    p.element_size_mm = 3.0;
    converges("blank 90 mm", &p);
}

#[test]
fn no_stabilisation_gives_the_same_answer() {
    // The stabilisation damps the Newton corrections only: without it the run converges to the
    // same state (to the path's own spread: the steps differ).
    let with = converges("stabilisation 1e-2 (default)", &base());
    let mut p = base();
    p.solver.stabilisation = 0.0;
    let without = converges("no stabilisation", &p);
    let rel = |a: f64, b: f64| (a / b - 1.0).abs();
    assert!(rel(with.punch_force_n, without.punch_force_n) < 5e-3);
    assert!(rel(with.max_tension_n(), without.max_tension_n()) < 1e-2);
    assert!((with.max_shear().1 - without.max_shear().1).abs() < 0.1);
}

#[test]
fn a_soft_mode_at_the_end_of_the_stroke() {
    // The tight punch in the open die (5/6/10 mm, friction 0.15) at the standard mesh and the
    // full stroke: near the end a slack part of the blank leaves a soft mode, along which a
    // residual a thousand times below the tolerance still moves nodes by micrometres, and
    // Newton cycles there. The step converges on the correction's work, not its length.
    let mut p = DrawingProblem::paper_box(5.0, 6.0, 10.0);
    p.fabric.undulation = false;
    p.friction = 0.15;
    converges("tight punch, open die, friction 0.15", &p);
}
