#![allow(clippy::needless_range_loop)]
//! The contact terms (normal penalty, friction, blank holder) against finite differences: their
//! forces are the gradient of the merit the line search uses (at the point where it is
//! frozen), and their node blocks (`spd + rest`) are the derivative of the forces, in stick and
//! in slip, on flat and curved faces of the punch and the die, and in the holder's band.
//!
//! ```text
//!        punch (hemisphere R 30, moving down)
//!          ╭───╮   a: pole, pressed        b: flank, pressed and sliding
//!   ───────╯   ╰───────  die face z = 0     c: flange under the holder, sliding
//!         ╲     ╱        entry radius rm    d: on the entry radius, sliding
//!                                           e: in the holder's band   f: hovering in the gap
//! ```

use crate::analytic;

use wovenform::core::contact::{Contact, ContactOptions, Holder, ToolMotion};
use wovenform::core::solver::{NodalTerms, NodeBlock};
use wovenform::core::tools::Tool;

const K: f64 = 2.0e4; // penalty, N/mm

struct Case {
    name: &'static str,
    /// Position at the step's start and now (mm).
    start: [f64; 3],
    now: [f64; 3],
}

fn setup(cases: &[Case], mu: f64) -> (Contact, Vec<[f64; 3]>, f64) {
    let radius = 30.0;
    let punch = Tool::EllipsoidPunch {
        axes: [radius; 3],
        tip: 0.0,
    };
    let die = Tool::elliptic_die([radius, radius], 1.5, 5.0);
    let tools = vec![
        ToolMotion {
            tool: punch,
            tip_start: 0.0,
            stroke: 10.0,
        },
        ToolMotion {
            tool: die.clone(),
            tip_start: 0.0,
            stroke: 0.0,
        },
    ];
    let holder = Holder {
        pressure: 1.0,
        die,
        band: 2.5,
        plate_force_n: None,
    };
    let mut contact = contact_with(tools, Some(holder), mu, cases.len());
    let start: Vec<[f64; 3]> = cases.iter().map(|c| c.start).collect();
    let lambda = 0.3;
    contact.begin_step(0.25, lambda, &start);
    let now: Vec<[f64; 3]> = cases.iter().map(|c| c.now).collect();
    (contact, now, lambda)
}

/// Contact terms for `n` nodes of 6.25 mm² and stiffness `K` (N/mm) with the tools and holder.
fn contact_with(tools: Vec<ToolMotion>, holder: Option<Holder>, mu: f64, n: usize) -> Contact {
    Contact::new(
        tools,
        holder,
        ContactOptions {
            friction: mu,
            slip_regularisation: 0.025,
            penalty_factor: 1.0,
            contact_smoothing: 0.025,
            lagged: false,
        },
        vec![6.25; n],
        &vec![K; n],
        1.0,
        5.0,
    )
}

/// Node `i`'s block against central differences of the residual: the worst error relative to
/// the block's largest entry, the block and the differences.
fn block_error(
    contact: &Contact,
    lambda: f64,
    x: &[[f64; 3]],
    i: usize,
) -> (f64, [[f64; 3]; 3], [[f64; 3]; 3]) {
    let mut r = vec![0.0; 3 * x.len()];
    let mut blocks = vec![NodeBlock::default(); x.len()];
    contact.add(lambda, x, &mut r, Some(&mut blocks)).unwrap();
    let j = blocks[i].total();
    let scale = j.iter().flatten().fold(1.0f64, |m, v| m.max(v.abs()));
    let h = 1e-6;
    let mut worst = 0.0f64;
    let mut fd = [[0.0; 3]; 3];
    for b in 0..3 {
        let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
        xp[i][b] += h;
        xm[i][b] -= h;
        let (rp, rm) = (
            residual(contact, lambda, &xp),
            residual(contact, lambda, &xm),
        );
        for a in 0..3 {
            fd[a][b] = (rp[3 * i + a] - rm[3 * i + a]) / (2.0 * h);
            worst = worst.max((fd[a][b] - j[a][b]).abs() / scale);
        }
    }
    (worst, j, fd)
}

fn residual(contact: &Contact, lambda: f64, x: &[[f64; 3]]) -> Vec<f64> {
    let mut r = vec![0.0; 3 * x.len()];
    contact.add(lambda, x, &mut r, None).expect("admissible");
    r
}

