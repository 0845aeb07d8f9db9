//! The process window of a sweep along one number (the holder's pressure, say): each figure the
//! verdict judges, over its limit, against the swept value — the max shear over the locking
//! angle, the max tension over the break tension, the wrinkles over their limit — so the
//! values where every line stays under 1 (the window) show at a glance. Each point's marker
//! says where that figure's error band stands against its limit.

use super::chart::{Layout, x_axis, x_label};
use crate::report::panels::{Panel, PanelLine, PanelPoint, Panels};
use crate::report::plot::{Colour, tick_label};
use crate::study::sweep::{Design, Plan, Row, unit_of};
use crate::verdict::{Figures, Limits, Standing, Verdict};

/// The window chart, when exactly one number is swept (else `None`: the shear chart).
pub(super) fn window_chart(
    plan: &Plan,
    rows: &[Row],
    designs: &[Design],
) -> Option<(Panels, Vec<String>)> {
    let layout = Layout::of(plan)?;
    if !layout.numeric || !layout.panel_axes.is_empty() || !layout.line_axes.is_empty() {
        return None;
    }
    let limits = Limits::of(&plan.base_scene);
    // Shear and tension always; wrinkles where the fabric bends.
    let figures = if rows.iter().any(|r| r.max_wrinkle_mm.is_some()) {
        3
    } else {
        2
    };
    let lines: Vec<PanelLine> = (0..figures)
        .map(|which| line(rows, designs, plan, &layout, limits, which))
        .collect();
    let names = [
        format!(
            "max shear / locking angle {}°",
            tick_label(limits.locking_angle_deg)
        ),
        format!(
            "max tension / break {} N",
            tick_label(limits.break_tension_n)
        ),
        format!(
            "wrinkles / limit {} mm",
            tick_label(limits.wrinkle_limit_mm)
        ),
    ];
    let key = (names.into_iter().take(figures).enumerate())
        .map(|(which, name)| (name, Colour::nth(which)))
        .collect();
    let ys = lines.iter().flat_map(|l| &l.points).filter_map(|p| p.y);
    let top = ys.fold(1.0_f64, f64::max);
    let (x_ticks, x_range) = x_axis(plan, &layout);
    let axis = &plan.axes[layout.x];
    let unit = unit_of(&axis.key).trim().to_string();
    let x_label = x_label(plan, &layout);
    let chart = Panels {
        title: format!("The window in {x_label}: each figure over its limit"),
        x_label: x_label.clone(),
        y_label: "figure / its limit".into(),
        x_ticks,
        x_range,
        y_range: (0.0, 1.1 * top.min(3.0)),
        limit: Some((1.0, "the limit".into())),
        columns: 1,
        connect: true,
        panels: vec![Panel {
            title: String::new(),
            lines,
        }],
        key_title: "figure".into(),
        key,
    };
    let notes = notes(plan, rows, designs, &layout, &axis.column, &unit);
    Some((chart, notes))
}

/// One figure's line (0 shear, 1 tension, 2 wrinkles): each answered design's figure over its
/// limit, its marker where the figure's band stands against the limit.
fn line(
    rows: &[Row],
    designs: &[Design],
    plan: &Plan,
    layout: &Layout,
    limits: Limits,
    which: usize,
) -> PanelLine {
    let mut points: Vec<PanelPoint> = rows
        .iter()
        .map(|r| {
            let x = layout.x_of(plan, &designs[r.index]);
            match figures(r) {
                Some(f) => {
                    let (value, limit) = match which {
                        0 => (Some(f.max_shear_deg), limits.locking_angle_deg),
                        1 => (Some(f.max_tension_n), limits.break_tension_n),
                        _ => (f.max_wrinkle_mm, limits.wrinkle_limit_mm),
                    };
                    let verdict = match f.standing(limits)[which] {
                        Standing::Within => Verdict::Feasible,
                        Standing::Inside => Verdict::Marginal,
                        Standing::Over => Verdict::Infeasible,
                    };
                    PanelPoint {
                        x,
                        y: value.map(|v| (v / limit).min(3.0)),
                        verdict,
                    }
                }
                None => PanelPoint {
                    x,
                    y: None,
                    verdict: r.verdict,
                },
            }
        })
        .collect();
    points.sort_by(|a, b| a.x.total_cmp(&b.x));
    PanelLine {
        colour: Colour::nth(which),
        points,
    }
}

