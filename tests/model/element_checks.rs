#![allow(clippy::needless_range_loop)]
//! The woven-cell membrane element against finite differences, rigid motions and homogeneous
//! states whose answers come from the law alone.

use crate::analytic;
use crate::common;
use common::Lcg;
use wovenform::core::fabric::law::{CellLaw, CellParams};
use wovenform::core::membrane::element::{self, ElementGeometry, ElementOutput, GAUSS};

/// A distorted element (about 5 mm, corners jittered by up to 1 mm) and yarns at `angle`.
fn distorted(g: &mut Lcg, angle: f64) -> ([[f64; 3]; 4], [[f64; 3]; 2]) {
    let base = [[0.0, 0.0], [5.0, 0.0], [5.0, 5.0], [0.0, 5.0]];
    let mut x0 = [[0.0; 3]; 4];
    for k in 0..4 {
        x0[k] = [
            base[k][0] + g.range(-1.0, 1.0),
            base[k][1] + g.range(-1.0, 1.0),
            0.0,
        ];
    }
    (x0, [[1.0, 0.0, 0.0], [angle.cos(), angle.sin(), 0.0]])
}

/// A deformation: in-plane stretch up to `max_strain` in yarn directions, some out-of-plane lift,
/// and per-node noise; some yarns end up slack and some taut.
fn deform(g: &mut Lcg, x0: &[[f64; 3]; 4], max_strain: f64) -> [[f64; 3]; 4] {
    let s1 = g.range(-0.02, max_strain);
    let s2 = g.range(-0.02, max_strain);
    let mut x = *x0;
    for k in 0..4 {
        x[k][0] *= 1.0 + s1;
        x[k][1] *= 1.0 + s2;
        x[k][2] += g.range(-0.3, 0.3);
        for m in 0..3 {
            x[k][m] += g.range(-0.01, 0.01);
        }
    }
    x
}

fn energy_and_force(
    geo: &ElementGeometry,
    law: &CellLaw,
    x: &[[f64; 3]; 4],
    tangent: bool,
) -> ElementOutput {
    let mut crimp = [law.initial_state(); GAUSS];
    let mut out = ElementOutput::default();
    element::evaluate(geo, law, x, &mut crimp, tangent, &mut out);
    out
}

#[test]
fn force_is_the_gradient_of_energy_and_tangent_the_gradient_of_force() {
    let mut g = Lcg(42);
    let mut slack_seen = 0;
    let mut taut_seen = 0;
    for trial in 0..60 {
        let mut p = CellParams::PAPER_GLASS;
        p.undulation = trial % 3 != 2;
        let law = CellLaw::new(p);
        let angle = g.range(70f64.to_radians(), 110f64.to_radians());
        let (x0, yarns) = distorted(&mut g, angle);
        // Every fourth element has its yarns along its natural directions (the paper's element),
        // and a warped (non-planar) initial shape.
        let (x0, yarns) = if trial % 4 == 3 {
            let mut w = x0;
            w[2][2] += 0.8;
            w[0][2] -= 0.3;
            (w, None)
        } else {
            (x0, Some(yarns))
        };
        let geo = ElementGeometry::new(&x0, yarns, law.p.l0[0] * law.p.l0[1]).unwrap();
        let x = deform(&mut g, &x0, 0.03);
        let out = energy_and_force(&geo, &law, &x, true);
        for t in out.tension.iter().flatten() {
            if *t == 0.0 {
                slack_seen += 1
            } else {
                taut_seen += 1
            }
        }
        let h = 1e-6;
        let fscale = out.f.iter().fold(0.0f64, |a, b| a.max(b.abs())).max(1e-9);
        let kscale = out
            .k
            .iter()
            .flatten()
            .fold(0.0f64, |a, b| a.max(b.abs()))
            .max(1e-9);
        for i in 0..12 {
            let (k, m) = (i / 3, i % 3);
            let mut xp = x;
            let mut xm = x;
            xp[k][m] += h;
            xm[k][m] -= h;
            let op = energy_and_force(&geo, &law, &xp, false);
            let om = energy_and_force(&geo, &law, &xm, false);
            // Skip a coordinate whose perturbation flips a yarn between slack and taut.
            let flips = op
                .tension
                .iter()
                .flatten()
                .zip(om.tension.iter().flatten())
                .zip(out.tension.iter().flatten())
                .any(|((a, b), c)| (*a == 0.0) != (*b == 0.0) || (*a == 0.0) != (*c == 0.0));
            if flips {
                continue;
            }
            let fd_force = (op.energy - om.energy) / (2.0 * h);
            assert!(
                (fd_force - out.f[i]).abs() <= 1e-6 * fscale + 1e-7,
                "trial {trial} dof {i}: fd {fd_force} vs f {}",
                out.f[i]
            );
            for j in 0..12 {
                let fd_k = (op.f[j] - om.f[j]) / (2.0 * h);
                assert!(
                    (fd_k - out.k[j][i]).abs() <= 1e-5 * kscale + 1e-6,
                    "trial {trial} K[{j}][{i}]: fd {fd_k} vs {}",
                    out.k[j][i]
                );
            }
        }
    }
    assert!(
        slack_seen > 20 && taut_seen > 100,
        "slack {slack_seen}, taut {taut_seen}"
    );
}

