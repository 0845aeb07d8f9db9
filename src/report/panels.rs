//! Small multiples: one small chart (a panel) per combination of some parameters, all on the
//! same axes, a few coloured lines in each, each point's marker saying its verdict.
//!
//! ```text
//!  Max shear against r (mm): a panel per rp × rm, a line per friction
//!  line colour — friction: ── 0.15  ── 0.2  ── 0.25
//!  marker — ● feasible  ○ marginal  × infeasible  □ no answer   ‐ ‐ locking angle 60°
//!        rp 6 mm · rm 5 mm     rp 6 mm · rm 7.5 mm    ...
//!   75 ┌──────────────────┐ ┌──────────────────┐
//!      │×──────×─────×    │ │ (shaded above    │
//!   60 │‐ ‐ ‐ ‐ ‐ ‐ ‐ ‐ ‐ │ │  the limit)      │
//!      └──────────────────┘ └──────────────────┘
//!        5    7.5    10        5    7.5    10
//!                            r (mm)
//! ```
//!
//! The markers take the line's colour and say the verdict by their shape alone (filled,
//! hollow, a cross, a square on the x axis), so no verdict colour can be taken for a line's.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::canvas::{Area, text_width};
use super::error::PlotError;
use super::maps::{OVER_LIMIT, nice_step};
use super::plot::{Colour, tick_label};
use crate::verdict::Verdict;

/// One point: its x exactly, its y when there is an answer, and its verdict.
#[derive(Clone, Debug, PartialEq)]
pub struct PanelPoint {
    pub x: f64,
    /// `None`: no answer (the run failed or was not run); drawn on the x axis.
    pub y: Option<f64>,
    pub verdict: Verdict,
}

/// One line of a panel, in one colour of the key.
#[derive(Clone, Debug, PartialEq)]
pub struct PanelLine {
    pub colour: Colour,
    /// Sorted by x.
    pub points: Vec<PanelPoint>,
}

/// One panel: its title (the values it holds fixed, with units) and its lines.
#[derive(Clone, Debug, PartialEq)]
pub struct Panel {
    pub title: String,
    pub lines: Vec<PanelLine>,
}

/// The whole set of panels with their shared axes, limit and keys.
#[derive(Clone, Debug, PartialEq)]
pub struct Panels {
    pub title: String,
    /// Under the panels, with its unit, e.g. `r (mm)`.
    pub x_label: String,
    /// Beside the first column, with its unit, e.g. `max shear (°)`.
    pub y_label: String,
    /// Where the x axis is ticked and what the tick says (the swept values).
    pub x_ticks: Vec<(f64, String)>,
    pub x_range: (f64, f64),
    pub y_range: (f64, f64),
    /// A horizontal line in every panel (the locking angle), shaded above: its value and its
    /// name in the key, e.g. `locking angle 60°`.
    pub limit: Option<(f64, String)>,
    pub columns: usize,
    /// Lines through the points (a numeric x); markers only when x is a list of words.
    pub connect: bool,
    pub panels: Vec<Panel>,
    /// What the line colours are, e.g. `friction`; empty when a panel has a single line.
    pub key_title: String,
    /// Each colour and the value(s) it stands for, e.g. `0.15`.
    pub key: Vec<(String, Colour)>,
}

const LEFT: i32 = 100;
const GAP_X: i32 = 20;
const PANEL_TITLE: i32 = 28;
const X_TICKS: i32 = 28;
const GAP_Y: i32 = 14;
const FOOT: i32 = 36;
const FONT: &str = "sans-serif";
const KEY_SWATCH: i32 = 30;
const NO_ANSWER_ROW: i32 = 14;

