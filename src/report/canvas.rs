//! The bitmap every PNG is drawn on: plotters' [`BitMapBackend`] with its text drawn here.
//!
//! plotters 0.3.7 lays a string out with each glyph's advance but draws each glyph from the
//! left edge of its ink, dropping the glyph's left side bearing: letters with a wide bearing
//! sit too far left and words read "m ax sh ear". [`Canvas`] passes every shape to the bitmap
//! and draws text itself with `ab_glyph` (the DejaVu Sans faces embedded in the binary), each
//! glyph at its pen position with its bearing and the font's kerning. Widths are the sum of
//! the advances, as plotters estimates them, so layouts computed from
//! `estimate_text_size` fit the text drawn.

use std::sync::OnceLock;

use image::ImageEncoder as _;

use ab_glyph::{Font, FontRef, GlyphId, PxScale, ScaleFont, point};
use plotters::prelude::*;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind, FontStyle,
};

/// A drawing area on a [`Canvas`], whole or a part of it.
pub type Area<'a> = DrawingArea<Canvas<'a>, plotters::coord::Shift>;

/// plotters' bitmap with text drawn by [`draw_string`].
pub struct Canvas<'a>(BitMapBackend<'a>);

impl<'a> Canvas<'a> {
    /// The same over an RGB buffer of `size` pixels.
    pub fn with_buffer(buffer: &'a mut [u8], size: (u32, u32)) -> Self {
        Canvas(BitMapBackend::with_buffer(buffer, size))
    }
}

/// Draws a picture of `size` pixels with `draw` in memory and writes it to `path` as PNG,
/// whole ([`crate::files::write_atomic`]): a failed write (a full disk) leaves no half or empty
/// file. Errors name the file and the picture (`what`: chart, map, sheet).
pub fn write_png(
    path: &std::path::Path,
    size: (u32, u32),
    what: &'static str,
    draw: impl FnOnce(&Area<'_>) -> Result<(), super::error::PlotError>,
) -> Result<(), super::error::DrawError> {
    let fail = super::error::DrawError::at(path, what);
    let mut pixels = vec![0u8; 3 * size.0 as usize * size.1 as usize];
    {
        let root = Canvas::with_buffer(&mut pixels, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| fail(&e))?;
        draw(&root).map_err(|e| fail(&e))?;
        root.present().map_err(|e| fail(&e))?;
    }
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image(&pixels, size.0, size.1, image::ExtendedColorType::Rgb8)
        .map_err(|e| fail(&e))?;
    crate::files::write_atomic(path, &png).map_err(|e| fail(&format!("cannot write it: {e}")))
}

/// The three faces of DejaVu Sans: regular, bold, oblique.
fn faces() -> &'static [FontRef<'static>; 3] {
    static FACES: OnceLock<[FontRef<'static>; 3]> = OnceLock::new();
    FACES.get_or_init(|| {
        let face = |bytes: &'static [u8]| {
            FontRef::try_from_slice(bytes).expect("the dejavu crate ships valid TrueType fonts")
        };
        [
            face(dejavu::sans::regular()),
            face(dejavu::sans::bold()),
            face(dejavu::sans::oblique()),
        ]
    })
}

fn face(style: FontStyle) -> &'static FontRef<'static> {
    let [regular, bold, oblique] = faces();
    match style {
        FontStyle::Bold => bold,
        FontStyle::Italic | FontStyle::Oblique => oblique,
        FontStyle::Normal => regular,
    }
}

/// The width of `text` in pixels at `size` (the advances and the kerning), as drawn.
pub fn text_width(text: &str, size: f64, style: FontStyle) -> f64 {
    let font = face(style).as_scaled(PxScale::from(size as f32));
    let mut w = 0.0f32;
    let mut prev: Option<GlyphId> = None;
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(p) = prev {
            w += font.kern(p, id);
        }
        w += font.h_advance(id);
        prev = Some(id);
    }
    w as f64
}

/// The layout height plotters gives a line of text at `size` (used for anchoring).
fn line_height(size: f64) -> i32 {
    (size / 1.24) as i32
}

/// Calls `pixel(dx, dy, coverage)` for each inked pixel of `text` at `size`, `(dx, dy)` from
/// the anchor in the text's own (unrotated) frame. The anchor's vertical meaning follows
/// plotters (top: the baseline half the size below it; bottom: the line's layout height
/// above that), except the centre, which centres the font's ascent and descent on it.
pub fn draw_string(
    text: &str,
    size: f64,
    style: FontStyle,
    (h, v): (HPos, VPos),
    mut pixel: impl FnMut(i32, i32, f32),
) {
    let font = face(style).as_scaled(PxScale::from(size as f32));
    let width = text_width(text, size, style);
    let x0 = match h {
        HPos::Left => 0.0,
        HPos::Center => -0.5 * width,
        HPos::Right => -width,
    } as f32;
    let baseline = match v {
        VPos::Top => 0.5 * size as f32,
        VPos::Center => 0.5 * (font.ascent() + font.descent()),
        VPos::Bottom => 0.5 * size as f32 - line_height(size) as f32,
    };
    let mut pen = x0;
    let mut prev: Option<GlyphId> = None;
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(p) = prev {
            pen += font.kern(p, id);
        }
        let glyph = id.with_scale_and_position(font.scale(), point(pen, baseline));
        if let Some(outline) = font.outline_glyph(glyph) {
            let b = outline.px_bounds();
            let (bx, by) = (b.min.x as i32, b.min.y as i32);
            outline.draw(|x, y, cover| pixel(bx + x as i32, by + y as i32, cover));
        }
        pen += font.h_advance(id);
        prev = Some(id);
    }
}

