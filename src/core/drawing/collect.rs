//! The fields and figures of a drawing's final state, gathered into a [`DrawingResult`].

use super::{DrawingFailure, DrawingProblem, DrawingResult, LeftOut};
use crate::core::contact::Contact;
use crate::core::membrane::mesh::Mesh;
use crate::core::solver::{Model, SolveStats};
use crate::core::wrinkles::amplitude::{Explained, wrinkles_resolved};

/// The fields and figures of the model's final state.
pub(super) fn collect(
    problem: &DrawingProblem,
    model: &Model,
    contact: &Contact,
    quarter: bool,
    stats: SolveStats,
    left_out: Vec<LeftOut>,
) -> DrawingResult {
    let lambda = stats.lambda;
    let x = model.positions();
    let sym = if quarter { 4.0 } else { 1.0 };
    // + 0.0: no force at all is 0 N, not -0 N.
    let punch_force_n = -sym * contact.tool_force(0, lambda, &x)[2] + 0.0;
    let force_history: Vec<(f64, f64)> = contact
        .punch_history
        .iter()
        .map(|(l, f)| (l * problem.stroke_mm, -sym * f))
        .collect();
    let outputs = model.element_outputs();
    let mean = |a: usize| -> Vec<f64> {
        outputs
            .iter()
            .map(|o| o.tension.iter().map(|t| t[a]).sum::<f64>() / 4.0)
            .collect()
    };
    let punch_work_nmm = punch_work(&force_history);
    let status = contact_status(contact, lambda, &x);
    let (t11_n, t22_n) = (mean(0), mean(1));
    let wrinkle_mm = problem.bending.and_then(|_| {
        let anchored: Vec<bool> = status.iter().map(|&c| c != 0).collect();
        let sag_mm = facet_sag_mm(contact, lambda, &x, &status, problem.element_size_mm);
        let taut = taut_nodes(&model.mesh, &model.least_membrane_force_n_per_mm());
        let explained = Explained {
            sag_mm: &sag_mm,
            taut: &taut,
        };
        wrinkles_resolved(&model.mesh, &x, &anchored, explained).map(|w| w.per_node_mm)
    });
    let unbalanced_work_share = if punch_work_nmm > 0.0 {
        sym * stats.unbalanced_work / punch_work_nmm
    } else {
        0.0
    };
    DrawingResult {
        converged: true,
        failure: None,
        quarter,
        element_size_mm: problem.element_size_mm,
        cell_mm: problem.fabric.cell_mm(),
        shear_deg: model.shear_angles_deg(),
        t11_n,
        t22_n,
        tension_max_n: model.max_tension_n(),
        contact: status,
        wrinkle_mm,
        stroke_reached_mm: lambda * problem.stroke_mm,
        punch_force_n,
        force_history,
        penetration_mm: contact.max_penetration(lambda, &x),
        draw_in_mm: edge_draw_in(&model.mesh, &x, quarter),
        dofs: model.free_dofs(),
        stats,
        punch_work_nmm,
        unbalanced_work_share,
        left_out,
        positions: x,
        mesh: model.mesh.clone(),
    }
}

/// Each node taut: every element around it has a positive least membrane force.
fn taut_nodes(mesh: &Mesh, least_n_per_mm: &[f64]) -> Vec<bool> {
    let mut taut = vec![true; mesh.nodes.len()];
    for (q, &least) in mesh.quads.iter().zip(least_n_per_mm) {
        if least <= 0.0 {
            for &n in q {
                taut[n] = false;
            }
        }
    }
    taut
}

/// Each anchored node's facet sag on its tool, mm: `h²κ/8` for elements `h` long on the
/// tool's largest principal curvature `κ` there (the punch for status 1, the die for 2 and 3;
/// 0 for a free node).
fn facet_sag_mm(contact: &Contact, lambda: f64, x: &[[f64; 3]], status: &[u8], h: f64) -> Vec<f64> {
    let tools = [contact.tools[0].at(lambda), contact.tools[1].at(lambda)];
    let scale = contact.options.contact_smoothing.max(1e-3);
    (0..x.len())
        .map(|i| match status[i] {
            1 => h * h * tools[0].largest_curvature(x[i], scale) / 8.0,
            2 | 3 => h * h * tools[1].largest_curvature(x[i], scale) / 8.0,
            _ => 0.0,
        })
        .collect()
}

/// Each node's contact: 0 free, 1 punch, 2 die, 3 die and holder.
fn contact_status(contact: &Contact, lambda: f64, x: &[[f64; 3]]) -> Vec<u8> {
    let punch = contact.in_contact(0, lambda, x);
    let die = contact.in_contact(1, lambda, x);
    let held = contact.holder_force(x);
    (0..x.len())
        .map(|i| match (punch[i], die[i], held[i] > 0.0) {
            (true, _, _) => 1,
            (false, true, true) => 3,
            (false, true, false) => 2,
            _ => 0,
        })
        .collect()
}

/// The punch's work over its force history (stroke in mm, force in N), by the trapezoid rule,
/// N·mm.
fn punch_work(history: &[(f64, f64)]) -> f64 {
    let mut w = 0.0;
    let mut last = (0.0, 0.0);
    for &(z, f) in history {
        w += 0.5 * (f + last.1) * (z - last.0);
        last = (z, f);
    }
    w
}

/// The largest inward plan displacement of a node on the blank's outer edge, mm.
fn edge_draw_in(mesh: &Mesh, x: &[[f64; 3]], quarter: bool) -> f64 {
    let (mut xmax, mut ymax, mut xmin, mut ymin) = (f64::MIN, f64::MIN, f64::MAX, f64::MAX);
    for p in &mesh.nodes {
        xmax = xmax.max(p[0]);
        ymax = ymax.max(p[1]);
        xmin = xmin.min(p[0]);
        ymin = ymin.min(p[1]);
    }
    let tol = 1e-9 * (xmax - xmin).abs().max(1.0);
    let mut best = 0.0f64;
    for (p0, p) in mesh.nodes.iter().zip(x) {
        let on_xmax = (p0[0] - xmax).abs() < tol;
        let on_ymax = (p0[1] - ymax).abs() < tol;
        let on_xmin = !quarter && (p0[0] - xmin).abs() < tol;
        let on_ymin = !quarter && (p0[1] - ymin).abs() < tol;
        if on_xmax {
            best = best.max(p0[0] - p[0]);
        }
        if on_ymax {
            best = best.max(p0[1] - p[1]);
        }
        if on_xmin {
            best = best.max(p[0] - p0[0]);
        }
        if on_ymin {
            best = best.max(p[1] - p0[1]);
        }
    }
    best
}

pub(super) fn failed_early(
    problem: &DrawingProblem,
    mesh: Mesh,
    quarter: bool,
    failure: DrawingFailure,
    left_out: Vec<LeftOut>,
) -> DrawingResult {
    let dofs = 3 * mesh.nodes.len() - super::symmetry_planes(&mesh, quarter).dofs.len();
    DrawingResult {
        failure: Some(failure),
        dofs,
        left_out,
        ..DrawingResult::at_rest(
            mesh,
            quarter,
            problem.element_size_mm,
            problem.fabric.cell_mm(),
        )
    }
}