/// The marker of a verdict at `(x, y)` in colour `c`, `size` its half width (pixels).
fn draw_marker(
    root: &Area,
    verdict: Verdict,
    (x, y): (i32, i32),
    c: RGBColor,
    size: i32,
) -> Result<(), PlotError> {
    let hollow = |r: &Area| -> Result<(), PlotError> {
        r.draw(&Circle::new((x, y), size, WHITE.filled()))?;
        r.draw(&Circle::new(
            (x, y),
            size,
            ShapeStyle::from(c).stroke_width(2),
        ))?;
        Ok(())
    };
    match verdict {
        Verdict::Feasible => root.draw(&Circle::new((x, y), size, c.filled()))?,
        Verdict::Marginal => hollow(root)?,
        Verdict::Infeasible => {
            let s = size;
            let line = ShapeStyle::from(c).stroke_width(3);
            root.draw(&PathElement::new(
                vec![(x - s, y - s), (x + s, y + s)],
                line,
            ))?;
            root.draw(&PathElement::new(
                vec![(x - s, y + s), (x + s, y - s)],
                line,
            ))?
        }
        Verdict::Failed | Verdict::Invalid => {
            let s = size - 1;
            root.draw(&Rectangle::new(
                [(x - s, y - s), (x + s, y + s)],
                WHITE.filled(),
            ))?;
            root.draw(&Rectangle::new(
                [(x - s, y - s), (x + s, y + s)],
                ShapeStyle::from(c).stroke_width(2),
            ))?
        }
    }
    Ok(())
}

/// Text at `(x, y)` anchored by `pos`, shrunk until it fits `max_w` pixels.
#[allow(clippy::too_many_arguments)]
fn label(
    root: &Area,
    text: &str,
    (x, y): (i32, i32),
    pos: (HPos, VPos),
    size: f64,
    bold: bool,
    colour: RGBColor,
    max_w: i32,
) -> Result<i32, PlotError> {
    let style = if bold {
        FontStyle::Bold
    } else {
        FontStyle::Normal
    };
    let mut size = size;
    while size > 9.0 && text_width(text, size, style) > max_w as f64 {
        size -= 1.0;
    }
    let font = (FONT, size)
        .into_font()
        .style(style)
        .color(&colour)
        .pos(Pos::new(pos.0, pos.1));
    root.draw(&Text::new(text.to_string(), (x, y), font))?;
    Ok(text_width(text, size, style).round() as i32)
}

impl Panels {
    fn rows(&self) -> usize {
        self.panels.len().div_ceil(self.columns.max(1))
    }

    fn key_heading(&self) -> String {
        format!("line colour — {}:", self.key_title)
    }

    /// Where each entry of the colour key goes in a drawing `width` wide: the heading's width,
    /// and each entry's offset from the left and its row (wrapped under the first entry).
    fn key_layout(&self, width: i32) -> (i32, Vec<(i32, i32)>) {
        let heading = text_width(&self.key_heading(), 18.0, FontStyle::Bold).ceil() as i32;
        let heading = heading.min(width / 3);
        let indent = heading + 14;
        let mut places = Vec::with_capacity(self.key.len());
        let (mut dx, mut row) = (indent, 0);
        for (name, _) in &self.key {
            let w = KEY_SWATCH + 6 + text_width(name, 18.0, FontStyle::Normal).ceil() as i32;
            if dx > indent && dx + w > width {
                (dx, row) = (indent, row + 1);
            }
            places.push((dx, row));
            dx += w + 22;
        }
        (heading, places)
    }

    /// The title and the keys: rows for the colours when there are several lines, then the
    /// verdicts' markers.
    fn head(&self, width: i32) -> i32 {
        match self.key_layout(width).1.last() {
            None => 84,
            Some((_, rows)) => 118 + 30 * rows,
        }
    }

    /// Width and height of one panel's plot, pixels, in a drawing `width` wide.
    fn plot_size(&self, width: i32) -> (i32, i32) {
        let cols = self.columns.max(1) as i32;
        let w = ((width - LEFT - (cols - 1) * GAP_X) / cols).max(60);
        let tallest = if cols == 1 { 520 } else { 270 };
        let h = ((0.62 * w as f64).round() as i32).clamp(150, tallest);
        (w, h)
    }

