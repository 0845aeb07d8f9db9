//! What a bias-extension test shows: its force–displacement curve against the ideal
//! kinematics' curve of the same shear law, its centre's shear against the ideal, and the
//! specimen's shear map.

use crate::core::fabric::shear::ShearLaw;
use crate::core::specimens::bias::{BiasProblem, BiasResult, ideal_force, ideal_shear};

use super::maps::{FieldMap, Unit};
use super::plot::{Colour, LineChart, Series};

/// How far the test's curves depart from the ideal kinematics (inextensible, pin-jointed
/// yarns), over the points reached.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Departure {
    /// Largest |γ − γ_ideal| at the centre, degrees, and where (grip displacement, mm).
    pub shear_deg: f64,
    pub shear_at_mm: f64,
    /// RMS of (F − F_ideal) / F_ideal over the points past 1 mm, and the largest.
    pub force_rms_rel: f64,
    pub force_max_rel: f64,
}

/// The departure of `result` from the ideal kinematics of `problem`'s law.
pub fn departure(problem: &BiasProblem, result: &BiasResult) -> Departure {
    let (h, w) = (problem.length, problem.width);
    let law = problem.shear.unwrap_or(ShearLaw::new([0.0; 3]));
    let mut d = Departure {
        shear_deg: 0.0,
        shear_at_mm: 0.0,
        force_rms_rel: 0.0,
        force_max_rel: 0.0,
    };
    let mut sum = 0.0;
    let mut count = 0;
    for ((&x, &f), &g) in result
        .displacement_mm
        .iter()
        .zip(&result.force_n)
        .zip(&result.shear_centre_deg)
    {
        let dg = (g - ideal_shear(h, w, x).to_degrees()).abs();
        if dg > d.shear_deg {
            d.shear_deg = dg;
            d.shear_at_mm = x;
        }
        let ideal = ideal_force(&law, h, w, x);
        if x > 1.0 && ideal > 0.0 {
            let rel = (f - ideal) / ideal;
            sum += rel * rel;
            count += 1;
            d.force_max_rel = d.force_max_rel.max(rel.abs());
        }
    }
    d.force_rms_rel = if count > 0 {
        (sum / count as f64).sqrt()
    } else {
        0.0
    };
    d
}

/// The force–displacement chart: the test's curve, the ideal kinematics' curve of its law,
/// and measured points when given.
pub fn force_chart(
    problem: &BiasProblem,
    result: &BiasResult,
    measured: Option<&[(f64, f64)]>,
) -> LineChart {
    let (h, w) = (problem.length, problem.width);
    let law = problem.shear.unwrap_or(ShearLaw::new([0.0; 3]));
    let fe: Vec<(f64, f64)> = result
        .displacement_mm
        .iter()
        .copied()
        .zip(result.force_n.iter().copied())
        .collect();
    let n = 200;
    let ideal: Vec<(f64, f64)> = (0..=n)
        .map(|i| {
            let x = problem.stroke * i as f64 / n as f64;
            (x, ideal_force(&law, h, w, x))
        })
        .collect();
    let k = law.k;
    let mut chart = LineChart::new(
        format!("Bias extension {h} × {w} mm, yarns at ±45°: force on the grip"),
        "grip displacement (mm)",
        "force (N)",
    )
    .with(Series::line(
        format!(
            "finite elements, M = {k1}γ {k3}γ³ {k5}γ⁵ N·mm/mm²",
            k1 = fmt(k[0]),
            k3 = signed(k[1]),
            k5 = signed(k[2])
        ),
        fe,
        Colour::nth(0),
    ))
    .with(Series::dashed(
        "ideal kinematics (pin-jointed, inextensible)",
        ideal,
        Colour::nth(1),
    ));
    if let Some(points) = measured {
        chart.push(Series::markers(
            "measured",
            points.to_vec(),
            Colour(40, 40, 40),
        ));
    }
    chart
}

/// A later coefficient with its sign as the operator: `+ 0.08`, `− 0.0786`.
fn signed(v: f64) -> String {
    if v < 0.0 {
        format!("− {}", fmt(-v))
    } else {
        format!("+ {}", fmt(v))
    }
}

/// A coefficient in four decimals.
fn fmt(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v:.4}")
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    }
}

/// The specimen's shear map at the end of the pull.
pub fn shear_map(problem: &BiasProblem, result: &BiasResult, locking_angle_deg: f64) -> FieldMap {
    let quads: Vec<[[f64; 2]; 4]> = result
        .mesh
        .quads
        .iter()
        .map(|q| q.map(|n| [result.positions[n][0], result.positions[n][1]]))
        .collect();
    let values: Vec<f64> = result.shear_deg.iter().map(|s| s.abs()).collect();
    let (e, max) = values
        .iter()
        .enumerate()
        .fold((0, 0.0), |a, (i, &v)| if v > a.1 { (i, v) } else { a });
    let centre = quads.get(e).map(|q| {
        let mut c = [0.0; 2];
        for p in q {
            c[0] += 0.25 * p[0];
            c[1] += 0.25 * p[1];
        }
        c
    });
    let reached = result.displacement_mm.last().copied().unwrap_or(0.0);
    let title = format!(
        "Bias extension {} × {} mm: shear at {reached:.1} mm of pull (centre {})",
        problem.length,
        problem.width,
        Unit::Degrees.show(result.shear_centre_deg.last().copied().unwrap_or(0.0))
    );
    let subtitle = format!(
        "|change of the angle between the yarns| in each element, final positions; ideal centre {}",
        Unit::Degrees.show(ideal_shear(problem.length, problem.width, reached).to_degrees())
    );
    FieldMap {
        max_at: centre,
        peak: Some(max),
        size: (1100, 700),
        ..FieldMap::shear(title, subtitle, quads, values, locking_angle_deg)
    }
}
