//! A deep-drawing operation as plain data in, plain data out: the fabric, the tools, the process
//! and the mesh make a [`DrawingProblem`]; [`solve`] meshes the blank (a quarter when the tools
//! and yarns are symmetric about both axes), builds the contact terms, drives the punch to full
//! stroke and returns a [`DrawingResult`] with the fields and figures a user checks.

use std::ops::ControlFlow;
use std::time::Instant;

use super::contact::{Contact, ContactOptions, Holder, ToolMotion};
use super::law::{CellLaw, CellParams};
use super::mesh::Mesh;
use super::solver::{LinearPrescribed, Model, SolveStats, Solver, SolverOptions};
use super::tools::Tool;

/// The punch and die pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tooling {
    /// A square (rectangular) box: punch sides `side` (mm), plan corner radius `r`, nose radius
    /// `rp`; die entry radius `rm`; die opening `side + 2·clearance`.
    Box {
        side: [f64; 2],
        r: f64,
        rp: f64,
        rm: f64,
        clearance: f64,
    },
    /// An ellipsoidal punch of semi-axes `[ax, ay, az]`; the die opening is its plan ellipse
    /// offset by the clearance.
    Ellipsoid {
        axes: [f64; 3],
        rm: f64,
        clearance: f64,
    },
    /// A hemispherical punch of radius `radius`.
    Hemisphere {
        radius: f64,
        rm: f64,
        clearance: f64,
    },
}

impl Tooling {
    /// The punch (tip at z = 0) and the die.
    pub fn tools(&self) -> (Tool, Tool) {
        match *self {
            Tooling::Box {
                side,
                r,
                rp,
                rm,
                clearance,
            } => (
                Tool::box_punch(side, r, rp, 0.0),
                Tool::box_die(side, r, clearance, rm),
            ),
            Tooling::Ellipsoid {
                axes,
                rm,
                clearance,
            } => (
                Tool::EllipsoidPunch { axes, tip: 0.0 },
                Tool::elliptic_die([axes[0], axes[1]], clearance, rm),
            ),
            Tooling::Hemisphere {
                radius,
                rm,
                clearance,
            } => (
                Tool::EllipsoidPunch {
                    axes: [radius; 3],
                    tip: 0.0,
                },
                Tool::elliptic_die([radius, radius], clearance, rm),
            ),
        }
    }

    /// Half extents of the die opening in plan, mm.
    pub fn opening_half(&self) -> [f64; 2] {
        match *self {
            Tooling::Box {
                side, clearance, ..
            } => [0.5 * side[0] + clearance, 0.5 * side[1] + clearance],
            Tooling::Ellipsoid {
                axes, clearance, ..
            } => [axes[0] + clearance, axes[1] + clearance],
            Tooling::Hemisphere {
                radius, clearance, ..
            } => [radius + clearance; 2],
        }
    }
}

/// How much of the blank is meshed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Symmetry {
    /// A quarter whenever the tools and the yarns are symmetric about x = 0 and y = 0.
    Auto,
    Full,
    Quarter,
}

/// Everything a drawing needs.
#[derive(Clone, Debug, PartialEq)]
pub struct DrawingProblem {
    pub fabric: CellParams,
    /// Initial angle between warp and weft, degrees (the warp along x).
    pub yarn_angle_deg: f64,
    pub tooling: Tooling,
    /// Blank side lengths (full blank, centred on the punch), mm.
    pub blank: [f64; 2],
    pub friction: f64,
    /// Blank-holder pressure, MPa.
    pub holder_pressure: f64,
    /// Punch travel from touching the blank, mm.
    pub stroke: f64,
    /// Target element size, mm.
    pub element_size: f64,
    pub symmetry: Symmetry,
    pub solver: SolverOptions,
    /// Contact penalty factor (times the cells' stiffness).
    pub penalty_factor: f64,
    /// Slip that mobilises full friction, as a fraction of the element size.
    pub slip_regularisation: f64,
}

