//! PNG maps of a drawing: the deformed blank seen from above (the x–y projection of the final
//! positions, each element a filled quad) coloured by a field — the shear angle against the
//! locking angle, or the largest yarn tension against the breaking tension.
//!
//! The full blank is drawn even when a quarter was solved (mirrored about x = 0 and y = 0). The
//! colour scale runs from 0 to the limit and a little past it (or to the largest value, if
//! that is higher): pale to dark blue below the limit, one saturated magenta above it, and the
//! cells over the limit are outlined in black, so they cannot be missed. The colour bar marks
//! the limit with a line and its value; the die opening is drawn dashed.

mod bar;
mod developed;
mod form;

pub use form::form_view;

pub use bar::nice_step;
pub use developed::{FullBlank, MaterialLine, shear_developed, tension_developed};

use super::error::{DrawError, PlotError};
use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::canvas::text_width;
use super::mirror::{PlanQuad, mirror_quads};
use super::plot::{register_fonts, tick_label};
use crate::core::drawing::{DrawingResult, Tooling};

/// The colour of every value over the limit.
pub const OVER_LIMIT: (u8, u8, u8) = (230, 0, 150);

/// The scale below the limit: ColorBrewer YlGnBu, pale yellow (0) to dark blue (the limit).
const SCALE: [(u8, u8, u8); 9] = [
    (255, 255, 217),
    (237, 248, 177),
    (199, 233, 180),
    (127, 205, 187),
    (65, 182, 196),
    (29, 145, 192),
    (34, 94, 168),
    (37, 52, 148),
    (8, 29, 88),
];

/// The colour of `value` on a scale whose limit is `limit`: the sequential scale below it,
/// [`OVER_LIMIT`] above it.
pub fn colour_of(value: f64, limit: f64) -> (u8, u8, u8) {
    colour_on(value, limit, limit)
}

/// The colour of `value` with the sequential scale spanning 0 … `span` (≤ `limit`) and
/// [`OVER_LIMIT`] above the limit.
pub fn colour_on(value: f64, limit: f64, span: f64) -> (u8, u8, u8) {
    if value > limit {
        return OVER_LIMIT;
    }
    let t = if span > 0.0 {
        (value / span).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = t * (SCALE.len() - 1) as f64;
    let i = (s.floor() as usize).min(SCALE.len() - 2);
    let f = s - i as f64;
    let mix = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (SCALE[i], SCALE[i + 1]);
    (mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// A map ready to draw: plan quads of the full blank, one value per quad, and the limit.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldMap {
    /// First title line (scene, figure, verdict).
    pub title: String,
    /// Second title line (what is shown); a line break starts another line.
    pub subtitle: String,
    /// Third title line: the design (tools, friction, pressure, mesh); empty: none.
    pub design: String,
    /// Spread the colours over the field's own range when its largest value is under the limit
    /// (the tension, often a fraction of the break); the limit is then written above the bar.
    pub fit_to_field: bool,
    pub quads: Vec<PlanQuad>,
    /// One value per quad, ≥ 0.
    pub values: Vec<f64>,
    /// The design limit (locking angle, breaking tension).
    pub limit: f64,
    /// Short name of the limit on the colour bar, e.g. "locking angle".
    pub limit_name: String,
    /// Caption of the colour bar with its unit, e.g. "shear (°)".
    pub bar_caption: String,
    /// Formats a value with its unit, e.g. `33.6°` or `78 N`.
    pub unit: Unit,
    /// Where the largest value is (plan, mm), marked on the map.
    pub max_at: Option<[f64; 2]>,
    /// The peak over a woven cell there (the figure the verdict uses), for the marker's label;
    /// the colour bar marks the largest element value.
    pub peak: Option<f64>,
    /// Lines drawn over the field (mm): the die opening, dashed, on a top view; the material
    /// that ends at the die-opening edge or the punch's nose on the flat blank.
    pub outlines: Vec<Outline>,
    /// Image size in pixels.
    pub size: (u32, u32),
    /// The top of the colour scale, when several maps share one (a sweep); `None`: a little
    /// past the limit, or the largest value (see [`FieldMap::scale_top`]).
    pub scale_max: Option<f64>,
    /// A view other than from above: the quads are projections (drawn in order, far first),
    /// each shaded by its factor, the axes named for the view. `None`: the plan.
    pub view: Option<View>,
}

/// A projected view of the formed blank ([`form::form_view`]).
#[derive(Clone, Debug, PartialEq)]
pub struct View {
    /// Each quad's shade, 0 (black) to 1 (its colour).
    pub shade: Vec<f64>,
    /// The axes' names.
    pub axes: [String; 2],
}

/// A line drawn over a map, a polyline in plan (mm).
#[derive(Clone, Debug, PartialEq)]
pub struct Outline {
    pub points: Vec<[f64; 2]>,
    pub style: OutlineStyle,
}

/// How an [`Outline`] is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutlineStyle {
    /// Long grey dashes (the die opening).
    Dashed,
    /// Short black dashes (the punch).
    Dotted,
}

impl Outline {
    pub fn dashed(points: Vec<[f64; 2]>) -> Self {
        Outline {
            points,
            style: OutlineStyle::Dashed,
        }
    }
    pub fn dotted(points: Vec<[f64; 2]>) -> Self {
        Outline {
            points,
            style: OutlineStyle::Dotted,
        }
    }
}

/// How values are written on a map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unit {
    Degrees,
    Newtons,
    Millimetres,
}

