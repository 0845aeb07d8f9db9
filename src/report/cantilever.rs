//! The picture of `wovenform cantilever`: the strip seen from the side against the heavy
//! elastica of the same rigidity, weight and overhang, and the small-deflection beam.

use super::plot::{Colour, LegendAt, LineChart, Series};
use crate::core::specimens::cantilever::{CantileverProblem, CantileverResult, heavy_elastica};

/// The strip's centre line (the mean over its width of each column of nodes, from the clamp's
/// edge) as `(x, z)` in mm, against the elastica and the beam, whose fall is
/// `w x²(6L² − 4Lx + x²)/(24B)`.
pub fn profile_chart(problem: &CantileverProblem, result: &CantileverResult) -> LineChart {
    let (b, w, l) = (
        problem.bending_rigidity[0],
        result.areal_weight_n_mm2,
        problem.length,
    );
    let [n1, n2] = result.mesh.grid.expect("a yarn grid");
    let fe: Vec<(f64, f64)> = (1..=n1)
        .map(|i| {
            let k = (n2 + 1) as f64;
            let column = (0..=n2).map(|j| result.positions[j * (n1 + 1) + i]);
            let (x, z) = column.fold((0.0, 0.0), |(x, z), p| (x + p[0] / k, z + p[2] / k));
            (x, z)
        })
        .collect();
    let (_, elastica) = heavy_elastica(b, w, l, 2000);
    let elastica: Vec<(f64, f64)> = elastica.into_iter().map(|(x, y)| (x, -y)).collect();
    let beam: Vec<(f64, f64)> = (0..=200)
        .map(|i| {
            let x = l * i as f64 / 200.0;
            (
                x,
                -w * x * x * (6.0 * l * l - 4.0 * l * x + x * x) / (24.0 * b),
            )
        })
        .collect();
    let mut chart = LineChart::new(
        format!(
            "Heavy cantilever: {l} mm overhang, B = {b} N·mm, {} g/m²",
            problem.areal_mass_g_m2
        ),
        "distance from the clamp (mm)",
        "height relative to the clamp (mm)",
    )
    .with(Series::markers(
        "finite elements (centre line)",
        fe,
        Colour::nth(0),
    ))
    .with(Series::line(
        "heavy elastica B θ'' = −w (L − s) cos θ",
        elastica,
        Colour::nth(1),
    ))
    .with(Series::dashed(
        "small-deflection beam",
        beam,
        Colour::nth(2),
    ));
    chart.legend_at = LegendAt::LowerLeft;
    chart
}
