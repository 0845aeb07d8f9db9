//! The sweep's chart: max shear against one swept parameter (a radius when one is swept), in
//! small multiples — a panel per combination of the swept parameters with the most values, a
//! coloured line per value of the rest (at most four lines a panel) — the locking angle in
//! every panel, each point at its exact swept value, its marker saying its verdict.

use crate::report::panels::{Panel, PanelLine, PanelPoint, Panels};
use crate::report::plot::{Colour, tick_label};
use crate::study::sweep::{Axis, Design, Plan, Row, as_number, show_value, unit_of};
use crate::verdict::Verdict;

/// Lines in one panel, at most (more only when the panels would be too many).
const LINES: usize = 4;
/// Panels drawn, at most: past this the first ones, and a note.
pub const MAX_PANELS: usize = 36;
/// A swept number whose largest value is at least this many times its smallest (all positive)
/// is drawn on a log scale.
const LOG_SPAN: f64 = 30.0;

/// Values of a numeric axis, sorted and distinct.
fn numeric_values(axis: &Axis) -> Option<Vec<f64>> {
    let mut v: Vec<f64> = axis.values.iter().map(as_number).collect::<Option<_>>()?;
    v.sort_by(|a, b| a.total_cmp(b));
    v.dedup();
    Some(v)
}

/// The x axis: the first swept radius with numbers, else the first numeric swept parameter.
fn numeric_x_axis(plan: &Plan) -> Option<usize> {
    let numeric = |a: usize| numeric_values(&plan.axes[a]).is_some_and(|v| v.len() > 1);
    let radius = |a: usize| matches!(plan.axes[a].column.as_str(), "r" | "rp" | "rm");
    (0..plan.axes.len())
        .find(|&a| radius(a) && numeric(a))
        .or_else(|| (0..plan.axes.len()).find(|&a| numeric(a)))
}

/// How the swept parameters are laid out on the chart.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Layout {
    /// Along x; `numeric` false: its values side by side in grid order.
    pub x: usize,
    pub numeric: bool,
    /// Along x on a log scale (positive numbers spanning at least `LOG_SPAN`).
    pub log: bool,
    /// One panel per combination of these (grid order, the first varying slowest).
    pub panel_axes: Vec<usize>,
    /// One line colour per combination of these.
    pub line_axes: Vec<usize>,
}

impl Layout {
    /// The layout of a plan's swept axes (those with more than one value); `None` when
    /// nothing is swept.
    pub fn of(plan: &Plan) -> Option<Layout> {
        let count = |a: usize| plan.axes[a].values.len();
        let swept: Vec<usize> = (0..plan.axes.len()).filter(|&a| count(a) > 1).collect();
        let (x, numeric) = match numeric_x_axis(plan) {
            Some(x) => (x, true),
            None => (*swept.first()?, false),
        };
        let mut others: Vec<usize> = swept.into_iter().filter(|&a| a != x).collect();
        // The axes with the most values make the panels; the lines take the rest, from the
        // fewest values up, while a panel holds at most LINES of them (more, up to the
        // palette, when the panels would be too many).
        others.sort_by_key(|&a| std::cmp::Reverse(count(a)));
        let split = |max_lines: usize| {
            let mut lines: Vec<usize> = Vec::new();
            let mut product = 1;
            for &a in others.iter().rev() {
                if product * count(a) > max_lines {
                    break;
                }
                product *= count(a);
                lines.push(a);
            }
            let mut panels: Vec<usize> = others
                .iter()
                .copied()
                .filter(|a| !lines.contains(a))
                .collect();
            panels.sort_unstable();
            lines.sort_unstable();
            (panels, lines)
        };
        let panel_count = |p: &[usize]| p.iter().map(|&a| count(a)).product::<usize>();
        let (mut panel_axes, mut line_axes) = split(LINES);
        if panel_count(&panel_axes) > MAX_PANELS {
            (panel_axes, line_axes) = split(Colour::PALETTE.len());
        }
        let log = numeric
            && numeric_values(&plan.axes[x])
                .is_some_and(|v| v[0] > 0.0 && v[v.len() - 1] >= LOG_SPAN * v[0]);
        Some(Layout {
            x,
            numeric,
            log,
            panel_axes,
            line_axes,
        })
    }

