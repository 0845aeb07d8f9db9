//! A small line/scatter chart written to PNG with plotters' bitmap backend.
//!
//! Text is drawn with the DejaVu Sans font embedded in the binary (registered once under the
//! family names plotters asks for), so charts are legible on a machine with no system fonts.
//!
//! ```no_run
//! use wovenform::report::plot::{Colour, LineChart, Series};
//! let chart = LineChart::new("Yarn tension", "warp strain ε11 (%)", "tension per yarn (N)")
//!     .with(Series::line("warp", vec![(0.0, 0.0), (1.0, 230.0)], Colour::PALETTE[0]))
//!     .with(Series::markers("data", vec![(0.5, 110.0)], Colour::BLACK));
//! chart.write_png(std::path::Path::new("out/chart.png")).unwrap();
//! ```

use super::canvas::{Area, Canvas, write_png};
use super::error::{DrawError, PlotError};
use std::path::Path;
use std::sync::Once;

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;

/// An sRGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Colour(pub u8, pub u8, pub u8);

impl Colour {
    pub const BLACK: Colour = Colour(0, 0, 0);
    pub const GREY: Colour = Colour(110, 110, 110);
    /// A palette that stays distinguishable in print and for common colour blindness
    /// (Okabe–Ito, without yellow).
    pub const PALETTE: [Colour; 7] = [
        Colour(0, 114, 178),   // blue
        Colour(213, 94, 0),    // vermilion
        Colour(0, 158, 115),   // bluish green
        Colour(204, 121, 167), // reddish purple
        Colour(86, 180, 233),  // sky blue
        Colour(230, 159, 0),   // orange
        Colour(0, 0, 0),       // black
    ];

    /// The `i`-th palette colour, cycling.
    pub fn nth(i: usize) -> Colour {
        Self::PALETTE[i % Self::PALETTE.len()]
    }

    fn rgb(self) -> RGBColor {
        RGBColor(self.0, self.1, self.2)
    }
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// A solid polyline through the points, in order.
    Line,
    /// A dashed polyline through the points, in order.
    Dashed,
    /// A filled circle at each point, no line.
    Markers,
    /// A cross at each point, no line.
    Crosses,
}

/// One named series. An empty `name` keeps it out of the legend; a named series with no points
/// appears in the legend only (useful for a key such as "solid: warp").
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
    pub colour: Colour,
}

impl Series {
    pub fn new(
        name: impl Into<String>,
        points: Vec<(f64, f64)>,
        style: Style,
        colour: Colour,
    ) -> Self {
        Series {
            name: name.into(),
            points,
            style,
            colour,
        }
    }
    pub fn line(name: impl Into<String>, points: Vec<(f64, f64)>, colour: Colour) -> Self {
        Self::new(name, points, Style::Line, colour)
    }
    pub fn dashed(name: impl Into<String>, points: Vec<(f64, f64)>, colour: Colour) -> Self {
        Self::new(name, points, Style::Dashed, colour)
    }
    pub fn markers(name: impl Into<String>, points: Vec<(f64, f64)>, colour: Colour) -> Self {
        Self::new(name, points, Style::Markers, colour)
    }
    pub fn crosses(name: impl Into<String>, points: Vec<(f64, f64)>, colour: Colour) -> Self {
        Self::new(name, points, Style::Crosses, colour)
    }
}

/// Axis scale.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Scale {
    #[default]
    Linear,
    /// Base-10 logarithmic; points with a coordinate ≤ 0 on this axis are left out.
    Log,
}

/// Where the legend box sits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LegendAt {
    #[default]
    UpperLeft,
    UpperRight,
    LowerLeft,
    LowerRight,
}

/// A 2-D chart of line and marker series. Axis labels should carry their unit, e.g.
/// `"tension per yarn (N)"`.
#[derive(Clone, Debug, PartialEq)]
pub struct LineChart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    pub x_scale: Scale,
    pub y_scale: Scale,
    /// Fixed axis range; `None` fits the data (with a small margin on linear axes).
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
    pub legend_at: LegendAt,
    /// Image size in pixels (width, height).
    pub size: (u32, u32),
}

static FONTS: Once = Once::new();

/// Registers the embedded DejaVu Sans under the family names plotters uses. Idempotent.
pub fn register_fonts() {
    FONTS.call_once(|| {
        for family in ["sans-serif", "serif", "monospace"] {
            // The bytes are a valid TTF shipped inside the `dejavu` crate; if they were not, the
            // text would simply not render, which the chart tests would catch.
            let _ =
                plotters::style::register_font(family, FontStyle::Normal, dejavu::sans::regular());
            let _ = plotters::style::register_font(family, FontStyle::Bold, dejavu::sans::bold());
            let _ =
                plotters::style::register_font(family, FontStyle::Italic, dejavu::sans::oblique());
            let _ =
                plotters::style::register_font(family, FontStyle::Oblique, dejavu::sans::oblique());
        }
    });
}

impl LineChart {
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        LineChart {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: Vec::new(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            x_range: None,
            y_range: None,
            legend_at: LegendAt::UpperLeft,
            size: (1000, 700),
        }
    }

