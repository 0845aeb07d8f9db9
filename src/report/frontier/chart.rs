//! `frontier.png`: the boundary against another axis, one line per value of a third (the
//! rest), its interval (the MARGINAL zone and the search's tolerance) shaded; a combination
//! whose whole range is on one side is a mark at the edge. With no other axis, the axis
//! itself as a line: the runs with their verdicts, the boundaries and their intervals.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{combo_words, decimals, unit};
use crate::report::canvas::Area;
use crate::report::error::PlotError;
use crate::report::fixed;
use crate::report::plot::{Colour, tick_label};
use crate::study::frontier::{Found, Frontier, Line};
use crate::study::sweep::{as_number, show_value, unit_of};
use crate::verdict::Verdict;

/// The picture's size, pixels.
pub const SIZE: (u32, u32) = (1200, 760);
const FONT: &str = "sans-serif";

fn rgb(c: Colour) -> RGBColor {
    RGBColor(c.0, c.1, c.2)
}

/// Draws the frontier into `area`.
pub fn draw(f: &Frontier, area: &Area) -> Result<(), PlotError> {
    crate::report::plot::register_fonts();
    let spread = f.lines.first().map_or(0, |l| l.values.len());
    if spread == 0 || f.lines.len() < 2 {
        return number_line(f, area);
    }
    against_axis(f, area)
}

/// The axis's value as drawn (its logarithm when the lattice is even in it).
fn to_plot(f: &Frontier, v: f64) -> f64 {
    if f.log { v.log10() } else { v }
}

fn from_plot(f: &Frontier, v: f64) -> f64 {
    if f.log { 10f64.powf(v) } else { v }
}

/// The axis's label with its unit: `r (mm)`.
fn axis_label(column: &str, key: &str) -> String {
    let u = unit_of(key).trim();
    if u.is_empty() {
        column.to_string()
    } else {
        format!("{column} ({u})")
    }
}

/// The side where the boundaries' limits are met, when they all agree (`Some(true)`: above).
fn common_side(f: &Frontier) -> Option<bool> {
    let mut sides = f.lines.iter().flat_map(|l| match &l.found {
        Found::Boundaries(bs) => bs.iter().map(|b| b.feasible_above).collect(),
        _ => Vec::new(),
    });
    let first = sides.next()?;
    sides.all(|s| s == first).then_some(first)
}

/// The rows under the chart: the key and the notes.
const FOOT: u32 = 84;

/// The first other axis's value of each line (its position in the order met when it is not
/// a number), its words when it is not, and whether it is.
fn x_positions(f: &Frontier) -> (Vec<f64>, Vec<String>, bool) {
    let numeric = f.lines.iter().all(|l| as_number(&l.values[0].2).is_some());
    let mut cats: Vec<String> = Vec::new();
    let xs = (f.lines.iter())
        .map(|l| {
            if numeric {
                return as_number(&l.values[0].2).unwrap_or(0.0);
            }
            let s = show_value(&l.values[0].2);
            let i = cats.iter().position(|c| *c == s).unwrap_or_else(|| {
                cats.push(s);
                cats.len() - 1
            });
            i as f64
        })
        .collect();
    (xs, cats, numeric)
}

/// A line's group: its values on the axes after the first, in words.
fn group_of(l: &Line) -> String {
    let rest: Vec<String> = (l.values[1..].iter())
        .map(|(c, k, x)| format!("{c} {}{}", show_value(x), unit_of(k)))
        .collect();
    rest.join(", ")
}

/// The chart's title: the smallest (largest) value that forms when every boundary has the
/// feasible side above (below).
fn title_of(f: &Frontier, against: &str) -> String {
    match common_side(f) {
        Some(true) => format!("The smallest {} that forms, against {against}", f.column),
        Some(false) => format!("The largest {} that forms, against {against}", f.column),
        None => format!(
            "Where the verdict changes along {}, against {against}",
            f.column
        ),
    }
}