/// A row's figures, when its run answered.
fn figures(r: &Row) -> Option<Figures> {
    let answered = matches!(
        r.verdict,
        Verdict::Feasible | Verdict::Marginal | Verdict::Infeasible
    );
    if !answered || !r.converged {
        return None;
    }
    Some(Figures {
        max_shear_deg: r.max_shear_deg?,
        max_tension_n: r.max_tension_n?,
        max_shear_err_deg: r.max_shear_err_deg.unwrap_or(0.0),
        max_tension_err_pct: r.max_tension_err_pct.unwrap_or(0.0),
        max_wrinkle_mm: r.max_wrinkle_mm,
        max_wrinkle_err_mm: r.max_wrinkle_err_mm.unwrap_or(0.0),
    })
}

/// The notes under the chart: the feasible values in words, and how to read the markers.
fn notes(
    plan: &Plan,
    rows: &[Row],
    designs: &[Design],
    layout: &Layout,
    column: &str,
    unit: &str,
) -> Vec<String> {
    let mut by_x: Vec<(f64, Verdict)> = rows
        .iter()
        .map(|r| (layout.value_of(&designs[r.index]), r.verdict))
        .collect();
    by_x.sort_by(|a, b| a.0.total_cmp(&b.0));
    let feasible: Vec<String> = (by_x.iter())
        .filter(|(_, v)| *v == Verdict::Feasible)
        .map(|(x, _)| tick_label(*x))
        .collect();
    let window = if feasible.is_empty() {
        format!("No {column} of the sweep is feasible.")
    } else {
        format!(
            "Feasible at {column} = {} {unit} (every figure's band under its limit).",
            feasible.join(", ")
        )
    };
    let mut notes = vec![
        window,
        "Each point at its design's value exactly; filled: that figure's band is under its limit, hollow: the limit lies inside it, ×: over it (a figure over 3× its limit is drawn at 3)."
            .into(),
    ];
    let missing = plan.len().saturating_sub(rows.len());
    if missing > 0 {
        notes.push(format!(
            "{missing} design(s) not computed yet: not plotted."
        ));
    }
    notes
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(sweep: &str) -> Plan {
        let doc: toml::Table = format!("[sweep]\n{sweep}").parse().unwrap();
        Plan::from_document(std::path::Path::new("t.toml"), &doc, &[]).unwrap()
    }

    /// A row whose shear falls and tension rises with the design's index.
    fn row(plan: &Plan, d: &Design, verdict: Verdict) -> Row {
        let i = d.index as f64;
        Row {
            max_shear_deg: Some(62.5 - 3.0 * i),
            max_tension_n: Some(100.0 + 600.0 * i),
            max_shear_err_deg: Some(1.0),
            max_tension_err_pct: Some(10.0),
            feasible: verdict == Verdict::Feasible,
            converged: true,
            ..Row::new(d, plan.params(&plan.columns(), d), verdict)
        }
    }

    #[test]
    fn a_sweep_along_one_number_draws_each_figure_over_its_limit_on_a_log_scale() {
        let plan = plan("holder_pressure = [0.01, 0.1, 1.0, 10.0]");
        let designs = plan.designs();
        let verdicts = [
            Verdict::Infeasible,
            Verdict::Feasible,
            Verdict::Feasible,
            Verdict::Infeasible,
        ];
        let rows: Vec<Row> = (designs.iter().zip(verdicts))
            .map(|(d, v)| row(&plan, d, v))
            .collect();
        let (chart, notes) = window_chart(&plan, &rows, &designs).unwrap();
        let lines = &chart.panels[0].lines;
        assert_eq!(lines.len(), 2, "no wrinkle line without bending");
        let xs: Vec<f64> = lines[0].points.iter().map(|p| p.x).collect();
        assert_eq!(xs, [-2.0, -1.0, 0.0, 1.0]);
        // 62.5° ± 1° against 60°: over; 59.5° ± 1°: the limit inside the band; 56.5°: under.
        let shear: Vec<Verdict> = lines[0].points.iter().map(|p| p.verdict).collect();
        assert_eq!(
            shear,
            [
                Verdict::Infeasible,
                Verdict::Marginal,
                Verdict::Feasible,
                Verdict::Feasible
            ]
        );
        // 1,900 N ± 10 % against 1,500 N: over the break tension.
        let tension = &lines[1].points[3];
        assert_eq!(tension.verdict, Verdict::Infeasible);
        assert!((tension.y.unwrap() - 1900.0 / 1500.0).abs() < 1e-12);
        assert!(notes[0].contains("0.1, 1"), "{}", notes[0]);
        assert_eq!(chart.limit.as_ref().unwrap().0, 1.0);
    }

    #[test]
    fn two_swept_parameters_keep_the_shear_chart() {
        let plan = plan("r = [5.0, 10.0]\nholder_pressure = [0.1, 1.0]");
        let designs = plan.designs();
        let rows: Vec<Row> = (designs.iter())
            .map(|d| row(&plan, d, Verdict::Feasible))
            .collect();
        assert!(window_chart(&plan, &rows, &designs).is_none());
    }
}