/// Cases on the punch (tip at −3 mm at λ = 0.3, −2.5 mm at the step's start) and the die.
fn cases() -> Vec<Case> {
    let tip = -3.0;
    // A point on the hemisphere at plan radius ρ, sunk by `sink` along the normal.
    let on_punch = |rho: f64, phi: f64, sink: f64| {
        let r = 30.0f64;
        let z0 = tip + r;
        let (x, y) = (rho * phi.cos(), rho * phi.sin());
        let z = z0 - (r * r - rho * rho).sqrt();
        let n = [x / r, y / r, (z - z0) / r];
        [x - sink * n[0], y - sink * n[1], z - sink * n[2]]
    };
    // A point on the die's entry radius (opening 31.5, rm 5) at angle θ from the face.
    let on_radius = |theta: f64, sink: f64| {
        let (cx, cz) = (31.5 + 5.0, -5.0);
        let (nx, nz) = (-theta.sin(), theta.cos());
        [cx + (5.0 - sink) * nx, 0.0, cz + (5.0 - sink) * nz]
    };
    let a_now = on_punch(0.5, 0.3, 0.004);
    let b_now = on_punch(12.0, 0.7, 0.003);
    let d_now = on_radius(0.6, 0.002);
    vec![
        Case {
            name: "a pole, pressed, nearly stuck",
            start: [a_now[0] - 0.01, a_now[1] + 0.005, a_now[2] + 0.5],
            now: a_now,
        },
        Case {
            name: "b flank, pressed, sliding",
            start: [b_now[0] + 0.6, b_now[1] + 0.2, b_now[2] + 0.3],
            now: b_now,
        },
        Case {
            name: "c flange under the holder, sliding",
            start: [50.0, 12.0, -0.0003],
            now: [49.3, 11.8, -0.0004],
        },
        Case {
            name: "d entry radius, sliding",
            start: [d_now[0] + 0.5, 0.1, d_now[2] + 0.2],
            now: d_now,
        },
        Case {
            name: "e holder band, sliding",
            start: [38.2, 1.0, -0.0002],
            now: [37.8, 0.9, -0.0003],
        },
        Case {
            name: "f hovering in the smoothing gap",
            start: [60.0, 5.0, 0.02],
            now: [59.7, 5.1, 0.012],
        },
    ]
}

#[test]
fn node_blocks_are_the_derivative_of_the_forces() {
    for mu in [0.0, 0.2] {
        let cases = cases();
        let (contact, x, lambda) = setup(&cases, mu);
        for (i, case) in cases.iter().enumerate() {
            let (worst, j, fd) = block_error(&contact, lambda, &x, i);
            println!("μ {mu}, {}: worst relative error {worst:.2e}", case.name);
            assert!(
                worst < 1e-5,
                "μ {mu}, {}: blocks {j:?}\nfinite differences {fd:?}",
                case.name
            );
        }
    }
}

#[test]
fn blocks_hold_in_the_corner_blend_of_a_box_punch() {
    // A punch whose corner radius (5 mm) is below its nose radius (15 mm): the corner is a
    // blend whose field is not a true distance (|∇d| ≠ 1). Friction projects with the unit
    // normal there; its derivative must still be the forces'.
    let punch = Tool::box_punch([60.0, 60.0], 5.0, 15.0, 0.0);
    let tools = vec![ToolMotion {
        tool: punch.clone(),
        tip_start: 0.0,
        stroke: 10.0,
    }];
    // Points on the corner's blend, pressed 3 µm in (placed by Newton along the gradient).
    let on_blend = |x: f64, y: f64, z: f64| {
        let tool = punch.at_tip(-3.0);
        let mut p = [x, y, z];
        for _ in 0..20 {
            let d = tool.distance(p);
            let g2: f64 = d.n.iter().map(|v| v * v).sum();
            for m in 0..3 {
                p[m] -= (d.d + 0.003) * d.n[m] / g2;
            }
        }
        let d = tool.distance(p);
        (p, d.n.iter().map(|v| v * v).sum::<f64>().sqrt())
    };
    let (p1, g1) = on_blend(27.0, 26.0, 3.0);
    let (p2, g2) = on_blend(28.5, 22.0, 1.0);
    println!("gradient lengths in the blend: {g1:.3}, {g2:.3}");
    assert!(
        (g1 - 1.0).abs() > 0.01 || (g2 - 1.0).abs() > 0.01,
        "not in the blend"
    );
    let mut contact = contact_with(tools, None, 0.2, 2);
    let start = [
        [p1[0] + 0.4, p1[1] - 0.2, p1[2] + 0.6],
        [p2[0] - 0.3, p2[1] + 0.5, p2[2] + 0.5],
    ];
    contact.begin_step(0.25, 0.3, &start);
    let x = vec![p1, p2];
    for i in 0..x.len() {
        let (worst, _, _) = block_error(&contact, 0.3, &x, i);
        println!("blend node {i}: worst relative error {worst:.2e}");
        assert!(worst < 1e-5, "node {i}: {worst}");
    }
}

