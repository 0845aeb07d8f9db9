//! The report sheet of a design sweep (`report.png`): one picture a person can put in front of
//! a colleague.
//!
//! ```text
//! ┌──────────────────────────────────────────────────────────────────────────────────────┐
//! │ title: the sweep, how many designs are feasible                                      │
//! │ subtitle: the base scene, what is held fixed                                         │
//! ├──────────────────────────────────────────┬───────────────────────────────────────────┤
//! │ colour bar (one scale for every map),    │ chart: max shear against a swept radius,  │
//! │ the locking angle marked                 │ a small panel per combination of the      │
//! │                                          │ other parameters, the locking angle in    │
//! │                                          │ each (see `panels.rs`)                    │
//! │ ┌──────┐ ┌──────┐ ┌──────┐               │                                           │
//! │ │ map  │ │ map  │ │ map  │  each tile:   │                                           │
//! │ └──────┘ └──────┘ └──────┘  parameters,  │                                           │
//! │   ...                       verdict, and │                                           │
//! │                             a border in  │                                           │
//! │                             its colour   │                                           │
//! └──────────────────────────────────────────┴───────────────────────────────────────────┘
//! ```
//!
//! The maps are drawn with [`super::maps::colour_of`], the scale of the single-design maps:
//! pale to dark blue up to the locking angle, magenta past it.

use super::error::{DrawError, PlotError};
use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::maps::{OVER_LIMIT, colour_of, nice_step};
use super::mirror::PlanQuad;
use super::panels::Panels;
use super::plot::{register_fonts, tick_label};
use crate::verdict::Verdict;

impl Verdict {
    /// The colour of the verdict on the sheet (Okabe–Ito green and vermilion, greys).
    pub fn colour(self) -> (u8, u8, u8) {
        match self {
            Verdict::Feasible => (0, 150, 100),
            Verdict::Marginal => (230, 159, 0),
            Verdict::Infeasible => (213, 70, 0),
            Verdict::Failed => (90, 90, 90),
            Verdict::Invalid => (160, 160, 160),
        }
    }
}

/// The shear field of one design for a tile: the full blank in plan.
#[derive(Clone, Debug, PartialEq)]
pub struct TileMap {
    pub quads: Vec<PlanQuad>,
    /// |shear| of each quad, degrees.
    pub values: Vec<f64>,
    /// The locking angle of this design, degrees.
    pub limit: f64,
    /// The die opening, a closed polyline (mm).
    pub die_opening: Vec<[f64; 2]>,
}

/// One design on the sheet.
#[derive(Clone, Debug, PartialEq)]
pub struct Tile {
    /// The design's id, e.g. `d007-3fa1c2` (its map is `maps/<id>.png`).
    pub id: String,
    /// The swept parameters, a line or two, e.g. `r 5, rp 6, rm 5 mm`.
    pub lines: Vec<String>,
    pub verdict: Verdict,
    /// The largest shear, degrees, when the design ran.
    pub max_shear_deg: Option<f64>,
    /// Why a design failed or is invalid (shortened on the sheet).
    pub reason: Option<String>,
    pub map: Option<TileMap>,
}

/// The whole sheet.
#[derive(Clone, Debug, PartialEq)]
pub struct Sheet {
    pub title: String,
    /// Lines under the title: the base scene, the parameters held fixed, the limits.
    pub subtitle: Vec<String>,
    pub tiles: Vec<Tile>,
    /// Said above the tiles, e.g. "36 of 81 designs shown".
    pub tiles_note: Option<String>,
    /// The top of the shared colour scale, degrees.
    pub scale_max: f64,
    /// The locking angle, degrees (marked on the colour bar).
    pub limit: f64,
    /// Max shear against a swept radius in small multiples, the locking angle in each.
    pub chart: Option<Panels>,
    /// Said under the chart (what the lines and markers are).
    pub chart_note: Vec<String>,
    /// Under the chart: the designs ranked (feasible first, then by max shear), one line each,
    /// in the colour of its verdict; the first line is a heading.
    pub ranking: Vec<(Option<Verdict>, String)>,
}

use super::canvas::{Area, write_png};

const MARGIN: i32 = 30;
const TITLE_H: i32 = 40 + 2 * 8;
const BAR_H: i32 = 120;
const CHART_W: i32 = 1150;