/// The solved part of the blank and what was found on it.
#[derive(Clone, Debug)]
pub struct DrawingResult {
    pub converged: bool,
    /// Why the run stopped short, if it did.
    pub failure: Option<String>,
    /// Whether the mesh is a quarter (x ≥ 0, y ≥ 0) to be mirrored for pictures.
    pub quarter: bool,
    pub mesh: Mesh,
    /// Final nodal positions, mm.
    pub positions: Vec<[f64; 3]>,
    /// Shear angle of each element, degrees (signed).
    pub shear_deg: Vec<f64>,
    /// Mean warp and weft tensions of each element, N per yarn.
    pub t11_n: Vec<f64>,
    pub t22_n: Vec<f64>,
    /// Largest yarn tension of each element, N.
    pub tension_max_n: Vec<f64>,
    /// Contact status of each node: 0 free, 1 punch, 2 die, 3 die and holder.
    pub contact: Vec<u8>,
    /// Punch stroke reached, mm.
    pub stroke_reached_mm: f64,
    /// Punch force on the whole blank, N, and its history against the stroke (mm, N).
    pub punch_force_n: f64,
    pub force_history: Vec<(f64, f64)>,
    /// Largest penetration of a node into a tool, mm.
    pub penetration_mm: f64,
    /// Largest draw-in of the blank's edge (inward plan displacement), mm.
    pub draw_in_mm: f64,
    /// Free dofs of the solved model.
    pub dofs: usize,
    pub stats: SolveStats,
    /// Work of the punch on the blank (the force history integrated over the stroke), N·mm.
    pub punch_work_nmm: f64,
    /// Work done against the stabilisation over the punch's work: how much of what the punch
    /// put in went into the numerical stabiliser rather than the paper's model (yarn energy,
    /// friction, holder).
    pub stabilisation_work_share: f64,
    pub wall_s: f64,
    /// Terms the scene did not need and that were not built.
    pub left_out: Vec<String>,
}

impl DrawingResult {
    /// The element with the largest absolute shear, and that shear (degrees).
    pub fn max_shear(&self) -> (usize, f64) {
        self.shear_deg
            .iter()
            .enumerate()
            .map(|(e, s)| (e, s.abs()))
            .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a })
    }

    /// Centre of element `e` in the final configuration, mm.
    pub fn element_centre(&self, e: usize) -> [f64; 3] {
        let q = self.mesh.quads[e];
        let mut c = [0.0; 3];
        for &n in &q {
            for m in 0..3 {
                c[m] += 0.25 * self.positions[n][m];
            }
        }
        c
    }

    /// Share of the blank's initial area whose shear exceeds `limit_deg`, %.
    pub fn area_over_limit_pct(&self, limit_deg: f64) -> f64 {
        let mut over = 0.0;
        let mut total = 0.0;
        for (e, q) in self.mesh.quads.iter().enumerate() {
            let a = quad_area(&[
                self.mesh.nodes[q[0]],
                self.mesh.nodes[q[1]],
                self.mesh.nodes[q[2]],
                self.mesh.nodes[q[3]],
            ]);
            total += a;
            if self.shear_deg[e].abs() > limit_deg {
                over += a;
            }
        }
        if total > 0.0 {
            100.0 * over / total
        } else {
            0.0
        }
    }

    /// The largest yarn tension anywhere, N.
    pub fn max_tension_n(&self) -> f64 {
        self.tension_max_n.iter().fold(0.0, |a, &b| a.max(b))
    }
}

fn quad_area(x: &[[f64; 3]; 4]) -> f64 {
    let d1 = [x[2][0] - x[0][0], x[2][1] - x[0][1], x[2][2] - x[0][2]];
    let d2 = [x[3][0] - x[1][0], x[3][1] - x[1][1], x[3][2] - x[1][2]];
    let c = [
        d1[1] * d2[2] - d1[2] * d2[1],
        d1[2] * d2[0] - d1[0] * d2[2],
        d1[0] * d2[1] - d1[1] * d2[0],
    ];
    0.5 * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt()
}

impl DrawingProblem {
    /// The paper's square box (Figure 11) with tool radii `r, rp, rm` (mm). Box side, depth,
    /// clearance and blank are not in the paper: chosen here (see `presets/paper-box-*.toml`).
    pub fn paper_box(r: f64, rp: f64, rm: f64) -> DrawingProblem {
        DrawingProblem {
            fabric: CellParams::PAPER_GLASS,
            yarn_angle_deg: 90.0,
            tooling: Tooling::Box {
                side: [60.0, 60.0],
                r,
                rp,
                rm,
                clearance: 1.5,
            },
            blank: [170.0, 170.0],
            friction: 0.2,
            holder_pressure: 1.0,
            stroke: 28.0,
            element_size: 2.5,
            symmetry: Symmetry::Auto,
            solver: SolverOptions::default(),
            penalty_factor: 10.0,
            slip_regularisation: 0.01,
        }
    }

