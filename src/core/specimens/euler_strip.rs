//! The Euler strip: a strip of fabric (warp along it) clamped flat at both ends and shortened
//! by `Δ`, the buckling check of bending stiffness with compressive yarns.
//!
//! The strip runs from `x = −h` to `x = L + h` (`h` the element length): the two rows of nodes
//! at each end are held, so the clamps are flat and the free length is `L`; the end at
//! `x = L` moves by `−Δ` along x in load steps. A buckling problem needs a trigger: a small
//! lateral pressure `q` along −z on the whole strip, given by the sag it alone would cause at
//! mid-length, `q L⁴/(384 B)` (`trigger_sag_mm`), which favours the first (symmetric) mode as
//! a seeded imperfection of that shape would. (An imperfection in the initial mesh would be
//! bent straight again: the hinges' rest state is a straight line.) The closed forms (`src/guide/bending.md`): it stays
//! nearly flat until the end force reaches `4π²BW/L²`, then buckles, the force staying near
//! that value and the amplitude `(2/π)√(L(Δ − Δc))`.

use crate::core::fabric::law::{CellLaw, CellParams};
use crate::core::solver::{Failure, Model, Prescribed, Solver, SolverOptions};
use crate::core::specimens::strip::{self, DeadLoad};

/// A clamped–clamped strip shortened by `shortening_mm`.
#[derive(Clone, Debug)]
pub struct EulerStripProblem {
    /// The fabric (the linear yarn law).
    pub fabric: CellParams,
    /// Bending rigidity per unit width `[B1, B2]`, N·mm.
    pub bending_rigidity: [f64; 2],
    /// The yarns' compressive stiffness as fractions of `C`.
    pub compression: [f64; 2],
    /// Free length `L` and width `W`, mm.
    pub length: f64,
    pub width: f64,
    pub element_size: f64,
    /// End shortening `Δ`, mm.
    pub shortening_mm: f64,
    /// The trigger: the mid-length sag the lateral pressure alone causes, mm.
    pub trigger_sag_mm: f64,
    /// Points of the force–shortening curve.
    pub points: usize,
    pub solver: SolverOptions,
}

/// The curve of the shortening.
#[derive(Clone, Debug, Default)]
pub struct EulerStripResult {
    pub shortening_mm: Vec<f64>,
    /// The force on the moving clamp along −x (compression positive), N.
    pub force_n: Vec<f64>,
    /// The deflection at mid-length below the clamps' plane (mean over the width), mm.
    pub amplitude_mm: Vec<f64>,
    /// The wrinkle figure of the strip ([`crate::core::wrinkles::amplitude`], the clamps anchored), mm.
    pub wrinkle_mm: Vec<f64>,
    pub failure: Option<Failure>,
}

impl EulerStripProblem {
    /// Shortens the strip in `points` increments; each point solved from the last.
    pub fn solve(&self) -> EulerStripResult {
        let (mesh, h) = strip::strip_mesh(self.length, self.width, self.element_size, 4, 1);
        let [n1, _] = mesh.grid.expect("a yarn grid");
        let column = |i: usize| i % (n1 + 1);
        let clamped = |c: usize| c <= 1 || c >= n1 - 1;
        let held: Vec<usize> = (0..mesh.nodes.len())
            .filter(|&i| clamped(column(i)))
            .flat_map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
            .collect();
        let moving: Vec<bool> = held
            .iter()
            .map(|&d| d % 3 == 0 && column(d / 3) >= n1 - 1)
            .collect();
        let mut hinges = crate::core::membrane::hinges::yarn_hinges(&mesh, self.bending_rigidity)
            .expect("a yarn grid");
        strip::stiffen_clamp_edges(&mut hinges, column, clamped);
        let law = CellLaw::new(self.fabric)
            .with_toe(crate::core::drawing::TOE_STRAIN)
            .with_compression(self.compression);
        let mut model = Model::with_hinges(mesh.clone(), law, &held, hinges)
            .expect("a rectangular strip has good elements");
        let options = strip::strip_solver(&self.solver);
        let mut out = EulerStripResult {
            shortening_mm: vec![0.0],
            force_n: vec![0.0],
            amplitude_mm: vec![0.0],
            wrinkle_mm: vec![0.0],
            failure: None,
        };
        let q = self.trigger_sag_mm * 384.0 * self.bending_rigidity[0] / self.length.powi(4);
        let mut trigger = DeadLoad {
            force_z: crate::core::membrane::mesh::tributary_areas(&mesh)
                .iter()
                .map(|a| -q * a)
                .collect(),
            scaled: false,
        };
        let points = self.points.max(1);
        let mid: Vec<usize> = (0..mesh.nodes.len())
            .filter(|&i| (mesh.nodes[i][0] - 0.5 * self.length).abs() < 0.5 * h + 1e-9)
            .collect();
        for k in 1..=points {
            let d = self.shortening_mm * k as f64 / points as f64;
            let prescribed = Shortening {
                dofs: &held,
                moving: &moving,
                from: self.shortening_mm * (k - 1) as f64 / points as f64,
                to: d,
            };
            let force = match prescribed.solve(&mut model, &options, &mut trigger) {
                Ok(f) => f,
                Err(f) => {
                    out.failure = Some(f);
                    break;
                }
            };
            let x = model.positions();
            let amp = -mid.iter().map(|&i| x[i][2]).sum::<f64>() / mid.len().max(1) as f64;
            out.shortening_mm.push(d);
            out.force_n.push(force);
            out.amplitude_mm.push(amp);
            let anchored: Vec<bool> = (0..x.len()).map(|i| clamped(column(i))).collect();
            let w = crate::core::wrinkles::amplitude::wrinkles(&mesh, &x, &anchored);
            out.wrinkle_mm.push(w.map_or(0.0, |w| w.max_mm));
        }
        out
    }
}

/// The clamps from one point of the curve to the next: the moving clamp's x from `−from` to
/// `−to` along the load path, the rest held.
pub(crate) struct Shortening<'a> {
    pub(crate) dofs: &'a [usize],
    pub(crate) moving: &'a [bool],
    pub(crate) from: f64,
    pub(crate) to: f64,
}

impl Shortening<'_> {
    /// Solves `model` from the clamps at `from` to `to` (with `trigger` held), and returns the
    /// force on the moving clamp along −x (compression positive), N.
    pub(crate) fn solve(
        &self,
        model: &mut Model,
        options: &SolverOptions,
        trigger: &mut DeadLoad,
    ) -> Result<f64, Failure> {
        let mut solver = Solver::new(model, options.clone());
        solver.solve(self, trigger, &mut |_| std::ops::ControlFlow::Continue(()))?;
        // The solver left the element outputs at the converged state.
        let f = model.internal_force();
        let pulled: f64 = (self.dofs.iter().zip(self.moving))
            .filter(|(_, m)| **m)
            .map(|(&dof, _)| f[dof])
            .sum();
        Ok(-pulled)
    }
}

impl Prescribed for Shortening<'_> {
    fn dofs(&self) -> &[usize] {
        self.dofs
    }
    fn values(&self, lambda: f64, out: &mut [f64]) {
        let d = self.from + lambda * (self.to - self.from);
        for (o, &m) in out.iter_mut().zip(self.moving) {
            *o = if m { -d } else { 0.0 };
        }
    }
}