impl<'a> DrawingBackend for Canvas<'a> {
    type ErrorType = <BitMapBackend<'a> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.0.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.blit_bitmap(pos, size, src)
    }

    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let colour = style.color();
        if colour.alpha == 0.0 {
            return Ok(());
        }
        let (w, h) = self.get_size();
        let turn = style.transform();
        let anchor = style.anchor();
        let mut result = Ok(());
        draw_string(
            text,
            style.size(),
            style.style(),
            (anchor.h_pos, anchor.v_pos),
            |dx, dy, cover| {
                let (dx, dy) = turn.transform(dx, dy);
                let (x, y) = (pos.0 + dx, pos.1 + dy);
                if result.is_ok() && x >= 0 && y >= 0 && x < w as i32 && y < h as i32 {
                    let c = BackendColor {
                        alpha: colour.alpha * cover.min(1.0) as f64,
                        rgb: colour.rgb,
                    };
                    result = self.0.draw_pixel((x, y), c);
                }
            },
        );
        result
    }

    fn estimate_text_size<S: BackendTextStyle>(
        &self,
        text: &str,
        style: &S,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        let size = style.size();
        Ok((
            text_width(text, size, style.style()).round() as u32,
            line_height(size) as u32,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The columns of an RGB buffer `w` wide that hold ink (any pixel not white).
    fn inked_columns(buf: &[u8], (w, h): (u32, u32)) -> Vec<bool> {
        (0..w as usize)
            .map(|x| (0..h as usize).any(|y| buf[3 * (y * w as usize + x)] < 200))
            .collect()
    }

    /// The runs of blank columns between the first and the last inked column.
    fn gaps(cols: &[bool]) -> Vec<usize> {
        let first = cols.iter().position(|&c| c).unwrap();
        let last = cols.iter().rposition(|&c| c).unwrap();
        let mut gaps = Vec::new();
        let mut run = 0;
        for &c in &cols[first..=last] {
            if c {
                if run > 0 {
                    gaps.push(run);
                }
                run = 0;
            } else {
                run += 1;
            }
        }
        gaps
    }

    #[test]
    fn letters_keep_the_fonts_spacing() {
        // "ixl" at 100 px: the blanks between the letters' ink are what the font's own
        // metrics (its advances and kerning, its outlines' boxes) put there. The three side
        // bearings differ by up to 6 px, so a glyph drawn without its bearing shows.
        let text = "ixl";
        let size = (300u32, 120u32);
        let mut buf = vec![255u8; (3 * size.0 * size.1) as usize];
        {
            let root = Canvas::with_buffer(&mut buf, size).into_drawing_area();
            root.draw(&Text::new(
                text,
                (10, 10),
                ("sans-serif", 100).into_font().color(&BLACK),
            ))
            .unwrap();
            root.present().unwrap();
        }
        let font = faces()[0].as_scaled(PxScale::from(100.0));
        // A glyph's ink from its outline's box (font units, from the pen position).
        let ink = |c: char| font.font().outline(font.glyph_id(c)).unwrap().bounds;
        let k = font.h_scale_factor();
        let chars: Vec<char> = text.chars().collect();
        let expected: Vec<f32> = chars
            .windows(2)
            .map(|p| {
                let (a, b) = (font.glyph_id(p[0]), font.glyph_id(p[1]));
                font.h_advance(a) + font.kern(a, b) + k * (ink(p[1]).min.x - ink(p[0]).max.x)
            })
            .collect();
        let found = gaps(&inked_columns(&buf, size));
        assert_eq!(found.len(), expected.len(), "{found:?}");
        for (f, e) in found.iter().zip(&expected) {
            assert!(
                (*f as f32 - e).abs() <= 1.5,
                "gaps {found:?} px, the font says {expected:?} px"
            );
        }
    }

    #[test]
    fn the_measured_width_is_the_drawn_width() {
        let size = (900u32, 60u32);
        let mut buf = vec![255u8; (3 * size.0 * size.1) as usize];
        let text = "max shear 74.3° over a woven cell";
        {
            let root = Canvas::with_buffer(&mut buf, size).into_drawing_area();
            root.draw(&Text::new(
                text,
                (20, 10),
                ("sans-serif", 30).into_font().color(&BLACK),
            ))
            .unwrap();
            root.present().unwrap();
        }
        let cols = inked_columns(&buf, size);
        let first = cols.iter().position(|&c| c).unwrap() as f64;
        let last = cols.iter().rposition(|&c| c).unwrap() as f64;
        let w = text_width(text, 30.0, FontStyle::Normal);
        // The ink spans the advances less the side bearings of the end letters (a few px).
        assert!((20.0..=24.0).contains(&first), "{first}");
        assert!(last <= 20.0 + w && last >= 20.0 + w - 6.0, "{last} vs {w}");
    }
}
