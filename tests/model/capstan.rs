#![allow(clippy::needless_range_loop)]
//! Benchmark: the capstan. A strip wrapped over the die's entry radius (θ = π/2) with a dead
//! load `T_in` on its flange end and its wall end pulled down carries, sliding with Coulomb
//! friction μ, `T_out / T_in = exp(μ θ)` (Euler–Eytelwein; `analytic::capstan_ratio`). On the
//! same strip, Newton with friction's non-symmetric coupling in its Jacobian converges
//! quadratically.
//!
//! ```text
//!        T_in ←──────────╮  die face z = 0
//!                        │  entry radius rm
//!                        ↓  T_out (pulled)
//! ```

use crate::analytic;
use crate::common::accepted_residuals;
use crate::contact_common;

use std::f64::consts::FRAC_PI_2;
use std::ops::ControlFlow;

use contact_common::{contact_for, linear_fabric};
use wovenform::core::contact::{Contact, ToolMotion};
use wovenform::core::membrane::mesh::Mesh;
use wovenform::core::solver::{
    LinearPrescribed, Model, NodalSums, NodalTerms, NodeBlock, SolveStats, Solver, SolverOptions,
};
use wovenform::core::tools::Tool;

/// Die entry radius (mm), element length along the strip (mm) and the strip's width (mm).
const RM: f64 = 10.0;
const H: f64 = 0.5;
const WIDTH: f64 = 2.0;

/// Contact plus dead loads on some nodes (force per node, N), ramped in over the first quarter
/// of the load path.
struct WithDeadLoad {
    contact: Contact,
    loads: Vec<(usize, [f64; 3])>,
}

fn ramp(lambda: f64) -> f64 {
    (lambda / 0.25).min(1.0)
}

impl NodalTerms for WithDeadLoad {
    fn begin_step(&mut self, lambda_start: f64, lambda: f64, x: &[[f64; 3]]) {
        self.contact.begin_step(lambda_start, lambda, x);
    }
    fn project(&self, lambda: f64, x: &mut [[f64; 3]], keep_slide: bool) {
        self.contact.project(lambda, x, keep_slide);
    }
    fn relag(&mut self, lambda: f64, x: &[[f64; 3]]) -> bool {
        self.contact.relag(lambda, x)
    }
    fn project_trial(&self, lambda: f64, x_base: &[[f64; 3]], x: &mut [[f64; 3]]) {
        self.contact.project_trial(lambda, x_base, x);
    }
    fn freeze(&mut self, lambda: f64, x: &[[f64; 3]]) {
        self.contact.freeze(lambda, x);
    }
    fn add(
        &self,
        lambda: f64,
        x: &[[f64; 3]],
        r: &mut [f64],
        blocks: Option<&mut [NodeBlock]>,
    ) -> Option<NodalSums> {
        let mut sums = self.contact.add(lambda, x, r, blocks)?;
        for (n, f) in &self.loads {
            for m in 0..3 {
                r[3 * n + m] -= ramp(lambda) * f[m];
            }
            sums.scale = sums
                .scale
                .max((f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt());
            let work = ramp(lambda) * (f[0] * x[*n][0] + f[1] * x[*n][1] + f[2] * x[*n][2]);
            sums.energy -= work;
            sums.energy_frozen -= work;
        }
        Some(sums)
    }
    fn end_step(&mut self, lambda: f64, x: &[[f64; 3]]) {
        self.contact.end_step(lambda, x);
    }
}

/// A strip one element wide (width `w`, along y) following the polyline `path` in the x–z plane.
fn strip(path: &[[f64; 2]], w: f64) -> Mesh {
    let mut nodes = Vec::new();
    for p in path {
        nodes.push([p[0], -0.5 * w, p[1]]);
        nodes.push([p[0], 0.5 * w, p[1]]);
    }
    let quads = (0..path.len() - 1)
        .map(|i| [2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1])
        .collect();
    Mesh {
        nodes,
        quads,
        yarns: None,
        grid: None,
    }
}

/// The strip's centre line in the x–z plane: 20 mm of flange on the die face (x from 130 down
/// to 110), the quarter circle of the entry radius about (110, −10), 20 mm of wall at x = 100.
fn wrapped_path() -> Vec<[f64; 2]> {
    let mut path = Vec::new();
    let nf = (20.0 / H) as usize;
    for i in 0..nf {
        path.push([130.0 - i as f64 * H, 0.0]);
    }
    // From the top (90°) to the wall (180°), elements of about H along the arc.
    let na = (analytic::arc_length(RM, FRAC_PI_2) / H).round() as usize;
    for i in 0..na {
        let phi = FRAC_PI_2 * (1.0 + i as f64 / na as f64);
        path.push([110.0 + RM * phi.cos(), -10.0 + RM * phi.sin()]);
    }
    let nw = (20.0 / H) as usize;
    for i in 0..=nw {
        path.push([100.0, -10.0 - i as f64 * H]);
    }
    path
}

/// The wall end (its last two nodes) pulled down by 3 mm; every node kept at its y (the strip
/// is one element wide).
fn pull_down_the_wall_end(n: usize) -> LinearPrescribed {
    let mut prescribed = LinearPrescribed::default();
    for i in 0..n {
        prescribed.dofs.push(3 * i + 1);
        prescribed.at_full_load.push(0.0);
    }
    for i in [n - 2, n - 1] {
        prescribed.dofs.push(3 * i);
        prescribed.at_full_load.push(0.0);
        prescribed.dofs.push(3 * i + 2);
        prescribed.at_full_load.push(-3.0);
    }
    prescribed
}

/// What the capstan strip gave: `T_out/T_in`, the run's counters and residual histories.
struct Capstan {
    ratio: f64,
    stats: SolveStats,
    penetration: f64,
}

/// The capstan strip (see the module's sketch) solved with or without friction's non-symmetric
/// coupling in the Jacobian, to a tight tolerance, its residuals recorded.
fn capstan(mu: f64, t_in: f64, exact_jacobian: bool) -> Capstan {
    // Die: opening half side 100 (straight edge along y near y = 0), entry radius RM.
    let die = Tool::box_die([200.0, 200.0], 5.0, 0.0, RM);
    let mesh = strip(&wrapped_path(), WIDTH);
    let n = mesh.nodes.len();
    let prescribed = pull_down_the_wall_end(n);
    let mut model = Model::new(mesh, linear_fabric(), &prescribed.dofs).unwrap();
    let die_motion = ToolMotion {
        tool: die,
        tip_start: 0.0,
        stroke: 0.0,
    };
    let contact = contact_for(&model, vec![die_motion], None, mu, H);
    // The flange end held back by T_in (half on each of its two nodes).
    let mut terms = WithDeadLoad {
        contact,
        loads: vec![(0, [0.5 * t_in, 0.0, 0.0]), (1, [0.5 * t_in, 0.0, 0.0])],
    };
    // (A tolerance near the round-off: a floor of a yarn strain of 1e-9 rather than 1e-7, so
    // that each step's tail of iterations is long enough to show its rate.)
    let options = SolverOptions {
        record_residuals: true,
        tol_force: 1e-12,
        tol_floor: 1e-9,
        tol_work: 0.0,
        exact_jacobian,
        ..SolverOptions::default()
    };
    let mut solver = Solver::new(&mut model, options);
    solver
        .solve(&prescribed, &mut terms, &mut |_| ControlFlow::Continue(()))
        .unwrap();
    let stats = solver.stats.clone();
    // The pull is what holds the wall end: the reaction at the pulled nodes plus the force the die
    // puts directly on them.
    let f = model.internal_force();
    let x = model.positions();
    let mut r_direct = vec![0.0; 3 * n];
    terms.contact.add(1.0, &x, &mut r_direct, None);
    let t_out = -(f[3 * (n - 2) + 2]
        + f[3 * (n - 1) + 2]
        + r_direct[3 * (n - 2) + 2]
        + r_direct[3 * (n - 1) + 2]);
    Capstan {
        ratio: t_out / t_in,
        penetration: terms.contact.max_penetration(1.0, &x),
        stats,
    }
}

/// The worst `r(k+1)/r(k)²` over a run's iterations after its first step (residuals relative to
/// `scale`; pairs from 1e-1 down, those near the round-off floor of the model's much larger
/// internal forces, 1e-8 of the scale, left out).
fn worst_quadratic_ratio<'a>(
    residuals: impl Iterator<Item = &'a Vec<f64>>,
    scale: f64,
) -> (usize, f64) {
    let mut ratios = Vec::new();
    for h in residuals.skip(1) {
        for k in 0..h.len().saturating_sub(1) {
            let (a, b) = (h[k] / scale, h[k + 1] / scale);
            if a < 1e-1 && b > 1e-8 {
                ratios.push(b / (a * a));
            }
        }
    }
    (ratios.len(), ratios.iter().cloned().fold(0.0, f64::max))
}