    /// Whether a quarter model represents the whole: tools symmetric about both axes (all are)
    /// and the yarns along the axes.
    pub fn quarter_applies(&self) -> bool {
        match self.symmetry {
            Symmetry::Full => false,
            Symmetry::Quarter => true,
            Symmetry::Auto => (self.yarn_angle_deg - 90.0).abs() < 1e-9,
        }
    }
}

/// Tributary area (mm²) and cell count of each node (a quarter of each element's).
pub fn node_shares(model: &Model) -> (Vec<f64>, Vec<f64>) {
    let n = model.mesh.nodes.len();
    let mut area = vec![0.0; n];
    let mut cells = vec![0.0; n];
    for (q, g) in model.mesh.quads.iter().zip(&model.geometry) {
        for &nd in q {
            area[nd] += 0.25 * g.area0;
            cells[nd] += 0.25 * g.cell_count();
        }
    }
    (area, cells)
}

/// Solves the drawing; `progress` receives the stroke fraction after every accepted step.
pub fn solve(problem: &DrawingProblem, progress: &mut dyn FnMut(f64)) -> DrawingResult {
    solve_until(problem, &mut |fraction| {
        progress(fraction);
        ControlFlow::Continue(())
    })
}

/// [`solve`] that can be stopped: when `progress` returns `ControlFlow::Break`, the run ends
/// after that step, not converged, its failure saying so (the fields are those of that step).
pub fn solve_until(
    problem: &DrawingProblem,
    progress: &mut dyn FnMut(f64) -> ControlFlow<()>,
) -> DrawingResult {
    let start = Instant::now();
    let law = CellLaw::new(problem.fabric);
    let quarter = problem.quarter_applies();
    let [bx, by] = problem.blank;
    let h = problem.element_size;
    let angle = problem.yarn_angle_deg.to_radians();
    let (origin, length) = if quarter {
        ([0.0, 0.0], [0.5 * bx, 0.5 * by])
    } else {
        ([-0.5 * bx, -0.5 * by], [bx, by])
    };
    let n = [
        ((length[0] / h).round() as usize).max(1),
        ((length[1] / h).round() as usize).max(1),
    ];
    let mut mesh = Mesh::yarn_grid(origin, length, n, angle);
    if !quarter && (angle - std::f64::consts::FRAC_PI_2).abs() > 1e-12 {
        // A sheared yarn grid is a parallelogram: centre it on the punch.
        let shift = [0.5 * by * angle.cos(), 0.0];
        for p in &mut mesh.nodes {
            p[0] -= shift[0];
        }
    }
    let mut left_out = Vec::new();
    // Symmetry planes: u_x = 0 on x = 0, u_y = 0 on y = 0.
    let mut prescribed = LinearPrescribed::default();
    if quarter {
        for (i, p) in mesh.nodes.iter().enumerate() {
            if p[0].abs() < 1e-9 {
                prescribed.dofs.push(3 * i);
                prescribed.at_full_load.push(0.0);
            }
            if p[1].abs() < 1e-9 {
                prescribed.dofs.push(3 * i + 1);
                prescribed.at_full_load.push(0.0);
            }
        }
    } else {
        left_out.push("quarter symmetry (yarns not along both axes)".to_string());
    }
    if !problem.fabric.undulation {
        left_out.push("undulation (the linear yarn law is used)".to_string());
    }
    let mut model = match Model::new(mesh.clone(), law, &prescribed.dofs) {
        Ok(m) => m,
        Err(f) => return failed_early(mesh, quarter, f.to_string(), start, left_out),
    };
    let (punch, die) = problem.tooling.tools();
    let tools = vec![
        ToolMotion {
            tool: punch,
            tip_start: 0.0,
            stroke: problem.stroke,
        },
        ToolMotion {
            tool: die,
            tip_start: 0.0,
            stroke: 0.0,
        },
    ];
    let holder = if problem.holder_pressure > 0.0 {
        Some(Holder {
            pressure: problem.holder_pressure,
            die,
            band: h,
        })
    } else {
        left_out.push("blank holder (pressure 0)".to_string());
        None
    };
    if problem.friction == 0.0 {
        left_out.push("friction (μ = 0)".to_string());
    }
    let (area, cells) = node_shares(&model);
    let c_mean = 0.5 * (law.p.c[0] + law.p.c[1]);
    let l_mean = 0.5 * (law.p.l0[0] + law.p.l0[1]);
    let mut contact = Contact::new(
        tools,
        holder,
        ContactOptions {
            friction: problem.friction,
            slip_regularisation: problem.slip_regularisation * h,
            penalty_factor: problem.penalty_factor,
        },
        area,
        &cells,
        c_mean / l_mean,
        2.0 * h,
    );
    let dofs = model.free_dofs();
    let mut solver = Solver::new(&mut model, problem.solver.clone());
    let outcome = solver.solve(&prescribed, &mut contact, progress);
    let stats = solver.stats.clone();
    let lambda = stats.lambda;
    let x = model.positions();
    let sym = if quarter { 4.0 } else { 1.0 };
    let punch_force_n = -sym * contact.tool_force(0, lambda, &x)[2];
    let force_history = contact
        .punch_history
        .iter()
        .map(|(l, f)| (l * problem.stroke, -sym * f))
        .collect();
    let outputs = model.element_outputs();
    let t11_n = outputs
        .iter()
        .map(|o| o.tension.iter().map(|t| t[0]).sum::<f64>() / 4.0)
        .collect();
    let t22_n = outputs
        .iter()
        .map(|o| o.tension.iter().map(|t| t[1]).sum::<f64>() / 4.0)
        .collect();
    let punch_contact = contact.in_contact(0, lambda, &x);
    let die_contact = contact.in_contact(1, lambda, &x);
    let held = contact.holder_force();
    let status = (0..x.len())
        .map(|i| {
            if punch_contact[i] {
                1
            } else if die_contact[i] && held[i] > 0.0 {
                3
            } else if die_contact[i] {
                2
            } else {
                0
            }
        })
        .collect();
    let draw_in_mm = edge_draw_in(&model.mesh, &x, quarter);
    let punch_work_nmm = {
        let mut w = 0.0;
        let mut last = (0.0, 0.0);
        for &(z, f) in &force_history {
            w += 0.5 * (f + last.1) * (z - last.0);
            last = (z, f);
        }
        w
    };
    let stabilisation_work_share = if punch_work_nmm > 0.0 {
        sym * stats.stabilisation_work / punch_work_nmm
    } else {
        0.0
    };
    DrawingResult {
        converged: outcome.is_ok(),
        failure: outcome.err().map(|f| f.to_string()),
        quarter,
        shear_deg: model.shear_angles_deg(),
        t11_n,
        t22_n,
        tension_max_n: model.max_tension_n(),
        contact: status,
        stroke_reached_mm: lambda * problem.stroke,
        punch_force_n,
        force_history,
        penetration_mm: contact.max_penetration(lambda, &x),
        draw_in_mm,
        dofs,
        stats,
        punch_work_nmm,
        stabilisation_work_share,
        wall_s: start.elapsed().as_secs_f64(),
        left_out,
        positions: x,
        mesh: model.mesh.clone(),
    }
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

fn failed_early(
    mesh: Mesh,
    quarter: bool,
    cause: String,
    start: Instant,
    left_out: Vec<String>,
) -> DrawingResult {
    let ne = mesh.quads.len();
    let nn = mesh.nodes.len();
    DrawingResult {
        converged: false,
        failure: Some(cause),
        quarter,
        positions: mesh.nodes.clone(),
        shear_deg: vec![0.0; ne],
        t11_n: vec![0.0; ne],
        t22_n: vec![0.0; ne],
        tension_max_n: vec![0.0; ne],
        contact: vec![0; nn],
        stroke_reached_mm: 0.0,
        punch_force_n: 0.0,
        force_history: Vec::new(),
        penetration_mm: 0.0,
        draw_in_mm: 0.0,
        dofs: 0,
        stats: SolveStats::default(),
        punch_work_nmm: 0.0,
        stabilisation_work_share: 0.0,
        wall_s: start.elapsed().as_secs_f64(),
        left_out,
        mesh,
    }
}