/// The key (a swatch and a name per colour) and the notes under a chart, from `left`.
fn draw_foot(
    foot: &Area,
    key: &[(String, RGBColor)],
    notes: &[String],
    left: i32,
) -> Result<(), PlotError> {
    let mut x = left;
    for (name, colour) in key {
        foot.draw(&PathElement::new(
            vec![(x, 18), (x + 30, 18)],
            colour.stroke_width(4),
        ))?;
        foot.draw(&Text::new(
            name.clone(),
            (x + 38, 10),
            (FONT, 17).into_font(),
        ))?;
        x += 60 + crate::report::canvas::text_width(name, 17.0, FontStyle::Normal) as i32;
    }
    for (i, n) in notes.iter().enumerate() {
        let at = (left, 36 + 22 * i as i32);
        foot.draw(&Text::new(n.clone(), at, (FONT, 16).into_font()))?;
    }
    Ok(())
}

/// The boundary against the first other axis, a line per combination of the rest.
fn against_axis(f: &Frontier, whole: &Area) -> Result<(), PlotError> {
    let (area, foot) = whole.split_vertically(SIZE.1 - FOOT);
    let first = &f.lines[0].values[0];
    let (xs, cats, numeric) = x_positions(f);
    let (x0, x1) = (xs.iter()).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(*x), b.max(*x))
    });
    let pad = 0.06 * (x1 - x0).max(1e-9);
    let (y0, y1) = (to_plot(f, f.range[0]), to_plot(f, f.range[1]));
    let ypad = 0.04 * (y1 - y0);
    let mut groups: Vec<String> = Vec::new();
    for g in f.lines.iter().map(group_of) {
        if !groups.contains(&g) {
            groups.push(g);
        }
    }
    let key_label = axis_label(&f.column, &f.key);
    let mut chart = ChartBuilder::on(&area)
        .caption(title_of(f, &first.0), (FONT, 28))
        .margin(20)
        .x_label_area_size(65)
        .y_label_area_size(90)
        .build_cartesian_2d((x0 - pad)..(x1 + pad), (y0 - ypad)..(y1 + ypad))?;
    chart
        .configure_mesh()
        .x_desc(axis_label(&first.0, &first.1))
        .y_desc(&key_label)
        .axis_desc_style((FONT, 22))
        .label_style((FONT, 17))
        .x_label_formatter(&|v| {
            let i = v.round();
            let near = (v - i).abs() < 1e-6 && i >= 0.0;
            match numeric {
                true => tick_label(*v),
                false => (cats.get(i as usize).filter(|_| near).cloned()).unwrap_or_default(),
            }
        })
        .y_label_formatter(&|v| tick_label(from_plot(f, *v)))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(205, 205, 205))
        .draw()?;
    let xspan = x1 - x0 + 2.0 * pad;
    let mut key = Vec::new();
    for (g, name) in groups.iter().enumerate() {
        let colour = rgb(Colour::nth(g));
        // Marks at the edges drawn side by side, not on top of each other.
        let dodge = (g as f64 - (groups.len() as f64 - 1.0) / 2.0) * 0.012 * xspan;
        let members: Vec<(f64, &Line)> = (f.lines.iter().zip(&xs))
            .filter(|(l, _)| group_of(l) == *name)
            .map(|(l, x)| (*x, l))
            .collect();
        let side = common_side(f);
        draw_group(f, &mut chart, &members, colour, side, (y0, y1), dodge)?;
        let label = if name.is_empty() {
            key_label.clone()
        } else {
            name.clone()
        };
        key.push((label, colour));
    }
    let notes = [
        "shaded: the MARGINAL zone (the figure within the level's error band of its limit) \
         and the search's bracket"
            .to_string(),
        format!(
            "× at an edge: INFEASIBLE over the whole range · ○ at an edge: FEASIBLE over it · \
             {} runs against {} for the grid",
            f.runs(),
            f.grid_runs()
        ),
    ];
    draw_foot(&foot, &key, &notes, 110)
}

type Chart<'a, 'b> = ChartContext<
    'a,
    crate::report::canvas::Canvas<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// One group's boundary lines (the k-th boundary of each combination joined along x where