    /// The x position of a design: its value (its log on a log scale), or its value's place
    /// on a non-numeric axis.
    pub(super) fn x_of(&self, plan: &Plan, design: &Design) -> f64 {
        let v = &design.values[self.x];
        if self.log {
            as_number(v).map_or(f64::NAN, f64::log10)
        } else if self.numeric {
            as_number(v).unwrap_or(f64::NAN)
        } else {
            plan.axes[self.x]
                .values
                .iter()
                .position(|w| w == v)
                .map_or(f64::NAN, |i| i as f64)
        }
    }
}

impl Layout {
    /// A design's value along x, as a number (NaN on a non-numeric axis).
    pub(super) fn value_of(&self, design: &Design) -> f64 {
        as_number(&design.values[self.x]).unwrap_or(f64::NAN)
    }
}

/// Every combination of the values of `axes` (the first varying slowest), as value indices.
fn combinations(plan: &Plan, axes: &[usize]) -> Vec<Vec<usize>> {
    let mut out = vec![Vec::new()];
    for &a in axes {
        out = out
            .into_iter()
            .flat_map(|c| {
                (0..plan.axes[a].values.len()).map(move |i| {
                    let mut c = c.clone();
                    c.push(i);
                    c
                })
            })
            .collect();
    }
    out
}

/// `rp 6 mm · rm 5 mm`: the values of `axes` at the value indices `at`, with their units.
fn describe(plan: &Plan, axes: &[usize], at: &[usize], sep: &str) -> String {
    axes.iter()
        .zip(at)
        .map(|(&a, &i)| {
            let axis = &plan.axes[a];
            format!(
                "{} {}{}",
                axis.column,
                show_value(&axis.values[i]),
                unit_of(&axis.key)
            )
        })
        .collect::<Vec<_>>()
        .join(sep)
}

/// Whether design `d` has the values `at` on `axes`.
fn holds(plan: &Plan, d: &Design, axes: &[usize], at: &[usize]) -> bool {
    axes.iter()
        .zip(at)
        .all(|(&a, &i)| d.values[a] == plan.axes[a].values[i])
}

/// The chart of a sweep and the notes under it; no chart when nothing is swept.
pub(super) fn shear_chart(
    plan: &Plan,
    rows: &[Row],
    designs: &[Design],
) -> (Option<Panels>, Vec<String>) {
    let Some(layout) = Layout::of(plan) else {
        return (
            None,
            vec!["(no chart: a single design; its map and verdict are on the left)".into()],
        );
    };
    let locking = plan.base_scene.fabric.locking_angle_deg;
    let panel_at = combinations(plan, &layout.panel_axes);
    let line_at = combinations(plan, &layout.line_axes);
    let shown = panel_at.len().min(MAX_PANELS);
    let panels = panels_of(plan, rows, designs, &layout, &panel_at[..shown], &line_at);
    let key = key_of(plan, &layout, &line_at);
    let (x_ticks, x_range) = x_axis(plan, &layout);
    let y_range = y_range(&panels, locking);
    let x_label = x_label(plan, &layout);
    let names = |axes: &[usize]| {
        axes.iter()
            .map(|&a| plan.axes[a].column.as_str())
            .collect::<Vec<_>>()
    };
    let title = chart_title(plan, &layout, &x_label, !key.is_empty());
    let columns = match layout.panel_axes.last() {
        Some(&a) if (2..=4).contains(&plan.axes[a].values.len()) => plan.axes[a].values.len(),
        _ => (shown as f64).sqrt().ceil().clamp(1.0, 4.0) as usize,
    };
    let chart = Panels {
        title,
        x_label,
        y_label: "max shear over a woven cell (°)".into(),
        x_ticks,
        x_range,
        y_range,
        limit: Some((locking, format!("locking angle {}°", tick_label(locking)))),
        columns,
        connect: layout.numeric,
        panels,
        key_title: names(&layout.line_axes).join(", "),
        key,
    };
    let notes = notes(&layout, plan, rows, locking, (shown, panel_at.len()));
    (Some(chart), notes)
}