fn rotation(axis: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let [x, y, z] = [axis[0] / n, axis[1] / n, axis[2] / n];
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ]
}

fn apply(r: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [
        r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2],
        r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
        r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2],
    ]
}

#[test]
fn objectivity_under_a_large_rotation_and_translation() {
    let mut g = Lcg(9);
    let law = CellLaw::new(CellParams::PAPER_GLASS);
    for _ in 0..20 {
        let (x0, yarns) = distorted(&mut g, std::f64::consts::FRAC_PI_2);
        let geo = ElementGeometry::new(&x0, Some(yarns), law.p.l0[0] * law.p.l0[1]).unwrap();
        let x = deform(&mut g, &x0, 0.02);
        let r = rotation(
            [g.range(-1.0, 1.0), g.range(-1.0, 1.0), g.range(0.1, 1.0)],
            g.range(1.0, 3.0),
        );
        let c = [
            g.range(-50.0, 50.0),
            g.range(-50.0, 50.0),
            g.range(-50.0, 50.0),
        ];
        let mut xr = x;
        for k in 0..4 {
            let v = apply(&r, x[k]);
            xr[k] = [v[0] + c[0], v[1] + c[1], v[2] + c[2]];
        }
        let a = energy_and_force(&geo, &law, &x, false);
        let b = energy_and_force(&geo, &law, &xr, false);
        let tscale = a.tension.iter().flatten().fold(1.0f64, |m, t| m.max(*t));
        for (ta, tb) in a.tension.iter().flatten().zip(b.tension.iter().flatten()) {
            assert!((ta - tb).abs() <= 1e-9 * tscale, "tension {ta} vs {tb}");
        }
        assert!((a.energy - b.energy).abs() <= 1e-9 * a.energy.abs().max(1e-9));
        let fscale = a.f.iter().fold(1e-9f64, |m, v| m.max(v.abs()));
        for k in 0..4 {
            let fa = apply(&r, [a.f[3 * k], a.f[3 * k + 1], a.f[3 * k + 2]]);
            for m in 0..3 {
                assert!((fa[m] - b.f[3 * k + m]).abs() <= 1e-9 * fscale);
            }
        }
        // A free element is in self-equilibrium: its forces sum to zero.
        for m in 0..3 {
            let sum: f64 = (0..4).map(|k| b.f[3 * k + m]).sum();
            assert!(sum.abs() <= 1e-9 * fscale);
        }
    }
}

#[test]
fn cell_count_is_the_area_over_the_cell_area() {
    let law = CellLaw::new(CellParams::PAPER_GLASS);
    let angle = 75f64.to_radians();
    let x0 = [
        [0.0, 0.0, 0.0],
        [10.0, 0.0, 0.0],
        [10.0 + 8.0 * angle.cos(), 8.0 * angle.sin(), 0.0],
        [8.0 * angle.cos(), 8.0 * angle.sin(), 0.0],
    ];
    let yarns = [[1.0, 0.0, 0.0], [angle.cos(), angle.sin(), 0.0]];
    let geo = ElementGeometry::new(&x0, Some(yarns), law.p.l0[0] * law.p.l0[1]).unwrap();
    let expected = analytic::cells_in_parallelogram([10.0, 8.0], angle, law.p.l0);
    assert!((geo.cell_count() - expected).abs() < 1e-12);
    assert!((geo.yarn_angle0 - angle).abs() < 1e-12);
}

#[test]
fn element_along_the_yarns_reduces_to_the_papers_explicit_force() {
    // Paper eq 35: F_s = n (B̄11s L01 T11/|g10|² + B̄22s L02 T22/|g20|²) with Ē from eq 23, and the
    // small-strain reading ε ≈ E (Remark 2) replaced by the exact pair of `src/guide/theory.md`:
    // S̃ = L0 T/(1+ε). Here: a rectangle along the yarns, a homogeneous stretch.
    let law = CellLaw::new(CellParams::PAPER_GLASS);
    let (a, b) = (6.0, 4.0);
    let x0 = [[0.0, 0.0, 0.0], [a, 0.0, 0.0], [a, b, 0.0], [0.0, b, 0.0]];
    let yarns = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let geo = ElementGeometry::new(&x0, Some(yarns), law.p.l0[0] * law.p.l0[1]).unwrap();
    let (e1, e2) = (0.006, 0.003);
    let x = x0.map(|p| [p[0] * (1.0 + e1), p[1] * (1.0 + e2), 0.0]);
    let out = energy_and_force(&geo, &law, &x, false);
    let t = law.evaluate([e1, e2], law.initial_state()).t;
    // Closed form for a homogeneous state: the nodal force on the x = a edge is the warp tension
    // times the yarns crossing that edge (b / L02), shared between its two nodes.
    let fx = analytic::edge_node_force(t[0], b, law.p.l0[1]);
    let fy = analytic::edge_node_force(t[1], a, law.p.l0[0]);
    assert!((out.f[3] - fx).abs() < 1e-9 * fx, "{} vs {fx}", out.f[3]);
    assert!((out.f[7] - fy).abs() < 1e-9 * fy, "{} vs {fy}", out.f[7]);
    assert!((out.f[0] + fx).abs() < 1e-9 * fx);
}