#[test]
fn capstan_over_the_die_entry_radius() {
    let (mu, t_in) = (0.2, 100.0);
    let c = capstan(mu, t_in, true);
    let exact = analytic::capstan_ratio(mu, FRAC_PI_2);
    println!(
        "capstan: T_out/T_in = {:.4} (exact {exact:.4}, error {:.2} %), {} steps, {} Newton iterations, penetration {:.4} mm",
        c.ratio,
        100.0 * (c.ratio / exact - 1.0),
        c.stats.steps,
        c.stats.newton_iterations,
        c.penetration
    );
    assert!(
        (c.ratio / exact - 1.0).abs() < 0.02,
        "T_out/T_in = {}, exact {exact}",
        c.ratio
    );
}

#[test]
fn newton_with_the_friction_coupling_converges_quadratically() {
    // Over the radius the friction follows the normal force the tension makes there, and the
    // tension follows the friction. With that coupling in the Jacobian (GMRES over its
    // non-symmetric part) Newton squares the residual once the strip slides; with the symmetric
    // part only, the same strip converges linearly.
    let t_in = 100.0;
    let exact = capstan(0.2, t_in, true);
    let symmetric = capstan(0.2, t_in, false);
    let (n, worst) = worst_quadratic_ratio(accepted_residuals(&exact.stats), t_in);
    let (_, worst_symmetric) = worst_quadratic_ratio(accepted_residuals(&symmetric.stats), t_in);
    println!(
        "capstan: exact Jacobian {n} pairs, worst r(k+1)/r(k)² = {worst:.2} ({} iterations); symmetric part only: worst {worst_symmetric:.2e} ({} iterations)",
        exact.stats.newton_iterations, symmetric.stats.newton_iterations
    );
    // (The bound leaves room for the contact law's double root where the flange nodes' contact
    // force goes to zero; the symmetric part alone goes far past it.)
    assert!(n >= 4 && worst < 1e3, "{:?}", exact.stats.residuals);
    assert!(worst_symmetric > 1e4, "{:?}", symmetric.stats.residuals);
    // Both reach the same answer (their steps differ, hence the path: within 0.1 %).
    println!("T_out/T_in {:.5} and {:.5}", exact.ratio, symmetric.ratio);
    assert!((exact.ratio / symmetric.ratio - 1.0).abs() < 1e-3);
}
