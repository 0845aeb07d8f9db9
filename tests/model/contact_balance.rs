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
//!
//! - A node on a symmetry plane (one dof held) in a tool's gap whose normal lies in the plane:
//!   balanced as the same node free in every direction, to the bisection's root; a node whose
//!   normal has a share along its held dof is left as the correction put it.
//!
//! And the predictor's projection that keeps the distance a node slid on a tool at rest
//! (`SolverOptions::keep_slide`): on the die's entry radius, a node slid along its tangent and
//! put back along the normal falls short by the circle's closed form; kept, it slides the whole
//! distance at its gap. The same box with it and without: fewer iterations, no figure moved.

use wovenform::core::contact::{Contact, ContactOptions, ToolMotion, normal};
use wovenform::core::drawing::{self, DrawingResult};
use wovenform::core::solver::{NodalTerms, OwnStiffness};
use wovenform::core::tools::Tool;

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

/// The penalty (N/mm) and eased gap (mm) of [`reshaped_on_the_radius`].
const PENALTY: f64 = 2.0e4;
const GAP: f64 = 0.025;

/// One node's contact with a die at rest whose entry radius is 5 mm (30 × 30 mm opening,
/// 1.5 mm clearance), frictionless, penalty [`PENALTY`] and eased gap [`GAP`].
fn die_radius() -> Contact {
    let die = ToolMotion {
        tool: Tool::elliptic_die([30.0, 30.0], 1.5, 5.0),
        tip_start: 0.0,
        stroke: 0.0,
    };
    let options = ContactOptions {
        friction: 0.0,
        slip_regularisation: 0.025,
        penalty_factor: 1.0,
        contact_smoothing: GAP,
        lagged: false,
    };
    Contact::new(vec![die], None, options, vec![6.25], &[PENALTY], 1.0, 5.0)
}

/// One node `depth` mm into the eased gap of a die's entry radius (rm 5 mm, the die at rest),
/// in the plane y = 0, where the radius's outward normal `n` lies in that plane. A correction
/// moved it `s_lin` mm along `n`; it is reshaped with the own stiffness `k_rest + φ'' n nᵀ`
/// (the tangent's block: the rest and the penalty's share) on its `free` dofs. Returns its
/// move along `n` after the reshape (`None`: left alone) and `n`.
fn reshaped_on_the_radius(
    depth: f64,
    s_lin: f64,
    k_rest: [[f64; 3]; 3],
    free: [bool; 3],
) -> (Option<f64>, [f64; 3]) {
    let mut contact = die_radius();
    let (centre, phi) = ([36.5, 0.0, -5.0], 0.4f64);
    let n = [-phi.sin(), 0.0, phi.cos()];
    let r = 5.0 + GAP - depth;
    let at = [centre[0] + r * n[0], 0.0, centre[2] + r * n[2]];
    contact.begin_step(0.25, 0.3, &[at]);
    let slope = normal::law(PENALTY, GAP, GAP - depth).1;
    let mut k = k_rest;
    for a in 0..3 {
        for b in 0..3 {
            k[a][b] += slope * n[a] * n[b];
            if !free[a] || !free[b] {
                k[a][b] = 0.0;
            }
        }
    }
    let mut du = [n.map(|v| v * s_lin)];
    let own = |_: usize| Some(OwnStiffness { k, free });
    let moved = contact.reshape(0.3, &[at], &mut du, &own);
    let along = (0..3).map(|m| du[0][m] * n[m]).sum::<f64>();
    (moved.then_some(along), n)
}