/// Columns of the tile grid for `n` tiles: a square-ish grid, at most 6 wide (9 past 36).
pub fn grid_columns(n: usize) -> usize {
    let cols = (n as f64).sqrt().ceil() as usize;
    cols.clamp(1, if n > 36 { 9 } else { 6 })
}

impl Sheet {
    /// Tile size in pixels (width, height of the map part, height of the label part).
    fn tile_size(&self) -> (i32, i32, i32) {
        let cols = grid_columns(self.tiles.len());
        let w = if cols > 6 { 215 } else { 260 };
        (w, w - 12, 80)
    }

    /// The chart's height in pixels (0 without a chart: its note says why).
    fn chart_height(&self) -> i32 {
        self.chart.as_ref().map_or(0, |c| c.height(CHART_W))
    }

    /// The picture's size in pixels.
    pub fn size(&self) -> (u32, u32) {
        let n = self.tiles.len().max(1);
        let cols = grid_columns(n) as i32;
        let rows = n.div_ceil(cols as usize) as i32;
        let (w, mh, lh) = self.tile_size();
        let grid_w = (cols * w).max(900);
        let grid_h = rows * (mh + lh + 14);
        let head = TITLE_H + 30 * self.subtitle.len() as i32 + 20;
        let chart_h = self.chart_height()
            + 26 * self.chart_note.len() as i32
            + 40
            + 27 * self.ranking.len() as i32;
        let width = MARGIN + grid_w + 50 + CHART_W + MARGIN;
        let height = head + (BAR_H + 36 + grid_h).max(chart_h) + MARGIN;
        (width as u32, height as u32)
    }

    /// Draws the sheet to a PNG file. Errors name the file.
    pub fn write_png(&self, path: &Path) -> Result<(), DrawError> {
        register_fonts();
        let size = self.size();
        write_png(path, size, "sheet", |root| self.draw(root, size))
    }

    fn draw(&self, root: &Area, (width, _): (u32, u32)) -> Result<(), PlotError> {
        let width = width as i32;
        fit_text(
            root,
            &self.title,
            (MARGIN, 18),
            width - 2 * MARGIN,
            36,
            true,
            BLACK,
        )?;
        let mut y = TITLE_H + 8;
        for line in &self.subtitle {
            fit_text(
                root,
                line,
                (MARGIN, y),
                width - 2 * MARGIN,
                21,
                false,
                RGBColor(60, 60, 60),
            )?;
            y += 30;
        }
        let top = y + 20;
        let n = self.tiles.len().max(1);
        let cols = grid_columns(n) as i32;
        let (tw, _, _) = self.tile_size();
        let grid_w = (cols * tw).max(900);
        self.draw_bar(root, MARGIN, top, grid_w)?;
        let mut grid_top = top + BAR_H;
        if let Some(note) = &self.tiles_note {
            fit_text(
                root,
                note,
                (MARGIN, grid_top),
                grid_w,
                20,
                true,
                RGBColor(40, 40, 40),
            )?;
        }
        grid_top += 36;
        self.draw_tiles(root, MARGIN, grid_top, cols)?;
        self.draw_right(root, MARGIN + grid_w + 50, top)?;
        Ok(())
    }

    /// The right column from `(chart_x, top)`: the chart, its notes, the ranking.
    fn draw_right(&self, root: &Area, chart_x: i32, top: i32) -> Result<(), PlotError> {
        if let Some(chart) = &self.chart {
            chart.draw(root, (chart_x, top), CHART_W)?;
        }
        let mut y = top + self.chart_height() + 10;
        for line in &self.chart_note {
            fit_text(
                root,
                line,
                (chart_x + 20, y),
                CHART_W - 20,
                19,
                false,
                RGBColor(60, 60, 60),
            )?;
            y += 26;
        }
        y += 24;
        for (verdict, line) in &self.ranking {
            let (colour, bold) = match verdict {
                Some(v) => {
                    let (r, g, b) = v.colour();
                    (RGBColor(r, g, b), false)
                }
                None => (BLACK, true),
            };
            fit_text(
                root,
                line,
                (chart_x + 20, y),
                CHART_W - 20,
                19,
                bold,
                colour,
            )?;
            y += 27;
        }
        Ok(())
    }

