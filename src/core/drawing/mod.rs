//! A deep-drawing operation as plain data in, plain data out: the fabric, the tools, the process
//! and the mesh make a [`DrawingProblem`]; [`solve`] meshes the blank (a quarter when the tools
//! and yarns are symmetric about both axes), builds the contact terms, drives the punch to full
//! stroke and returns a [`DrawingResult`] with the fields and figures a user checks.

mod collect;
mod failure;
mod outline;
mod peak;
mod result;
mod size;

pub use crate::core::tools::tooling::Tooling;
pub use failure::{DrawingFailure, Unrestrained};
pub use result::{DrawingResult, PENETRATION_LIMIT, UNBALANCED_WORK_LIMIT, Unsound};
pub use size::SizeEstimate;

use std::ops::ControlFlow;

use super::contact::{Contact, ContactOptions, Holder, ToolMotion};
use super::solver::{LinearPrescribed, Model, SolveStats, Solver, SolverOptions};
use crate::core::fabric::law::{CellLaw, CellParams};
use crate::core::membrane::mesh::Mesh;
use crate::core::wrinkles::trigger::Trigger;

/// The toe of the drawings' yarn law ([`crate::core::fabric::toe`]): the slack/taut kink rounded over a
/// yarn strain of 10⁻³, the narrowest that let fine meshes of the paper's grid converge in
/// about as many load steps as standard ones (3·10⁻⁴ took up to 1.7× more steps; the kink itself
/// up to 25×, or failed), and that moved no figure of the presets by a tenth of its band.
pub const TOE_STRAIN: f64 = 1e-3;

/// The drawings' work test ([`SolverOptions::tol_work`]): a step may end once the residual's
/// work over it is 10⁻³ of the stored energy it added (and the residual within 10⁻⁴ of the
/// forces). On the 81 designs of the paper's grid it saves 12 % of the Newton iterations at
/// standard and 15 % at fine and moves no figure by a tenth of its band (`guide::solver`,
/// "The end of a step").
pub const TOL_WORK: f64 = 1e-3;

/// The drawings' decrement test ([`SolverOptions::tol_decrement`]): a step may end with a
/// correction that releases at most 10⁻³ of the stored energy the step added (the residual
/// within 10⁻³ of the forces, and the state it reaches leaving at most 1 % of that energy as
/// the residual's work). On the 81 designs of the paper's grid it saves 7 % of the Newton
/// iterations at standard and 10 % at fine and moves no figure by a tenth of its band
/// (`guide::solver`, "The end of a step").
pub const TOL_DECREMENT: f64 = 1e-3;

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
    /// The fabric's in-plane shear law (beyond the paper); `None`: the paper's fabric.
    pub shear: Option<crate::core::fabric::shear::ShearLaw>,
    /// Initial angle between warp and weft, degrees (the warp along x).
    pub yarn_angle_deg: f64,
    pub tooling: Tooling,
    /// Blank side lengths (full blank, centred on the punch), mm.
    pub blank_mm: [f64; 2],
    pub friction: f64,
    /// Blank-holder pressure, MPa.
    pub holder_pressure_mpa: f64,
    /// A rigid holder plate pressed with this total force, N, instead of the pressure
    /// ([`crate::core::contact::Holder::plate_force_n`]); `None`: the pressure on each node, or
    /// with bending a plate pressed with the pressure times the flange's initial area.
    pub holder_force_n: Option<f64>,
    /// Punch travel from touching the blank, mm.
    pub stroke_mm: f64,
    /// Target element size, mm.
    pub element_size_mm: f64,
    pub symmetry: Symmetry,
    pub solver: SolverOptions,
    /// Contact penalty factor (times the cells' stiffness).
    pub penalty_factor: f64,
    /// Slip that mobilises full friction, as a fraction of the element size.
    pub slip_regularisation: f64,
    /// Gap over which the contact force fades in, as a fraction of the element size.
    pub contact_smoothing: f64,
    /// The yarn strain over which the law's slack/taut kink is rounded ([`crate::core::fabric::toe`];
    /// 0: the paper's kink).
    pub toe_strain: f64,
    /// Lag friction's normal force and direction (measured against; see `ContactOptions`).
    pub lagged_friction: bool,
    /// The fabric's bending (beyond the paper): hinges along the yarn lines
    /// ([`crate::core::fabric::bending`]); `None`: the paper's membrane.
    pub bending: Option<Bending>,
}

/// Bending stiffness and the yarns' compressive stiffness that goes with it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bending {
    /// Bending rigidity per unit width `[B1, B2]`, N·mm.
    pub rigidity: [f64; 2],
    /// The yarns' stiffness in compression, as fractions of `C`.
    pub compression: [f64; 2],
    /// What makes the blank leave its plane where it may ([`crate::core::wrinkles::trigger`]).
    pub trigger: Trigger,
}

