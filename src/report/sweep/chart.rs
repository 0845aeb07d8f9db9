//! The sweep's chart: max shear against a swept radius, the locking angle as a dashed line.

use std::collections::{BTreeMap, HashSet};

use crate::report::plot::{Colour, LegendAt, LineChart, Series, Style, tick_label};
use crate::study::sweep::{Axis, Design, Plan, Row, as_number, show_value, unit_of};
use crate::verdict::Verdict;

/// Values of a numeric axis, sorted and distinct.
fn numeric_values(axis: &Axis) -> Option<Vec<f64>> {
    let mut v: Vec<f64> = axis.values.iter().map(as_number).collect::<Option<_>>()?;
    v.sort_by(|a, b| a.total_cmp(b));
    v.dedup();
    Some(v)
}

/// Max shear against a swept radius (or the first numeric swept parameter), one line per
/// combination of the other swept parameters, the locking angle as a dashed line.
pub(super) fn shear_chart(
    plan: &Plan,
    rows: &[Row],
    designs: &[Design],
) -> (Option<LineChart>, Vec<String>) {
    let swept: Vec<usize> = (0..plan.axes.len())
        .filter(|&a| plan.axes[a].values.len() > 1)
        .collect();
    let numeric = |a: usize| numeric_values(&plan.axes[a]).filter(|v| v.len() > 1);
    let x_axis = swept
        .iter()
        .copied()
        .find(|&a| {
            matches!(plan.axes[a].column.as_str(), "r" | "rp" | "rm") && numeric(a).is_some()
        })
        .or_else(|| swept.iter().copied().find(|&a| numeric(a).is_some()));
    let Some(xa) = x_axis else {
        return (
            None,
            vec!["(no chart: no numeric parameter takes more than one value)".into()],
        );
    };
    let xs = numeric(xa).expect("numeric");
    let spacing = xs
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    let others: Vec<usize> = swept.iter().copied().filter(|&a| a != xa).collect();
    let xname = plan.axes[xa].column.clone();
    let xunit = unit_of(&plan.axes[xa].key).trim().to_string();
    let locking = plan.base_scene.fabric.locking_angle_deg;
    // Groups: the designs sharing the values of the other swept axes.
    let mut groups: BTreeMap<Vec<String>, Vec<&Row>> = BTreeMap::new();
    let mut order: Vec<Vec<String>> = Vec::new();
    for r in rows {
        let d = &designs[r.index];
        let key: Vec<String> = others.iter().map(|&a| show_value(&d.values[a])).collect();
        if !groups.contains_key(&key) {
            order.push(key.clone());
        }
        groups.entry(key).or_default().push(r);
    }
    // Only the groups with a point to plot (a converged run) take a place in the dodge.
    let plotted = |r: &Row| r.converged && r.max_shear_deg.is_some();
    order.retain(|k| groups[k].iter().any(|r| plotted(r)));
    let ng = order.len().max(1);
    let left_out = rows.iter().filter(|r| !plotted(r)).count();
    // Lines coloured by the first other axis when it has few values.
    let colour_axis = others
        .first()
        .copied()
        .filter(|&a| plan.axes[a].values.len() <= 7);
    let mut chart = LineChart::new(
        format!(
            "Max shear against {xname}{}",
            if xunit.is_empty() {
                String::new()
            } else {
                format!(" ({xunit})")
            }
        ),
        if xunit.is_empty() {
            xname.clone()
        } else {
            format!("{xname} ({xunit})")
        },
        "max shear (°)",
    );
    let mut feasible_pts = Vec::new();
    let mut infeasible_pts = Vec::new();
    let mut named: HashSet<String> = HashSet::new();
    for (gi, key) in order.iter().enumerate() {
        let dodge = if ng > 1 && spacing.is_finite() {
            ((gi as f64 + 0.5) / ng as f64 - 0.5) * 0.25 * spacing
        } else {
            0.0
        };
        let mut pts: Vec<(f64, f64)> = Vec::new();
        for r in &groups[key] {
            let d = &designs[r.index];
            let (Some(x), Some(y)) = (as_number(&d.values[xa]), r.max_shear_deg) else {
                continue;
            };
            if !r.converged {
                continue;
            }
            let p = (x + dodge, y);
            pts.push(p);
            if r.verdict == Verdict::Feasible {
                feasible_pts.push(p);
            } else {
                infeasible_pts.push(p);
            }
        }
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        if pts.is_empty() {
            continue;
        }
        let (name, colour) = match colour_axis {
            Some(ca) => {
                let v = &designs[groups[key][0].index].values[ca];
                let vi = plan.axes[ca]
                    .values
                    .iter()
                    .position(|x| x == v)
                    .unwrap_or(0);
                let label = format!(
                    "{} = {}{}",
                    plan.axes[ca].column,
                    show_value(v),
                    unit_of(&plan.axes[ca].key)
                );
                let name = if named.insert(label.clone()) {
                    label
                } else {
                    String::new()
                };
                (name, Colour::nth(vi))
            }
            None => (String::new(), Colour::nth(gi)),
        };
        chart.push(Series::new(name, pts, Style::Line, colour));
    }
    let pad = if spacing.is_finite() {
        0.45 * spacing
    } else {
        1.0
    };
    let (x0, x1) = (xs[0] - pad, xs[xs.len() - 1] + pad);
    chart.push(Series::dashed(
        format!("locking angle {}°", tick_label(locking)),
        vec![(x0, locking), (x1, locking)],
        Colour::BLACK,
    ));
    chart.x_range = Some((x0, x1));
    // The y axis spans the designs and the locking angle (the boundary stays in view).
    let ys = feasible_pts.iter().chain(&infeasible_pts).map(|p| p.1);
    let (lo, hi) = ys.fold((locking, locking), |(lo, hi), y| (lo.min(y), hi.max(y)));
    let pad = 0.12 * (hi - lo) + 1.0;
    chart.y_range = Some(((lo - pad).max(0.0), hi + pad));
    chart.push(Series::markers(
        "✓ feasible",
        feasible_pts,
        Colour(0, 150, 100),
    ));
    chart.push(Series::crosses(
        "✗ infeasible",
        infeasible_pts,
        Colour(213, 70, 0),
    ));
    chart.legend_at = LegendAt::LowerLeft;
    let mut note = Vec::new();
    if !others.is_empty() {
        let names: Vec<&str> = others
            .iter()
            .map(|&a| plan.axes[a].column.as_str())
            .collect();
        note.push(format!(
            "Each line: one combination of {}; points nudged sideways to keep them apart.",
            names.join(", ")
        ));
    }
    note.push(format!(
        "Above the dashed line the fabric shears past its locking angle ({}°): infeasible.",
        tick_label(locking)
    ));
    if left_out > 0 {
        note.push(format!(
            "{left_out} design(s) without a converged run are not plotted."
        ));
    }
    (Some(chart), note)
}