    /// Adds a series (builder style).
    pub fn with(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// Adds a series.
    pub fn push(&mut self, series: Series) {
        self.series.push(series);
    }

    /// Both axes logarithmic (builder style), e.g. for error-against-step-size charts.
    pub fn log_log(mut self) -> Self {
        self.x_scale = Scale::Log;
        self.y_scale = Scale::Log;
        self
    }

    /// The range drawn on each axis: the fixed one, or the data's with a margin.
    pub fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let x = self
            .x_range
            .unwrap_or_else(|| data_range(self.visible_points().map(|p| p.0), self.x_scale));
        let y = self
            .y_range
            .unwrap_or_else(|| data_range(self.visible_points().map(|p| p.1), self.y_scale));
        (x, y)
    }

    fn visible(&self, p: (f64, f64)) -> bool {
        p.0.is_finite()
            && p.1.is_finite()
            && (self.x_scale == Scale::Linear || p.0 > 0.0)
            && (self.y_scale == Scale::Linear || p.1 > 0.0)
    }

    fn visible_points(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .filter(|&p| self.visible(p))
    }

    /// Draws the chart to a PNG file. Errors name the file.
    pub fn write_png(&self, path: &Path) -> Result<(), DrawError> {
        register_fonts();
        write_png(path, self.size, "chart", |root| self.draw_into(root))
    }

    /// Draws the chart into a part of a larger picture (a report sheet); `self.size` is not
    /// used, the chart fills `area`. The caller presents the picture.
    pub fn draw_into(&self, area: &Area<'_>) -> Result<(), PlotError> {
        register_fonts();
        let ((x0, x1), (y0, y1)) = self.ranges();
        match (self.x_scale, self.y_scale) {
            (Scale::Linear, Scale::Linear) => self.draw_on(area, x0..x1, y0..y1),
            (Scale::Log, Scale::Linear) => self.draw_on(area, (x0..x1).log_scale(), y0..y1),
            (Scale::Linear, Scale::Log) => self.draw_on(area, x0..x1, (y0..y1).log_scale()),
            (Scale::Log, Scale::Log) => {
                self.draw_on(area, (x0..x1).log_scale(), (y0..y1).log_scale())
            }
        }
    }

    fn draw_on<X, Y>(&self, root: &Area<'_>, x_spec: X, y_spec: Y) -> Result<(), PlotError>
    where
        X: AsRangedCoord<Value = f64>,
        Y: AsRangedCoord<Value = f64>,
        X::CoordDescType: ValueFormatter<f64>,
        Y::CoordDescType: ValueFormatter<f64>,
    {
        let font = "sans-serif";
        let mut chart = ChartBuilder::on(root)
            .caption(&self.title, (font, 28))
            .margin(20)
            .x_label_area_size(65)
            .y_label_area_size(90)
            .build_cartesian_2d(x_spec, y_spec)?;
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .axis_desc_style((font, 22))
            .label_style((font, 17))
            .x_label_formatter(&|v| tick_label(*v))
            .y_label_formatter(&|v| tick_label(*v))
            .light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(205, 205, 205))
            .draw()?;

        let any_legend = self.draw_series(&mut chart)?;
        if any_legend {
            let position = match self.legend_at {
                LegendAt::UpperLeft => SeriesLabelPosition::UpperLeft,
                LegendAt::UpperRight => SeriesLabelPosition::UpperRight,
                LegendAt::LowerLeft => SeriesLabelPosition::LowerLeft,
                LegendAt::LowerRight => SeriesLabelPosition::LowerRight,
            };
            chart
                .configure_series_labels()
                .position(position)
                .margin(12)
                .legend_area_size(34)
                .background_style(WHITE.mix(0.9))
                .border_style(RGBColor(150, 150, 150))
                .label_font((font, 17))
                .draw()?;
        }
        Ok(())
    }

    /// Draws every series on `chart`, each with its legend entry when it has a name; whether
    /// any has one.
    fn draw_series<'a, X, Y>(
        &self,
        chart: &mut ChartContext<'a, Canvas<'a>, Cartesian2d<X, Y>>,
    ) -> Result<bool, PlotError>
    where
        X: Ranged<ValueType = f64>,
        Y: Ranged<ValueType = f64>,
    {
        let mut any_legend = false;
        for s in &self.series {
            let colour = s.colour.rgb();
            let points: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|&p| self.visible(p))
                .collect();
            let line = ShapeStyle::from(colour).stroke_width(2);
            let anno = match s.style {
                Style::Line => chart.draw_series(LineSeries::new(points, line)),
                Style::Dashed => chart.draw_series(DashedLineSeries::new(points, 10, 6, line)),
                Style::Markers => chart.draw_series(
                    points
                        .into_iter()
                        .map(|p| Circle::new(p, 4, ShapeStyle::from(colour).filled())),
                ),
                Style::Crosses => chart.draw_series(
                    points
                        .into_iter()
                        .map(|p| Cross::new(p, 5, ShapeStyle::from(colour).stroke_width(2))),
                ),
            }?;
            if s.name.is_empty() {
                continue;
            }
            any_legend = true;
            // The little picture beside a legend entry.
            let anno = anno.label(s.name.as_str());
            match s.style {
                Style::Line => {
                    anno.legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 26, y)], line))
                }
                Style::Dashed => anno.legend(move |(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new(vec![(0, 0), (8, 0)], line)
                        + PathElement::new(vec![(13, 0), (21, 0)], line)
                        + PathElement::new(vec![(26, 0), (28, 0)], line)
                }),
                Style::Markers => anno.legend(move |(x, y)| {
                    Circle::new((x + 13, y), 4, ShapeStyle::from(colour).filled())
                }),
                Style::Crosses => anno.legend(move |(x, y)| Cross::new((x + 13, y), 5, line)),
            };
        }
        Ok(any_legend)
    }
}

