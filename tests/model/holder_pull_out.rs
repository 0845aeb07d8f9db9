//! Benchmark: the holder pull-out. A flat strip of area S on the die's flange, under the blank
//! holder at pressure p, pulled out sideways slides at `F = 2 μ p S`: Coulomb friction on the
//! die face and on the holder face (`analytic::holder_pull_out_force`).
//!
//! ```text
//!          holder, pressure p
//!   ══════════════════════════
//!      ┌────────────────┐ ──→ pulled 2 mm
//!      └────────────────┘      strip 40 × 10 mm, x from 200 to 240
//!   ──────────────────────────  die face z = 0 (opening far away: half side 100 mm)
//! ```

use crate::analytic;
use crate::contact_common;

use std::ops::ControlFlow;

use contact_common::{contact_for, linear_fabric};
use wovenform::core::contact::{Holder, ToolMotion};
use wovenform::core::membrane::mesh::Mesh;
use wovenform::core::solver::{LinearPrescribed, Model, Solver, SolverOptions};
use wovenform::core::tools::Tool;

#[test]
fn holder_pull_out_force_is_two_mu_p_s() {
    let exact = analytic::holder_pull_out_force(0.2, 1.0, 40.0 * 10.0);
    let pull = pull_out(None);
    println!(
        "pull-out: {pull:.3} N, 2μpS = {exact:.3} N, error {:.3} %",
        100.0 * (pull / exact - 1.0)
    );
    assert!(
        (pull / exact - 1.0).abs() < 0.01,
        "pull-out {pull} N, 2μpS = {exact} N"
    );
}

/// The rigid plate (`Holder::plate_force_n`) pressed with F = p S: the same 2μF, its force
/// carried by the strip whatever the plate's height.
#[test]
fn a_rigid_holder_plate_pulls_out_at_two_mu_f() {
    let force = 1.0 * 40.0 * 10.0;
    let exact = analytic::holder_pull_out_force(0.2, 1.0, 40.0 * 10.0);
    let pull = pull_out(Some(force));
    assert!(
        (pull / exact - 1.0).abs() < 0.01,
        "pull-out {pull} N under a plate of {force} N, 2μF = {exact} N"
    );
    // Twice the force, twice the pull.
    let twice = pull_out(Some(2.0 * force));
    assert!((twice / (2.0 * exact) - 1.0).abs() < 0.01, "{twice}");
}

/// The force that pulls the strip out 2 mm under the holder (a pressure of 1 MPa, or a plate
/// pressed with `plate_force_n` N), μ = 0.2.
fn pull_out(plate_force_n: Option<f64>) -> f64 {
    let (mu, p) = (0.2, 1.0);
    let die = Tool::box_die([200.0, 200.0], 5.0, 0.0, 10.0);
    let h = 2.0;
    let (length, width) = (40.0, 10.0);
    let mesh = Mesh::yarn_grid(
        [200.0, -0.5 * width],
        [length, width],
        [20, 5],
        std::f64::consts::FRAC_PI_2,
    );
    // The x = 240 edge pulled outward by 2 mm.
    let mut prescribed = LinearPrescribed::default();
    for (i, node) in mesh.nodes.iter().enumerate() {
        if (node[0] - 240.0).abs() < 1e-9 {
            prescribed.dofs.push(3 * i);
            prescribed.at_full_load.push(2.0);
        }
    }
    let mut model = Model::new(mesh, linear_fabric(), &prescribed.dofs).unwrap();
    let die_motion = ToolMotion {
        tool: die.clone(),
        tip_start: 0.0,
        stroke: 0.0,
    };
    let holder = Holder {
        pressure: p,
        die,
        band: h,
        plate_force_n,
    };
    let mut contact = contact_for(&model, vec![die_motion], Some(holder), mu, h);
    let mut solver = Solver::new(&mut model, SolverOptions::default());
    solver
        .solve(
            &prescribed,
            &mut contact,
            &mut |_| ControlFlow::Continue(()),
        )
        .unwrap();
    // The pull balances all the friction on the strip, the pulled nodes' own included.
    -contact.tool_force(0, 1.0, &model.positions())[0]
}

/// A quarter of the blank carries a quarter of the plate's force: the open box under a plate
/// of 20 kN gives the same figures solved whole and as a quarter (coarse).
#[test]
fn a_quarter_carries_a_quarter_of_the_plates_force() {
    use wovenform::core::drawing::{DrawingProblem, Symmetry, solve};
    let mut p = DrawingProblem::paper_box(10.0, 15.0, 10.0);
    p.element_size_mm = 5.0;
    p.holder_pressure_mpa = 0.0;
    p.holder_force_n = Some(20_000.0);
    let quarter = solve(&p, &mut |_| {});
    p.symmetry = Symmetry::Full;
    let whole = solve(&p, &mut |_| {});
    assert!(quarter.converged && whole.converged);
    assert!(quarter.quarter && !whole.quarter);
    let rel = (quarter.punch_force_n / whole.punch_force_n - 1.0).abs();
    assert!(
        rel < 0.005,
        "{} N against {} N",
        quarter.punch_force_n,
        whole.punch_force_n
    );
    assert!((quarter.draw_in_mm - whole.draw_in_mm).abs() < 0.05);
}
