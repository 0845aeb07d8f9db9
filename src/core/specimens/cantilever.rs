//! The heavy cantilever (Peirce; the fabric bending test of ASTM D1388) as a scene: a strip of
//! fabric, its warp along its length, clamped flat at one end and bent by its own weight.
//!
//! The strip is a yarn grid from `x = −h` to `x = L` (`h` the element length along it); the
//! nodes at `x = −h` and `x = 0` are held, so the clamp is flat and the free overhang is `L`.
//! Gravity is a dead load along −z on every node, its initial tributary area times the areal
//! weight `w = areal mass × g`, applied in load steps. The closed forms it is checked against
//! (small deflection `w L⁴/(8B)`, the heavy elastica, Peirce's bending length
//! `c = (B/w)^{1/3}`) are in `src/guide/bending.md`.

use crate::core::fabric::law::{CellLaw, CellParams};
use crate::core::membrane::mesh::Mesh;
use crate::core::solver::{Failure, LinearPrescribed, Model, Solver, SolverOptions};
use crate::core::specimens::strip::{self, DeadLoad};

/// Peirce's rigidity from an overhang `l` (mm), its chord angle `phi` (rad) and the areal
/// weight `w` (N/mm²): `(L/c)³ = 8 tan φ / cos(φ/2)`, `B = w c³` (Peirce 1930; ASTM D1388).
pub fn peirce_rigidity(l: f64, phi: f64, w: f64) -> f64 {
    w * l.powi(3) * (0.5 * phi).cos() / (8.0 * phi.tan())
}

/// Standard gravity, m/s² (= N/kg).
pub const GRAVITY: f64 = 9.80665;

/// A cantilever test.
#[derive(Clone, Debug)]
pub struct CantileverProblem {
    /// The fabric (the linear yarn law: `undulation` off).
    pub fabric: CellParams,
    /// Bending rigidity per unit width `[B1, B2]`, N·mm (warp along the strip).
    pub bending_rigidity: [f64; 2],
    /// The yarns' compressive stiffness as fractions of `C`.
    pub compression: [f64; 2],
    /// Areal mass of the fabric, g/m².
    pub areal_mass_g_m2: f64,
    /// Overhang `L` and width `W`, mm.
    pub length: f64,
    pub width: f64,
    /// Target element size, mm.
    pub element_size: f64,
    pub solver: SolverOptions,
}

/// Why a cantilever test has no answer.
#[derive(Clone, Debug, PartialEq)]
pub enum CantileverError {
    /// A size, rigidity or mass is not positive and finite.
    NotPositive { what: &'static str, value: f64 },
}

impl std::fmt::Display for CantileverError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CantileverError::NotPositive { what, value } => {
                write!(f, "{what} must be positive and finite, got {value}")
            }
        }
    }
}

/// What the test gives.
#[derive(Clone, Debug)]
pub struct CantileverResult {
    /// Tip deflection below the clamp (mean over the tip's nodes), mm.
    pub tip_deflection_mm: f64,
    /// Tip's horizontal distance from the clamp, mm.
    pub tip_reach_mm: f64,
    /// Slope of the strip at the tip below horizontal, degrees.
    pub tip_angle_deg: f64,
    /// Angle of the chord clamp → tip below horizontal (Peirce's φ), degrees.
    pub chord_angle_deg: f64,
    /// The areal weight `w`, N/mm².
    pub areal_weight_n_mm2: f64,
    pub newton_iterations: u32,
    pub steps: u32,
    pub failure: Option<Failure>,
    pub mesh: Mesh,
    pub positions: Vec<[f64; 3]>,
}