/// consecutive combinations have one), their shaded intervals, and the edge marks.
fn draw_group(
    f: &Frontier,
    chart: &mut Chart,
    members: &[(f64, &Line)],
    colour: RGBColor,
    side: Option<bool>,
    (y0, y1): (f64, f64),
    dodge: f64,
) -> Result<(), PlotError> {
    let mut sorted = members.to_vec();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    for k in 0..2 {
        let mut segment: Vec<(f64, [f64; 3])> = Vec::new();
        let mut segments = Vec::new();
        for (x, l) in &sorted {
            match &l.found {
                Found::Boundaries(bs) if bs.len() > k => {
                    let b = &bs[k];
                    let t = |v| to_plot(f, v);
                    segment.push((*x, [t(b.value), t(b.interval[0]), t(b.interval[1])]));
                }
                _ => segments.push(std::mem::take(&mut segment)),
            }
        }
        segments.push(segment);
        for s in segments.iter().filter(|s| !s.is_empty()) {
            let mut poly: Vec<(f64, f64)> = s.iter().map(|(x, v)| (*x, v[2])).collect();
            poly.extend(s.iter().rev().map(|(x, v)| (*x, v[1])));
            if s.len() == 1 {
                let (x, v) = s[0];
                let w = 0.01 * (chart.x_range().end - chart.x_range().start);
                poly = vec![(x - w, v[1]), (x + w, v[1]), (x + w, v[2]), (x - w, v[2])];
            }
            chart.draw_series(std::iter::once(Polygon::new(
                poly,
                colour.mix(0.16).filled(),
            )))?;
            let line: Vec<(f64, f64)> = s.iter().map(|(x, v)| (*x, v[0])).collect();
            chart.draw_series(LineSeries::new(line.clone(), colour.stroke_width(3)))?;
            chart.draw_series(line.into_iter().map(|p| Circle::new(p, 5, colour.filled())))?;
        }
    }
    // Whole ranges on one side: a mark at the edge where the boundary would be.
    for (x, l) in &sorted {
        let Found::Whole { over, .. } = &l.found else {
            continue;
        };
        let infeasible = !over.is_empty();
        let top = match side {
            Some(above) => infeasible == above,
            None => infeasible,
        };
        let at = (*x + dodge, if top { y1 } else { y0 });
        if infeasible {
            chart.draw_series(std::iter::once(Cross::new(at, 8, colour.stroke_width(3))))?;
        } else {
            chart.draw_series(std::iter::once(Circle::new(at, 7, colour.stroke_width(3))))?;
        }
    }
    Ok(())
}

/// One combination: each figure over its limit at the runs against the axis (a log axis when
/// the lattice is even in the logarithm), each boundary a vertical line in its shaded interval.
fn number_line(f: &Frontier, area: &Area) -> Result<(), PlotError> {
    let (lo, hi) = (f.range[0], f.range[1]);
    if f.log {
        let pad = (hi / lo).powf(0.04);
        number_line_on(f, area, ((lo / pad)..(hi * pad)).log_scale())
    } else {
        let pad = 0.04 * (hi - lo);
        number_line_on(f, area, (lo - pad)..(hi + pad))
    }
}

/// A run's figures over their limits: shear, tension, wrinkles (`None`: not answered).
fn ratios(f: &Frontier, design: &str) -> [Option<f64>; 3] {
    let Some(r) = f.rows.iter().find(|r| r.design == design) else {
        return [None; 3];
    };
    if matches!(r.verdict, Verdict::Failed | Verdict::Invalid) {
        return [None; 3];
    }
    let l = f.limits;
    [
        r.max_shear_deg.map(|v| v / l.locking_angle_deg),
        r.max_tension_n.map(|v| v / l.break_tension_n),
        r.max_wrinkle_mm.map(|v| v / l.wrinkle_limit_mm),
    ]
}