    /// The height the panels take in a drawing `width` pixels wide.
    pub fn height(&self, width: i32) -> i32 {
        let (_, h) = self.plot_size(width);
        self.head(width) + self.rows() as i32 * (PANEL_TITLE + h + X_TICKS + GAP_Y) + FOOT
    }

    /// The top-left corner of panel `i`'s plot, in a drawing at `(x, y)`, `width` wide.
    pub fn plot_origin(&self, i: usize, (x, y): (i32, i32), width: i32) -> (i32, i32) {
        let (w, h) = self.plot_size(width);
        let cols = self.columns.max(1);
        let (c, r) = ((i % cols) as i32, (i / cols) as i32);
        (
            x + LEFT + c * (w + GAP_X),
            y + self.head(width) + r * (PANEL_TITLE + h + X_TICKS + GAP_Y) + PANEL_TITLE,
        )
    }

    /// The height of the band for the designs without an answer: a row for each line up to
    /// the last one that has such a design (none: no band).
    fn no_answer_strip(&self) -> i32 {
        let rows = self
            .panels
            .iter()
            .flat_map(|p| p.lines.iter().enumerate())
            .filter(|(_, l)| l.points.iter().any(|p| p.y.is_none()))
            .map(|(li, _)| li + 1)
            .max()
            .unwrap_or(0);
        if rows == 0 {
            0
        } else {
            8 + NO_ANSWER_ROW * rows as i32
        }
    }

    /// Pixel column of `v` on a plot starting at `left`, `w` wide.
    pub fn px(&self, v: f64, left: i32, w: i32) -> i32 {
        let (x0, x1) = self.x_range;
        left + ((v - x0) / (x1 - x0) * w as f64).round() as i32
    }

    fn py(&self, v: f64, top: i32, h: i32) -> i32 {
        let (y0, y1) = self.y_range;
        top + ((y1 - v) / (y1 - y0) * h as f64).round() as i32
    }

