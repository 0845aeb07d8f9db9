//! The drawing's consistency checks on the paper's open box, coarse and shallow: penetration,
//! the quarter model against the full one, a blank held by nothing refused at once, the whole
//! blank meshed at any yarn angle. (A run stopped on request is checked in `core::drawing`,
//! the size estimate against the model it describes in `core::drawing::size`; the contact
//! benchmarks with closed forms are `capstan.rs` and `holder_pull_out.rs`.)

use wovenform::core::drawing::{self, DrawingFailure, DrawingProblem, Symmetry};

fn coarse_open_box() -> DrawingProblem {
    let mut p = DrawingProblem::paper_box(10.0, 15.0, 10.0);
    p.fabric.undulation = false;
    p.element_size_mm = 5.0;
    p.stroke_mm = 12.0;
    p
}

#[test]
fn penetration_stays_below_a_twentieth_of_the_element() {
    let p = coarse_open_box();
    let r = drawing::solve(&p, &mut |_| {});
    assert!(r.converged, "{:?}", r.failure);
    println!(
        "penetration {:.4} mm for elements of {} mm",
        r.penetration_mm, p.element_size_mm
    );
    assert!(r.penetration_mm < 0.05 * p.element_size_mm);
}

#[test]
fn quarter_model_equals_the_full_model() {
    let mut p = coarse_open_box();
    p.symmetry = Symmetry::Quarter;
    let q = drawing::solve(&p, &mut |_| {});
    p.symmetry = Symmetry::Full;
    let f = drawing::solve(&p, &mut |_| {});
    assert!(
        q.converged && f.converged,
        "{:?} {:?}",
        q.failure,
        f.failure
    );
    let (sq, sf) = (q.max_shear().1, f.max_shear().1);
    println!(
        "quarter: shear {sq:.3}°, force {:.1} N; full: shear {sf:.3}°, force {:.1} N",
        q.punch_force_n, f.punch_force_n
    );
    assert!((sq - sf).abs() < 0.5, "max shear {sq} vs {sf}");
    assert!((q.punch_force_n / f.punch_force_n - 1.0).abs() < 0.02);
    assert!((q.draw_in_mm - f.draw_in_mm).abs() < 0.05);
}

#[test]
fn a_blank_held_by_nothing_has_no_unique_shape_and_says_so_at_once() {
    // The paper's fabric has no shear and no bending stiffness: without friction, or without a
    // holder pressing the flange, nothing holds the blank back and any drape is an equilibrium.
    for (friction, pressure, key) in [
        (0.0, 1.0, "process.friction"),
        (0.2, 0.0, "process.holder_pressure"),
    ] {
        let mut p = coarse_open_box();
        p.friction = friction;
        p.holder_pressure_mpa = pressure;
        let r = drawing::solve(&p, &mut |_| {});
        assert!(!r.converged);
        assert_eq!(r.stats.newton_iterations, 0, "it tried to solve");
        let failure = r.failure.expect("a failure");
        assert!(
            matches!(failure, DrawingFailure::NoUniqueShape { .. }),
            "{failure:?}"
        );
        let text = failure.to_string();
        assert!(
            text.contains("no unique shape") && text.contains(key),
            "{text}"
        );
        assert!(text.contains("no shear and no bending stiffness"), "{text}");
    }
    // With bending the reason is the fabric's shear in its plane, not a lack of bending.
    let bends = DrawingFailure::NoUniqueShape {
        why: drawing::Unrestrained::NoHolder,
        bends: true,
    }
    .to_string();
    assert!(!bends.contains("no bending stiffness"), "{bends}");
    assert!(
        bends.contains("in its plane it has no shear stiffness"),
        "{bends}"
    );
}

#[test]
fn the_whole_blank_is_meshed_at_any_yarn_angle_and_the_angle_is_continuous() {
    // A yarn angle off 90° used to mesh the blank as a parallelogram along the yarns: at 1° a
    // sliver away from the punch, "feasible" at zero force. The blank is now the rectangle at
    // any angle, and a fabric whose yarns are 0.01° off the axes draws as the full model does.
    let mut p = coarse_open_box();
    p.symmetry = Symmetry::Full;
    let at90 = drawing::solve(&p, &mut |_| {});
    p.yarn_angle_deg = 89.99;
    let near = drawing::solve(&p, &mut |_| {});
    assert!(
        at90.converged && near.converged,
        "{:?} {:?}",
        at90.failure,
        near.failure
    );
    for r in [&at90, &near] {
        let (lo, hi) = r
            .mesh
            .nodes
            .iter()
            .fold(([f64::MAX; 2], [f64::MIN; 2]), |(lo, hi), n| {
                (
                    [lo[0].min(n[0]), lo[1].min(n[1])],
                    [hi[0].max(n[0]), hi[1].max(n[1])],
                )
            });
        for v in [lo[0], lo[1], -hi[0], -hi[1]] {
            assert!((v + 85.0).abs() < 1e-9, "the blank's extent: {lo:?} {hi:?}");
        }
    }
    let (s90, s) = (at90.max_shear().1, near.max_shear().1);
    println!(
        "90°: shear {s90:.3}°, force {:.1} N; 89.99°: shear {s:.3}°, force {:.1} N",
        at90.punch_force_n, near.punch_force_n
    );
    assert!((s90 - s).abs() < 0.2, "max shear {s90} vs {s}");
    assert!((at90.punch_force_n / near.punch_force_n - 1.0).abs() < 0.01);
    // At 45° the punch still draws the whole blank: a real force, not a sliver's zero.
    p.yarn_angle_deg = 45.0;
    let oblique = drawing::solve(&p, &mut |_| {});
    println!("45°: force {:.1} N", oblique.punch_force_n);
    assert!(oblique.punch_force_n > 0.3 * at90.punch_force_n);
}
