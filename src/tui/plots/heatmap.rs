//! A grid of values drawn as half-blocks (two grid rows per terminal row, `▀` with fore- and
//! background colours), or as one glyph per cell when there is no colour.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::text::Line;
use ratatui::widgets::Widget;

use super::frame::{Axis, draw_axes, draw_footer, footer_room, wrap_footer};

/// How a grid cell is drawn.
pub enum Paint<'a> {
    /// A colour per cell (`None`: not computed, left blank).
    Colors(&'a dyn Fn(usize, usize) -> Option<Color>),
    /// A glyph per cell.
    Glyphs(&'a dyn Fn(usize, usize) -> &'static str),
}

/// An `nx × ny` grid (`iy` counted from the bottom) over axes `x` and `y`.
pub struct HeatMap<'a> {
    pub x: Axis,
    pub y: Axis,
    pub nx: usize,
    pub ny: usize,
    pub paint: Paint<'a>,
    /// A grid cell to mark.
    pub cursor: Option<(usize, usize)>,
    /// Glyphs drawn over the map at data coordinates (x, y), over the cell's colours.
    pub marks: Vec<(f64, f64, &'static str, Style)>,
    pub axis_style: Style,
    pub cursor_style: Style,
    pub footer: Vec<Line<'static>>,
}

impl HeatMap<'_> {
    /// The grid cell under terminal cell (c, r) of `canvas`, `sub` of `subs` rows down in it.
    fn grid_at(&self, canvas: Rect, c: u16, r: u16, sub: u16, subs: u16) -> (usize, usize) {
        let ix = (c as usize * self.nx / canvas.width as usize).min(self.nx - 1);
        let rows = canvas.height as usize * subs as usize;
        let down = r as usize * subs as usize + sub as usize;
        let iy_from_top = (down * self.ny / rows).min(self.ny - 1);
        (ix, self.ny - 1 - iy_from_top)
    }
}

impl Widget for HeatMap<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let footer = wrap_footer(&self.footer, area.width, footer_room(area.height));
        let Some(canvas) = draw_axes(area, &self.x, &self.y, footer.len(), self.axis_style, buf)
        else {
            buf.set_stringn(
                area.x,
                area.y,
                "(too small)",
                area.width as usize,
                self.axis_style,
            );
            return;
        };
        if self.nx == 0 || self.ny == 0 {
            return;
        }
        for r in 0..canvas.height {
            for c in 0..canvas.width {
                let cell = &mut buf[(canvas.x + c, canvas.y + r)];
                match &self.paint {
                    Paint::Colors(color) => {
                        let (tx, ty) = self.grid_at(canvas, c, r, 0, 2);
                        let (bx, by) = self.grid_at(canvas, c, r, 1, 2);
                        match (color(tx, ty), color(bx, by)) {
                            (None, None) => {
                                cell.set_symbol(" ");
                            }
                            (top, bottom) => {
                                cell.set_symbol("▀")
                                    .set_fg(top.unwrap_or(Color::Reset))
                                    .set_bg(bottom.unwrap_or(Color::Reset));
                            }
                        }
                    }
                    Paint::Glyphs(glyph) => {
                        let (ix, iy) = self.grid_at(canvas, c, r, 0, 1);
                        cell.set_symbol(glyph(ix, iy));
                    }
                }
            }
        }
        let (xr, yr) = (self.x.max - self.x.min, self.y.max - self.y.min);
        for &(x, y, glyph, style) in &self.marks {
            let (fx, fy) = ((x - self.x.min) / xr, (y - self.y.min) / yr);
            if !(0.0..=1.0).contains(&fx) || !(0.0..=1.0).contains(&fy) {
                continue;
            }
            let c = ((fx * canvas.width as f64) as u16).min(canvas.width - 1);
            let r = (((1.0 - fy) * canvas.height as f64) as u16).min(canvas.height - 1);
            let cell = &mut buf[(canvas.x + c, canvas.y + r)];
            // keep the lower half's colour as the background under the glyph
            let under = cell.bg;
            cell.set_symbol(glyph).set_style(style.bg(under));
        }
        if let Some((ix, iy)) = self.cursor
            && ix < self.nx
            && iy < self.ny
        {
            let c = ((ix as f64 + 0.5) * canvas.width as f64 / self.nx as f64) as u16;
            let r = ((self.ny - 1 - iy) as f64 + 0.5) * canvas.height as f64 / self.ny as f64;
            let (c, r) = (c.min(canvas.width - 1), (r as u16).min(canvas.height - 1));
            buf[(canvas.x + c, canvas.y + r)]
                .set_symbol("╋")
                .set_style(self.cursor_style);
        }
        draw_footer(area, canvas, &footer, buf);
    }
}