#[test]
fn a_node_on_a_symmetry_plane_is_balanced_as_a_free_one() {
    // The rest of its own stiffness, N/mm: y's row and column are the free node's only.
    let k_rest = [[200.0, 15.0, 40.0], [15.0, 90.0, -7.0], [40.0, -7.0, 300.0]];
    for (depth, s_lin) in [(0.02, -0.03), (0.005, 0.01), (0.012, -0.004)] {
        let (free, n) = reshaped_on_the_radius(depth, s_lin, k_rest, [true; 3]);
        let (held, _) = reshaped_on_the_radius(depth, s_lin, k_rest, [true, false, true]);
        let free = free.expect("a free node in the gap is balanced");
        let held = held.expect("a held node whose normal lies in its free plane is balanced");
        assert!((free - held).abs() < 1e-12, "{free} against {held}");
        // Its own balance along n, `p(y0 − s) = g + K s`: K the rest's stiffness along n, g
        // the load the linear correction left on it.
        let other: f64 = (0..3)
            .map(|a| n[a] * (0..3).map(|b| k_rest[a][b] * n[b]).sum::<f64>())
            .sum();
        let (p0, slope, _) = normal::law(PENALTY, GAP, GAP - depth);
        let g = p0 - (slope + other) * s_lin;
        let expected = bisect(PENALTY, GAP, depth, g, other);
        assert!(
            (held - expected).abs() < 1e-9,
            "depth {depth}, s_lin {s_lin}: {held} against {expected}"
        );
        assert!((held - s_lin).abs() > 1e-4, "the balance moved it: {held}");
    }
    // Held along x, where the radius's normal has a share (−sin 0.4): left as it was.
    let (left, _) = reshaped_on_the_radius(0.005, 0.01, k_rest, [false, true, true]);
    assert_eq!(left, None);
}

fn run(reshape: bool, keep_slide: bool) -> DrawingResult {
    let mut problem = common::off_grid_box();
    problem.solver.reshape_contact = reshape;
    problem.solver.keep_slide = keep_slide;
    let r = drawing::solve(&problem, &mut |_| {});
    assert!(r.converged, "{:?}", r.failure);
    r
}

/// The box run without a change (`plain`) and with it (`changed`): fewer Newton iterations in
/// no more load steps, and no figure moved by a tenth of the standard band.
fn saves_iterations_and_moves_no_figure(plain: &DrawingResult, changed: &DrawingResult) {
    let (a, b) = (&plain.stats, &changed.stats);
    println!(
        "Newton iterations {} -> {}, steps {} -> {}",
        a.newton_iterations, b.newton_iterations, a.steps, b.steps
    );
    assert!(b.newton_iterations < a.newton_iterations);
    assert!(b.steps <= a.steps);
    common::moves_no_figure(plain, changed);
}

#[test]
fn the_node_balance_saves_iterations_and_moves_no_figure_on_a_box() {
    saves_iterations_and_moves_no_figure(&run(false, true), &run(true, true));
}

/// A node on the die's entry radius (rm 5 mm, the die at rest), `sink` inside it, slid `slide`
/// mm along the radius's tangent towards the cavity and put back: its start and where it ends.
fn slid_on_the_radius(slide: f64, sink: f64, keep_slide: bool) -> ([f64; 3], [f64; 3]) {
    let mut contact = die_radius();
    let (centre, theta) = ([36.5, 0.0, -5.0], 0.4f64);
    let r = 5.0 - sink;
    let start = [
        centre[0] - r * theta.sin(),
        0.0,
        centre[2] + r * theta.cos(),
    ];
    contact.begin_step(0.25, 0.3, &[start]);
    let mut x = [[
        start[0] - slide * theta.cos(),
        0.0,
        start[2] - slide * theta.sin(),
    ]];
    contact.project(0.3, &mut x, keep_slide);
    (start, x[0])
}

fn length(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|m| (a[m] - b[m]).powi(2)).sum::<f64>().sqrt()
}

#[test]
fn the_predictor_keeps_the_distance_a_node_slid_over_the_die_radius() {
    let (slide, sink) = (1.2, 0.004);
    let r = 5.0 - sink;
    let centre = [36.5, 0.0, -5.0];
    // Put back along the normal: the chord of the angle atan(L/r) on the circle of radius r.
    let (start, plain) = slid_on_the_radius(slide, sink, false);
    let expected = 2.0 * r * ((slide / r).atan() / 2.0).sin();
    let got = length(plain, start);
    assert!((got - expected).abs() < 1e-9, "{got} against {expected}");
    assert!(
        slide - got > 0.01,
        "the shortfall the projection makes: {}",
        slide - got
    );
    // Kept: the whole distance, on the circle at the same gap.
    let (_, kept) = slid_on_the_radius(slide, sink, true);
    let shortfall = slide - length(kept, start);
    assert!(
        shortfall.abs() < 1e-2 * (slide - got),
        "still short by {shortfall}"
    );
    assert!((length(kept, centre) - r).abs() < 1e-9, "off its gap");
}

#[test]
fn keeping_the_slide_saves_iterations_and_moves_no_figure_on_a_box() {
    saves_iterations_and_moves_no_figure(&run(true, false), &run(true, true));
}
