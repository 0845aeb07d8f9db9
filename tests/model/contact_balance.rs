//! A Newton correction with each node's contact solved exactly (`SolverOptions::reshape_contact`,
//! `NodalTerms::reshape`): where a contact fades out in the penalty's eased gap, Newton's linear
//! model halves a lifting node's depth at each correction; the node's own balance, solved in
//! the correction, takes it there at once.
//! - The one-node balance `p(y0 − s) = g + K s` against a bisection of the same equation on
//!   the penalty's three pieces (off the tool, in the gap, pressed), and `None` where nothing
//!   bounds the move.
//! - A box off the paper's grid and off the presets (8/13/6 mm, μ 0.22), on and off: fewer
//!   Newton iterations with it, the same load steps, and no figure moved by a tenth of the
//!   standard level's band (0.12° of shear, 0.5 % of the punch force, 3.5 % of the max
//!   tension).

use wovenform::core::contact::normal;
use wovenform::core::drawing::{self, DrawingResult};

use crate::common;

/// The root of `p(y0 − s) − g − K s` (falling in `s`) by bisection on a bracket.
fn bisect(k: f64, delta: f64, y0: f64, g: f64, stiffness: f64) -> f64 {
    let f = |s: f64| normal::law(k, delta, delta - (y0 - s)).0 - g - stiffness * s;
    let (mut lo, mut hi) = (-1e3, 1e3);
    assert!(f(lo) > 0.0 && f(hi) < 0.0, "bracket");
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}

#[test]
fn a_node_balance_matches_a_bisection_on_each_piece_of_the_penalty() {
    let (k, delta) = (2.0e4, 0.05);
    // (depth before the move y0, load g, stiffness K): ending pressed, in the gap, off.
    let cases = [
        (0.08, 900.0, 0.0),
        (0.08, 900.0, 3.0e3),
        (0.03, 5.0, 0.0),
        (0.03, 5.0, 150.0),
        (0.001, 0.2, 40.0),
        (0.001, -1.0, 100.0),
        (-0.2, 3.0, 10.0),
        (0.04, -2.0, 100.0),
        (0.2, -50.0, 2.0e4),
    ];
    for (y0, g, stiffness) in cases {
        let s = normal::balancing_move(k, delta, y0, g, stiffness).expect("a root");
        let expected = bisect(k, delta, y0, g, stiffness);
        assert!(
            (s - expected).abs() <= 1e-9 * (1.0 + expected.abs()),
            "y0 {y0}, g {g}, K {stiffness}: {s} against {expected}"
        );
    }
    // A load pulling a node off the tool, nothing else holding it: no bounded move.
    assert_eq!(normal::balancing_move(k, delta, 0.03, -1.0, 0.0), None);
}

fn run(reshape: bool) -> DrawingResult {
    let mut problem = common::off_grid_box();
    problem.solver.reshape_contact = reshape;
    let r = drawing::solve(&problem, &mut |_| {});
    assert!(r.converged, "{:?}", r.failure);
    r
}

#[test]
fn the_node_balance_saves_iterations_and_moves_no_figure_on_a_box() {
    let (plain, reshaped) = (run(false), run(true));
    let (a, b) = (&plain.stats, &reshaped.stats);
    println!(
        "Newton iterations {} -> {}, steps {} -> {}",
        a.newton_iterations, b.newton_iterations, a.steps, b.steps
    );
    assert!(b.newton_iterations < a.newton_iterations);
    assert!(b.steps <= a.steps);
    common::moves_no_figure(&plain, &reshaped);
}
