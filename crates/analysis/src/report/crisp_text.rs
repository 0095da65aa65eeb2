//! A bitmap-backend wrapper that draws text with the embedded font through ab_glyph directly.

use ab_glyph::{Font, FontRef, ScaleFont};
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind, FontTransform,
};

/// The embedded font (Bitstream Vera licence, see `fonts/LICENSE-DejaVu.txt`).
pub(super) static FONT_BYTES: &[u8] = include_bytes!("fonts/DejaVuSans.ttf");

/// A bitmap backend wrapper that lays out text itself with the embedded font.
///
/// plotters 0.3.7's `ab_glyph` text drawing drops each glyph's left side bearing, which jumbles the spacing
/// of digits and punctuation in PNGs; this wrapper rasterises text with ab_glyph directly (bearings, kerning,
/// anchors and 90° rotations) and forwards every other call to the inner backend.
pub struct CrispText<B: DrawingBackend> {
    inner: B,
    font: Option<FontRef<'static>>,
}

impl<B: DrawingBackend> CrispText<B> {
    /// Wraps `inner`.
    pub fn new(inner: B) -> CrispText<B> {
        CrispText { inner, font: FontRef::try_from_slice(FONT_BYTES).ok() }
    }

    /// Glyph outlines of `text` at `size` px laid out from (0, 0) at the top-left, and the box (w, h).
    fn layout(&self, text: &str, size: f32) -> Option<(Vec<ab_glyph::Glyph>, f32, f32)> {
        let font = self.font.as_ref()?;
        let scaled = font.as_scaled(size);
        let mut caret = 0.0f32;
        let mut previous = None;
        let mut glyphs = Vec::with_capacity(text.len());
        for c in text.chars() {
            let id = scaled.glyph_id(c);
            if let Some(prev) = previous {
                caret += scaled.kern(prev, id);
            }
            glyphs.push(id.with_scale_and_position(size, ab_glyph::point(caret, scaled.ascent())));
            caret += scaled.h_advance(id);
            previous = Some(id);
        }
        Some((glyphs, caret, scaled.ascent() - scaled.descent()))
    }
}

impl<B: DrawingBackend> DrawingBackend for CrispText<B> {
    type ErrorType = B::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_path(path, style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.fill_polygon(vert, style)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.blit_bitmap(pos, size, src)
    }

    fn estimate_text_size<S: BackendTextStyle>(
        &self,
        text: &str,
        style: &S,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        match self.layout(text, style.size() as f32) {
            Some((_, w, h)) => Ok((w.ceil() as u32, h.ceil() as u32)),
            None => self.inner.estimate_text_size(text, style),
        }
    }

    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let Some((glyphs, width, height)) = self.layout(text, style.size() as f32) else {
            return self.inner.draw_text(text, style, pos);
        };
        let Some(font) = self.font.clone() else { return Ok(()) };
        let anchor = style.anchor();
        let dx = match anchor.h_pos {
            HPos::Left => 0.0,
            HPos::Center => -width / 2.0,
            HPos::Right => -width,
        };
        let dy = match anchor.v_pos {
            VPos::Top => 0.0,
            VPos::Center => -height / 2.0,
            VPos::Bottom => -height,
        };
        let transform: FontTransform = style.transform();
        let mut pixels = Vec::new();
        for glyph in glyphs {
            if let Some(outline) = font.outline_glyph(glyph) {
                let bounds = outline.px_bounds();
                // Round the glyph origin once: rounding each pixel's fractional position would skip the
                // row or column where the position crosses zero (round(-0.5) = -1, round(0.5) = 1).
                let origin_x = (bounds.min.x + dx).floor() as i32;
                let origin_y = (bounds.min.y + dy).floor() as i32;
                outline.draw(|gx, gy, coverage| {
                    let x = origin_x + gx as i32;
                    let y = origin_y + gy as i32;
                    pixels.push((transform.transform(x, y), coverage));
                });
            }
        }
        for ((x, y), coverage) in pixels {
            if coverage > 0.0 {
                let alpha = color.alpha * f64::from(coverage.min(1.0));
                self.inner.draw_pixel((pos.0 + x, pos.1 + y), BackendColor { alpha, rgb: color.rgb })?;
            }
        }
        Ok(())
    }
}