/// The merit the line search uses along a correction from `x` (frozen there).
fn frozen_merit(contact: &Contact, lambda: f64, x: &[[f64; 3]]) -> f64 {
    let mut r = vec![0.0; 3 * x.len()];
    contact.add(lambda, x, &mut r, None).unwrap().energy_frozen
}

#[test]
fn forces_are_the_gradient_of_the_merit_where_it_is_frozen() {
    for mu in [0.0, 0.2] {
        let cases = cases();
        let (mut contact, x, lambda) = setup(&cases, mu);
        contact.freeze(lambda, &x);
        let r = residual(&contact, lambda, &x);
        // At the point where it is frozen (friction's normal force and the holder's weights
        // taken there) the merit is the terms' own energy.
        let mut rr = vec![0.0; 3 * x.len()];
        let sums = contact.add(lambda, &x, &mut rr, None).unwrap();
        assert!((sums.energy - sums.energy_frozen).abs() <= 1e-12 * sums.energy.abs().max(1.0));
        for (i, case) in cases.iter().enumerate() {
            let h = 1e-6;
            let mut worst = 0.0f64;
            let scale = (0..3).fold(1e-3f64, |m, a| m.max(r[3 * i + a].abs()));
            for b in 0..3 {
                let mut xp = x.clone();
                let mut xm = x.clone();
                xp[i][b] += h;
                xm[i][b] -= h;
                let g = (frozen_merit(&contact, lambda, &xp) - frozen_merit(&contact, lambda, &xm))
                    / (2.0 * h);
                worst = worst.max((g - r[3 * i + b]).abs() / scale);
            }
            println!(
                "μ {mu}, {}: gradient against force, worst {worst:.2e}",
                case.name
            );
            assert!(worst < 1e-5, "μ {mu}, {}: {worst}", case.name);
        }
    }
}

#[test]
fn friction_is_mu_n_times_the_regularised_slip_direction() {
    // Coulomb's law regularised: |friction| = μ N |s| / sqrt(|s|² + ε²), with s the slip in the
    // tool's tangent plane since the anchor (the step's start, moving with the punch: 0.5 mm
    // down from λ = 0.25 to 0.3). Case b slides 0.6 mm (full μN to 5e-4); case a has slipped
    // about 0.011 mm, under ε = 0.025 mm (stick, a fraction of μN).
    let cases = cases();
    let mu = 0.2;
    let eps = 0.025;
    let (contact, x, lambda) = setup(&cases, mu);
    let (without, _, _) = setup(&cases, 0.0);
    let r = residual(&contact, lambda, &x);
    let r0 = residual(&without, lambda, &x);
    let punch = Tool::EllipsoidPunch {
        axes: [30.0; 3],
        tip: -3.0,
    };
    for i in [0usize, 1] {
        let n = punch.distance(x[i]).n;
        let anchor = [
            cases[i].start[0],
            cases[i].start[1],
            cases[i].start[2] - 0.5,
        ];
        let rel: Vec<f64> = (0..3).map(|m| x[i][m] - anchor[m]).collect();
        let rn: f64 = (0..3).map(|m| rel[m] * n[m]).sum();
        let slip = (0..3)
            .map(|m| (rel[m] - rn * n[m]).powi(2))
            .sum::<f64>()
            .sqrt();
        let expected = analytic::regularised_friction_share(slip, eps);
        let friction: f64 = (0..3)
            .map(|m| (r[3 * i + m] - r0[3 * i + m]).powi(2))
            .sum::<f64>()
            .sqrt();
        let normal: f64 = (0..3).map(|m| r0[3 * i + m].powi(2)).sum::<f64>().sqrt();
        let share = friction / (mu * normal);
        println!(
            "{}: slip {slip:.4} mm, |friction| / μN = {share:.6} (closed form {expected:.6})",
            cases[i].name
        );
        assert!(
            (share / expected - 1.0).abs() < 1e-9,
            "{share} vs {expected}"
        );
    }
}

