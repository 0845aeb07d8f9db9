#![allow(clippy::needless_range_loop)]
//! The Newton solver on states whose answers come from the law alone.
//!
//! ```text
//!   irregular 4×4 patch (interior nodes jittered)      boundary nodes: x = F X (prescribed)
//!   o---o---o---o---o                                   interior nodes: free
//!   |  /   |    \   |
//!   o---o----o--o---o
//!   ...
//! ```

use crate::analytic;
use crate::common;
use common::Lcg;
use std::ops::ControlFlow;
use wovenform::core::fabric::law::{CellLaw, CellParams};
use wovenform::core::membrane::element::GAUSS;
use wovenform::core::membrane::mesh::Mesh;
use wovenform::core::solver::{
    LinearPrescribed, Model, NoNodalTerms, Prescribed, Solver, SolverOptions,
};

fn boundary_nodes(mesh: &Mesh) -> Vec<usize> {
    let [n1, n2] = mesh.grid.unwrap();
    (0..mesh.nodes.len())
        .filter(|&i| {
            let (a, b) = (i % (n1 + 1), i / (n1 + 1));
            a == 0 || b == 0 || a == n1 || b == n2
        })
        .collect()
}

fn irregular_patch(n: usize, jitter: f64, seed: u64) -> Mesh {
    let mut mesh = Mesh::yarn_grid(
        [0.0, 0.0],
        [20.0, 20.0],
        [n, n],
        std::f64::consts::FRAC_PI_2,
    );
    let boundary = boundary_nodes(&mesh);
    let mut g = Lcg(seed);
    for i in 0..mesh.nodes.len() {
        if !boundary.contains(&i) {
            mesh.nodes[i][0] += g.range(-jitter, jitter);
            mesh.nodes[i][1] += g.range(-jitter, jitter);
        }
    }
    mesh
}

fn affine_prescribed(mesh: &Mesh, nodes: &[usize], f: [[f64; 3]; 3]) -> LinearPrescribed {
    let mut p = LinearPrescribed::default();
    for &nd in nodes {
        let x = mesh.nodes[nd];
        for m in 0..3 {
            let target = f[m][0] * x[0] + f[m][1] * x[1] + f[m][2] * x[2];
            p.dofs.push(3 * nd + m);
            p.at_full_load.push(target - x[m]);
        }
    }
    p
}

#[test]
fn patch_test_on_an_irregular_mesh_gives_the_law_in_every_element() {
    let law = CellLaw::new(CellParams::PAPER_GLASS);
    let mesh = irregular_patch(4, 1.5, 1);
    let boundary = boundary_nodes(&mesh);
    let (e1, e2) = (0.006, 0.003);
    let f = [[1.0 + e1, 0.0, 0.0], [0.0, 1.0 + e2, 0.0], [0.0, 0.0, 1.0]];
    let prescribed = affine_prescribed(&mesh, &boundary, f);
    let mut model = Model::new(mesh, law, &prescribed.dofs).unwrap();
    let mut solver = Solver::new(&mut model, SolverOptions::default());
    solver
        .solve(&prescribed, &mut NoNodalTerms, &mut |_| {
            ControlFlow::Continue(())
        })
        .unwrap();
    let stats = solver.stats.clone();
    let expected = law.evaluate([e1, e2], law.initial_state()).t;
    for out in model.element_outputs() {
        for gp in 0..GAUSS {
            for a in 0..2 {
                let t = out.tension[gp][a];
                assert!(
                    (t - expected[a]).abs() <= 1e-6 * expected[a],
                    "T{a} = {t}, law {}",
                    expected[a]
                );
            }
        }
    }
    // Every interior node sits where the homogeneous stretch puts it.
    let x = model.positions();
    for (i, x0) in model.mesh.nodes.iter().enumerate() {
        let target = [x0[0] * (1.0 + e1), x0[1] * (1.0 + e2), 0.0];
        for m in 0..3 {
            assert!((x[i][m] - target[m]).abs() < 1e-7, "node {i}");
        }
    }
    println!(
        "patch test: {} steps, {} Newton iterations, work out of balance {:.2e} N·mm",
        stats.steps, stats.newton_iterations, stats.unbalanced_work
    );
    assert!(stats.newton_iterations < 80);
}

