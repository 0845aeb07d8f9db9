//! Shear-driven wrinkles: a bias strip (yarns at ±45° to its length, the bias-extension
//! specimen of `core::specimens::bias`) clamped at both ends and shortened by `Δ`, out of its plane free,
//! with a shear law, bending and compressive yarns. It shortens first by trellising (the yarns
//! turn, none is compressed), which costs the shear law's moment; once pushing the trellis
//! further costs more than bending the strip, it buckles.
//!
//! The estimate it is checked against (`src/guide/bending.md`): the trellis's force, from the
//! ideal kinematics' energy balance in compression ([`crate::core::specimens::bias::ideal_force_of`] at
//! `−Δ`), reaches the clamped strip's Euler force `4π² B_x W / H²`, `B_x = (B1 + B2)/4` the
//! strip's rigidity along its length (a yarn at 45° sees half the curvature, and a hinge
//! counts the square: each family gives `B/4`).

use crate::core::fabric::bending;
use crate::core::fabric::law::{CellLaw, CellParams};
use crate::core::fabric::shear::ShearLaw;
use crate::core::membrane::mesh::Mesh;
use crate::core::solver::{Failure, Model, SolverOptions};
use crate::core::specimens::bias::{ideal_force_of, kinematic_limit, specimen_mesh};
use crate::core::specimens::euler_strip::Shortening;
use crate::core::specimens::strip::{self, DeadLoad};
use crate::core::wrinkles::trigger::Trigger;

/// A bias strip shortened between clamps.
#[derive(Clone, Debug)]
pub struct BiasWrinkleProblem {
    /// The fabric (its linear yarn law) and its shear law (with locking, as a user gives it).
    pub fabric: CellParams,
    pub shear: ShearLaw,
    /// Bending rigidity per unit width `[B1, B2]`, N·mm; the yarns' compressive stiffness as
    /// fractions of `C`.
    pub bending_rigidity: [f64; 2],
    pub compression: [f64; 2],
    /// Free length `H` between the clamps and width `W`, mm.
    pub length: f64,
    pub width: f64,
    pub element_size: f64,
    /// End shortening, mm, reached in `points` equal increments.
    pub shortening_mm: f64,
    pub points: usize,
    /// The out-of-plane trigger ([`crate::core::wrinkles::trigger`]).
    pub trigger: Trigger,
    pub solver: SolverOptions,
}

/// The curve of the shortening, from 0.
#[derive(Clone, Debug, Default)]
pub struct BiasWrinkleResult {
    pub shortening_mm: Vec<f64>,
    /// The force on the moving clamp, compression positive, N.
    pub force_n: Vec<f64>,
    /// The largest wrinkle amplitude ([`crate::core::wrinkles::amplitude`], the clamps anchored), mm.
    pub wrinkle_mm: Vec<f64>,
    /// |Shear| of the element nearest the centre, degrees.
    pub shear_centre_deg: Vec<f64>,
    pub failure: Option<Failure>,
}

/// The diamond mesh's yarn lines: its nodes sit at `(p ax/2, q ay/2)` with `p + q` even; yarn
/// 1 runs along `(1, 1)` in `(p, q)`, yarn 2 along `(1, −1)`.
fn yarn_lines(mesh: &Mesh) -> [Vec<Vec<usize>>; 2] {
    let half = |m: usize| {
        mesh.nodes
            .iter()
            .map(|p| p[m])
            .filter(|v| *v > 1e-9)
            .fold(f64::INFINITY, f64::min)
    };
    let (hx, hy) = (half(0), half(1));
    let pq: Vec<(i64, i64)> = (mesh.nodes.iter())
        .map(|p| ((p[0] / hx).round() as i64, (p[1] / hy).round() as i64))
        .collect();
    [1i64, -1].map(|s| {
        let mut by: std::collections::BTreeMap<i64, Vec<usize>> = Default::default();
        for (i, &(p, q)) in pq.iter().enumerate() {
            by.entry(p - s * q).or_default().push(i);
        }
        by.into_values()
            .map(|mut line| {
                line.sort_by_key(|&i| pq[i].0);
                line
            })
            .filter(|line| line.len() >= 3)
            .collect()
    })
}

impl BiasWrinkleProblem {
    /// The strip's Euler force between its clamps, N: `4π² (B1 + B2)/4 · W / H²`.
    pub fn euler_force_n(&self) -> f64 {
        let b = 0.25 * (self.bending_rigidity[0] + self.bending_rigidity[1]);
        4.0 * std::f64::consts::PI.powi(2) * b * self.width / self.length.powi(2)
    }

    /// The force that trellises the strip to a shortening `d` (mm), N (compression positive):
    /// the ideal kinematics' energy balance.
    pub fn trellis_force_n(&self, d: f64) -> f64 {
        -ideal_force_of(&|g| self.shear.moment(g), self.length, self.width, -d)
    }