/// A tick label without float noise or needless zeros: `0.3`, `400`, `1e-6`.
pub fn tick_label(v: f64) -> String {
    let trim = |s: String| -> String {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if v == 0.0 {
        return "0".to_string();
    }
    if v.abs() < 1e-3 || v.abs() >= 1e6 {
        let s = format!("{v:.4e}");
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        return format!("{}e{exponent}", trim(mantissa.to_string()));
    }
    let s = trim(format!("{v:.6}"));
    if s == "-0" { "0".to_string() } else { s }
}

/// The data's extent with a margin: 4 % each side on a linear axis (and 0 included when the data
/// are all of one sign and start near it), a factor of 1.3 on a log axis.
fn data_range(values: impl Iterator<Item = f64>, scale: Scale) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return match scale {
            Scale::Linear => (0.0, 1.0),
            Scale::Log => (0.1, 10.0),
        };
    }
    match scale {
        Scale::Log => {
            if hi <= lo * 1.000_001 {
                (lo / 2.0, hi * 2.0)
            } else {
                (lo / 1.3, hi * 1.3)
            }
        }
        Scale::Linear => {
            if lo >= 0.0 && lo <= 0.25 * hi {
                lo = 0.0;
            }
            if hi <= 0.0 && hi >= 0.25 * lo {
                hi = 0.0;
            }
            let span = hi - lo;
            if span <= f64::EPSILON * (lo.abs() + hi.abs()).max(1e-300) {
                let pad = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
                return (lo - pad, hi + pad);
            }
            let pad = 0.04 * span;
            let lo = if lo == 0.0 { 0.0 } else { lo - pad };
            let hi = if hi == 0.0 { 0.0 } else { hi + pad };
            (lo, hi)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_range_starts_at_zero_for_positive_data() {
        let (lo, hi) = data_range([0.1, 5.0, 10.0].into_iter(), Scale::Linear);
        assert_eq!(lo, 0.0);
        assert!((hi - 10.4).abs() < 1e-12);
    }

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(tick_label(400.0), "400");
        assert_eq!(tick_label(0.1 + 0.2), "0.3");
        assert_eq!(tick_label(1e-6), "1e-6");
        assert_eq!(tick_label(2.5e7), "2.5e7");
        assert_eq!(tick_label(-0.0000001), "-1e-7");
    }

    #[test]
    fn log_range_brackets_the_data() {
        let (lo, hi) = data_range([1e-3, 1e-1].into_iter(), Scale::Log);
        assert!(lo < 1e-3 && hi > 1e-1);
    }

    #[test]
    fn log_log_chart_draws_and_decodes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("loglog.png");
        let h: Vec<f64> = (0..6).map(|i| 0.5f64.powi(i)).collect();
        let chart = LineChart::new("Convergence", "element size h (mm)", "error (N)")
            .with(Series::line(
                "error",
                h.iter().map(|&h| (h, 3.0 * h * h)).collect(),
                Colour::nth(0),
            ))
            .with(Series::dashed(
                "slope 2",
                h.iter().map(|&h| (h, 2.0 * h * h)).collect(),
                Colour::GREY,
            ))
            .with(Series::markers(
                "",
                vec![(1.0, 3.0), (-1.0, 2.0)],
                Colour::nth(0),
            ))
            .log_log();
        chart.write_png(&path).unwrap();
        let img = image::open(&path).unwrap();
        assert_eq!((img.width(), img.height()), chart.size);
        if let Ok(keep) = std::env::var("WOVENFORM_KEEP_CHART") {
            std::fs::copy(&path, keep).unwrap();
        }
    }

    #[test]
    fn write_png_names_the_file_on_failure() {
        let chart = LineChart::new("t", "x (mm)", "y (N)").with(Series::line(
            "a",
            vec![(0.0, 0.0), (1.0, 1.0)],
            Colour::nth(0),
        ));
        let bad = Path::new("/nonexistent-dir-for-wovenform/chart.png");
        let e = chart.write_png(bad).unwrap_err().to_string();
        assert!(
            e.contains("/nonexistent-dir-for-wovenform/chart.png"),
            "{e}"
        );
    }
}
