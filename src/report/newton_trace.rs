//! The Newton trace of one run (`wovenform run --newton-trace`): every iteration of every load
//! step as a CSV row, and a chart of the residual against the iterations, so that a person can
//! see where a run's iterations go (a quadratic tail, a linear one, an active set settling).

use crate::core::solver::SolveStats;
use crate::report::plot::{Colour, LineChart, Scale, Series};

/// The trace's columns, in order.
pub const COLUMNS: [&str; 17] = [
    "step",
    "accepted",
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

/// The trace as CSV: one row per iteration of each attempted load step. `step` counts the
/// load steps; an attempt that was cut back (`accepted` false) and its retry share a number. A
/// step's last row is the state it converged at (or stopped at): it has no correction, so no
/// line search length or damping. A correction whose line search found no length to take has
/// length 0. Empty of rows when the run did not record its iterations.
pub fn csv(stats: &SolveStats, stroke_mm: f64) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(COLUMNS).expect("writing to memory");
    let mut step = 1;
    for (s, residuals) in stats.residuals.iter().enumerate() {
        let accepted = stats.accepted(s);
        let load = stats.step_loads.get(s).copied().unwrap_or(f64::NAN);
        for k in 0..residuals.len() {
            let mut row = vec![
                step.to_string(),
                accepted.to_string(),
                format!("{load:.5}"),
                format!("{:.3}", load * stroke_mm),
            ];
            row.extend(iteration_fields(stats, s, k));
            w.write_record(&row).expect("writing to memory");
        }
        step += usize::from(accepted);
    }
    String::from_utf8(w.into_inner().expect("writing to memory")).expect("CSV of ASCII")
}

/// The columns from `iteration` on, for iteration `k` of recorded attempt `s`.
fn iteration_fields(stats: &SolveStats, s: usize, k: usize) -> Vec<String> {
    let at = |v: &Vec<Vec<f64>>| v.get(s).and_then(|a| a.get(k)).copied();
    let e3 = |v: f64| format!("{v:.3e}");
    let opt = |v: Option<f64>, fmt: &dyn Fn(f64) -> String| v.map_or(String::new(), fmt);
    let changes = stats.active_changes.get(s).and_then(|c| c.get(k));
    let mut row = vec![
        k.to_string(),
        opt(at(&stats.residuals), &e3),
        changes.map_or(String::new(), |c| c.to_string()),
        opt(at(&stats.alphas), &|v| format!("{v:.4}")),
        opt(at(&stats.damping), &e3),
    ];
    match stats.sites.get(s).and_then(|x| x.get(k)) {
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
    row
}

/// The residual of every iteration against the iterations counted through the run
/// (logarithmic), a line per load step (dashed for an attempt that was cut back); a cross marks
/// an iteration after which the active set (slack yarns, contacts) changed, a dot one after
/// which it did not.
pub fn chart(stats: &SolveStats, title: &str) -> LineChart {
    let mut chart = LineChart::new(title, "Newton iterations through the run", "residual (N)");
    chart.y_scale = Scale::Log;
    let (mut changed, mut settled) = (Vec::new(), Vec::new());
    let (mut count, mut cut_back) = (0usize, false);
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
        // Counted in corrections: a converged step's last residual has none, and is where the
        // next step starts from.
        let corrections = stats.alphas.get(s).map(Vec::len);
        count += corrections.unwrap_or(residuals.len().saturating_sub(1));
        if stats.accepted(s) {
            chart.push(Series::line("", line, Colour::GREY));
        } else {
            // An attempt cut back: dashed, named in the legend once.
            let name = if cut_back { "" } else { "an attempt cut back" };
            cut_back = true;
            chart.push(Series::dashed(name, line, Colour::PALETTE[1]));
        }
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
            step_accepted: vec![true, true],
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
            &last[..9],
            [
                "1", "true", "0.05000", "1.400", "2", "1.000e-1", "0", "", ""
            ]
        );
        assert!(lines[4].starts_with("2,true,0.10000,2.800,0,5.000e1,0,1.0000,"));
    }

    #[test]
    fn an_attempt_cut_back_keeps_its_rows_and_its_step_number() {
        let mut s = stats();
        // Step 2 first failed at 0.15 (its line search found nothing), then converged at 0.1.
        s.residuals.insert(1, vec![60.0, 40.0]);
        s.active_changes.insert(1, vec![0, 5]);
        s.alphas.insert(1, vec![0.5, 0.0]);
        s.damping.insert(1, vec![1e-4, 1e-3]);
        s.sites.insert(1, vec![ResidualSite::default(); 2]);
        s.step_loads.insert(1, 0.15);
        s.step_accepted.insert(1, false);
        let text = csv(&s, 28.0);
        let steps: Vec<&str> = text
            .lines()
            .skip(1)
            .map(|l| &l[..l.find(',').unwrap()])
            .collect();
        assert_eq!(steps, ["1", "1", "1", "2", "2", "2", "2"]);
        assert!(
            text.lines()
                .nth(5)
                .unwrap()
                .starts_with("2,false,0.15000,4.200,1,4.000e1,5,0.0000,")
        );
        let c = chart(&s, "t");
        assert_eq!(c.series.len(), 5);
        // The failed attempt's two corrections come before the retry's.
        assert_eq!(c.series[1].points, vec![(2.0, 60.0), (3.0, 40.0)]);
        assert_eq!(c.series[2].points, vec![(4.0, 50.0), (5.0, 0.5)]);
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
