#![allow(clippy::needless_range_loop)]
//! The in-plane shear law in the woven-cell element: its force and tangent against finite
//! differences, objectivity, and the pure-shear patch whose energy and reaction are closed
//! forms (`wovenform::guide::shear_law`, "In-plane shear stiffness (beyond the paper)").

use crate::common;
use common::Lcg;
use wovenform::core::fabric::law::{CellLaw, CellParams};
use wovenform::core::fabric::shear::ShearLaw;
use wovenform::core::membrane::element::{self, ElementGeometry, ElementOutput, GAUSS};
use wovenform::core::membrane::mesh::Mesh;
use wovenform::core::solver::Model;

const LAW: ShearLaw = ShearLaw::new([0.09, -0.04, 0.25]);

fn evaluate(
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

/// A distorted element about 5 mm, yarns at `angle`, sheared by `s` and lifted a little.
fn sheared_element(g: &mut Lcg, angle: f64, s: f64) -> (ElementGeometry, [[f64; 3]; 4]) {
    let base = [[0.0, 0.0], [5.0, 0.0], [5.0, 5.0], [0.0, 5.0]];
    let mut x0 = [[0.0; 3]; 4];
    for k in 0..4 {
        x0[k] = [
            base[k][0] + g.range(-0.8, 0.8),
            base[k][1] + g.range(-0.8, 0.8),
            0.0,
        ];
    }
    let yarns = [[1.0, 0.0, 0.0], [angle.cos(), angle.sin(), 0.0]];
    let geo = ElementGeometry::new(&x0, Some(yarns), 4.76 * 4.76).unwrap();
    let mut x = x0;
    for k in 0..4 {
        x[k][0] += s * x0[k][1];
        x[k][2] += g.range(-0.2, 0.2);
    }
    (geo, x)
}

#[test]
fn shear_force_and_tangent_are_the_derivatives_of_its_energy() {
    // The linear yarn law on an element shrunk to 90 % before it is sheared: the yarns are
    // slack (no tension), so the energy is the shear law's alone.
    let mut p = CellParams::PAPER_GLASS;
    p.undulation = false;
    let mut g = Lcg(7);
    let mut checked = 0;
    for trial in 0..60 {
        // Every other element with locking as a stiffening past 12° (the sheared elements
        // reach 0–22°): both sides of the lock checked.
        let shear = if trial % 2 == 0 {
            LAW
        } else {
            LAW.with_locking(12.0)
        };
        let law = CellLaw::new(p).with_shear(Some(shear));
        let angle = g.range(60f64.to_radians(), 120f64.to_radians());
        let s = g.range(-0.4, 0.4);
        let (geo, mut x) = sheared_element(&mut g, angle, s);
        for p in x.iter_mut() {
            p[0] *= 0.9;
            p[1] *= 0.9;
        }
        let out = evaluate(&geo, &law, &x, true);
        if out.tension.iter().flatten().any(|t| *t != 0.0) {
            continue;
        }
        checked += 1;
        assert!(
            out.energy > 0.0,
            "trial {trial}: a sheared cell stores energy"
        );
        let h = 1e-6;
        let fscale = out.f.iter().fold(0.0f64, |a, b| a.max(b.abs())).max(1e-9);
        let kscale = out
            .k
            .iter()
            .flatten()
            .fold(0.0f64, |a, b| a.max(b.abs()))
            .max(1e-9);
        for i in 0..12 {
            let (mut xp, mut xm) = (x, x);
            xp[i / 3][i % 3] += h;
            xm[i / 3][i % 3] -= h;
            let (op, om) = (
                evaluate(&geo, &law, &xp, false),
                evaluate(&geo, &law, &xm, false),
            );
            let fd = (op.energy - om.energy) / (2.0 * h);
            assert!(
                (fd - out.f[i]).abs() <= 1e-6 * fscale + 1e-10,
                "trial {trial} dof {i}: {fd} vs {}",
                out.f[i]
            );
            for j in 0..12 {
                let fd_k = (op.f[j] - om.f[j]) / (2.0 * h);
                assert!(
                    (fd_k - out.k[j][i]).abs() <= 1e-5 * kscale + 1e-9,
                    "trial {trial} K[{j}][{i}]: {fd_k} vs {}",
                    out.k[j][i]
                );
            }
        }
    }
    assert!(checked >= 30, "only {checked} elements had slack yarns");
}

#[test]
fn no_shear_law_and_a_zero_one_give_the_same_element_to_the_last_digit() {
    let mut g = Lcg(11);
    let (geo, x) = sheared_element(&mut g, 1.4, 0.3);
    let paper = CellLaw::new(CellParams::PAPER_GLASS);
    let zero = paper.with_shear(Some(ShearLaw::new([0.0; 3])));
    let (a, b) = (
        evaluate(&geo, &paper, &x, true),
        evaluate(&geo, &zero, &x, true),
    );
    assert_eq!(a.f, b.f);
    assert_eq!(a.k, b.k);
    assert_eq!(a.energy, b.energy);
}

#[test]
fn the_shear_energy_is_objective() {
    let mut g = Lcg(3);
    let law = CellLaw::new(CellParams::PAPER_GLASS).with_shear(Some(LAW));
    let (geo, x) = sheared_element(&mut g, 1.5, 0.5);
    let out = evaluate(&geo, &law, &x, false);
    // A rotation of 1 rad about (1, 2, 3)/|…| and a translation.
    let (c, s) = (1f64.cos(), 1f64.sin());
    let n = [1.0, 2.0, 3.0].map(|v: f64| v / 14f64.sqrt());
    let rot = |v: [f64; 3]| {
        let d = n[0] * v[0] + n[1] * v[1] + n[2] * v[2];
        let cr = [
            n[1] * v[2] - n[2] * v[1],
            n[2] * v[0] - n[0] * v[2],
            n[0] * v[1] - n[1] * v[0],
        ];
        [0, 1, 2].map(|m| v[m] * c + cr[m] * s + n[m] * d * (1.0 - c))
    };
    let xr = x.map(|p| {
        let r = rot(p);
        [r[0] + 10.0, r[1] - 4.0, r[2] + 2.0]
    });
    let outr = evaluate(&geo, &law, &xr, false);
    assert!((out.energy - outr.energy).abs() < 1e-10 * out.energy.abs().max(1.0));
    for k in 0..4 {
        let f = [out.f[3 * k], out.f[3 * k + 1], out.f[3 * k + 2]];
        let fr = rot(f);
        for m in 0..3 {
            assert!((fr[m] - outr.f[3 * k + m]).abs() < 1e-9, "node {k}");
        }
    }
}

#[test]
fn a_pure_shear_patch_stores_psi_times_area_and_reacts_with_m_times_area() {
    // A 4 × 4 yarn grid of 5 mm cells (20 × 20 mm, yarns along x and y) trellised by γ: the
    // weft turned by γ towards the warp, every yarn keeping its length (no tension). Closed
    // forms: energy Ψ(γ)·A, and the work of the nodal forces along d x/dγ equals M(γ)·A.
    let mesh = Mesh::yarn_grid(
        [0.0, 0.0],
        [20.0, 20.0],
        [4, 4],
        std::f64::consts::FRAC_PI_2,
    );
    let area = 400.0;
    let law = CellLaw::new(CellParams::PAPER_GLASS).with_shear(Some(LAW));
    let mut model = Model::new(mesh.clone(), law, &[]).unwrap();
    for gamma in [0.1f64, 0.4, 0.8] {
        // θ = 90° − γ: the weft at angle 90° − γ from the warp, (sin γ, cos γ).
        let weft = |g: f64| [g.sin(), g.cos()];
        let set = |model: &mut Model, g: f64| {
            let w = weft(g);
            for (n, p) in mesh.nodes.iter().enumerate() {
                model.u[3 * n] = p[0] + p[1] * w[0] - p[0];
                model.u[3 * n + 1] = p[1] * w[1] - p[1];
            }
        };
        set(&mut model, gamma);
        model.evaluate_elements(false, false);
        let energy = model.stored_energy();
        assert!(
            (energy - LAW.energy(gamma) * area).abs() < 1e-9 * energy,
            "γ {gamma}: {energy} vs {}",
            LAW.energy(gamma) * area
        );
        let f = model.internal_force();
        // d x/dγ of node (a, b): b (cos γ, −sin γ).
        let work: f64 = mesh
            .nodes
            .iter()
            .enumerate()
            .map(|(n, p)| f[3 * n] * p[1] * gamma.cos() - f[3 * n + 1] * p[1] * gamma.sin())
            .sum();
        let reaction = LAW.moment(gamma) * area;
        assert!(
            (work - reaction).abs() < 1e-9 * reaction,
            "γ {gamma}: {work} vs {reaction}"
        );
    }
}