    /// The shared colour scale, horizontal, with the locking angle marked.
    fn draw_bar(&self, root: &Area, x: i32, y: i32, w: i32) -> Result<(), PlotError> {
        let font = "sans-serif";
        let top = if self.scale_max > 0.0 {
            self.scale_max
        } else {
            1.1 * self.limit.max(1.0)
        };
        let (x0, x1) = (x + 150, x + w - 40);
        let (y0, y1) = (y + 34, y + 66);
        let px = |v: f64| x0 + ((v / top).clamp(0.0, 1.0) * (x1 - x0) as f64).round() as i32;
        root.draw(&Text::new(
            "shear (°)",
            (x, (y0 + y1) / 2),
            (font, 22)
                .into_font()
                .style(FontStyle::Bold)
                .color(&BLACK)
                .pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
        for i in x0..x1 {
            let v = top * ((i - x0) as f64 + 0.5) / (x1 - x0) as f64;
            let c = colour_of(v, self.limit);
            root.draw(&Rectangle::new(
                [(i, y0), (i + 1, y1)],
                RGBColor(c.0, c.1, c.2).filled(),
            ))?;
        }
        root.draw(&Rectangle::new(
            [(x0, y0), (x1, y1)],
            ShapeStyle::from(BLACK).stroke_width(1),
        ))?;
        let step = nice_step(top / 8.0);
        let label = (font, 17)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Top));
        let mut v = 0.0;
        while v <= top + 1e-9 {
            let p = px(v);
            // Clear of the bar: a gap, the tick, a gap, the label.
            root.draw(&PathElement::new(
                vec![(p, y1 + 5), (p, y1 + 11)],
                ShapeStyle::from(BLACK).stroke_width(1),
            ))?;
            if (p - px(self.limit)).abs() > 28 {
                root.draw(&Text::new(tick_label(v), (p, y1 + 19), label.clone()))?;
            }
            v += step;
        }
        // The locking angle: a thick line across the bar, named above it.
        self.draw_bar_limit(root, px(self.limit), (x1, y0, y1))?;
        root.draw(&Text::new(
            "one colour scale for every map of the sweep",
            (x0, y1 + 44),
            (font, 17)
                .into_font()
                .color(&RGBColor(70, 70, 70))
                .pos(Pos::new(HPos::Left, VPos::Top)),
        ))?;
        Ok(())
    }

    /// The locking angle on the colour bar at `pl`: a thick line across the bar (from `x1`'s
    /// left, rows `y0..y1`), named above it and valued under it.
    fn draw_bar_limit(
        &self,
        root: &Area,
        pl: i32,
        (x1, y0, y1): (i32, i32, i32),
    ) -> Result<(), PlotError> {
        root.draw(&PathElement::new(
            vec![(pl, y0 - 10), (pl, y1 + 8)],
            ShapeStyle::from(BLACK).stroke_width(4),
        ))?;
        root.draw(&Text::new(
            format!("locking angle {}°", tick_label(self.limit)),
            (pl, y0 - 12),
            ("sans-serif", 20)
                .into_font()
                .style(FontStyle::Bold)
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Bottom)),
        ))?;
        root.draw(&Text::new(
            format!("{}°", tick_label(self.limit)),
            (pl, y1 + 19),
            ("sans-serif", 17)
                .into_font()
                .style(FontStyle::Bold)
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Top)),
        ))?;
        if x1 - pl > 150 {
            root.draw(&Text::new(
                "over the limit",
                ((pl + x1) / 2, (y0 + y1) / 2),
                ("sans-serif", 18)
                    .into_font()
                    .style(FontStyle::Bold)
                    .color(&WHITE)
                    .pos(Pos::new(HPos::Center, VPos::Center)),
            ))?;
        }
        Ok(())
    }

    fn draw_tiles(&self, root: &Area, x: i32, y: i32, cols: i32) -> Result<(), PlotError> {
        let (w, mh, lh) = self.tile_size();
        for (i, tile) in self.tiles.iter().enumerate() {
            let (c, r) = (i as i32 % cols, i as i32 / cols);
            let x0 = x + c * w;
            let y0 = y + r * (mh + lh + 14);
            draw_tile(root, tile, (x0, y0), (w - 10, mh + lh), lh)?;
        }
        Ok(())
    }
}