/// The yarns' compressive stiffness, as a fraction of `C`, when a scene gives bending rigidity
/// and no compressive stiffness: a yarn a hundred times softer in compression than in tension.
pub const DEFAULT_COMPRESSION: f64 = 1e-2;

impl DrawingProblem {
    /// The paper's square box (Figure 11) with tool radii `r, rp, rm` (mm). Box side, depth,
    /// clearance and blank are not in the paper: chosen here (see `presets/paper-box-*.toml`).
    pub fn paper_box(r: f64, rp: f64, rm: f64) -> DrawingProblem {
        DrawingProblem {
            fabric: CellParams::PAPER_GLASS,
            shear: None,
            yarn_angle_deg: 90.0,
            tooling: Tooling::Box {
                side: [60.0, 60.0],
                r,
                rp,
                rm,
                clearance: 1.5,
            },
            blank_mm: [170.0, 170.0],
            friction: 0.2,
            holder_pressure_mpa: 1.0,
            holder_force_n: None,
            stroke_mm: 28.0,
            element_size_mm: 2.5,
            symmetry: Symmetry::Auto,
            solver: SolverOptions {
                tol_work: TOL_WORK,
                tol_decrement: TOL_DECREMENT,
                ..SolverOptions::default()
            },
            penalty_factor: 10.0,
            slip_regularisation: 0.01,
            contact_smoothing: 0.01,
            toe_strain: TOE_STRAIN,
            lagged_friction: false,
            bending: None,
        }
    }

    /// Whether a quarter model represents the whole: tools symmetric about both axes (all are)
    /// and the yarns along the axes.
    pub fn quarter_applies(&self) -> bool {
        match self.symmetry {
            Symmetry::Full => false,
            Symmetry::Quarter => true,
            // A mesh tool's symmetry is not known: the whole blank unless asked. Bending lets
            // the blank wrinkle, and wrinkles are not symmetric: the whole blank too.
            Symmetry::Auto => {
                (self.yarn_angle_deg - 90.0).abs() < 1e-9
                    && !matches!(self.tooling, Tooling::Mesh { .. })
                    && self.bending.is_none()
            }
        }
    }

    /// What is missing for the paper's model to have a unique answer, if anything: the fabric
    /// has no shear and no bending stiffness, so it takes tension only when the flange is held
    /// back, by the holder's pressure through friction.
    pub fn unrestrained(&self) -> Option<Unrestrained> {
        // A shear law does not change this: a law as soft as a measured fabric's does not hold
        // the flange (tried with the glass fabric's fitted law: 1000 steps used up at a fifth
        // of the stroke, `guide::shear_law`).
        if self.friction == 0.0 {
            Some(Unrestrained::NoFriction)
        } else if self.holder_pressure_mpa == 0.0 && self.holder_force_n.is_none() {
            Some(Unrestrained::NoHolder)
        } else {
            None
        }
    }

    /// Element counts along the warp and weft of the solved part.
    pub fn grid(&self) -> [usize; 2] {
        let length = self.solved_lengths(self.quarter_applies());
        [0, 1].map(|a| ((length[a] / self.element_size_mm).round() as usize).max(1))
    }

    fn solved_lengths(&self, quarter: bool) -> [f64; 2] {
        let [bx, by] = self.blank_mm;
        if quarter {
            [0.5 * bx, 0.5 * by]
        } else {
            [bx, by]
        }
    }

    /// The mesh of the solved part: a grid over the whole rectangular blank (or its quarter
    /// x, y ≥ 0) with the warp along x. When the yarns are not at 90° the elements stay
    /// rectangular and the weft runs across them at the yarn angle (the element projects the
    /// yarn directions on itself), so the blank keeps its shape at any yarn angle.
    fn blank_mesh(&self, quarter: bool) -> Mesh {
        let [bx, by] = self.blank_mm;
        let angle = self.yarn_angle_deg.to_radians();
        let origin = if quarter {
            [0.0, 0.0]
        } else {
            [-0.5 * bx, -0.5 * by]
        };
        let right = std::f64::consts::FRAC_PI_2;
        if (angle - right).abs() <= 1e-12 {
            return Mesh::yarn_grid(origin, self.solved_lengths(quarter), self.grid(), angle);
        }
        let mut mesh = Mesh::yarn_grid(origin, self.solved_lengths(quarter), self.grid(), right);
        mesh.yarns = Some([[1.0, 0.0, 0.0], [angle.cos(), angle.sin(), 0.0]]);
        mesh
    }

