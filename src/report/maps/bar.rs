//! The colour bar beside a map: the scale from 0 (bottom) to its top, ticked and labelled on
//! its left with a clear gap between the bar, the ticks and the labels; on its right the limit
//! (a thick line with its name and value) and the largest element value (a red tick).

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{FieldMap, colour_on};
use crate::report::canvas::Area;
use crate::report::error::PlotError;
use crate::report::plot::tick_label;

/// Width of the bar, px.
pub const BAR_W: i32 = 30;
/// Blank between the bar's left edge and its tick marks, px.
pub const TICK_GAP: i32 = 5;
/// Length of a tick mark, px.
const TICK_LEN: i32 = 6;
/// Blank between a tick mark and its label, px.
const LABEL_GAP: i32 = 5;
/// From the bar area's left edge to the bar: room for the labels, the ticks and the gaps.
const BAR_LEFT: i32 = 72;

/// 1, 2 or 5 times a power of ten, at least `raw`.
pub fn nice_step(raw: f64) -> f64 {
    if !(raw > 0.0 && raw.is_finite()) {
        return 1.0;
    }
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * p)
}

impl FieldMap {
    /// The colour bar in `area`, its ends on the map's plot rows `(top, bottom)` (pixels of
    /// the whole picture `root`).
    pub(super) fn draw_bar(
        &self,
        root: &Area,
        area: &Area,
        rows: (i32, i32),
    ) -> Result<(), PlotError> {
        let font = "sans-serif";
        let top = self.scale_top();
        let (cols, _) = area.get_pixel_range();
        let (x0, x1) = (cols.start + BAR_LEFT, cols.start + BAR_LEFT + BAR_W);
        let (y_top, y_bottom) = rows;
        let height = (y_bottom - y_top).max(1) as f64;
        let y_of = |v: f64| y_bottom - ((v / top).clamp(0.0, 1.0) * height).round() as i32;
        self.draw_bands(root, (x0, x1), rows)?;
        root.draw(&Rectangle::new(
            [(x0, y_top), (x1, y_bottom)],
            ShapeStyle::from(BLACK).stroke_width(1),
        ))?;
        // Ticks and labels on the left, clear of the bar.
        draw_ticks(root, top, x0, &y_of)?;
        let text = |s: String, y: i32, bold: bool| {
            let f = (font, 17).into_font();
            let f = if bold { f.style(FontStyle::Bold) } else { f };
            Text::new(
                s,
                (x1 + 16, y),
                f.color(&BLACK).pos(Pos::new(HPos::Left, VPos::Center)),
            )
        };
        // The largest element value: a red tick on the right (under the limit's line when
        // they meet, so the limit stays seen).
        let max = self.values.iter().cloned().fold(0.0, f64::max);
        let y_max = y_of(max.min(top));
        root.draw(&PathElement::new(
            vec![(x1 + 1, y_max), (x1 + 13, y_max)],
            ShapeStyle::from(RGBColor(220, 0, 0)).stroke_width(3),
        ))?;
        // Whether the largest value's label is clear of the limit's.
        let max_label_clear = if self.limit_off_scale() {
            // The field stays under its limit: name the limit above the scale, under the
            // largest value's label (the top of this scale is a little past it).
            let y = y_max.max(y_top + 10) + 30;
            root.draw(&text(self.limit_name.clone(), y, true))?;
            root.draw(&text(
                format!("{}, above", self.unit.show(self.limit)),
                y + 21,
                true,
            ))?;
            root.draw(&text("this scale".into(), y + 42, true))?;
            true
        } else {
            // The limit: a thick line across the bar and out to the right, where its name
            // and value are.
            let y_limit = y_of(self.limit);
            root.draw(&PathElement::new(
                vec![(x0, y_limit), (x1 + 12, y_limit)],
                ShapeStyle::from(BLACK).stroke_width(3),
            ))?;
            root.draw(&text(self.limit_name.clone(), y_limit + 14, true))?;
            root.draw(&text(self.unit.show(self.limit), y_limit + 35, true))?;
            // Over the limit: say what the magenta means.
            if y_limit - y_top > 24 {
                root.draw(&text("over the limit".into(), (y_top + y_limit) / 2, false))?;
            }
            y_max < y_limit - 24 || y_max > y_limit + 50
        };
        if max_label_clear {
            root.draw(&text(
                format!("element {}", self.unit.show(max)),
                y_max,
                false,
            ))?;
        }
        // The caption above the bar.
        self.draw_bar_caption(root, (x0 + x1) / 2, y_top)
    }