impl Unit {
    pub fn show(self, v: f64) -> String {
        let s = match self {
            Unit::Degrees => format!("{v:.1}°"),
            Unit::Newtons if v.abs() >= 100.0 => format!("{v:.0} N"),
            Unit::Newtons => format!("{v:.1} N"),
            Unit::Millimetres => return format!("{v:.2} mm"),
        };
        s.replace(".0°", "°").replace(".0 N", " N")
    }
}

/// What the maps of one run share: the scene's name, the verdict, the tools.
#[derive(Clone, Debug)]
pub struct MapContext<'a> {
    pub scene: &'a str,
    /// The verdict in a few words, e.g. "FEASIBLE" or "INFEASIBLE: shear over the limit".
    pub verdict: &'a str,
    pub tooling: Tooling,
    /// The stroke asked for, mm.
    pub stroke_mm: f64,
    /// The design in one line (`RunSummary::design_line`).
    pub design: &'a str,
}

/// The plan quads of the solved part, final positions.
pub fn plan_quads(result: &DrawingResult) -> Vec<PlanQuad> {
    result
        .mesh
        .quads
        .iter()
        .map(|q| q.map(|n| [result.positions[n][0], result.positions[n][1]]))
        .collect()
}

/// The quads and values of the full blank (mirrored when a quarter was solved).
fn full_blank(result: &DrawingResult, values: &[f64]) -> (Vec<PlanQuad>, Vec<f64>) {
    let quads = plan_quads(result);
    if result.quarter {
        mirror_quads(&quads, values)
    } else {
        (quads, values.to_vec())
    }
}

fn what_is_drawn(result: &DrawingResult, ctx: &MapContext) -> String {
    crate::summary::what_is_drawn(result, ctx.stroke_mm)
}

/// The map of the shear angle (|change of the angle between the yarns|, degrees).
pub fn shear_map(result: &DrawingResult, ctx: &MapContext, locking_angle_deg: f64) -> FieldMap {
    let values: Vec<f64> = result.shear_deg.iter().map(|s| s.abs()).collect();
    let (e, max) = result.max_shear();
    let (quads, values) = full_blank(result, &values);
    let c = result.element_centre(e);
    let title = format!(
        "{}: max shear {} over a woven cell (locking {}) — {}",
        ctx.scene,
        Unit::Degrees.show(max),
        Unit::Degrees.show(locking_angle_deg),
        ctx.verdict
    );
    let subtitle = crate::summary::shear_subtitle(result, ctx.stroke_mm);
    FieldMap {
        design: ctx.design.to_string(),
        max_at: (!result.shear_deg.is_empty()).then_some([c[0], c[1]]),
        peak: Some(max),
        outlines: vec![Outline::dashed(die_opening_outline(&ctx.tooling))],
        ..FieldMap::shear(title, subtitle, quads, values, locking_angle_deg)
    }
}

