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
use crate::core::fabric::shear::ShearLaw;
use crate::core::membrane::mesh::Mesh;
use crate::core::solver::{BadElement, Failure, Model};
use crate::core::specimens::bias::{ideal_force_of, kinematic_limit, specimen_mesh};
use crate::core::specimens::clamped::{ClampedStrip, Clamps};
use crate::core::specimens::strip::DeadLoad;
use crate::core::wrinkles::trigger::Trigger;

/// A bias strip shortened between clamps (its free length `H`, its width `W`), with a shear
/// law and a trigger.
#[derive(Clone, Debug)]
pub(crate) struct BiasWrinkleProblem {
    /// The fabric's linear yarn law, its bending and compression, the strip and its shortening.
    pub(crate) strip: ClampedStrip,
    /// The fabric's shear law (with locking, as a user gives it).
    pub(crate) shear: ShearLaw,
    /// The out-of-plane trigger ([`crate::core::wrinkles::trigger`]).
    pub(crate) trigger: Trigger,
}

/// The curve of the shortening, from 0.
#[derive(Clone, Debug, Default)]
pub(crate) struct BiasWrinkleResult {
    pub(crate) shortening_mm: Vec<f64>,
    /// The force on the moving clamp, compression positive, N.
    pub(crate) force_n: Vec<f64>,
    /// The largest wrinkle amplitude ([`crate::core::wrinkles::amplitude`], the clamps anchored), mm.
    pub(crate) wrinkle_mm: Vec<f64>,
    /// |Shear| of the element nearest the centre, degrees.
    pub(crate) shear_centre_deg: Vec<f64>,
    pub(crate) failure: Option<Failure>,
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
    pub(crate) fn euler_force_n(&self) -> f64 {
        let p = &self.strip;
        let b = 0.25 * (p.bending_rigidity[0] + p.bending_rigidity[1]);
        4.0 * std::f64::consts::PI.powi(2) * b * p.width / p.length.powi(2)
    }

    /// The force that trellises the strip to a shortening `d` (mm), N (compression positive):
    /// the ideal kinematics' energy balance.
    fn trellis_force_n(&self, d: f64) -> f64 {
        let p = &self.strip;
        -ideal_force_of(&|g| self.shear.moment(g), p.length, p.width, -d)
    }

