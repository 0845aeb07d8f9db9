//! The woven-cell law's own checks: the linear law's toe at zero strain, and the woven law's
//! compressive branch against central differences of its tensions and of its energy.

use super::*;

#[test]
fn zero_strain_gives_zero_tension_and_closure() {
    let law = CellLaw::new(CellParams::PAPER_GLASS);
    let r = law.evaluate([0.0, 0.0], law.initial_state());
    assert_eq!(r.t, [0.0, 0.0]);
    assert_eq!(r.crimp.s, 0.0);
}

#[test]
fn an_unstrained_yarn_on_the_toe_is_given_the_taut_slope_and_no_tension() {
    let p = CellParams {
        undulation: false,
        ..CellParams::PAPER_GLASS
    };
    let w = 1e-3;
    let law = CellLaw::new(p).with_toe(w);
    let c = p.c[0];
    let at = |e: f64| law.evaluate([e, e], law.initial_state());
    let r = at(0.0);
    assert_eq!(r.t, [0.0, 0.0]);
    assert_eq!(r.dt[0][0], c);
    // Off zero the toe's own slope, `C ε/w`, and its tension `C ε²/2w`: a closed form.
    let e = 1e-4;
    let r = at(e);
    assert!((r.dt[0][0] - c * e / w).abs() < 1e-9 * c);
    assert!((r.t[0] - c * e * e / (2.0 * w)).abs() < 1e-9 * c * e);
    assert_eq!(at(-e).dt[0][0], 0.0);
}

/// The woven law with yarns that resist compression, at strains across compression, zero,
/// the toe and taut, one yarn against the other.
fn compressed_woven() -> CellLaw {
    CellLaw::new(CellParams::PAPER_GLASS)
        .with_toe(1e-3)
        .with_compression([0.01, 0.02])
}

const ACROSS: [f64; 9] = [-0.02, -3e-3, -1e-3, -2e-4, 2e-4, 7e-4, 1.5e-3, 0.01, 0.03];

#[test]
fn the_compressed_woven_laws_tangent_is_its_tensions_derivative() {
    let law = compressed_woven();
    let h = 1e-8;
    for &e1 in &ACROSS {
        for &e2 in &ACROSS {
            let r = law.evaluate_bracketed([e1, e2]);
            for b in 0..2 {
                let mut up = [e1, e2];
                let mut down = [e1, e2];
                up[b] += h;
                down[b] -= h;
                let (tu, td) = (law.evaluate_bracketed(up).t, law.evaluate_bracketed(down).t);
                for a in 0..2 {
                    let fd = (tu[a] - td[a]) / (2.0 * h);
                    let scale = 1e-5 * law.p.c[a] + 1e-4 * fd.abs();
                    assert!(
                        (r.dt[a][b] - fd).abs() < scale,
                        "at ({e1}, {e2}): dT{a}/dε{b} {} against {fd}",
                        r.dt[a][b]
                    );
                }
            }
        }
    }
}

#[test]
fn the_compressed_woven_laws_tensions_are_its_energys_gradient() {
    let law = compressed_woven();
    let h = 1e-7;
    for &e1 in &ACROSS {
        for &e2 in &ACROSS {
            let r = law.evaluate_bracketed([e1, e2]);
            for a in 0..2 {
                let at = |d: f64| {
                    let mut e = [e1, e2];
                    e[a] += d;
                    law.energy(e, law.evaluate_bracketed(e).crimp)
                };
                let fd = (at(h) - at(-h)) / (2.0 * h) / law.p.l0[a];
                assert!(
                    (r.t[a] - fd).abs() < 1e-3 + 1e-4 * fd.abs(),
                    "at ({e1}, {e2}): T{a} {} against dW/dε / L0 {fd}",
                    r.t[a]
                );
            }
        }
    }
}

#[test]
fn compression_resists_a_shortened_cell_and_leaves_the_crimp_interchange_alone() {
    let plain = CellLaw::new(CellParams::PAPER_GLASS).with_toe(1e-3);
    let law = compressed_woven();
    let c = CellParams::PAPER_GLASS.c;
    // A cell shortened along the warp, stretched along the weft: the crimp interchange is
    // the plain law's (the weft flattens, the warp's crown rises and it goes taut), and the
    // warp pushes back with r C ε beside it, the weft carries r C w/2 more.
    let (e1, e2) = (-0.01, 0.02);
    let (p, r) = (
        plain.evaluate([e1, e2], plain.initial_state()),
        law.evaluate([e1, e2], law.initial_state()),
    );
    assert!(
        p.t[0] > 0.0,
        "the weft's stretch lifts the warp's crown: it is taut"
    );
    assert!((r.t[0] - p.t[0] - 0.01 * c[0] * e1).abs() < 1e-9 * c[0]);
    assert!((r.t[1] - p.t[1] - 0.02 * c[1] * 0.5e-3).abs() < 1e-9 * c[1]);
    assert_eq!(r.crimp, p.crimp);
    // No compression: the plain law, bit for bit.
    let none = plain.with_compression([0.0, 0.0]);
    for &e1 in &ACROSS {
        for &e2 in &ACROSS {
            let (a, b) = (
                none.evaluate([e1, e2], none.initial_state()),
                plain.evaluate([e1, e2], plain.initial_state()),
            );
            assert_eq!((a.t, a.dt, a.crimp), (b.t, b.dt, b.crimp));
        }
    }
}
