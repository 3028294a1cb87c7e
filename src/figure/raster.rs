//! The PNG backend: plotters' bitmap backend with text set by isola.
//!
//! plotters' own glyph drawing (its `ab_glyph` font code) places each glyph's bitmap at the
//! pen position without the glyph's left side bearing and truncates the pen to whole pixels,
//! so digits of different bearings sit unevenly ("0.41 6": the `1`, whose bearing is wide,
//! is drawn too far left). Here each glyph is outlined at its exact pen position, bearing
//! included, and its coverage blended into the pixels.

use ab_glyph::{Font, PxScale, point};
use plotters::prelude::BitMapBackend;
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};

use super::text::{Line, em, face, size_of, turn};

/// A bitmap backend whose text is drawn by [`Line`].
pub(super) struct Raster<'a>(pub BitMapBackend<'a>);

type Error<'a> = DrawingErrorKind<<BitMapBackend<'a> as DrawingBackend>::ErrorType>;

impl<'a> DrawingBackend for Raster<'a> {
    type ErrorType = <BitMapBackend<'a> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.0.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), Error<'a>> {
        self.0.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), Error<'a>> {
        self.0.present()
    }

    fn draw_pixel(&mut self, point: BackendCoord, color: BackendColor) -> Result<(), Error<'a>> {
        self.0.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), Error<'a>> {
        self.0.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), Error<'a>> {
        self.0.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), Error<'a>> {
        self.0.draw_path(path, style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), Error<'a>> {
        self.0.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), Error<'a>> {
        self.0.fill_polygon(vert, style)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), Error<'a>> {
        self.0.blit_bitmap(pos, size, src)
    }

    fn estimate_text_size<S: BackendTextStyle>(
        &self,
        text: &str,
        style: &S,
    ) -> Result<(u32, u32), Error<'a>> {
        Ok(size_of(text, style))
    }

    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), Error<'a>> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let f = face();
        let em = em(style.size());
        let units = f.units_per_em().unwrap_or(2048.0);
        // ab_glyph scales a font to the height from descender to ascender
        let scale = PxScale::from(em as f32 * f.height_unscaled() / units);
        let line = Line::of(text);
        let (x0, y0) = line.origin(em, style.anchor());
        let transform = style.transform();
        let (w, h) = self.get_size();
        for g in &line.glyphs {
            let at = point((x0 + g.x * em) as f32, y0 as f32);
            let Some(outline) = f.outline_glyph(g.glyph.with_scale_and_position(scale, at)) else {
                continue;
            };
            let corner = outline.px_bounds().min;
            let mut covered = Vec::new();
            outline.draw(|x, y, c| covered.push((x, y, c)));
            for (x, y, c) in covered {
                // the pixel's centre, turned, names the page's pixel under it
                let centre = (
                    f64::from(corner.x) + f64::from(x) + 0.5,
                    f64::from(corner.y) + f64::from(y) + 0.5,
                );
                let (dx, dy) = turn(&transform, centre);
                let (px, py) = (pos.0 + dx.floor() as i32, pos.1 + dy.floor() as i32);
                if px >= 0 && py >= 0 && px < w as i32 && py < h as i32 && c > 0.0 {
                    let alpha = color.alpha * f64::from(c.min(1.0));
                    self.0
                        .draw_pixel((px, py), BackendColor { alpha, ..color })?;
                }
            }
        }
        Ok(())
    }
}
