//! A shear map in the terminal: the blank's elements rasterised into half blocks (two square-ish
//! pixels per cell, `▀` with the upper pixel's colour in front and the lower one's behind), on
//! the palette of the PNG maps; shades (`░▒▓█`) where there are no colours.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::widgets::Widget;

use crate::report::maps::colour_of;
use crate::report::mirror::PlanQuad;

/// The map of one design.
pub struct ShearMap<'a> {
    /// The full blank's quads in plan (mm) and their shear (°).
    pub quads: &'a [PlanQuad],
    pub shear_deg: &'a [f64],
    pub locking_angle_deg: f64,
    /// The top of the colour scale, °.
    pub scale_max: f64,
    pub colour: bool,
}

/// Whether `p` lies in the triangle `a b c` (either orientation).
fn in_triangle(p: [f64; 2], a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> bool {
    let cross = |o: [f64; 2], u: [f64; 2], v: [f64; 2]| {
        (u[0] - o[0]) * (v[1] - o[1]) - (u[1] - o[1]) * (v[0] - o[0])
    };
    let (d1, d2, d3) = (cross(a, b, p), cross(b, c, p), cross(c, a, p));
    let neg = d1 < 0.0 || d2 < 0.0 || d3 < 0.0;
    let pos = d1 > 0.0 || d2 > 0.0 || d3 > 0.0;
    !(neg && pos)
}

/// The shear at each pixel of a `width × height` raster (row 0 at the top, +y up in plan),
/// `None` off the blank.
pub fn rasterise(
    quads: &[PlanQuad],
    values: &[f64],
    width: usize,
    height: usize,
) -> Vec<Option<f64>> {
    let mut pixels = vec![None; width * height];
    if quads.is_empty() || width == 0 || height == 0 {
        return pixels;
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for q in quads {
        for p in q {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    // One scale for both directions (square pixels), centred.
    let span = [(hi[0] - lo[0]).max(1e-9), (hi[1] - lo[1]).max(1e-9)];
    let scale = (width as f64 / span[0]).min(height as f64 / span[1]);
    let offset = [
        0.5 * (width as f64 - span[0] * scale),
        0.5 * (height as f64 - span[1] * scale),
    ];
    let to_px = |p: [f64; 2]| {
        [
            offset[0] + (p[0] - lo[0]) * scale,
            offset[1] + (hi[1] - p[1]) * scale,
        ]
    };
    for (q, &v) in quads.iter().zip(values) {
        let c = q.map(to_px);
        let x0 = c
            .iter()
            .map(|p| p[0])
            .fold(f64::INFINITY, f64::min)
            .floor()
            .max(0.0) as usize;
        let x1 = c
            .iter()
            .map(|p| p[0])
            .fold(f64::NEG_INFINITY, f64::max)
            .ceil() as usize;
        let y0 = c
            .iter()
            .map(|p| p[1])
            .fold(f64::INFINITY, f64::min)
            .floor()
            .max(0.0) as usize;
        let y1 = c
            .iter()
            .map(|p| p[1])
            .fold(f64::NEG_INFINITY, f64::max)
            .ceil() as usize;
        for y in y0..y1.min(height) {
            for x in x0..x1.min(width) {
                let p = [x as f64 + 0.5, y as f64 + 0.5];
                if in_triangle(p, c[0], c[1], c[2]) || in_triangle(p, c[0], c[2], c[3]) {
                    let px = &mut pixels[y * width + x];
                    *px = Some(px.map_or(v, |old: f64| old.max(v)));
                }
            }
        }
    }
    pixels
}

/// The colour of a shear value.
pub fn colour(value: f64, limit: f64) -> Color {
    let (r, g, b) = colour_of(value, limit);
    Color::Rgb(r, g, b)
}

/// A shade for a shear value where there are no colours: rising with the shear, full over the
/// locking angle.
pub fn shade(value: f64, limit: f64) -> char {
    if value > limit {
        '█'
    } else if value > 0.66 * limit {
        '▓'
    } else if value > 0.33 * limit {
        '▒'
    } else {
        '░'
    }
}

impl Widget for ShearMap<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let (w, h) = (area.width as usize, area.height as usize);
        let limit = self.locking_angle_deg;
        let top = self.scale_max.max(limit);
        // Values above the scale's top are shown at the top.
        let clip = |v: f64| v.min(top);
        if self.colour {
            let px = rasterise(self.quads, self.shear_deg, w, 2 * h);
            for y in 0..h {
                for x in 0..w {
                    let (up, down) = (px[2 * y * w + x], px[(2 * y + 1) * w + x]);
                    let cell = &mut buf[(area.x + x as u16, area.y + y as u16)];
                    match (up, down) {
                        (None, None) => {}
                        (Some(u), None) => {
                            cell.set_char('▀')
                                .set_style(Style::default().fg(colour(clip(u), limit)));
                        }
                        (None, Some(d)) => {
                            cell.set_char('▄')
                                .set_style(Style::default().fg(colour(clip(d), limit)));
                        }
                        (Some(u), Some(d)) => {
                            cell.set_char('▀').set_style(
                                Style::default()
                                    .fg(colour(clip(u), limit))
                                    .bg(colour(clip(d), limit)),
                            );
                        }
                    }
                }
            }
        } else {
            // A cell is twice as high as wide: a pixel is two cells side by side.
            let half = w / 2;
            let px = rasterise(self.quads, self.shear_deg, half, h);
            for y in 0..h {
                for x in 0..half {
                    if let Some(v) = px[y * half + x] {
                        for k in 0..2 {
                            buf[(area.x + (2 * x + k) as u16, area.y + y as u16)]
                                .set_char(shade(v, limit));
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_unit_square_fills_a_square_raster_and_leaves_the_rest() {
        let quads = [[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]];
        let px = rasterise(&quads, &[5.0], 8, 4);
        // The square is 4 pixels wide, centred in an 8 × 4 raster.
        let row: Vec<bool> = (0..8).map(|x| px[x].is_some()).collect();
        assert_eq!(row, [false, false, true, true, true, true, false, false]);
        assert_eq!(px.iter().flatten().count(), 16);
        assert!(px.iter().flatten().all(|&v| v == 5.0));
    }

    #[test]
    fn plan_y_points_up() {
        // Two stacked elements: the upper one (y in 1..2) is drawn on the upper rows.
        let quads = [
            [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            [[0.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]],
        ];
        let px = rasterise(&quads, &[1.0, 2.0], 2, 4);
        assert_eq!(px[0], Some(2.0));
        assert_eq!(px[7], Some(1.0));
    }

    #[test]
    fn shades_rise_to_full_over_the_limit() {
        assert_eq!(shade(5.0, 60.0), '░');
        assert_eq!(shade(30.0, 60.0), '▒');
        assert_eq!(shade(50.0, 60.0), '▓');
        assert_eq!(shade(61.0, 60.0), '█');
    }
}