    /// Draws the panels into `root` at `(x, y)`, `width` pixels wide.
    pub fn draw(&self, root: &Area, (x, y): (i32, i32), width: i32) -> Result<(), PlotError> {
        self.draw_head(root, (x, y), width)?;
        let (w, h) = self.plot_size(width);
        for (i, panel) in self.panels.iter().enumerate() {
            let origin = self.plot_origin(i, (x, y), width);
            self.draw_panel(root, panel, origin, (w, h), i % self.columns.max(1) == 0)?;
        }
        // The axis names: x under the grid, y up the left side.
        let bottom = y + self.height(width) - FOOT;
        label(
            root,
            &self.x_label,
            (x + LEFT + (width - LEFT) / 2, bottom + 6),
            (HPos::Center, VPos::Top),
            20.0,
            false,
            BLACK,
            width - LEFT,
        )?;
        let head = self.head(width);
        let mid = y + head + (self.height(width) - head - FOOT) / 2;
        root.draw(&Text::new(
            self.y_label.clone(),
            (x + 6, mid),
            (FONT, 20)
                .into_font()
                .transform(FontTransform::Rotate270)
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Top)),
        ))?;
        Ok(())
    }

    /// The title, the colour key and the marker key.
    fn draw_head(&self, root: &Area, (x, y): (i32, i32), width: i32) -> Result<(), PlotError> {
        let grey = RGBColor(50, 50, 50);
        label(
            root,
            &self.title,
            (x, y),
            (HPos::Left, VPos::Top),
            26.0,
            true,
            BLACK,
            width,
        )?;
        if !self.key.is_empty() {
            self.draw_colour_key(root, (x, y), width, grey)?;
        }
        self.draw_marker_key(root, (x, y), width, grey)?;
        Ok(())
    }

    /// The colours of the lines and their names, on as many rows as they need.
    fn draw_colour_key(
        &self,
        root: &Area,
        (x, y): (i32, i32),
        width: i32,
        grey: RGBColor,
    ) -> Result<(), PlotError> {
        let (title_w, places) = self.key_layout(width);
        label(
            root,
            &self.key_heading(),
            (x, y + 52),
            (HPos::Left, VPos::Center),
            18.0,
            true,
            grey,
            title_w,
        )?;
        for ((name, colour), (dx, row)) in self.key.iter().zip(places) {
            let (cx, ky) = (x + dx, y + 52 + 30 * row);
            let c = RGBColor(colour.0, colour.1, colour.2);
            root.draw(&PathElement::new(
                vec![(cx, ky), (cx + KEY_SWATCH, ky)],
                ShapeStyle::from(c).stroke_width(4),
            ))?;
            label(
                root,
                name,
                (cx + KEY_SWATCH + 6, ky),
                (HPos::Left, VPos::Center),
                18.0,
                false,
                BLACK,
                width - dx - KEY_SWATCH - 6,
            )?;
        }
        Ok(())
    }

    /// What the markers say, drawn in grey (each panel draws them in its lines' colours),
    /// and the limit's line and shade.
    fn draw_marker_key(
        &self,
        root: &Area,
        (x, y): (i32, i32),
        width: i32,
        grey: RGBColor,
    ) -> Result<(), PlotError> {
        let my = y + self.head(width) - 30;
        let mut mx = x;
        mx += label(
            root,
            "verdict —",
            (mx, my),
            (HPos::Left, VPos::Center),
            18.0,
            true,
            grey,
            200,
        )? + 16;
        for (verdict, name) in [
            (Verdict::Feasible, "feasible"),
            (Verdict::Marginal, "marginal"),
            (Verdict::Infeasible, "infeasible"),
            (
                Verdict::Failed,
                "no answer (failed or not run), under the values",
            ),
        ] {
            draw_marker(root, verdict, (mx + 7, my), grey, 7)?;
            mx += 24;
            mx += label(
                root,
                name,
                (mx, my),
                (HPos::Left, VPos::Center),
                18.0,
                false,
                BLACK,
                width / 2,
            )? + 22;
        }
        if let Some((_, name)) = &self.limit {
            let shade = over_limit_shade();
            root.draw(&Rectangle::new(
                [(mx, my - 11), (mx + 34, my + 11)],
                shade.filled(),
            ))?;
            dashed(root, (mx, mx + 34), my, BLACK)?;
            mx += 42;
            label(
                root,
                &format!("{name}, shaded above"),
                (mx, my),
                (HPos::Left, VPos::Center),
                18.0,
                false,
                BLACK,
                (x + width - mx).max(60),
            )?;
        }
        Ok(())
    }

    fn draw_panel(
        &self,
        root: &Area,
        panel: &Panel,
        (left, top): (i32, i32),
        (w, h): (i32, i32),
        first_column: bool,
    ) -> Result<(), PlotError> {
        let (right, bottom) = (left + w, top + h);
        // The values above, the band of the designs without an answer below.
        let strip = self.no_answer_strip();
        let (dh, floor) = (h - strip, bottom - strip);
        label(
            root,
            &panel.title,
            (left + w / 2, top - 6),
            (HPos::Center, VPos::Bottom),
            18.0,
            true,
            BLACK,
            w,
        )?;
        // Shaded above the limit, then the grid, the frame and the limit's line.
        if let Some((limit, _)) = self.limit {
            let yl = self.py(limit, top, dh).clamp(top, floor);
            if yl > top {
                root.draw(&Rectangle::new(
                    [(left, top), (right, yl)],
                    over_limit_shade().filled(),
                ))?;
            }
        }
        self.draw_grid(root, (left, top), (w, h), dh, first_column)?;
        if strip > 0 {
            root.draw(&Rectangle::new(
                [(left, floor), (right, bottom)],
                RGBColor(238, 238, 238).filled(),
            ))?;
            if first_column {
                label(
                    root,
                    "no answer",
                    (left - 8, floor + strip / 2),
                    (HPos::Right, VPos::Center),
                    13.0,
                    false,
                    RGBColor(90, 90, 90),
                    LEFT - 12,
                )?;
            }
        }
        root.draw(&Rectangle::new(
            [(left, top), (right, bottom)],
            ShapeStyle::from(RGBColor(130, 130, 130)).stroke_width(1),
        ))?;
        if let Some((limit, _)) = self.limit {
            let yl = self.py(limit, top, dh);
            if yl >= top && yl <= floor {
                dashed(root, (left, right), yl, BLACK)?;
            }
        }
        self.draw_lines(root, panel, (left, top), (w, h), dh)?;
        Ok(())
    }

    /// The grid of a panel: its y values (labelled in the first column) and its x ticks.
    fn draw_grid(
        &self,
        root: &Area,
        (left, top): (i32, i32),
        (w, h): (i32, i32),
        dh: i32,
        first_column: bool,
    ) -> Result<(), PlotError> {
        let (right, bottom) = (left + w, top + h);
        let grid = ShapeStyle::from(RGBColor(225, 225, 225)).stroke_width(1);
        let (y0, y1) = self.y_range;
        let step = nice_step((y1 - y0) / 5.0);
        let mut v = (y0 / step).ceil() * step;
        while v <= y1 + 1e-9 {
            let yy = self.py(v, top, dh);
            root.draw(&PathElement::new(vec![(left, yy), (right, yy)], grid))?;
            if first_column {
                label(
                    root,
                    &tick_label(v),
                    (left - 8, yy),
                    (HPos::Right, VPos::Center),
                    16.0,
                    false,
                    BLACK,
                    LEFT - 30,
                )?;
            }
            v += step;
        }
        for (v, text) in &self.x_ticks {
            let xx = self.px(*v, left, w);
            root.draw(&PathElement::new(vec![(xx, top), (xx, bottom)], grid))?;
            root.draw(&PathElement::new(
                vec![(xx, bottom + 2), (xx, bottom + 6)],
                ShapeStyle::from(BLACK).stroke_width(1),
            ))?;
            label(
                root,
                text,
                (xx, bottom + 10),
                (HPos::Center, VPos::Top),
                16.0,
                false,
                BLACK,
                (w / self.x_ticks.len().max(1) as i32).max(20),
            )?;
        }
        Ok(())
    }

    /// A panel's lines, then their markers on top (those without an answer in the band at
    /// the bottom, a row per line).
    fn draw_lines(
        &self,
        root: &Area,
        panel: &Panel,
        (left, top): (i32, i32),
        (w, h): (i32, i32),
        dh: i32,
    ) -> Result<(), PlotError> {
        let bottom = top + h;
        // The lines, then their markers on top.
        for line in &panel.lines {
            let c = RGBColor(line.colour.0, line.colour.1, line.colour.2);
            let pts: Vec<(i32, i32)> = line
                .points
                .iter()
                .filter_map(|p| Some((self.px(p.x, left, w), self.py(p.y?, top, dh))))
                .collect();
            if self.connect && pts.len() > 1 {
                root.draw(&PathElement::new(pts, ShapeStyle::from(c).stroke_width(2)))?;
            }
        }
        for (li, line) in panel.lines.iter().enumerate() {
            let c = RGBColor(line.colour.0, line.colour.1, line.colour.2);
            for p in &line.points {
                let xx = self.px(p.x, left, w);
                // Without an answer: in the band at the bottom, a row per line.
                let yy = match p.y {
                    Some(y) => self.py(y, top, dh),
                    None => bottom - 10 - NO_ANSWER_ROW * li as i32,
                };
                draw_marker(root, p.verdict, (xx, yy), c, 6)?;
            }
        }
        Ok(())
    }
}

