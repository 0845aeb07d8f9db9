//! A strip clamped at both ends and shortened in equal increments, each solved from the last:
//! what the Euler strip (`core::specimens::euler_strip`) and the bias-wrinkle strip
//! (`core::specimens::bias_wrinkle`) share, their inputs and their driver. Like them, compiled
//! for the tests only.

use crate::core::fabric::law::{CellLaw, CellParams};
use crate::core::fabric::shear::ShearLaw;
use crate::core::solver::{Failure, Model, Prescribed, Solver, SolverOptions};
use crate::core::specimens::strip::{DeadLoad, strip_solver};

/// The strip: its fabric, its size and mesh, how far it is shortened and in how many points.
#[derive(Clone, Debug)]
pub(crate) struct ClampedStrip {
    /// The fabric (its linear yarn law).
    pub(crate) fabric: CellParams,
    /// Bending rigidity per unit width `[B1, B2]`, N·mm; the yarns' compressive stiffness as
    /// fractions of `C`.
    pub(crate) bending_rigidity: [f64; 2],
    pub(crate) compression: [f64; 2],
    /// Free length between the clamps and width, mm; the target element size, mm.
    pub(crate) length: f64,
    pub(crate) width: f64,
    pub(crate) element_size: f64,
    /// End shortening, mm, reached in `points` equal increments.
    pub(crate) shortening_mm: f64,
    pub(crate) points: usize,
    pub(crate) solver: SolverOptions,
}

impl ClampedStrip {
    /// The strip's law: the fabric's with `shear` (or none), the drawings' toe and the yarns'
    /// compressive stiffness.
    pub(crate) fn law(&self, shear: Option<ShearLaw>) -> CellLaw {
        CellLaw::new(self.fabric)
            .with_shear(shear)
            .with_toe(crate::core::drawing::TOE_STRAIN)
            .with_compression(self.compression)
    }
}

/// The clamps, one held and the other moving along −x: the held dofs (all three of each
/// clamped node) and, for each, whether it is an x of the moving clamp.
pub(crate) struct Clamps {
    pub(crate) held: Vec<usize>,
    moving: Vec<bool>,
}

impl Clamps {
    /// The clamps of a strip of `nodes` nodes: node `i` held when `clamped(i)`, on the moving
    /// clamp when `moving(i)` as well.
    pub(crate) fn new(
        nodes: usize,
        clamped: impl Fn(usize) -> bool,
        moving: impl Fn(usize) -> bool,
    ) -> Clamps {
        let held: Vec<usize> = (0..nodes)
            .filter(|&i| clamped(i))
            .flat_map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
            .collect();
        let moving = held.iter().map(|&d| d % 3 == 0 && moving(d / 3)).collect();
        Clamps { held, moving }
    }

    /// Shortens the strip of `model` (built with [`Clamps::held`] held) by the strip's
    /// shortening in its points (at least one), each solved from the last with `trigger` held
    /// and the strip's solver settings ([`strip_solver`]); after each, `at_point(d, force_n,
    /// model)`: the shortening so far (mm) and the force on the moving clamp along −x
    /// (compression positive, N). The solver's failure ends the shortening, and is returned.
    pub(crate) fn shorten(
        &self,
        model: &mut Model,
        strip: &ClampedStrip,
        trigger: &mut DeadLoad,
        mut at_point: impl FnMut(f64, f64, &Model),
    ) -> Option<Failure> {
        let options = strip_solver(&strip.solver);
        let points = strip.points.max(1);
        let d = |k: usize| strip.shortening_mm * k as f64 / points as f64;
        for k in 1..=points {
            let step = Shortening {
                clamps: self,
                from: d(k - 1),
                to: d(k),
            };
            let mut solver = Solver::new(model, options.clone());
            let solved = solver.solve(&step, trigger, &mut |_| std::ops::ControlFlow::Continue(()));
            if let Err(f) = solved {
                return Some(f);
            }
            // The solver left the element outputs at the converged state.
            let f = model.internal_force();
            let pulled: f64 = (self.held.iter().zip(&self.moving))
                .filter(|(_, m)| **m)
                .map(|(&dof, _)| f[dof])
                .sum();
            at_point(d(k), -pulled, model);
        }
        None
    }
}

/// The clamps from one point of the shortening to the next: the moving clamp's x from `−from`
/// to `−to` along the load path, the rest held.
struct Shortening<'a> {
    clamps: &'a Clamps,
    from: f64,
    to: f64,
}

impl Prescribed for Shortening<'_> {
    fn dofs(&self) -> &[usize] {
        &self.clamps.held
    }
    fn values(&self, lambda: f64, out: &mut [f64]) {
        let d = self.from + lambda * (self.to - self.from);
        for (o, &m) in out.iter_mut().zip(&self.clamps.moving) {
            *o = if m { -d } else { 0.0 };
        }
    }
}