    /// The shortening at which trellising further costs the Euler force, mm (`None`: not
    /// within the kinematics' reach).
    pub fn onset_estimate_mm(&self) -> Option<f64> {
        let euler = self.euler_force_n();
        let (mut lo, mut hi) = (0.0, 0.99 * kinematic_limit(self.length, self.width));
        if self.trellis_force_n(hi) < euler {
            return None;
        }
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if self.trellis_force_n(mid) < euler {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Some(0.5 * (lo + hi))
    }

    /// Shortens the strip in `points` increments, each solved from the last.
    pub fn solve(&self) -> Result<BiasWrinkleResult, crate::core::solver::BadElement> {
        let (h, w) = (self.length, self.width);
        let mesh = specimen_mesh(h, w, self.element_size);
        let lines = yarn_lines(&mesh);
        let area = crate::core::membrane::mesh::tributary_areas(&mesh);
        let first = mesh.nodes.iter().map(|p| p[0]).filter(|v| *v > 1e-9);
        let clamp = first.fold(f64::INFINITY, f64::min) + 1e-9;
        let clamped: Vec<bool> = (mesh.nodes.iter())
            .map(|p| p[0] <= clamp || p[0] >= h - clamp)
            .collect();
        let held: Vec<usize> = (0..mesh.nodes.len())
            .filter(|&i| clamped[i])
            .flat_map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
            .collect();
        let moving: Vec<bool> = held
            .iter()
            .map(|&d| d % 3 == 0 && mesh.nodes[d / 3][0] >= h - clamp)
            .collect();
        let mut hinges = Vec::new();
        for (family, b) in lines.iter().zip(self.bending_rigidity) {
            hinges.extend(bending::line_hinges(&mesh.nodes, family, &area, b));
        }
        let law = CellLaw::new(self.fabric)
            .with_shear(Some(self.shear))
            .with_toe(crate::core::drawing::TOE_STRAIN)
            .with_compression(self.compression);
        let mut model = Model::with_hinges(mesh.clone(), law, &held, hinges)?;
        let mut trigger = DeadLoad {
            force_z: self.trigger.forces(&mesh.nodes, &area),
            scaled: false,
        };
        let centre = nearest_element(&mesh, [0.5 * h, 0.5 * w]);
        let all_lines: Vec<Vec<usize>> = lines.into_iter().flatten().collect();
        let mut out = BiasWrinkleResult {
            shortening_mm: vec![0.0],
            force_n: vec![0.0],
            wrinkle_mm: vec![0.0],
            shear_centre_deg: vec![0.0],
            failure: None,
        };
        let options = strip::strip_solver(&self.solver);
        let points = self.points.max(1);
        for k in 1..=points {
            let d = |k: usize| self.shortening_mm * k as f64 / points as f64;
            let prescribed = Shortening {
                dofs: &held,
                moving: &moving,
                from: d(k - 1),
                to: d(k),
            };
            let force = match prescribed.solve(&mut model, &options, &mut trigger) {
                Ok(f) => f,
                Err(f) => {
                    out.failure = Some(f);
                    break;
                }
            };
            let x = model.positions();
            let wrinkles =
                crate::core::wrinkles::amplitude::wrinkles_along(&mesh, &all_lines, &x, &clamped);
            out.shortening_mm.push(d(k));
            out.force_n.push(force);
            out.wrinkle_mm.push(wrinkles.max_mm);
            out.shear_centre_deg
                .push(model.shear_angles_deg()[centre].abs());
        }
        Ok(out)
    }
}

/// The element whose initial centre is nearest `at` (plan, mm).
fn nearest_element(mesh: &Mesh, at: [f64; 2]) -> usize {
    let d2 = |q: &[usize; 4]| {
        let c = [0, 1].map(|m| q.iter().map(|&n| mesh.nodes[n][m]).sum::<f64>() / 4.0);
        (c[0] - at[0]).powi(2) + (c[1] - at[1]).powi(2)
    };
    (0..mesh.quads.len())
        .min_by(|&a, &b| d2(&mesh.quads[a]).total_cmp(&d2(&mesh.quads[b])))
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_diamond_meshs_yarn_lines_run_at_45_degrees_through_every_node() {
        let mesh = specimen_mesh(60.0, 30.0, 2.5);
        let lines = yarn_lines(&mesh);
        for (family, dir) in lines.iter().zip([[1.0, 1.0], [1.0, -1.0]]) {
            let mut seen = vec![0; mesh.nodes.len()];
            for line in family {
                for w in line.windows(2) {
                    let (a, b) = (mesh.nodes[w[0]], mesh.nodes[w[1]]);
                    let e = [b[0] - a[0], b[1] - a[1]];
                    let len = (e[0] * e[0] + e[1] * e[1]).sqrt();
                    let c = (e[0] * dir[0] + e[1] * dir[1]) / (len * 2f64.sqrt());
                    assert!((c - 1.0).abs() < 1e-9, "{e:?}");
                }
                line.iter().for_each(|&i| seen[i] += 1);
            }
            // Every node on at most one line of a family; all but the corners' on one.
            assert!(seen.iter().all(|&s| s <= 1));
            assert!(seen.iter().filter(|&&s| s == 1).count() + 4 >= mesh.nodes.len());
        }
    }
}