fn number_line_on<X>(f: &Frontier, area: &Area, x_spec: X) -> Result<(), PlotError>
where
    X: plotters::coord::ranged1d::AsRangedCoord<Value = f64>,
    X::CoordDescType: plotters::coord::ranged1d::ValueFormatter<f64>,
{
    let (area, foot) = area.split_vertically(SIZE.1 - 60);
    let line = f.lines.first();
    let runs: Vec<(f64, [Option<f64>; 3], Verdict)> = line
        .map(|l| {
            (l.runs.iter())
                .map(|p| (p.value, ratios(f, &p.design), p.verdict))
                .collect()
        })
        .unwrap_or_default();
    let top = (runs.iter().flat_map(|r| r.1).flatten())
        .fold(1.2_f64, f64::max)
        .min(3.0);
    let title = match line {
        Some(l) if !l.values.is_empty() => {
            format!(
                "Where the verdict changes along {} ({})",
                f.column,
                combo_words(l)
            )
        }
        _ => format!("Where the verdict changes along {}", f.column),
    };
    let mut chart = ChartBuilder::on(&area)
        .caption(&title, (FONT, 28))
        .margin(20)
        .x_label_area_size(65)
        .y_label_area_size(90)
        .build_cartesian_2d(x_spec, 0.0..1.1 * top)?;
    chart
        .configure_mesh()
        .x_desc(axis_label(&f.column, &f.key))
        .y_desc("figure / its limit")
        .axis_desc_style((FONT, 22))
        .label_style((FONT, 17))
        .x_label_formatter(&|v| tick_label(*v))
        .y_label_formatter(&|v| tick_label(*v))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(205, 205, 205))
        .draw()?;
    if let Some(Found::Boundaries(bs)) = line.map(|l| &l.found) {
        draw_vertical_boundaries(f, &mut chart, bs, 1.1 * top)?;
    }
    let limit = vec![(f.range[0], 1.0), (f.range[1], 1.0)];
    chart.draw_series(DashedLineSeries::new(limit, 10, 6, BLACK.stroke_width(2)))?;
    let key = draw_figures(&mut chart, &runs, top)?;
    let note = format!(
        "at each run: ● under the limit, × over · dashed: the limit · shaded: the MARGINAL zone \
         and the search's bracket · {} runs against {} for the grid",
        f.runs(),
        f.grid_runs()
    );
    draw_foot(&foot, &key, &[note], 60)
}

/// Each boundary as a vertical line in its shaded interval, with its value in words.
fn draw_vertical_boundaries<DB, X>(
    f: &Frontier,
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, plotters::coord::types::RangedCoordf64>>,
    bs: &[crate::study::frontier::Boundary],
    y_top: f64,
) -> Result<(), PlotError>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64>,
    PlotError: From<DrawingAreaErrorKind<DB::ErrorType>>,
{
    for (k, b) in bs.iter().enumerate() {
        let grey = RGBColor(120, 120, 120);
        let band = Rectangle::new(
            [(b.interval[0], 0.0), (b.interval[1], y_top)],
            grey.mix(0.14).filled(),
        );
        chart.draw_series(std::iter::once(band))?;
        let line = vec![(b.value, 0.0), (b.value, y_top)];
        chart.draw_series(LineSeries::new(line, grey.stroke_width(3)))?;
        let side = if b.feasible_above {
            "feasible above"
        } else {
            "feasible below"
        };
        let d = decimals(f);
        let text = format!(
            "{} {} ({}; {side})",
            fixed(b.value, d),
            unit(f),
            b.governing.name()
        );
        let at = (b.value, y_top * (0.97 - 0.07 * k as f64));
        // Right of the line in the range's first half, left of it in the second.
        let past_middle = if f.log {
            b.value * b.value > f.range[0] * f.range[1]
        } else {
            2.0 * b.value > f.range[0] + f.range[1]
        };
        let h = if past_middle { HPos::Right } else { HPos::Left };
        let style = TextStyle::from((FONT, 18).into_font()).pos(Pos::new(h, VPos::Top));
        chart.draw_series(std::iter::once(Text::new(format!(" {text} "), at, style)))?;
    }
    Ok(())
}

/// Each figure over its limit at the runs, a line in its colour, a dot under the limit and a
/// cross over it; the key's entries for the figures drawn.
fn draw_figures<DB, X>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, plotters::coord::types::RangedCoordf64>>,
    runs: &[(f64, [Option<f64>; 3], Verdict)],
    top: f64,
) -> Result<Vec<(String, RGBColor)>, PlotError>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64>,
    PlotError: From<DrawingAreaErrorKind<DB::ErrorType>>,
{
    let names = [
        "max shear / locking angle",
        "max tension / break",
        "wrinkles / limit",
    ];
    let mut key = Vec::new();
    for (which, name) in names.iter().enumerate() {
        let mut pts: Vec<(f64, f64)> = (runs.iter())
            .filter_map(|(x, r, _)| Some((*x, r[which]?.min(top))))
            .collect();
        if pts.is_empty() {
            continue;
        }
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let c = rgb(Colour::nth(which));
        chart.draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))?;
        for at in pts {
            if at.1 > 1.0 {
                chart.draw_series(std::iter::once(Cross::new(at, 6, c.stroke_width(3))))?;
            } else {
                chart.draw_series(std::iter::once(Circle::new(at, 5, c.filled())))?;
            }
        }
        key.push((name.to_string(), c));
    }
    Ok(key)
}