/// The map of the largest yarn tension of each element (N per yarn).
pub fn tension_map(result: &DrawingResult, ctx: &MapContext, break_tension_n: f64) -> FieldMap {
    let values = &result.tension_max_n;
    let (e, max) = result.neighbourhood_peak(values, result.cell_mm);
    let (quads, values) = full_blank(result, values);
    let c = result.element_centre(e);
    FieldMap {
        title: format!(
            "{}: max yarn tension {} over a woven cell ({:.0} % of the break) — {}",
            ctx.scene,
            Unit::Newtons.show(max),
            100.0 * max / break_tension_n,
            ctx.verdict
        ),
        subtitle: format!("Largest yarn tension: {}", what_is_drawn(result, ctx)),
        design: ctx.design.to_string(),
        fit_to_field: true,
        quads,
        values,
        limit: break_tension_n,
        limit_name: "break tension".into(),
        bar_caption: "tension (N)".into(),
        unit: Unit::Newtons,
        max_at: (max > 0.0).then_some([c[0], c[1]]),
        peak: Some(max),
        outlines: vec![Outline::dashed(die_opening_outline(&ctx.tooling))],
        size: (1100, 900),
        scale_max: None,
        view: None,
    }
}

/// The map of the wrinkle amplitude (`core::wrinkles::amplitude`, mm): each element the largest of its
/// nodes'. `None` for the paper's membrane, which has no bending and no wrinkles.
pub fn wrinkle_map(result: &DrawingResult, ctx: &MapContext, limit_mm: f64) -> Option<FieldMap> {
    let per_node = result.wrinkle_mm.as_ref()?;
    let (max, at) = result.max_wrinkle()?;
    let values: Vec<f64> = result
        .mesh
        .quads
        .iter()
        .map(|q| q.iter().map(|&n| per_node[n]).fold(0.0, f64::max))
        .collect();
    let (quads, values) = full_blank(result, &values);
    Some(FieldMap {
        title: format!(
            "{}: wrinkles {} peak to valley (limit {}) — {}",
            ctx.scene,
            Unit::Millimetres.show(max),
            Unit::Millimetres.show(limit_mm),
            ctx.verdict
        ),
        subtitle: format!(
            "Wrinkle amplitude along the yarns, off the tools: {}",
            what_is_drawn(result, ctx)
        ),
        design: ctx.design.to_string(),
        fit_to_field: true,
        quads,
        values,
        limit: limit_mm,
        limit_name: "wrinkle limit".into(),
        bar_caption: "wrinkle (mm)".into(),
        unit: Unit::Millimetres,
        max_at: (max > 0.0).then_some([at[0], at[1]]),
        peak: Some(max),
        outlines: vec![Outline::dashed(die_opening_outline(&ctx.tooling))],
        size: (1100, 900),
        scale_max: None,
        view: None,
    })
}

/// The die opening in plan as a closed polyline, mm.
pub fn die_opening_outline(tooling: &Tooling) -> Vec<[f64; 2]> {
    tooling.die_opening_outline()
}

use super::canvas::{Area, Canvas, write_png};
use plotters::coord::types::RangedCoordf64;

impl FieldMap {
    /// A map of the shear angle (degrees) against the locking angle, 1100 × 900 pixels, seen
    /// from above with nothing marked: what every shear map shares, the run's, the formed
    /// blank's, a sweep design's and the bias specimen's.
    pub fn shear(
        title: String,
        subtitle: String,
        quads: Vec<PlanQuad>,
        values: Vec<f64>,
        locking_angle_deg: f64,
    ) -> FieldMap {
        FieldMap {
            title,
            subtitle,
            design: String::new(),
            fit_to_field: false,
            quads,
            values,
            limit: locking_angle_deg,
            limit_name: "locking angle".into(),
            bar_caption: "shear (°)".into(),
            unit: Unit::Degrees,
            max_at: None,
            peak: None,
            outlines: Vec::new(),
            size: (1100, 900),
            scale_max: None,
            view: None,
        }
    }

    /// The top of the colour scale: the shared one when given ([`FieldMap::scale_max`]), else
    /// a little past the limit, or the largest value.
    pub fn scale_top(&self) -> f64 {
        if let Some(top) = self.scale_max.filter(|t| t.is_finite() && *t > 0.0) {
            return top;
        }
        let max = self.largest();
        if self.off_scale(max) {
            return 1.05 * max;
        }
        (1.1 * self.limit).max(max)
    }

    /// The largest value of the field.
    fn largest(&self) -> f64 {
        self.values.iter().cloned().fold(0.0, f64::max)
    }

