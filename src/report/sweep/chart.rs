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
    let Some(xa) = x_axis(plan) else {
        return (
            None,
            vec!["(no chart: no numeric parameter takes more than one value)".into()],
        );
    };
    let xs = numeric_values(&plan.axes[xa]).expect("a numeric axis");
    let spacing = xs
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    let others: Vec<usize> = (0..plan.axes.len())
        .filter(|&a| a != xa && plan.axes[a].values.len() > 1)
        .collect();
    let locking = plan.base_scene.fabric.locking_angle_deg;
    let (groups, order) = groups(rows, designs, &others);
    let left_out = rows.iter().filter(|r| !plotted(r)).count();
    // Lines coloured by the first other axis when it has few values.
    let colour_axis = others
        .first()
        .copied()
        .filter(|&a| plan.axes[a].values.len() <= 7);
    let mut chart = empty_chart(plan, xa);
    let mut points = Points::default();
    let mut named: HashSet<String> = HashSet::new();
    let ng = order.len().max(1);
    for (gi, key) in order.iter().enumerate() {
        let dodge = if ng > 1 && spacing.is_finite() {
            ((gi as f64 + 0.5) / ng as f64 - 0.5) * 0.25 * spacing
        } else {
            0.0
        };
        let pts = points.of_group(&groups[key], designs, xa, dodge);
        if pts.is_empty() {
            continue;
        }
        let (name, colour) = match colour_axis {
            Some(ca) => {
                let v = &designs[groups[key][0].index].values[ca];
                let (label, colour) = line_label(plan, ca, v);
                let name = if named.insert(label.clone()) {
                    label
                } else {
                    String::new()
                };
                (name, colour)
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
    points.frame(&mut chart, (xs[0] - pad, xs[xs.len() - 1] + pad), locking);
    (Some(chart), notes(plan, &others, locking, left_out))
}

/// The x axis: the first swept radius with numbers, else the first numeric swept parameter.
fn x_axis(plan: &Plan) -> Option<usize> {
    let numeric = |a: usize| {
        plan.axes[a].values.len() > 1 && numeric_values(&plan.axes[a]).is_some_and(|v| v.len() > 1)
    };
    let radius = |a: usize| matches!(plan.axes[a].column.as_str(), "r" | "rp" | "rm");
    (0..plan.axes.len())
        .find(|&a| radius(a) && numeric(a))
        .or_else(|| (0..plan.axes.len()).find(|&a| numeric(a)))
}

/// A point to plot: a converged run with a max shear.
fn plotted(r: &Row) -> bool {
    r.converged && r.max_shear_deg.is_some()
}

type Groups<'a> = BTreeMap<Vec<String>, Vec<&'a Row>>;

/// The designs grouped by the values of the other swept axes, and the groups with a point to
/// plot in order of first appearance (only they take a place in the dodge).
fn groups<'a>(
    rows: &'a [Row],
    designs: &[Design],
    others: &[usize],
) -> (Groups<'a>, Vec<Vec<String>>) {
    let mut groups: Groups = BTreeMap::new();
    let mut order: Vec<Vec<String>> = Vec::new();
    for r in rows {
        let d = &designs[r.index];
        let key: Vec<String> = others.iter().map(|&a| show_value(&d.values[a])).collect();
        if !groups.contains_key(&key) {
            order.push(key.clone());
        }
        groups.entry(key).or_default().push(r);
    }
    order.retain(|k| groups[k].iter().any(|r| plotted(r)));
    (groups, order)
}

/// The chart with its title and axis names, no series yet.
fn empty_chart(plan: &Plan, xa: usize) -> LineChart {
    let xname = plan.axes[xa].column.clone();
    let xunit = unit_of(&plan.axes[xa].key).trim().to_string();
    let (title, x_label) = if xunit.is_empty() {
        (format!("Max shear against {xname}"), xname)
    } else {
        (
            format!("Max shear against {xname} ({xunit})"),
            format!("{xname} ({xunit})"),
        )
    };
    LineChart::new(title, x_label, "max shear (°)")
}

/// The legend label and colour of a line coloured by axis `ca` at value `v`.
fn line_label(plan: &Plan, ca: usize, v: &toml::Value) -> (String, Colour) {
    let axis = &plan.axes[ca];
    let vi = axis.values.iter().position(|x| x == v).unwrap_or(0);
    let label = format!("{} = {}{}", axis.column, show_value(v), unit_of(&axis.key));
    (label, Colour::nth(vi))
}

/// The points plotted, by verdict.
#[derive(Default)]
struct Points {
    feasible: Vec<(f64, f64)>,
    marginal: Vec<(f64, f64)>,
    infeasible: Vec<(f64, f64)>,
}

impl Points {
    /// The points of one group, nudged sideways by `dodge`, sorted along x.
    fn of_group(
        &mut self,
        group: &[&Row],
        designs: &[Design],
        xa: usize,
        dodge: f64,
    ) -> Vec<(f64, f64)> {
        let mut pts: Vec<(f64, f64)> = Vec::new();
        for r in group {
            let d = &designs[r.index];
            let (Some(x), Some(y)) = (as_number(&d.values[xa]), r.max_shear_deg) else {
                continue;
            };
            if !r.converged {
                continue;
            }
            let p = (x + dodge, y);
            pts.push(p);
            match r.verdict {
                Verdict::Feasible => self.feasible.push(p),
                Verdict::Marginal => self.marginal.push(p),
                _ => self.infeasible.push(p),
            }
        }
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        pts
    }

    /// The locking line, the ranges (the y axis spans the designs and the locking angle, so
    /// the boundary stays in view) and the verdict markers.
    fn frame(self, chart: &mut LineChart, (x0, x1): (f64, f64), locking: f64) {
        chart.push(Series::dashed(
            format!("locking angle {}°", tick_label(locking)),
            vec![(x0, locking), (x1, locking)],
            Colour::BLACK,
        ));
        chart.x_range = Some((x0, x1));
        let ys = self
            .feasible
            .iter()
            .chain(&self.marginal)
            .chain(&self.infeasible)
            .map(|p| p.1);
        let (lo, hi) = ys.fold((locking, locking), |(lo, hi), y| (lo.min(y), hi.max(y)));
        let pad = 0.12 * (hi - lo) + 1.0;
        chart.y_range = Some(((lo - pad).max(0.0), hi + pad));
        let colour = |v: Verdict| {
            let (r, g, b) = v.colour();
            Colour(r, g, b)
        };
        chart.push(Series::markers(
            "✓ feasible",
            self.feasible,
            colour(Verdict::Feasible),
        ));
        if !self.marginal.is_empty() {
            chart.push(Series::markers(
                "≈ marginal",
                self.marginal,
                colour(Verdict::Marginal),
            ));
        }
        chart.push(Series::crosses(
            "✗ infeasible",
            self.infeasible,
            colour(Verdict::Infeasible),
        ));
        chart.legend_at = LegendAt::LowerLeft;
    }
}

/// The notes under the chart.
fn notes(plan: &Plan, others: &[usize], locking: f64, left_out: usize) -> Vec<String> {
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
    note
}