    /// The contact terms: the punch moving down by the stroke, the die, the holder.
    fn contact(&self, model: &Model) -> Contact {
        let h = self.element_size_mm;
        let (punch, die) = self.tooling.tools();
        let tools = vec![
            ToolMotion {
                tool: punch,
                tip_start: 0.0,
                stroke: self.stroke_mm,
            },
            ToolMotion {
                tool: die.clone(),
                tip_start: 0.0,
                stroke: 0.0,
            },
        ];
        let (area, cells) = node_shares(model);
        let holder = (self.holder_pressure_mpa > 0.0 || self.holder_force_n.is_some()).then(|| {
            let mut holder = Holder {
                pressure: self.holder_pressure_mpa,
                die,
                band: h,
                // A quarter carries a quarter of the plate's force.
                plate_force_n: self
                    .holder_force_n
                    .map(|f| if self.quarter_applies() { 0.25 * f } else { f }),
            };
            if self.bending.is_some() && holder.plate_force_n.is_none() {
                // With bending a wrinkle can lift the holder: the holder is the rigid plate,
                // pressed with the pressure times the flange it holds at the start.
                holder.plate_force_n = Some(holder.pressure * held_area(&holder, model, &area));
            }
            holder
        });
        let trigger = self
            .bending
            .map(|b| b.trigger.forces(&model.mesh.nodes, &area))
            .unwrap_or_default();
        let mut contact = Contact::new(
            tools,
            holder,
            ContactOptions {
                friction: self.friction,
                slip_regularisation: self.slip_regularisation * h,
                penalty_factor: self.penalty_factor,
                contact_smoothing: self.contact_smoothing * h,
                lagged: self.lagged_friction,
            },
            area,
            &cells,
            model.law.stiffness_per_cell(),
            2.0 * h,
        );
        contact.trigger = trigger;
        contact
    }
}

/// The area the holder's pressure acts on in the flat blank, mm² (the nodes' areas times the
/// holder's weight at their places).
fn held_area(holder: &Holder, model: &Model, area: &[f64]) -> f64 {
    (model.mesh.nodes.iter().zip(area))
        .map(|(p, a)| a * holder.weight(p[0], p[1]).0)
        .sum()
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

/// The symmetry planes of a quarter: `u_x = 0` on x = 0, `u_y = 0` on y = 0.
fn symmetry_planes(mesh: &Mesh, quarter: bool) -> LinearPrescribed {
    let mut prescribed = LinearPrescribed::default();
    if quarter {
        for (i, p) in mesh.nodes.iter().enumerate() {
            for m in 0..2 {
                if p[m].abs() < 1e-9 {
                    prescribed.dofs.push(3 * i + m);
                    prescribed.at_full_load.push(0.0);
                }
            }
        }
    }
    prescribed
}

/// Solves the drawing; `progress` receives the stroke fraction after every accepted step.
pub fn solve(problem: &DrawingProblem, progress: &mut dyn FnMut(f64)) -> DrawingResult {
    solve_until(problem, &mut |fraction| {
        progress(fraction);
        ControlFlow::Continue(())
    })
}

/// A term of the model a drawing does without.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LeftOut {
    /// The whole blank is solved: the yarns are not along both axes.
    QuarterSymmetry,
    /// The whole blank is solved: the tools are meshes, whose symmetry is not known.
    QuarterSymmetryUnknown,
    /// The whole blank is solved: the fabric bends, and wrinkles are not symmetric.
    QuarterSymmetryWrinkles,
    /// The linear yarn law `T = C max(ε, 0)` stands for the woven one.
    Undulation,
    /// No blank holder (pressure 0).
    Holder,
    /// No friction (μ = 0).
    Friction,
}

impl std::fmt::Display for LeftOut {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            LeftOut::QuarterSymmetry => "quarter symmetry (yarns not along both axes)",
            LeftOut::QuarterSymmetryUnknown => {
                "quarter symmetry (mesh tools: the whole blank unless mesh.symmetry = \"quarter\")"
            }
            LeftOut::QuarterSymmetryWrinkles => {
                "quarter symmetry (the fabric bends: wrinkles are not symmetric)"
            }
            LeftOut::Undulation => "undulation (the linear yarn law is used)",
            LeftOut::Holder => "blank holder (pressure 0)",
            LeftOut::Friction => "friction (μ = 0)",
        })
    }
}

/// A drawing ready to solve: its model at the start, the contact terms, the symmetry planes.
pub struct Prepared {
    pub model: Model,
    pub contact: Contact,
    pub prescribed: LinearPrescribed,
    pub quarter: bool,
    /// Terms the scene did not need and that were not built.
    pub left_out: Vec<LeftOut>,
}