/// One tile: a border in the verdict's colour, the labels, the map (or the reason).
fn draw_tile(
    root: &Area,
    tile: &Tile,
    (x0, y0): (i32, i32),
    (w, h): (i32, i32),
    label_h: i32,
) -> Result<(), PlotError> {
    let font = "sans-serif";
    let (cr, cg, cb) = tile.verdict.colour();
    let colour = RGBColor(cr, cg, cb);
    // The label band, tinted with the verdict's colour; then the border.
    root.draw(&Rectangle::new(
        [(x0, y0), (x0 + w, y0 + label_h)],
        colour.mix(0.12).filled(),
    ))?;
    let mut ly = y0 + 9;
    let first = match tile.lines.first() {
        Some(l) => format!("{}  {l}", short_id(&tile.id)),
        None => short_id(&tile.id).to_string(),
    };
    fit_text(root, &first, (x0 + 12, ly), w - 24, 17, false, BLACK)?;
    ly += 21;
    for line in tile.lines.iter().skip(1).take(1) {
        fit_text(root, line, (x0 + 12, ly), w - 24, 17, false, BLACK)?;
        ly += 21;
    }
    let shear = tile
        .max_shear_deg
        .map(|s| format!("  {s:.1}°"))
        .unwrap_or_default();
    let verdict = format!("{} {}{shear}", tile.verdict.mark(), tile.verdict.word());
    fit_text(
        root,
        &verdict,
        (x0 + 12, y0 + label_h - 24),
        w - 24,
        19,
        true,
        colour,
    )?;
    let (mx0, my0, mx1, my1) = (x0 + 6, y0 + label_h + 4, x0 + w - 6, y0 + h - 6);
    match &tile.map {
        Some(map) => draw_tile_map(root, map, (mx0, my0, mx1, my1))?,
        None => {
            let reason = tile.reason.as_deref().unwrap_or("not run");
            let mut yy = my0 + 10;
            for line in wrap(reason, ((mx1 - mx0) / 8).max(10) as usize)
                .into_iter()
                .take(((my1 - my0) / 20 - 1).max(1) as usize)
            {
                root.draw(&Text::new(
                    line,
                    (mx0 + 4, yy),
                    (font, 15).into_font().color(&RGBColor(70, 70, 70)),
                ))?;
                yy += 19;
            }
        }
    }
    let width = if tile.verdict == Verdict::Feasible {
        6
    } else {
        4
    };
    for k in 0..width {
        root.draw(&Rectangle::new(
            [(x0 + k, y0 + k), (x0 + w - k, y0 + h - k)],
            ShapeStyle::from(colour).stroke_width(1),
        ))?;
    }
    Ok(())
}

/// `d007-3fa1c2` → `d007`: the index is enough on a tile (the full id names the map file).
fn short_id(id: &str) -> &str {
    id.split('-').next().unwrap_or(id)
}