#[test]
fn pure_trellising_costs_nothing_and_is_recognised_as_a_mechanism() {
    let law = CellLaw::new(CellParams::PAPER_GLASS);
    let mesh = Mesh::yarn_grid(
        [0.0, 0.0],
        [20.0, 20.0],
        [4, 4],
        std::f64::consts::FRAC_PI_2,
    );
    // Trellis: the warp stays along x, the weft turns by γ; no yarn changes length.
    let gamma_deg = 40.0;
    let f = analytic::pure_trellis(f64::to_radians(gamma_deg));
    // 1. Imposed on every node: zero internal force everywhere, i.e. zero reaction.
    let all: Vec<usize> = (0..mesh.nodes.len()).collect();
    let p_all = affine_prescribed(&mesh, &all, f);
    let mut model = Model::new(mesh.clone(), law, &p_all.dofs).unwrap();
    for (d, v) in p_all.dofs.iter().zip(&p_all.at_full_load) {
        model.u[*d] = *v;
    }
    model.evaluate_elements(false, false);
    let reaction = model.internal_force();
    assert!(
        reaction.iter().all(|r| r.abs() < 1e-9),
        "max reaction {:?}",
        reaction.iter().fold(0.0f64, |a, b| a.max(b.abs()))
    );
    let shear = model.shear_angles_deg();
    assert!(
        shear.iter().all(|s| (s - gamma_deg).abs() < 1e-9),
        "{shear:?}"
    );
    // 2. Imposed on the boundary only, without stabilisation: the interior has no stiffness and
    // the solver must say the state is a mechanism instead of returning it silently. It does so
    // by converging on a shifted tangent and flagging the mechanism; the state it returns has
    // no yarn in tension (any tension would be out of balance in the trellis).
    let boundary = boundary_nodes(&mesh);
    let p_b = affine_prescribed(&mesh, &boundary, f);
    let mut model = Model::new(mesh, law, &p_b.dofs).unwrap();
    let mut solver = Solver::new(
        &mut model,
        SolverOptions {
            stabilisation: 0.0,
            ..Default::default()
        },
    );
    let outcome = solver.solve(&p_b, &mut NoNodalTerms, &mut |_| ControlFlow::Continue(()));
    let stats = solver.stats.clone();
    assert!(outcome.is_ok(), "{outcome:?}");
    assert!(
        stats.mechanism,
        "converged without flagging the mechanism: {stats:?}"
    );
    assert!(stats.shifted_solves > 0);
    assert!(model.u.iter().all(|v| v.is_finite()));
    let tension = model.max_tension_n().into_iter().fold(0.0f64, f64::max);
    println!(
        "trellis on the boundary: {} shifted solves, largest tension {tension:.2e} N",
        stats.shifted_solves
    );
    // (The solver's tolerance floor is a yarn strain of 1e-7: C · 1e-7 = 3.8 mN.)
    let floor = 1e-7 * CellParams::PAPER_GLASS.c[0];
    assert!(tension < floor, "a yarn in tension: {tension} N");
}

/// Boundary nodes follow `x = c + R(λθ) S(λ) X`: a biaxial stretch and a large rotation.
struct StretchRotate {
    dofs: Vec<usize>,
    x0: Vec<[f64; 3]>,
    stretch: [f64; 2],
    angle: f64,
}

impl Prescribed for StretchRotate {
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }
    fn values(&self, lambda: f64, out: &mut [f64]) {
        let th = lambda * self.angle;
        let (s, c) = th.sin_cos();
        for (i, &d) in self.dofs.iter().enumerate() {
            let x = self.x0[i];
            let sx = x[0] * (1.0 + lambda * self.stretch[0]);
            let sy = x[1] * (1.0 + lambda * self.stretch[1]);
            // Rotation about the y axis by θ, then the target minus the initial position.
            let target = [c * sx, sy, -s * sx];
            out[i] = target[d % 3] - x[d % 3];
        }
    }
}

#[test]
fn newton_converges_quadratically_on_a_stretched_and_rotated_sheet() {
    let law = CellLaw::new(CellParams::PAPER_GLASS);
    let mesh = irregular_patch(6, 1.0, 3);
    let boundary = boundary_nodes(&mesh);
    let dofs: Vec<usize> = boundary
        .iter()
        .flat_map(|&n| [3 * n, 3 * n + 1, 3 * n + 2])
        .collect();
    let x0 = dofs.iter().map(|d| mesh.nodes[d / 3]).collect();
    let path = StretchRotate {
        dofs: dofs.clone(),
        x0,
        stretch: [0.008, 0.004],
        angle: 1.2,
    };
    let mut model = Model::new(mesh, law, &dofs).unwrap();
    let mut solver = Solver::new(
        &mut model,
        SolverOptions {
            record_residuals: true,
            // Converged far below the law's precision: the tolerance, not the drawings' floor
            // of a 1e-7 yarn strain (which would end a step at a residual of 4e-3 N, a
            // tension 2e-5 off).
            tol_force: 1e-11,
            tol_floor: 1e-13,
            tol_work: 0.0,
            ..Default::default()
        },
    );
    solver
        .solve(&path, &mut NoNodalTerms, &mut |_| ControlFlow::Continue(()))
        .unwrap();
    let stats = solver.stats.clone();
    // Quadratic convergence: once the residual is small, r(k+1)/r(k)² stays bounded. Residuals
    // are made dimensionless by the internal force scale of the solution; pairs within 100× of
    // the round-off floor (~1e-13 of that scale) are left out.
    let f_scale = model
        .internal_force()
        .iter()
        .map(|v| v * v)
        .sum::<f64>()
        .sqrt();
    let mut ratios = Vec::new();
    for h in common::accepted_residuals(&stats) {
        for k in 0..h.len().saturating_sub(1) {
            let (a, b) = (h[k] / f_scale, h[k + 1] / f_scale);
            if a < 1e-4 && b > 1e-11 {
                ratios.push(b / (a * a));
            }
        }
    }
    assert!(!ratios.is_empty(), "{:?}", stats.residuals);
    let worst = ratios.iter().cloned().fold(0.0, f64::max);
    println!(
        "rotation test: {} steps ({} cut back), {} Newton iterations, worst r(k+1)/r(k)^2 = {worst:.3}, residuals of the last step {:?}",
        stats.steps,
        stats.cutbacks,
        stats.newton_iterations,
        stats.residuals.last()
    );
    assert!(worst < 1e3, "not quadratic: {ratios:?}");
    // Objectivity at the structure level: the rotated, stretched sheet carries the law's tensions.
    let expected = law.evaluate([0.008, 0.004], law.initial_state()).t;
    for out in model.element_outputs() {
        for t in out.tension {
            assert!(
                (t[0] - expected[0]).abs() < 1e-5 * expected[0],
                "{t:?} vs {expected:?}"
            );
            assert!((t[1] - expected[1]).abs() < 1e-5 * expected[1]);
        }
    }
}
