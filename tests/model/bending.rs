//! Bending stiffness (`core::fabric::bending`, beyond the paper) against the heavy cantilever's closed
//! forms (`wovenform::guide::bending`): small deflection `w L⁴/(8B)`, the heavy elastica
//! integrated here by shooting, and Peirce's 41.5° chord at an overhang of twice the bending
//! length `c = (B/w)^{1/3}`. (The Euler strip's buckling against its closed forms is checked
//! beside the strip, in `core::specimens::euler_strip`.)

use wovenform::core::fabric::law::CellParams;
use wovenform::core::solver::SolverOptions;
use wovenform::core::specimens::cantilever::{CantileverError, CantileverProblem, GRAVITY};

/// A glass fabric's strip: B = 0.08 N·mm per mm of width, 300 g/m² (c = 30.07 mm).
fn strip(length: f64, element_size: f64) -> CantileverProblem {
    let mut fabric = CellParams::PAPER_GLASS;
    fabric.undulation = false;
    CantileverProblem {
        fabric,
        bending_rigidity: [0.08, 0.08],
        compression: [1e-3, 1e-3],
        areal_mass_g_m2: 300.0,
        length,
        width: 10.0,
        element_size,
        solver: SolverOptions::default(),
    }
}

fn weight() -> f64 {
    300.0 * 1e-9 * GRAVITY
}

/// The heavy elastica `B θ'' = −w (L − s) cos θ`, `θ(0) = 0`, `θ'(L) = 0`, by shooting on
/// `θ'(0)` with RK4: the tip's angle (rad), deflection and reach (mm).
fn elastica(b: f64, w: f64, l: f64) -> (f64, f64, f64) {
    let run = |k0: f64| {
        let n = 4000;
        let h = l / n as f64;
        let f = |s: f64, t: f64| -w * (l - s) * t.cos() / b;
        let (mut th, mut dth, mut x, mut y, mut s) = (0.0f64, k0, 0.0, 0.0, 0.0);
        for _ in 0..n {
            let (k1t, k1d) = (dth, f(s, th));
            let (k2t, k2d) = (dth + h / 2.0 * k1d, f(s + h / 2.0, th + h / 2.0 * k1t));
            let (k3t, k3d) = (dth + h / 2.0 * k2d, f(s + h / 2.0, th + h / 2.0 * k2t));
            let (k4t, k4d) = (dth + h * k3d, f(s + h, th + h * k3t));
            let mid = th + h / 2.0 * k1t;
            x += h * mid.cos();
            y += h * mid.sin();
            th += h / 6.0 * (k1t + 2.0 * k2t + 2.0 * k3t + k4t);
            dth += h / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
            s += h;
        }
        (th, dth, y, x)
    };
    let (mut lo, mut hi) = (0.0, 10.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if run(mid).1 > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let (th, _, y, x) = run(0.5 * (lo + hi));
    (th, y, x)
}

#[test]
fn a_short_heavy_cantilever_falls_w_l4_over_8b() {
    let (b, l): (f64, f64) = (0.08, 20.0);
    let r = strip(l, 1.0).solve().unwrap();
    assert!(r.failure.is_none(), "{:?}", r.failure);
    let closed = weight() * l.powi(4) / (8.0 * b);
    let rel = r.tip_deflection_mm / closed - 1.0;
    assert!(
        rel.abs() < 0.02,
        "{:.4} mm against w L⁴/8B = {closed:.4} mm",
        r.tip_deflection_mm
    );
    // δ/L = 3.7 %: the elastica is a little stiffer than the linear beam; closer still to it.
    let (_, y, _) = elastica(b, weight(), l);
    assert!(
        (r.tip_deflection_mm / y - 1.0).abs() < 0.005,
        "{} against {y}",
        r.tip_deflection_mm
    );
}

#[test]
fn a_long_heavy_cantilever_follows_the_heavy_elastica_and_peirces_chord() {
    let b = 0.08;
    let c = (b / weight()).cbrt();
    // The standard's overhang: twice the bending length.
    let l = 2.0 * c;
    let r = strip(l, 1.0).solve().unwrap();
    assert!(r.failure.is_none(), "{:?}", r.failure);
    let (th, y, x) = elastica(b, weight(), l);
    let tip = r.tip_angle_deg;
    assert!(
        (tip / th.to_degrees() - 1.0).abs() < 0.02,
        "tip {tip:.3}° against {:.3}°",
        th.to_degrees()
    );
    assert!(
        (r.tip_deflection_mm / y - 1.0).abs() < 0.02,
        "{} against {y}",
        r.tip_deflection_mm
    );
    assert!(
        (r.tip_reach_mm / x - 1.0).abs() < 0.02,
        "{} against {x}",
        r.tip_reach_mm
    );
    // Peirce (ASTM D1388): at L = 2c the chord clamp → tip is 41.5° below horizontal.
    assert!(
        (r.chord_angle_deg - 41.5).abs() < 0.5,
        "chord {:.2}°",
        r.chord_angle_deg
    );
}

#[test]
fn the_cantilever_converges_with_the_mesh() {
    let l: f64 = 20.0;
    let closed = weight() * l.powi(4) / (8.0 * 0.08);
    let err = |h: f64| (strip(l, h).solve().unwrap().tip_deflection_mm / closed - 1.0).abs();
    let (coarse, fine) = (err(4.0), err(1.0));
    assert!(fine < coarse, "{fine} against {coarse}");
}

#[test]
fn the_woven_law_bends_as_the_elastica_too() {
    // The paper's crimp-interchange law with its compressive branch: the strip's membrane
    // strains are tiny, so its bending is the hinges' and the tip falls as the elastica's.
    let (b, l): (f64, f64) = (0.08, 40.0);
    let mut p = strip(l, 1.0);
    p.fabric.undulation = true;
    let r = p.solve().unwrap();
    assert!(r.failure.is_none(), "{:?}", r.failure);
    let (_, y, _) = elastica(b, weight(), l);
    assert!(
        (r.tip_deflection_mm / y - 1.0).abs() < 0.01,
        "{} mm against the elastica's {y} mm",
        r.tip_deflection_mm
    );
}

#[test]
fn bad_sizes_are_refused_before_any_work() {
    let mut p = strip(20.0, 1.0);
    p.areal_mass_g_m2 = 0.0;
    assert!(matches!(
        p.solve().unwrap_err(),
        CantileverError::NotPositive { .. }
    ));
}