#[test]
fn a_free_blank_needs_almost_no_punch_force_until_the_yarns_go_taut() {
    // No holder, no friction: the punch only carries the blank down into the die. The drawing
    // refuses this problem (no unique shape); the solver itself must still find one of its
    // zero-force equilibria without crawling.
    use std::ops::ControlFlow;
    use wovenform::core::drawing::{self, DrawingProblem};
    use wovenform::core::solver::{Solver, SolverOptions};
    let mut p = DrawingProblem::paper_box(10.0, 15.0, 10.0);
    p.fabric.undulation = false;
    p.element_size_mm = 5.0;
    p.stroke_mm = 6.0;
    p.friction = 0.0;
    p.holder_pressure_mpa = 0.0;
    let mut free = p.build().expect("the model builds");
    let mut solver = Solver::new(&mut free.model, SolverOptions::default());
    let outcome = solver.solve(&free.prescribed, &mut free.contact, &mut |_| {
        ControlFlow::Continue(())
    });
    assert!(outcome.is_ok(), "{outcome:?}");
    let x = free.model.positions();
    let force = -4.0 * free.contact.tool_force(0, 1.0, &x)[2];
    let tension = free
        .model
        .max_tension_n()
        .into_iter()
        .fold(0.0f64, f64::max);
    // The same stroke with the paper's holder and friction, for scale.
    let mut held = p.clone();
    held.friction = 0.2;
    held.holder_pressure_mpa = 1.0;
    let held = drawing::solve(&held, &mut |_| {});
    let held_force = held.force_history.iter().map(|f| f.1).fold(0.0, f64::max);
    println!(
        "free blank: max tension {tension:.3} N, punch force {force:.3} N (held blank: {held_force:.1} N)"
    );
    assert!(tension < 1.0);
    assert!(force.abs() < 1e-2 * held_force);
}

/// The holder plate couples the nodes it presses (its height follows each of them): the node
/// blocks' z diagonal plus the plate's coupling (`NodalTerms::coupling`, applied beside the
/// blocks by the Krylov solve) is the whole derivative of the held nodes' z forces, off the
/// diagonal too (central differences, the plate's height solved again at each).
#[test]
fn the_plates_coupling_completes_the_held_nodes_tangent() {
    let die = Tool::elliptic_die([30.0, 30.0], 1.5, 5.0);
    let tools = vec![ToolMotion {
        tool: die.clone(),
        tip_start: 0.0,
        stroke: 0.0,
    }];
    let holder = Holder {
        pressure: 1.0,
        die,
        band: 2.5,
        plate_force_n: Some(300.0),
    };
    // Four flange nodes at slightly different heights (their contact stiffnesses differ).
    let x: Vec<[f64; 3]> = (0..4)
        .map(|i| [45.0 + 3.0 * i as f64, 2.0 * i as f64, 0.004 * i as f64])
        .collect();
    let mut contact = contact_with(tools, Some(holder), 0.0, x.len());
    contact.begin_step(0.0, 1.0, &x);
    let mut r = vec![0.0; 3 * x.len()];
    let mut blocks = vec![NodeBlock::default(); x.len()];
    contact.add(1.0, &x, &mut r, Some(&mut blocks)).unwrap();
    let coupling = contact.coupling(&x).expect("a plate couples its nodes");
    assert_eq!(coupling.nodes.len(), 4);
    let u = |i: usize| coupling.nodes.iter().find(|n| n.0 == i).unwrap().1;
    let h = 1e-7;
    let mut worst = 0.0f64;
    let scale = (0..4).map(u).fold(0.0, f64::max);
    for j in 0..4 {
        let (mut xp, mut xm) = (x.clone(), x.clone());
        xp[j][2] += h;
        xm[j][2] -= h;
        let (rp, rm) = (residual(&contact, 1.0, &xp), residual(&contact, 1.0, &xm));
        for i in 0..4 {
            let fd = (rp[3 * i + 2] - rm[3 * i + 2]) / (2.0 * h);
            let own = if i == j { blocks[i].total()[2][2] } else { 0.0 };
            let coupled = if i == j { u(i) * u(i) } else { 0.0 } - u(i) * u(j);
            let exact = own + coupled / coupling.total;
            worst = worst.max((fd - exact).abs() / scale);
        }
    }
    println!("plate coupling: worst relative error {worst:.2e}");
    assert!(worst < 1e-5, "worst relative error {worst:.2e}");
}