    /// The bar's colours: one band per pixel row between `x0` and `x1`, its colour that of the
    /// value at its middle.
    fn draw_bands(
        &self,
        root: &Area,
        (x0, x1): (i32, i32),
        rows: (i32, i32),
    ) -> Result<(), PlotError> {
        let top = self.scale_top();
        let (y_top, y_bottom) = rows;
        let height = (y_bottom - y_top).max(1) as f64;
        let span = self.colour_span();
        for y in y_top..y_bottom {
            let v = top * (y_bottom as f64 - y as f64 - 0.5) / height;
            let c = colour_on(v, self.limit, span);
            root.draw(&Rectangle::new(
                [(x0, y), (x1, y + 1)],
                RGBColor(c.0, c.1, c.2).filled(),
            ))?;
        }
        Ok(())
    }

    /// The bar's caption, centred on `x` above the bar's top row `y_top`.
    fn draw_bar_caption(&self, root: &Area, x: i32, y_top: i32) -> Result<(), PlotError> {
        root.draw(&Text::new(
            self.bar_caption.clone(),
            (x, y_top - 12),
            ("sans-serif", 18)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Bottom)),
        ))?;
        Ok(())
    }
}

/// The ticks and labels of a bar scaled 0..`top`, on the left of its edge `x0`, clear of it;
/// `y_of` places a value.
fn draw_ticks(root: &Area, top: f64, x0: i32, y_of: &dyn Fn(f64) -> i32) -> Result<(), PlotError> {
    let step = nice_step(top / 8.0);
    let tick_style = ShapeStyle::from(BLACK).stroke_width(1);
    let label = ("sans-serif", 16)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Right, VPos::Center));
    let (t1, t0) = (x0 - TICK_GAP, x0 - TICK_GAP - TICK_LEN);
    let mut k = 0;
    loop {
        let v = k as f64 * step;
        if v > top * (1.0 + 1e-9) {
            break;
        }
        let y = y_of(v);
        root.draw(&PathElement::new(vec![(t0, y), (t1, y)], tick_style))?;
        root.draw(&Text::new(
            tick_label(v),
            (t0 - LABEL_GAP, y),
            label.clone(),
        ))?;
        k += 1;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::canvas::Canvas;

    /// A map of two cells, one over the limit, drawn into an RGB buffer.
    fn drawn() -> (Vec<u8>, (u32, u32)) {
        let quad = |x: f64| [[x, 0.0], [x + 50.0, 0.0], [x + 50.0, 40.0], [x, 40.0]];
        let map = FieldMap::shear(
            "max shear".into(),
            String::new(),
            vec![quad(-50.0), quad(0.0)],
            vec![12.0, 71.0],
            60.0,
        );
        let size = map.size;
        let mut buf = vec![255u8; (3 * size.0 * size.1) as usize];
        {
            let root = Canvas::with_buffer(&mut buf, size).into_drawing_area();
            map.draw(&root).unwrap();
            root.present().unwrap();
        }
        (buf, size)
    }

    #[test]
    fn ticks_and_labels_stand_clear_of_the_bar() {
        let (buf, (w, h)) = drawn();
        let rgb = |x: i32, y: i32| {
            let i = 3 * (y as usize * w as usize + x as usize);
            (buf[i], buf[i + 1], buf[i + 2])
        };
        let white = |x: i32, y: i32| rgb(x, y) == (255, 255, 255);
        // The bar is where the over-limit magenta is, in the picture's right 250 columns (the
        // map's over-limit cell is further left).
        let magenta = super::super::OVER_LIMIT;
        let mut left = i32::MAX;
        let mut top = i32::MAX;
        for y in 0..h as i32 {
            for x in (w as i32 - 250)..w as i32 {
                if rgb(x, y) == magenta {
                    left = left.min(x);
                    top = top.min(y);
                }
            }
        }
        assert!(left < i32::MAX, "no over-limit colour on the bar");
        // The bar's left border, then down the bar to its bottom (its palest colour is not
        // white).
        let border = left - 1;
        assert!(rgb(border, top + 5).0 < 60, "no border at {border}");
        let mut bottom = top;
        while bottom + 1 < h as i32 && !white(left + 3, bottom + 1) {
            bottom += 1;
        }
        assert!(bottom - top > 300, "bar from {top} to {bottom}");
        // Four columns just left of the bar are background over its whole height.
        for x in border - 4..border {
            for y in top - 3..=bottom + 3 {
                assert!(
                    white(x, y),
                    "ink at ({x}, {y}) between the bar and its ticks"
                );
            }
        }
        // And the ticks and labels are there, further left: ink on several rows.
        let tick_col = border - TICK_GAP - 2;
        let ticks = (top..=bottom)
            .filter(|&y| !white(tick_col, y) && white(tick_col, y - 1))
            .count();
        assert!(ticks >= 5, "{ticks} ticks");
        let label_ink = (top..=bottom)
            .filter(|&y| (border - 45..tick_col - 4).any(|x| !white(x, y)))
            .count();
        assert!(label_ink > 50, "labels: {label_ink} rows of ink");
    }
}