    /// The shortening at which trellising further costs the Euler force, mm (`None`: not
    /// within the kinematics' reach).
    pub(crate) fn onset_estimate_mm(&self) -> Option<f64> {
        let euler = self.euler_force_n();
        let limit = kinematic_limit(self.strip.length, self.strip.width);
        let (mut lo, mut hi) = (0.0, 0.99 * limit);
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
    pub(crate) fn solve(&self) -> Result<BiasWrinkleResult, BadElement> {
        let p = &self.strip;
        let (h, w) = (p.length, p.width);
        let mesh = specimen_mesh(h, w, p.element_size);
        let lines = yarn_lines(&mesh);
        let area = crate::core::membrane::mesh::tributary_areas(&mesh);
        let first = mesh.nodes.iter().map(|p| p[0]).filter(|v| *v > 1e-9);
        let clamp = first.fold(f64::INFINITY, f64::min) + 1e-9;
        let clamped: Vec<bool> = (mesh.nodes.iter())
            .map(|p| p[0] <= clamp || p[0] >= h - clamp)
            .collect();
        let clamps = Clamps::new(
            mesh.nodes.len(),
            |i| clamped[i],
            |i| mesh.nodes[i][0] >= h - clamp,
        );
        let mut hinges = Vec::new();
        for (family, b) in lines.iter().zip(p.bending_rigidity) {
            hinges.extend(bending::line_hinges(&mesh.nodes, family, &area, b));
        }
        let law = p.law(Some(self.shear));
        let mut model = Model::with_hinges(mesh.clone(), law, &clamps.held, hinges)?;
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
        let at_point = |d: f64, force: f64, model: &Model| {
            let x = model.positions();
            let wrinkles =
                crate::core::wrinkles::amplitude::wrinkles_along(&mesh, &all_lines, &x, &clamped);
            out.shortening_mm.push(d);
            out.force_n.push(force);
            out.wrinkle_mm.push(wrinkles.max_mm);
            out.shear_centre_deg
                .push(model.shear_angles_deg()[centre].abs());
        };
        out.failure = clamps.shorten(&mut model, p, &mut trigger, at_point);
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
    use crate::core::fabric::law::CellParams;
    use crate::core::solver::SolverOptions;

    /// A 60 × 30 mm bias strip of the glass fabric's fitted shear law with locking at 60°,
    /// B = 1 N·mm, compressive yarns of 1 % of C, 2.5 mm elements, shortened by 3 mm in 30 points.
    fn strip(trigger_pa: f64) -> BiasWrinkleProblem {
        let mut fabric = CellParams::PAPER_GLASS;
        fabric.undulation = false;
        BiasWrinkleProblem {
            strip: ClampedStrip {
                fabric,
                bending_rigidity: [1.0, 1.0],
                compression: [1e-2, 1e-2],
                length: 60.0,
                width: 30.0,
                element_size: 2.5,
                shortening_mm: 3.0,
                points: 30,
                solver: SolverOptions::default(),
            },
            shear: ShearLaw::new([0.0376068, -0.0786365, 0.0822838]).with_locking(60.0),
            trigger: Trigger {
                pressure_mpa: trigger_pa * 1e-6,
                seed: 1,
            },
        }
    }

    /// The first point whose wrinkle passes 0.5 mm.
    fn onset(r: &BiasWrinkleResult) -> usize {
        (r.wrinkle_mm.iter().position(|w| *w > 0.5)).expect("the strip buckles")
    }

    #[test]
    fn a_bias_strip_trellises_then_wrinkles_where_shearing_costs_more_than_bending() {
        let p = strip(1.0);
        let euler = p.euler_force_n();
        let r = p.solve().unwrap();
        assert!(r.failure.is_none(), "{:?}", r.failure);
        let k = onset(&r);
        // Flat while it trellises (up to 85 % of the onset's shortening: the last points before
        // it already lift), the shear growing with the shortening.
        for i in 1..k {
            let d = r.shortening_mm[i];
            if d < 0.85 * r.shortening_mm[k] {
                assert!(r.wrinkle_mm[i] < 0.1, "Δ {d}: {} mm", r.wrinkle_mm[i]);
            }
            assert!(r.shear_centre_deg[i] > r.shear_centre_deg[i - 1]);
        }
        // It buckles at a force below the beam's Euler force (an upper bound: the hinges have no
        // twisting stiffness, so the strip finds a cheaper mode), but not far below.
        let buckling = r.force_n[k];
        assert!(
            buckling > 0.6 * euler && buckling < euler,
            "{buckling} N against {euler} N"
        );
        // Past it, the force stays near that and the shear all but stops: the strip shortens by
        // wrinkling. Rate of shear per mm before and after.
        let last = r.force_n.len() - 1;
        assert!(
            (r.force_n[last] / buckling - 1.0) < 0.15,
            "{}",
            r.force_n[last]
        );
        let before = r.shear_centre_deg[k - 1] / r.shortening_mm[k - 1];
        let after = (r.shear_centre_deg[last] - r.shear_centre_deg[k + 1])
            / (r.shortening_mm[last] - r.shortening_mm[k + 1]);
        assert!(
            after < 0.25 * before,
            "{after} °/mm after against {before} before"
        );
        // Against the estimate: trellising the strip (its measured pre-buckling force, which runs
        // above the ideal kinematics' by the clamps' share) reaches the onset's force by then.
        let estimate = p.onset_estimate_mm().unwrap();
        assert!(
            r.shortening_mm[k] < estimate,
            "buckled at {} mm, estimate {estimate} mm",
            r.shortening_mm[k]
        );
        assert!(r.wrinkle_mm[last] > 5.0, "{}", r.wrinkle_mm[last]);
    }

    #[test]
    fn the_bias_strips_wrinkles_do_not_hang_on_the_trigger() {
        let (a, b) = (strip(1.0).solve().unwrap(), strip(0.1).solve().unwrap());
        let last = a.wrinkle_mm.len() - 1;
        assert!(
            (a.wrinkle_mm[last] / b.wrinkle_mm[last] - 1.0).abs() < 0.01,
            "{} against {}",
            a.wrinkle_mm[last],
            b.wrinkle_mm[last]
        );
        assert!((onset(&a) as i64 - onset(&b) as i64).abs() <= 1);
    }

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
