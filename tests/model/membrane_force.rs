//! The element's least principal membrane force, which tells a taut fabric (it cannot wrinkle)
//! from a compressed or slack one: against the statics of a uniformly stretched rectangle (the
//! yarns' tension times the yarns per millimetre) and of a pure shear (the shear moment per
//! unit area is the shear stress, principal forces ±M).

use wovenform::core::fabric::law::{CellLaw, CellParams};
use wovenform::core::fabric::shear::ShearLaw;
use wovenform::core::membrane::element::{self, ElementGeometry, ElementOutput, GAUSS};

fn solved(geo: &ElementGeometry, law: &CellLaw, x: &[[f64; 3]; 4]) -> ElementOutput {
    let mut crimp = [law.initial_state(); GAUSS];
    let mut out = ElementOutput::default();
    element::evaluate(geo, law, x, &mut crimp, false, &mut out);
    out
}

fn rectangle(a: f64, b: f64) -> [[f64; 3]; 4] {
    [[0.0, 0.0, 0.0], [a, 0.0, 0.0], [a, b, 0.0], [0.0, b, 0.0]]
}

#[test]
fn a_stretched_rectangle_carries_its_yarns_tension_per_millimetre() {
    let mut p = CellParams::PAPER_GLASS;
    p.undulation = false;
    let law = CellLaw::new(p);
    let x0 = rectangle(5.0, 4.0);
    let geo = ElementGeometry::new(&x0, None, p.l0[0] * p.l0[1]).unwrap();
    // Tilted out of the plane too: the force lies in the fabric's own plane.
    for (e1, e2, tilt) in [(0.004, 0.01, 0.0), (0.01, 0.004, 0.3), (0.006, -0.01, 0.5)] {
        let x = x0.map(|q| {
            let (u, v) = (q[0] * (1.0 + e1), q[1] * (1.0 + e2));
            [u, v * f64::cos(tilt), v * f64::sin(tilt)]
        });
        let out = solved(&geo, &law, &x);
        let t = out.tension[0];
        // A yarn family α carries Tα on each yarn, 1/l0β yarns per mm across it; Kirchhoff's
        // measure per initial length multiplies by the stretch along it.
        let along = [t[0] * (1.0 + e1) / p.l0[1], t[1] * (1.0 + e2) / p.l0[0]];
        let want = along[0].min(along[1]);
        let got = element::least_membrane_force_n_per_mm(&geo, &law, &x, &out.tension);
        assert!(
            (got - want).abs() <= 1e-9 * want.abs().max(1.0),
            "{e1} {e2}: {got} against {want}"
        );
        assert_eq!(
            got > 0.0,
            e1 > 0.0 && e2 > 0.0,
            "{e1} {e2}: taut only when both stretch"
        );
    }
}

#[test]
fn a_pure_shear_has_principal_forces_of_plus_and_minus_its_moment() {
    let mut p = CellParams::PAPER_GLASS;
    p.undulation = false;
    let shear = ShearLaw::new([0.09, -0.04, 0.25]);
    let law = CellLaw::new(p).with_shear(Some(shear));
    let x0 = rectangle(5.0, 5.0);
    let geo = ElementGeometry::new(&x0, None, p.l0[0] * p.l0[1]).unwrap();
    let gamma: f64 = 0.02;
    // Pure shear without rotation: each yarn turns by γ/2 towards the other, both lengths kept.
    let (c, s) = ((gamma / 2.0).cos(), (gamma / 2.0).sin());
    let x = x0.map(|q| [c * q[0] + s * q[1], s * q[0] + c * q[1], 0.0]);
    let mut out = solved(&geo, &law, &x);
    // The yarns' tension (a stretch of 1 − γ²/8 at most) is the law's: the shear alone here.
    out.tension = [[0.0; 2]; GAUSS];
    let got = element::least_membrane_force_n_per_mm(&geo, &law, &x, &out.tension);
    let m = shear.moment(gamma);
    assert!(
        got < 0.0,
        "a sheared cell is compressed along one bisector: {got}"
    );
    assert!((got + m).abs() < 0.03 * m, "{got} against −{m}");
}