    /// The field, whose largest value is `max`, stays under its limit and is drawn on its own
    /// range (see `fit_to_field`).
    fn off_scale(&self, max: f64) -> bool {
        self.fit_to_field && max > 0.0 && max < self.limit
    }

    fn limit_off_scale(&self) -> bool {
        self.off_scale(self.largest())
    }

    /// The value drawn darkest: the limit, or the top of the field's own range.
    fn colour_span(&self) -> f64 {
        if self.limit_off_scale() {
            self.scale_top()
        } else {
            self.limit
        }
    }

    /// Draws the map to a PNG file. Errors name the file.
    pub fn write_png(&self, path: &Path) -> Result<(), DrawError> {
        register_fonts();
        write_png(path, self.size, "map", |root| self.draw(root))
    }

    fn draw(&self, root: &Area) -> Result<(), PlotError> {
        let font = "sans-serif";
        let (w, _) = self.size;
        // The title, then the subtitle's lines and the design's, 26 px apart.
        let lines: Vec<&str> = self
            .subtitle
            .lines()
            .chain((!self.design.is_empty()).then_some(self.design.as_str()))
            .collect();
        let head = 60 + 26 * lines.len().max(1) as u32;
        let (top, body) = root.split_vertically(head);
        // Each title line at the largest size (up to its nominal one) that fits the width.
        let line = |text: &str, y: i32, size: u32, bold: bool, colour: RGBColor| {
            let style_at = |size: u32| {
                let f = (font, size).into_font();
                let f = if bold { f.style(FontStyle::Bold) } else { f };
                f.color(&colour).pos(Pos::new(HPos::Center, VPos::Top))
            };
            let mut size = size;
            while size > 10 {
                match top.estimate_text_size(text, &style_at(size)) {
                    Ok((tw, _)) if tw + 24 > w => size -= 1,
                    _ => break,
                }
            }
            top.draw(&Text::new(
                text.to_string(),
                (w as i32 / 2, y),
                style_at(size),
            ))
        };
        line(&self.title, 14, 26, true, BLACK)?;
        for (i, text) in lines.iter().enumerate() {
            line(text, 54 + 26 * i as i32, 17, false, RGBColor(60, 60, 60))?;
        }
        let bar_width = 250;
        let (map_area, bar_area) = body.split_horizontally(w - bar_width);
        let plot_rows = self.draw_map(&map_area)?;
        self.draw_bar(root, &bar_area, plot_rows)?;
        Ok(())
    }

    /// The data range: the blank and the die opening with a margin, widened along one axis
    /// so that a millimetre is as long across as up on a plot area of `px × py` pixels.
    fn ranges(&self, px: u32, py: u32) -> ((f64, f64), (f64, f64)) {
        let (mut x0, mut x1, mut y0, mut y1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        let lines = self.outlines.iter().flat_map(|o| &o.points);
        for p in self.quads.iter().flatten().chain(lines) {
            if p[0].is_finite() && p[1].is_finite() {
                x0 = x0.min(p[0]);
                x1 = x1.max(p[0]);
                y0 = y0.min(p[1]);
                y1 = y1.max(p[1]);
            }
        }
        if !(x0 < x1 && y0 < y1) {
            return ((-1.0, 1.0), (-1.0, 1.0));
        }
        let pad = 0.03 * (x1 - x0).max(y1 - y0);
        let (x0, x1, y0, y1) = (x0 - pad, x1 + pad, y0 - pad, y1 + pad);
        let per_px = ((x1 - x0) / px.max(1) as f64).max((y1 - y0) / py.max(1) as f64);
        let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
        let (hx, hy) = (0.5 * per_px * px as f64, 0.5 * per_px * py as f64);
        ((cx - hx, cx + hx), (cy - hy, cy + hy))
    }

    /// A projected view's quads, far first, each filled (shaded) and then edged, so that the
    /// near hide the far.
    fn draw_view<'a>(
        &self,
        chart: &mut ChartContext<'a, Canvas<'a>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
        view: &View,
        span: f64,
        edge: ShapeStyle,
    ) -> Result<(), PlotError> {
        let over = ShapeStyle::from(RGBColor(110, 0, 80)).stroke_width(1);
        for (k, (q, &v)) in self.quads.iter().zip(&self.values).enumerate() {
            let f = view.shade[k];
            let m = |c: u8| (c as f64 * f).round().clamp(0.0, 255.0) as u8;
            let c = colour_on(v, self.limit, span);
            let mut p: Vec<(f64, f64)> = q.iter().map(|p| (p[0], p[1])).collect();
            let fill = Polygon::new(p.clone(), RGBColor(m(c.0), m(c.1), m(c.2)).filled());
            p.push(p[0]);
            let line = PathElement::new(p, if v > self.limit { over } else { edge });
            chart.plotting_area().draw(&fill)?;
            chart.plotting_area().draw(&line)?;
        }
        Ok(())
    }