/// The panels (at most those of `panel_at`), a line in each per combination of `line_at`
/// that has rows.
fn panels_of(
    plan: &Plan,
    rows: &[Row],
    designs: &[Design],
    layout: &Layout,
    panel_at: &[Vec<usize>],
    line_at: &[Vec<usize>],
) -> Vec<Panel> {
    let mut panels = Vec::with_capacity(panel_at.len());
    for at in panel_at {
        let mut lines = Vec::new();
        for (li, line) in line_at.iter().enumerate() {
            let mut points: Vec<PanelPoint> = rows
                .iter()
                .filter(|r| {
                    let d = &designs[r.index];
                    holds(plan, d, &layout.panel_axes, at)
                        && holds(plan, d, &layout.line_axes, line)
                })
                .map(|r| point(layout, plan, r, &designs[r.index]))
                .collect();
            if points.is_empty() {
                continue;
            }
            points.sort_by(|a, b| a.x.total_cmp(&b.x));
            lines.push(PanelLine {
                colour: Colour::nth(li),
                points,
            });
        }
        panels.push(Panel {
            title: describe(plan, &layout.panel_axes, at, " · "),
            lines,
        });
    }
    panels
}

/// The key of the lines: their names and colours, when there is more than one line.
fn key_of(plan: &Plan, layout: &Layout, line_at: &[Vec<usize>]) -> Vec<(String, Colour)> {
    // The key names the values only when one parameter makes the lines (its name is the
    // key's title).
    if line_at.len() > 1 {
        line_at
            .iter()
            .enumerate()
            .map(|(li, at)| {
                let name = match (layout.line_axes.as_slice(), at.as_slice()) {
                    ([a], [i]) => {
                        let axis = &plan.axes[*a];
                        format!("{}{}", show_value(&axis.values[*i]), unit_of(&axis.key))
                    }
                    _ => describe(plan, &layout.line_axes, at, ", "),
                };
                (name, Colour::nth(li))
            })
            .collect()
    } else {
        Vec::new()
    }
}

/// The chart's title: what the x axis is, and what the panels and lines are.
fn chart_title(plan: &Plan, layout: &Layout, x_label: &str, keyed: bool) -> String {
    let names = |axes: &[usize]| {
        axes.iter()
            .map(|&a| plan.axes[a].column.as_str())
            .collect::<Vec<_>>()
    };
    let mut title = format!("Max shear against {x_label}");
    if !layout.panel_axes.is_empty() {
        title.push_str(&format!(
            ": a panel per {}",
            names(&layout.panel_axes).join(" × ")
        ));
    }
    if keyed {
        title.push_str(&format!(
            "{} a line per {}",
            if layout.panel_axes.is_empty() {
                ":"
            } else {
                ","
            },
            names(&layout.line_axes).join(" × ")
        ));
    }
    title
}

/// A design's point: at its x exactly, its max shear when the run gave an answer.
fn point(layout: &Layout, plan: &Plan, r: &Row, d: &Design) -> PanelPoint {
    let answered = matches!(
        r.verdict,
        Verdict::Feasible | Verdict::Marginal | Verdict::Infeasible
    );
    PanelPoint {
        x: layout.x_of(plan, d),
        y: if answered && r.converged {
            r.max_shear_deg
        } else {
            None
        },
        verdict: r.verdict,
    }
}

