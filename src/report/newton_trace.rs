//! The Newton trace of one run (`wovenform run --newton-trace`): every iteration of every load
//! step as a CSV row, and a chart of the residual against the iterations, so that a person can
//! see where a run's iterations go (a quadratic tail, a linear one, an active set settling).

use crate::core::solver::SolveStats;
use crate::report::plot::{Colour, LineChart, Scale, Series};

/// The trace's columns, in order.
pub const COLUMNS: [&str; 16] = [
    "step",
    "load_factor",
    "punch_travel_mm",
    "iteration",
    "residual_n",
    "active_changes",
    "line_search_length",
    "damping",
    "largest_node",
    "largest_x_mm",
    "largest_y_mm",
    "largest_z_mm",
    "largest_residual_n",
    "largest_touching",
    "share_touching",
    "share_on_toe",
];

/// The trace as CSV: one row per iteration of each accepted step (a step's last row is the
/// state that converged: it has no correction, so no line search length or damping). Empty
/// of rows when the run did not record its iterations.
pub fn csv(stats: &SolveStats, stroke_mm: f64) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(COLUMNS).expect("writing to memory");
    for (s, residuals) in stats.residuals.iter().enumerate() {
        let load = stats.step_loads.get(s).copied().unwrap_or(f64::NAN);
        for (k, &r) in residuals.iter().enumerate() {
            let changes = stats.active_changes.get(s).and_then(|c| c.get(k));
            let alpha = stats.alphas.get(s).and_then(|a| a.get(k));
            let damping = stats.damping.get(s).and_then(|d| d.get(k));
            let site = stats.sites.get(s).and_then(|x| x.get(k));
            let opt =
                |v: Option<&f64>, fmt: fn(f64) -> String| v.map_or(String::new(), |&v| fmt(v));
            let e3 = |v: f64| format!("{v:.3e}");
            let f4 = |v: f64| format!("{v:.4}");
            let mut row = vec![
                (s + 1).to_string(),
                format!("{load:.5}"),
                format!("{:.3}", load * stroke_mm),
                k.to_string(),
                e3(r),
                changes.map_or(String::new(), |c| c.to_string()),
                opt(alpha, f4),
                opt(damping, e3),
            ];
            match site {
                Some(x) => row.extend([
                    x.node.to_string(),
                    format!("{:.3}", x.position_mm[0]),
                    format!("{:.3}", x.position_mm[1]),
                    format!("{:.3}", x.position_mm[2]),
                    e3(x.residual_n),
                    x.touching.to_string(),
                    format!("{:.3}", x.share_touching),
                    format!("{:.3}", x.share_on_toe),
                ]),
                None => row.extend(std::iter::repeat_n(String::new(), 8)),
            }
            w.write_record(&row).expect("writing to memory");
        }
    }
    String::from_utf8(w.into_inner().expect("writing to memory")).expect("CSV of ASCII")
}

/// The residual of every iteration against the iterations counted through the run
/// (logarithmic), a line per load step; a cross marks an iteration after which the active set
/// (slack yarns, contacts) changed, a dot one after which it did not.
pub fn chart(stats: &SolveStats, title: &str) -> LineChart {
    let mut chart = LineChart::new(title, "Newton iterations through the run", "residual (N)");
    chart.y_scale = Scale::Log;
    let (mut changed, mut settled) = (Vec::new(), Vec::new());
    let mut count = 0usize;
    for (s, residuals) in stats.residuals.iter().enumerate() {
        let mut line = Vec::with_capacity(residuals.len());
        for (k, &r) in residuals.iter().enumerate() {
            let x = (count + k) as f64;
            line.push((x, r));
            let change = stats.active_changes.get(s).and_then(|c| c.get(k));
            match change {
                Some(&c) if k > 0 && c > 0 => changed.push((x, r)),
                Some(_) if k > 0 => settled.push((x, r)),
                _ => {}
            }
        }
        // A step's last residual is its converged state, where the next step starts from.
        count += residuals.len().saturating_sub(1);
        chart.push(Series::line("", line, Colour::GREY));
    }
    chart.push(Series::crosses(
        "after a change of the active set",
        changed,
        Colour::PALETTE[1],
    ));
    chart.push(Series::markers(
        "active set unchanged",
        settled,
        Colour::PALETTE[0],
    ));
    chart.legend_at = crate::report::plot::LegendAt::LowerRight;
    chart
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::solver::ResidualSite;

    fn stats() -> SolveStats {
        SolveStats {
            residuals: vec![vec![100.0, 10.0, 0.1], vec![50.0, 0.5]],
            active_changes: vec![vec![0, 3, 0], vec![0, 0]],
            alphas: vec![vec![1.0, 0.5], vec![1.0]],
            damping: vec![vec![1e-4, 0.0], vec![0.0]],
            sites: vec![
                vec![ResidualSite::default(); 3],
                vec![ResidualSite::default(); 2],
            ],
            step_loads: vec![0.05, 0.1],
            ..Default::default()
        }
    }

    #[test]
    fn a_row_per_iteration_and_the_last_of_a_step_without_a_correction() {
        let text = csv(&stats(), 28.0);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], COLUMNS.join(","));
        assert_eq!(lines.len(), 1 + 3 + 2);
        // Step 1's converged state: no line search length, no damping.
        let last: Vec<&str> = lines[3].split(',').collect();
        assert_eq!(
            &last[..8],
            ["1", "0.05000", "1.400", "2", "1.000e-1", "0", "", ""]
        );
        assert!(lines[4].starts_with("2,0.10000,2.800,0,5.000e1,0,1.0000,"));
    }

    #[test]
    fn the_chart_counts_the_iterations_through_the_run() {
        let c = chart(&stats(), "t");
        // Two step lines, then the crosses and the dots.
        assert_eq!(c.series.len(), 4);
        assert_eq!(c.series[1].points, vec![(2.0, 50.0), (3.0, 0.5)]);
        assert_eq!(c.series[2].points, vec![(1.0, 10.0)]);
        assert_eq!(c.series[3].points, vec![(2.0, 0.1), (3.0, 0.5)]);
    }
}
