//! The chart of `wovenform converge`: each rung's error against its wall time, log-log.

use crate::converge::Ladder;
use crate::report::plot::{Colour, LegendAt, LineChart, Series};

/// Error of the maximum shear (°) and of the punch force (%) against wall time (s), for the
/// mesh ladder and the step ladder. Rungs with no error to show (the reference itself) are
/// left out of the logarithmic axes.
pub fn chart(mesh: &Ladder, steps: &Ladder) -> LineChart {
    let mut chart = LineChart::new(
        "Error against run time (one core)",
        "wall time (s)",
        "error: max shear (°), punch force (%)",
    )
    .log_log();
    chart.legend_at = LegendAt::UpperRight;
    let points = |ladder: &Ladder, k: usize| -> Vec<(f64, f64)> {
        ladder
            .rungs
            .iter()
            .enumerate()
            .filter(|(_, r)| r.converged)
            .map(|(i, r)| (r.wall_s, ladder.error(i, k)))
            .filter(|p| p.0 > 0.0 && p.1 > 0.0)
            .collect()
    };
    for (ladder, name, colour) in [
        (mesh, "mesh ladder", Colour::nth(0)),
        (steps, "step ladder", Colour::nth(1)),
    ] {
        let (shear, force) = (points(ladder, 0), points(ladder, 1));
        chart.push(Series::line(
            format!("{name}: max shear (°)"),
            shear.clone(),
            colour,
        ));
        chart.push(Series::markers("", shear, colour));
        chart.push(Series::dashed(
            format!("{name}: punch force (%)"),
            force.clone(),
            colour,
        ));
        chart.push(Series::crosses("", force, colour));
    }
    chart
}