/// The x ticks (the swept values, or round numbers when there are many) and the range.
pub(super) fn x_axis(plan: &Plan, layout: &Layout) -> (Vec<(f64, String)>, (f64, f64)) {
    let axis = &plan.axes[layout.x];
    if layout.log {
        return log_axis(&numeric_values(axis).unwrap_or_default());
    }
    if !layout.numeric {
        let ticks = (0..axis.values.len())
            .map(|i| (i as f64, show_value(&axis.values[i])))
            .collect();
        return (ticks, (-0.5, axis.values.len() as f64 - 0.5));
    }
    let xs = numeric_values(axis).unwrap_or_default();
    let (lo, hi) = (xs[0], xs[xs.len() - 1]);
    let pad = 0.12 * (hi - lo);
    let ticks = if xs.len() <= 8 {
        xs.iter().map(|&x| (x, tick_label(x))).collect()
    } else {
        let step = crate::report::maps::nice_step((hi - lo) / 6.0);
        let mut t = Vec::new();
        let mut v = (lo / step).ceil() * step;
        while v <= hi + 1e-9 * step {
            t.push((v, tick_label(v)));
            v += step;
        }
        t
    };
    (ticks, (lo - pad, hi + pad))
}

/// The x axis's label: the swept column and its unit, e.g. `r (mm)`.
pub(super) fn x_label(plan: &Plan, layout: &Layout) -> String {
    let axis = &plan.axes[layout.x];
    let unit = unit_of(&axis.key).trim();
    if unit.is_empty() {
        axis.column.clone()
    } else {
        format!("{} ({unit})", axis.column)
    }
}

/// A log axis over sorted positive values: ticks at 1, 2 and 5 of each decade in their range
/// (labelled with the values), positions in log10.
fn log_axis(xs: &[f64]) -> (Vec<(f64, String)>, (f64, f64)) {
    let (lo, hi) = (xs[0].log10(), xs[xs.len() - 1].log10());
    let mut ticks = Vec::new();
    for decade in (lo.floor() as i32)..=(hi.ceil() as i32) {
        for m in [1.0, 2.0, 5.0] {
            let v = m * 10f64.powi(decade);
            let at = v.log10();
            if at >= lo - 1e-9 && at <= hi + 1e-9 {
                ticks.push((at, tick_label(v)));
            }
        }
    }
    let pad = 0.06 * (hi - lo);
    (ticks, (lo - pad, hi + pad))
}

/// The y range: the points and the locking angle, with a margin, from 0 at the lowest.
fn y_range(panels: &[Panel], locking: f64) -> (f64, f64) {
    let ys = panels
        .iter()
        .flat_map(|p| &p.lines)
        .flat_map(|l| &l.points)
        .filter_map(|p| p.y);
    let (lo, hi) = ys.fold((locking, locking), |(lo, hi), y| (lo.min(y), hi.max(y)));
    let pad = 0.1 * (hi - lo) + 1.0;
    ((lo - pad).max(0.0), hi + pad)
}