    /// The peak at `at` (mm): a red ring, and its value on a pale label beside it.
    fn draw_peak<'a>(
        &self,
        chart: &mut ChartContext<'a, Canvas<'a>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
        at: [f64; 2],
    ) -> Result<(), PlotError> {
        let label = match self.peak {
            // The wrinkle amplitude is a span's, not a cell's mean.
            Some(peak) if self.unit == Unit::Millimetres => {
                format!("peak to valley {}", self.unit.show(peak))
            }
            Some(peak) => format!("cell peak {}", self.unit.show(peak)),
            None => format!(
                "max {}",
                self.unit
                    .show(self.values.iter().cloned().fold(0.0, f64::max))
            ),
        };
        let width = text_width(&label, 18.0, FontStyle::Bold).ceil() as i32;
        let style = ShapeStyle::from(RGBColor(220, 0, 0)).stroke_width(3);
        chart.draw_series(std::iter::once(
            EmptyElement::at((at[0], at[1]))
                + Circle::new((0, 0), 9, style)
                + Rectangle::new(
                    [(8, -29), (16 + width, -5)],
                    ShapeStyle::from(WHITE.mix(0.85)).filled(),
                )
                + Text::new(
                    label,
                    (12, -26),
                    ("sans-serif", 18)
                        .into_font()
                        .style(FontStyle::Bold)
                        .color(&BLACK),
                ),
        ))?;
        Ok(())
    }

    /// Draws the blank; returns the plot area's pixel rows (top, bottom) for the colour bar.
    fn draw_map(&self, area: &Area) -> Result<(i32, i32), PlotError> {
        let font = "sans-serif";
        let builder = |x: (f64, f64), y: (f64, f64)| {
            ChartBuilder::on(area)
                .margin(18)
                .x_label_area_size(55)
                .y_label_area_size(70)
                .build_cartesian_2d(x.0..x.1, y.0..y.1)
        };
        // Build once to learn the plot area's size, then again with equal scales.
        let probe = builder((0.0, 1.0), (0.0, 1.0))?;
        let (px, py) = probe.plotting_area().dim_in_pixel();
        let (xr, yr) = self.ranges(px, py);
        let mut chart = builder(xr, yr)?;
        let [x_desc, y_desc] = self.view.as_ref().map_or(["x (mm)", "y (mm)"], |v| {
            [v.axes[0].as_str(), v.axes[1].as_str()]
        });
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc(y_desc)
            .axis_desc_style((font, 20))
            .label_style((font, 16))
            .x_label_formatter(&|v| tick_label(*v))
            .y_label_formatter(&|v| tick_label(*v))
            .disable_mesh()
            .draw()?;
        let rgb = |c: (u8, u8, u8)| RGBColor(c.0, c.1, c.2);
        let poly = |q: &PlanQuad| -> Vec<(f64, f64)> { q.iter().map(|p| (p[0], p[1])).collect() };
        // Once per map, not once per quad: it scans every value.
        let span = self.colour_span();
        // The element edges, faint: they are the yarns, and show the shear by themselves.
        let edge = ShapeStyle::from(BLACK.mix(0.12)).stroke_width(1);
        if let Some(view) = &self.view {
            self.draw_view(&mut chart, view, span, edge)?;
            let (_, rows) = chart.plotting_area().get_pixel_range();
            return Ok((rows.start, rows.end));
        }
        chart.draw_series(self.quads.iter().zip(&self.values).map(|(q, &v)| {
            let c = colour_on(v, self.limit, span);
            Polygon::new(poly(q), rgb(c).filled())
        }))?;
        chart.draw_series(self.quads.iter().map(|q| {
            let mut p = poly(q);
            p.push(p[0]);
            PathElement::new(p, edge)
        }))?;
        for outline in &self.outlines {
            let pts: Vec<(f64, f64)> = outline.points.iter().map(|p| (p[0], p[1])).collect();
            let (dash, gap, colour) = match outline.style {
                OutlineStyle::Dashed => (9, 6, RGBColor(90, 90, 90)),
                OutlineStyle::Dotted => (3, 5, RGBColor(20, 20, 20)),
            };
            chart.draw_series(DashedLineSeries::new(
                pts,
                dash,
                gap,
                ShapeStyle::from(colour).stroke_width(2),
            ))?;
        }
        // Over the limit: outlined on top of everything else, thin and in a darker magenta, so
        // that a corner of small sheared cells reads as magenta cells, not as a black blob.
        let outline = ShapeStyle::from(RGBColor(110, 0, 80)).stroke_width(1);
        chart.draw_series(
            self.quads
                .iter()
                .zip(&self.values)
                .filter(|(_, v)| **v > self.limit)
                .map(|(q, _)| {
                    let mut p = poly(q);
                    p.push(p[0]);
                    PathElement::new(p, outline)
                }),
        )?;
        if let Some(at) = self.max_at {
            self.draw_peak(&mut chart, at)?;
        }
        let (_, rows) = chart.plotting_area().get_pixel_range();
        Ok((rows.start, rows.end))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_run_pale_to_dark_then_magenta() {
        let lum = |c: (u8, u8, u8)| 0.3 * c.0 as f64 + 0.59 * c.1 as f64 + 0.11 * c.2 as f64;
        let mut last = f64::INFINITY;
        for i in 0..=20 {
            let c = colour_of(60.0 * i as f64 / 20.0, 60.0);
            assert_ne!(c, OVER_LIMIT);
            assert!(lum(c) <= last + 1e-9, "not darker at step {i}");
            last = lum(c);
        }
        assert_eq!(colour_of(60.01, 60.0), OVER_LIMIT);
        assert_eq!(colour_of(0.0, 60.0), SCALE[0]);
        assert_eq!(colour_of(60.0, 60.0), SCALE[8]);
    }

    #[test]
    fn die_outlines_close_and_span_the_opening() {
        for tooling in [
            Tooling::Box {
                side: [60.0, 40.0],
                r: 10.0,
                rp: 5.0,
                rm: 5.0,
                clearance: 1.5,
            },
            Tooling::Ellipsoid {
                axes: [40.0, 25.0, 20.0],
                rm: 5.0,
                clearance: 1.5,
            },
            Tooling::Hemisphere {
                radius: 30.0,
                rm: 5.0,
                clearance: 1.5,
            },
        ] {
            let pts = die_opening_outline(&tooling);
            assert_eq!(pts.first(), pts.last());
            let half = tooling.opening_half();
            let xmax = pts.iter().map(|p| p[0]).fold(f64::MIN, f64::max);
            let ymin = pts.iter().map(|p| p[1]).fold(f64::MAX, f64::min);
            assert!((xmax - half[0]).abs() < 1e-9, "{tooling:?}: {xmax}");
            assert!((ymin + half[1]).abs() < 1e-9, "{tooling:?}: {ymin}");
        }
    }

    #[test]
    fn equal_scales_on_both_axes() {
        let map = FieldMap {
            title: String::new(),
            subtitle: String::new(),
            design: String::new(),
            fit_to_field: false,
            quads: vec![[[-70.0, -50.0], [70.0, -50.0], [70.0, 50.0], [-70.0, 50.0]]],
            values: vec![1.0],
            limit: 2.0,
            limit_name: String::new(),
            bar_caption: String::new(),
            unit: Unit::Degrees,
            max_at: None,
            peak: None,
            outlines: Vec::new(),
            size: (100, 100),
            scale_max: None,
            view: None,
        };
        let ((x0, x1), (y0, y1)) = map.ranges(700, 600);
        assert!(((x1 - x0) / 700.0 - (y1 - y0) / 600.0).abs() < 1e-12);
        assert!(x0 < -70.0 && x1 > 70.0 && y0 < -50.0 && y1 > 50.0);
        // The colour scale: its own, or one shared by several maps.
        assert!((map.scale_top() - 2.2).abs() < 1e-12);
        let shared = FieldMap {
            scale_max: Some(80.0),
            ..map
        };
        assert_eq!(shared.scale_top(), 80.0);
    }
}