impl Prepared {
    /// The fields and figures of the drawing's current state (as converged), after `stats`.
    pub fn result(&self, problem: &DrawingProblem, stats: SolveStats) -> DrawingResult {
        collect::collect(
            problem,
            &self.model,
            &self.contact,
            self.quarter,
            stats,
            self.left_out.clone(),
        )
    }
}

impl DrawingProblem {
    /// Meshes the blank and builds the model and the contact terms, or says why the problem
    /// has no answer.
    pub fn prepare(&self) -> Result<Prepared, DrawingFailure> {
        if let Some(why) = self.unrestrained() {
            let bends = self.bending.is_some();
            return Err(DrawingFailure::NoUniqueShape { why, bends });
        }
        self.build()
    }

    /// [`DrawingProblem::prepare`] without asking whether the problem has a unique answer: for
    /// checks of the solver on degenerate problems (a blank held by nothing).
    pub fn build(&self) -> Result<Prepared, DrawingFailure> {
        let quarter = self.quarter_applies();
        let mesh = self.blank_mesh(quarter);
        let left_out = self.left_out();
        let prescribed = symmetry_planes(&mesh, quarter);
        let mut law = CellLaw::new(self.fabric)
            .with_shear(self.shear)
            .with_toe(self.toe_strain);
        let mut hinges = Vec::new();
        if let Some(b) = self.bending {
            law = law.with_compression(b.compression);
            use crate::core::membrane::hinges::{grid_line_hinges, yarn_hinges};
            hinges = yarn_hinges(&mesh, b.rigidity)
                .or_else(|| grid_line_hinges(&mesh, b.rigidity))
                .ok_or(DrawingFailure::BendingOffYarnLines)?;
        }
        let model = Model::with_hinges(mesh, law, &prescribed.dofs, hinges)
            .map_err(DrawingFailure::BadElement)?;
        let contact = self.contact(&model);
        Ok(Prepared {
            model,
            contact,
            prescribed,
            quarter,
            left_out,
        })
    }

    /// Terms the problem does not need and that are not built.
    fn left_out(&self) -> Vec<LeftOut> {
        let mut left_out = Vec::new();
        if !self.quarter_applies() {
            left_out.push(if matches!(self.tooling, Tooling::Mesh { .. }) {
                LeftOut::QuarterSymmetryUnknown
            } else if self.bending.is_some() && (self.yarn_angle_deg - 90.0).abs() < 1e-9 {
                LeftOut::QuarterSymmetryWrinkles
            } else {
                LeftOut::QuarterSymmetry
            });
        }
        if !self.fabric.undulation {
            left_out.push(LeftOut::Undulation);
        }
        if self.holder_pressure_mpa == 0.0 && self.holder_force_n.is_none() {
            left_out.push(LeftOut::Holder);
        }
        if self.friction == 0.0 {
            left_out.push(LeftOut::Friction);
        }
        left_out
    }
}

/// [`solve`] that can be stopped: when `progress` returns `ControlFlow::Break`, the run ends
/// after that step, not converged, its failure saying so (the fields are those of that step).
pub fn solve_until(
    problem: &DrawingProblem,
    progress: &mut dyn FnMut(f64) -> ControlFlow<()>,
) -> DrawingResult {
    let mut p = match problem.prepare() {
        Ok(p) => p,
        Err(failure) => {
            let quarter = problem.quarter_applies();
            let mesh = problem.blank_mesh(quarter);
            return collect::failed_early(problem, mesh, quarter, failure, problem.left_out());
        }
    };
    let mut solver = Solver::new(&mut p.model, problem.solver.clone());
    let outcome = solver.solve(&p.prescribed, &mut p.contact, progress);
    let stats = solver.stats.clone();
    let mut result = p.result(problem, stats);
    result.converged = outcome.is_ok();
    result.failure = outcome.err().map(DrawingFailure::Solver);
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::solver::Failure;

    #[test]
    fn a_run_stops_at_the_step_it_is_asked_to() {
        // The paper's open box, coarse and shallow.
        let mut p = DrawingProblem::paper_box(10.0, 15.0, 10.0);
        p.fabric.undulation = false;
        p.element_size_mm = 5.0;
        p.stroke_mm = 12.0;
        let mut seen = 0;
        let r = solve_until(&p, &mut |_| {
            seen += 1;
            if seen == 3 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        assert!(!r.converged);
        assert_eq!(r.stats.steps, 3);
        assert!(
            matches!(
                r.failure,
                Some(DrawingFailure::Solver(Failure::Stopped { .. }))
            ),
            "{:?}",
            r.failure
        );
        assert!(r.stroke_reached_mm > 0.0 && r.stroke_reached_mm < p.stroke_mm);
        assert!(r.shear_deg.iter().all(|s| s.is_finite()));
    }
}