/// The notes under the chart.
fn notes(
    layout: &Layout,
    plan: &Plan,
    rows: &[Row],
    locking: f64,
    (shown, panels): (usize, usize),
) -> Vec<String> {
    let mut note = vec![format!(
        "Each point at its design's {} exactly; above the dashed line (shaded) the fabric shears past its locking angle ({}°).",
        plan.axes[layout.x].column,
        tick_label(locking)
    )];
    if shown < panels {
        note.push(format!(
            "The first {shown} of {panels} panels (grid order); every row is in results.csv."
        ));
    }
    let missing = plan.len().saturating_sub(rows.len());
    if missing > 0 {
        note.push(format!(
            "{missing} design(s) not computed yet: not plotted."
        ));
    }
    note
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::sweep::Plan;

    fn plan(sweep: &str) -> Plan {
        let doc: toml::Table = format!("[sweep]\n{sweep}").parse().unwrap();
        Plan::from_document(std::path::Path::new("t.toml"), &doc, &[]).unwrap()
    }

    /// A row per design: its max shear is its index plus a half (so a point names its
    /// design); every seventh has no answer.
    fn rows(plan: &Plan, designs: &[Design]) -> Vec<Row> {
        designs
            .iter()
            .enumerate()
            .map(|(i, d)| {
                let failed = i % 7 == 3;
                let verdict = match i % 7 {
                    3 => Verdict::Failed,
                    0 | 1 => Verdict::Feasible,
                    2 => Verdict::Marginal,
                    _ => Verdict::Infeasible,
                };
                Row {
                    index: i,
                    max_shear_deg: (!failed).then_some(i as f64 + 0.5),
                    converged: !failed,
                    ..Row::new(d, plan.params(&plan.columns(), d), verdict)
                }
            })
            .collect()
    }

    /// Every point of the chart, with its panel and line: (panel, line, point).
    fn points(chart: &Panels) -> Vec<(usize, usize, &PanelPoint)> {
        chart
            .panels
            .iter()
            .enumerate()
            .flat_map(|(pi, p)| {
                p.lines
                    .iter()
                    .enumerate()
                    .flat_map(move |(li, l)| l.points.iter().map(move |pt| (pi, li, pt)))
            })
            .collect()
    }

    #[test]
    fn the_paper_sweep_is_a_panel_per_rp_and_rm_and_a_line_per_friction() {
        let plan = plan(
            "r = [5.0, 7.5, 10.0]\nrp = [6.0, 10.5, 15.0]\nrm = [5.0, 7.5, 10.0]\nfriction = [0.15, 0.2, 0.25]\n",
        );
        let designs = plan.designs();
        let rows = rows(&plan, &designs);
        let (chart, _) = shear_chart(&plan, &rows, &designs);
        let chart = chart.unwrap();
        // 3 rp × 3 rm panels, 3 columns (rm across), 3 friction lines each, the key naming
        // them.
        assert_eq!(chart.panels.len(), 3 * 3);
        assert_eq!(chart.columns, 3);
        assert_eq!(chart.panels[1].title, "rp 6 mm · rm 7.5 mm");
        assert_eq!(chart.x_label, "r (mm)");
        assert_eq!(chart.key_title, "friction");
        let key: Vec<&str> = chart.key.iter().map(|k| k.0.as_str()).collect();
        assert_eq!(key, ["0.15", "0.2", "0.25"]);
        assert!(chart.panels.iter().all(|p| p.lines.len() == 3));
        // The ticks at the swept values.
        let ticks: Vec<f64> = chart.x_ticks.iter().map(|t| t.0).collect();
        assert_eq!(ticks, [5.0, 7.5, 10.0]);
        // Every design once, at its r exactly, in the panel of its rp and rm, on the line of
        // its friction, with its verdict; its shear when it has an answer.
        let pts = points(&chart);
        assert_eq!(pts.len(), designs.len());
        let mut seen = vec![false; designs.len()];
        for (pi, li, p) in pts {
            let i = match p.y {
                Some(y) => (y - 0.5) as usize,
                None => {
                    // A design without an answer: the one of this panel, line and x.
                    (0..designs.len())
                        .find(|&i| {
                            rows[i].max_shear_deg.is_none()
                                && as_number(&designs[i].values[0]) == Some(p.x)
                                && (i / 9) % 3 == pi / 3
                                && (i / 3) % 3 == pi % 3
                                && i % 3 == li
                        })
                        .unwrap()
                }
            };
            let d = &designs[i];
            assert_eq!(as_number(&d.values[0]), Some(p.x), "x of {}", d.id);
            // Grid order: r varies slowest (27), then rp (9), rm (3), friction (1).
            assert_eq!(
                ((i / 9) % 3, (i / 3) % 3),
                (pi / 3, pi % 3),
                "panel of {}",
                d.id
            );
            assert_eq!(i % 3, li, "line of {}", d.id);
            assert_eq!(p.verdict, rows[i].verdict);
            assert!(!seen[i], "{} twice", d.id);
            seen[i] = true;
        }
        // The locking angle in every panel, in the y range.
        let (limit, _) = chart.limit.clone().unwrap();
        assert!(chart.y_range.0 < limit && limit < chart.y_range.1);
    }

    #[test]
    fn one_two_and_five_swept_parameters() {
        // One: a single panel, a single line, no key.
        let p = plan("rm = [5.0, 7.5, 10.0]\n");
        let d = p.designs();
        let (chart, _) = shear_chart(&p, &rows(&p, &d), &d);
        let chart = chart.unwrap();
        assert_eq!((chart.panels.len(), chart.panels[0].lines.len()), (1, 1));
        assert!(chart.key.is_empty() && chart.panels[0].title.is_empty());
        assert_eq!(chart.x_label, "rm (mm)");
        // Friction × holder pressure: friction along x, a line per pressure (MPa in the key).
        let p = plan("friction = [0.1, 0.2, 0.3]\nholder_pressure = [0.5, 1.0]\n");
        let d = p.designs();
        let (chart, _) = shear_chart(&p, &rows(&p, &d), &d);
        let chart = chart.unwrap();
        assert_eq!(chart.panels.len(), 1);
        assert_eq!(chart.key[1].0, "1 MPa");
        assert_eq!(chart.x_label, "friction");
        assert!(
            points(&chart)
                .iter()
                .all(|(_, _, q)| [0.1, 0.2, 0.3].contains(&q.x))
        );
        // Five: x = r; rp and rm (3 values) make 9 panels; friction × holder (2 × 2) 4 lines.
        let p = plan(
            "r = [5.0, 10.0]\nrp = [6.0, 10.0, 15.0]\nrm = [5.0, 7.5, 10.0]\nfriction = [0.1, 0.2]\nholder_pressure = [0.5, 1.0]\n",
        );
        let d = p.designs();
        let (chart, _) = shear_chart(&p, &rows(&p, &d), &d);
        let chart = chart.unwrap();
        assert_eq!(chart.panels.len(), 9);
        assert_eq!(chart.key.len(), 4);
        assert_eq!(chart.key[3].0, "friction 0.2, holder_pressure 1 MPa");
        assert_eq!(points(&chart).len(), d.len());
    }

    #[test]
    fn more_panels_than_fit_show_the_first_and_say_so() {
        let p = plan(
            "r = [5.0, 10.0]\nrp = [6.0, 10.0, 15.0]\nrm = [5.0, 7.5, 10.0]\nfriction = [0.1, 0.2, 0.3]\ntools.clearance = [1.0, 1.5, 2.0]\nholder_pressure = [0.5, 1.0, 2.0]\n",
        );
        let d = p.designs();
        let (chart, notes) = shear_chart(&p, &rows(&p, &d), &d);
        let chart = chart.unwrap();
        assert_eq!(chart.panels.len(), MAX_PANELS);
        assert!(
            notes.iter().any(|n| n.contains("first 36 of 81 panels")),
            "{notes:?}"
        );
    }

    #[test]
    fn a_word_axis_or_a_single_design() {
        // No numeric parameter: its values side by side.
        let p = plan("mesh.symmetry = [\"quarter\", \"full\"]\n");
        let d = p.designs();
        let (chart, _) = shear_chart(&p, &rows(&p, &d), &d);
        let chart = chart.unwrap();
        let ticks: Vec<(f64, &str)> = chart
            .x_ticks
            .iter()
            .map(|(x, s)| (*x, s.as_str()))
            .collect();
        assert_eq!(ticks, [(0.0, "quarter"), (1.0, "full")]);
        assert_eq!(chart.x_range, (-0.5, 1.5));
        // A word axis beside a numeric one makes the lines.
        let p = plan("friction = [0.1, 0.2]\nmesh.symmetry = [\"quarter\", \"full\"]\n");
        let d = p.designs();
        let (chart, _) = shear_chart(&p, &rows(&p, &d), &d);
        let key: Vec<String> = chart.unwrap().key.into_iter().map(|k| k.0).collect();
        assert_eq!(key, ["quarter", "full"]);
        // Nothing swept: no chart, a note.
        let p = plan("friction = [0.2]\n");
        let d = p.designs();
        let (chart, notes) = shear_chart(&p, &rows(&p, &d), &d);
        assert!(chart.is_none());
        assert!(notes[0].contains("single design"), "{notes:?}");
    }
}