/// The blank seen from above inside the pixel box `(x0, y0, x1, y1)`, equal scales.
fn draw_tile_map(
    root: &Area,
    map: &TileMap,
    (x0, y0, x1, y1): (i32, i32, i32, i32),
) -> Result<(), PlotError> {
    let (mut bx0, mut bx1, mut by0, mut by1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for p in map.quads.iter().flatten().chain(&map.die_opening) {
        if p[0].is_finite() && p[1].is_finite() {
            bx0 = bx0.min(p[0]);
            bx1 = bx1.max(p[0]);
            by0 = by0.min(p[1]);
            by1 = by1.max(p[1]);
        }
    }
    if !(bx0 < bx1 && by0 < by1) {
        return Ok(());
    }
    let s = ((x1 - x0) as f64 / (bx1 - bx0)).min((y1 - y0) as f64 / (by1 - by0));
    let (cx, cy) = (0.5 * (bx0 + bx1), 0.5 * (by0 + by1));
    let (px, py) = (0.5 * (x0 + x1) as f64, 0.5 * (y0 + y1) as f64);
    let to_px = |p: &[f64; 2]| {
        (
            (px + s * (p[0] - cx)).round() as i32,
            (py - s * (p[1] - cy)).round() as i32,
        )
    };
    for (q, &v) in map.quads.iter().zip(&map.values) {
        let c = colour_of(v, map.limit);
        let pts: Vec<(i32, i32)> = q.iter().map(to_px).collect();
        root.draw(&Polygon::new(pts, RGBColor(c.0, c.1, c.2).filled()))?;
    }
    if !map.die_opening.is_empty() {
        let pts: Vec<(i32, i32)> = map.die_opening.iter().map(to_px).collect();
        root.draw(&PathElement::new(
            pts,
            ShapeStyle::from(RGBColor(90, 90, 90)).stroke_width(1),
        ))?;
    }
    // Cells past the limit are magenta in the fill; a dot of their colour at their centre keeps
    // a single over-limit cell visible at this size.
    let over = RGBColor(OVER_LIMIT.0, OVER_LIMIT.1, OVER_LIMIT.2);
    for (q, _) in map
        .quads
        .iter()
        .zip(&map.values)
        .filter(|(_, v)| **v > map.limit)
    {
        let c = [
            0.25 * (q[0][0] + q[1][0] + q[2][0] + q[3][0]),
            0.25 * (q[0][1] + q[1][1] + q[2][1] + q[3][1]),
        ];
        root.draw(&Circle::new(to_px(&c), 2, over.filled()))?;
    }
    Ok(())
}

/// Left-aligned text at the largest size up to `size` that fits `max_w` pixels.
#[allow(clippy::too_many_arguments)]
fn fit_text(
    root: &Area,
    text: &str,
    at: (i32, i32),
    max_w: i32,
    size: u32,
    bold: bool,
    colour: RGBColor,
) -> Result<(), PlotError> {
    let style_at = |size: u32| {
        let f = ("sans-serif", size).into_font();
        let f = if bold { f.style(FontStyle::Bold) } else { f };
        f.color(&colour).pos(Pos::new(HPos::Left, VPos::Top))
    };
    let mut size = size;
    while size > 9 {
        match root.estimate_text_size(text, &style_at(size)) {
            Ok((tw, _)) if tw as i32 > max_w => size -= 1,
            _ => break,
        }
    }
    root.draw(&Text::new(text.to_string(), at, style_at(size)))?;
    Ok(())
}

/// Splits text into lines of at most `width` characters at spaces.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > width {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_stay_square_ish() {
        assert_eq!(grid_columns(1), 1);
        assert_eq!(grid_columns(6), 3);
        assert_eq!(grid_columns(27), 6);
        assert_eq!(grid_columns(36), 6);
        assert_eq!(grid_columns(81), 9);
        assert_eq!(nice_step(7.3), 10.0);
        assert_eq!(nice_step(1.2), 2.0);
        assert_eq!(wrap("a bb ccc dddd", 6), vec!["a bb", "ccc", "dddd"]);
    }

    #[test]
    fn a_sheet_draws_and_decodes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sheet.png");
        let quad = |x: f64, y: f64| [[x, y], [x + 10.0, y], [x + 10.0, y + 10.0], [x, y + 10.0]];
        let map = TileMap {
            quads: vec![quad(0.0, 0.0), quad(10.0, 0.0)],
            values: vec![10.0, 70.0],
            limit: 60.0,
            die_opening: vec![[0.0, 0.0], [20.0, 0.0], [20.0, 10.0], [0.0, 0.0]],
        };
        let tile = |v: Verdict, m: Option<TileMap>| Tile {
            id: "d000-abcdef".into(),
            lines: vec!["r 5, rp 6, rm 5 mm".into(), "friction 0.2".into()],
            verdict: v,
            max_shear_deg: m.as_ref().map(|_| 70.0),
            reason: Some("tools.r = 40: expected a corner radius r < side/2 = 30 mm".into()),
            map: m,
        };
        let sheet = Sheet {
            title: "Sweep test: 3 designs".into(),
            subtitle: vec!["base".into()],
            tiles: vec![
                tile(Verdict::Feasible, Some(map.clone())),
                tile(Verdict::Infeasible, Some(map)),
                tile(Verdict::Invalid, None),
            ],
            tiles_note: None,
            scale_max: 77.0,
            limit: 60.0,
            chart: None,
            chart_note: vec![],
            ranking: vec![
                (None, "Ranked".into()),
                (Some(Verdict::Feasible), "d000".into()),
            ],
        };
        sheet.write_png(&path).unwrap();
        let img = image::open(&path).unwrap();
        assert_eq!((img.width(), img.height()), sheet.size());
    }
}