impl CantileverProblem {
    fn check(&self) -> Result<(), CantileverError> {
        let positive = [
            ("the overhang length", self.length),
            ("the strip's width", self.width),
            ("the element size", self.element_size),
            ("fabric.areal_mass", self.areal_mass_g_m2),
            ("the warp's bending rigidity", self.bending_rigidity[0]),
        ];
        for (what, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(CantileverError::NotPositive { what, value });
            }
        }
        Ok(())
    }

    /// Bends the strip under its weight, in load steps from no weight to all of it.
    pub fn solve(&self) -> Result<CantileverResult, CantileverError> {
        self.check()?;
        let (mesh, _) = strip::strip_mesh(self.length, self.width, self.element_size, 2, 0);
        let [n1, _] = mesh.grid.expect("a yarn grid");
        let column = |i: usize| i % (n1 + 1);
        let held: Vec<usize> = (0..mesh.nodes.len())
            .filter(|&i| column(i) <= 1)
            .flat_map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
            .collect();
        let w = self.areal_mass_g_m2 * 1e-9 * GRAVITY; // g/m² → kg/mm², times g: N/mm²
        let mut weight = DeadLoad {
            force_z: crate::core::membrane::mesh::tributary_areas(&mesh)
                .iter()
                .map(|a| -w * a)
                .collect(),
            scaled: true,
        };
        let mut hinges = crate::core::membrane::hinges::yarn_hinges(&mesh, self.bending_rigidity)
            .expect("a yarn grid");
        strip::stiffen_clamp_edges(&mut hinges, column, |c| c <= 1);
        let law = CellLaw::new(self.fabric)
            .with_toe(crate::core::drawing::TOE_STRAIN)
            .with_compression(self.compression);
        let mut model = Model::with_hinges(mesh.clone(), law, &held, hinges)
            .expect("a rectangular strip has good elements");
        let fixed = LinearPrescribed {
            at_full_load: vec![0.0; held.len()],
            dofs: held,
        };
        let mut solver = Solver::new(&mut model, strip::strip_solver(&self.solver));
        let solved = solver.solve(&fixed, &mut weight, &mut |_| {
            std::ops::ControlFlow::Continue(())
        });
        let stats = solver.stats.clone();
        let x = model.positions();
        Ok(self.measure(
            mesh,
            x,
            w,
            stats.newton_iterations,
            stats.steps,
            solved.err(),
        ))
    }

    fn measure(
        &self,
        mesh: Mesh,
        x: Vec<[f64; 3]>,
        w: f64,
        newton_iterations: u32,
        steps: u32,
        failure: Option<Failure>,
    ) -> CantileverResult {
        let [n1, n2] = mesh.grid.expect("a yarn grid");
        let id = |i: usize, j: usize| j * (n1 + 1) + i;
        let (mut dz, mut reach, mut slope) = (0.0, 0.0, 0.0);
        for j in 0..=n2 {
            let (tip, before, root) = (x[id(n1, j)], x[id(n1 - 1, j)], x[id(1, j)]);
            dz += root[2] - tip[2];
            reach += tip[0] - root[0];
            slope += (before[2] - tip[2]).atan2(tip[0] - before[0]);
        }
        let k = (n2 + 1) as f64;
        let (dz, reach) = (dz / k, reach / k);
        CantileverResult {
            tip_deflection_mm: dz,
            tip_reach_mm: reach,
            tip_angle_deg: (slope / k).to_degrees(),
            chord_angle_deg: dz.atan2(reach).to_degrees(),
            areal_weight_n_mm2: w,
            newton_iterations,
            steps,
            failure,
            mesh,
            positions: x,
        }
    }
}

/// The heavy elastica of a strip of rigidity `b` (N·mm per mm), weight `w` (N/mm²) and overhang
/// `l` (mm): `B θ'' = −w (L − s) cos θ`, `θ(0) = 0`, `θ'(L) = 0`, by shooting on `θ'(0)`
/// (bisection) with RK4 over `n` steps. Returns the tip's slope (rad) and the shape as
/// `(x, −z)` points from the clamp, mm: the reference the strip's picture is drawn against.
pub fn heavy_elastica(b: f64, w: f64, l: f64, n: usize) -> (f64, Vec<(f64, f64)>) {
    let run = |k0: f64, keep: bool| {
        let h = l / n as f64;
        let f = |s: f64, t: f64| -w * (l - s) * t.cos() / b;
        let (mut th, mut dth, mut x, mut y) = (0.0f64, k0, 0.0, 0.0);
        let mut shape = vec![(0.0, 0.0)];
        for i in 0..n {
            let s = i as f64 * h;
            let (k1t, k1d) = (dth, f(s, th));
            let (k2t, k2d) = (dth + 0.5 * h * k1d, f(s + 0.5 * h, th + 0.5 * h * k1t));
            let (k3t, k3d) = (dth + 0.5 * h * k2d, f(s + 0.5 * h, th + 0.5 * h * k2t));
            let (k4t, k4d) = (dth + h * k3d, f(s + h, th + h * k3t));
            let mid = th + 0.5 * h * k1t;
            x += h * mid.cos();
            y += h * mid.sin();
            th += h / 6.0 * (k1t + 2.0 * k2t + 2.0 * k3t + k4t);
            dth += h / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
            if keep {
                shape.push((x, y));
            }
        }
        (th, dth, shape)
    };
    // θ'(L) rises with θ'(0); the root lies below the linear beam's w L²/(2B) times two.
    let (mut lo, mut hi) = (0.0, w * l * l / b);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if run(mid, false).1 > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let (th, _, shape) = run(0.5 * (lo + hi), true);
    (th, shape)
}

#[cfg(test)]
mod tests {
    use super::heavy_elastica;

    #[test]
    fn a_light_elastica_is_the_linear_beam() {
        // w L⁴/(8B) for a small load; the tip's slope w L³/(6B).
        let (b, w, l) = (1.0, 1e-6, 10.0);
        let (th, shape) = heavy_elastica(b, w, l, 2000);
        let tip = shape.last().unwrap().1;
        assert!(
            (tip / (w * l.powi(4) / (8.0 * b)) - 1.0).abs() < 1e-4,
            "{tip}"
        );
        assert!(
            (th / (w * l.powi(3) / (6.0 * b)) - 1.0).abs() < 1e-4,
            "{th}"
        );
    }
}