/// The pale magenta behind the part of a panel over the limit (the maps' over-limit colour,
/// much lightened).
fn over_limit_shade() -> RGBColor {
    let mix = |c: u8| (255.0 - 0.08 * (255.0 - c as f64)).round() as u8;
    RGBColor(mix(OVER_LIMIT.0), mix(OVER_LIMIT.1), mix(OVER_LIMIT.2))
}

/// A horizontal dashed line from `x0` to `x1` at row `y`.
fn dashed(root: &Area, (x0, x1): (i32, i32), y: i32, c: RGBColor) -> Result<(), PlotError> {
    let mut x = x0;
    while x < x1 {
        let end = (x + 9).min(x1);
        root.draw(&PathElement::new(
            vec![(x, y), (end, y)],
            ShapeStyle::from(c).stroke_width(2),
        ))?;
        x += 15;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::canvas::Canvas;

    #[test]
    fn each_marker_sits_at_its_value_and_says_its_verdict_by_its_shape() {
        let blue = Colour::nth(0);
        let pt = |x: f64, y: Option<f64>, verdict: Verdict| PanelPoint { x, y, verdict };
        let chart = Panels {
            title: "t".into(),
            x_label: "r (mm)".into(),
            y_label: "max shear (°)".into(),
            x_ticks: vec![(5.0, "5".into()), (10.0, "10".into())],
            x_range: (4.0, 13.5),
            y_range: (50.0, 80.0),
            limit: Some((60.0, "locking angle 60°".into())),
            columns: 1,
            connect: true,
            panels: vec![Panel {
                title: "rp 6 mm".into(),
                lines: vec![PanelLine {
                    colour: blue,
                    points: vec![
                        pt(5.0, Some(70.0), Verdict::Feasible),
                        pt(7.5, Some(65.0), Verdict::Marginal),
                        pt(10.0, Some(55.0), Verdict::Infeasible),
                        pt(12.5, None, Verdict::Failed),
                    ],
                }],
            }],
            key_title: String::new(),
            key: Vec::new(),
        };
        let width = 900;
        let size = (width as u32, chart.height(width) as u32);
        let mut buf = vec![255u8; (3 * size.0 * size.1) as usize];
        {
            let root = Canvas::with_buffer(&mut buf, size).into_drawing_area();
            chart.draw(&root, (0, 0), width).unwrap();
            root.present().unwrap();
        }
        let rgb = |(x, y): (i32, i32)| {
            let i = 3 * (y as usize * size.0 as usize + x as usize);
            (buf[i], buf[i + 1], buf[i + 2])
        };
        let line = (blue.0, blue.1, blue.2);
        let (w, h) = chart.plot_size(width);
        let (left, top) = chart.plot_origin(0, (0, 0), width);
        let data_h = h - chart.no_answer_strip();
        let at = |x: f64, y: f64| (chart.px(x, left, w), chart.py(y, top, data_h));
        // Feasible: filled in the line's colour, at its x and y.
        assert_eq!(rgb(at(5.0, 70.0)), line);
        assert_eq!(rgb((at(5.0, 70.0).0 + 3, at(5.0, 70.0).1)), line);
        // Marginal: hollow (white inside), its ring in the line's colour.
        let (mx, my) = at(7.5, 65.0);
        assert_eq!(rgb((mx + 2, my)), (255, 255, 255));
        assert!((4..=8).any(|d| rgb((mx + d, my)) == line), "no ring");
        // Infeasible: a cross — its arms on the diagonals, nothing straight out from its
        // centre.
        let (ix, iy) = at(10.0, 55.0);
        assert_eq!(rgb((ix + 4, iy + 4)), line);
        assert_eq!(rgb((ix - 4, iy + 4)), line);
        assert_ne!(rgb((ix, iy + 5)), line);
        assert_ne!(rgb((ix + 5, iy)), line);
        // No answer: a hollow square in the band under the values.
        let sx = chart.px(12.5, left, w);
        let sy = top + h - 10;
        assert!(sy > top + data_h, "in the band");
        assert_eq!(rgb((sx, sy)), (255, 255, 255));
        assert!((4..=7).any(|d| rgb((sx + d, sy)) == line), "no square");
        // The locking angle: black dashes across the panel at 60°.
        let yl = chart.py(60.0, top, data_h);
        let black = (left..left + w)
            .filter(|&x| rgb((x, yl)) == (0, 0, 0))
            .count();
        assert!(
            black > w as usize / 3,
            "{black} black pixels on the limit's row"
        );
    }
}
