//! Text set in the shipped font by isola itself, for the PNG and PDF backends: the glyphs of
//! a line with their kerned pen positions, and where a text anchor puts the baseline.
//!
//! The metrics are those plotters' SVG backend writes (an em of `size / 1.24` pixels, the
//! baseline at `0.76em`, `0.5ex` or `−0.5ex` from a top, centre or bottom anchor), so a
//! label sits in the same place in all three formats.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, GlyphId};
use plotters_backend::text_anchor::{HPos, Pos, VPos};
use plotters_backend::{BackendTextStyle, FontTransform};

use super::FONT_BYTES;

/// The shipped font's x-height (DejaVu Sans: 1120 of 2048 units), in ems.
const X_HEIGHT: f64 = 1120.0 / 2048.0;

/// The shipped font, parsed once.
pub fn face() -> &'static FontRef<'static> {
    static FACE: OnceLock<FontRef<'static>> = OnceLock::new();
    FACE.get_or_init(|| {
        // the bytes are a TrueType font checked in: a failure here is a broken checkout
        FontRef::try_from_slice(FONT_BYTES)
            .unwrap_or_else(|_| panic!("assets/fonts/DejaVuSans.ttf is not a font"))
    })
}

/// The em in pixels of text of plotters' size `size` (as its SVG backend's `font-size`).
pub(super) fn em(size: f64) -> f64 {
    size / 1.24
}

/// One glyph of a line: the character it shows and its pen position in ems.
#[derive(Debug, Clone, Copy)]
pub(super) struct Placed {
    pub glyph: GlyphId,
    pub ch: char,
    pub x: f64,
    /// The pair kerning before it, in ems (negative: closer).
    pub kern: f64,
}

/// A line of text laid out along its baseline from 0, in ems.
pub(super) struct Line {
    pub glyphs: Vec<Placed>,
    pub width: f64,
}

impl Line {
    /// `text` in the shipped font, kerned by its `kern` table.
    pub fn of(text: &str) -> Self {
        let f = face();
        let units = f.units_per_em().unwrap_or(2048.0) as f64;
        let mut x = 0.0;
        let mut before: Option<GlyphId> = None;
        let mut glyphs = Vec::with_capacity(text.len());
        for ch in text.chars() {
            let glyph = f.glyph_id(ch);
            let kern = before.map_or(0.0, |b| f.kern_unscaled(b, glyph) as f64 / units);
            x += kern;
            glyphs.push(Placed { glyph, ch, x, kern });
            x += f.h_advance_unscaled(glyph) as f64 / units;
            before = Some(glyph);
        }
        Line { glyphs, width: x }
    }

    /// The start of the baseline relative to the anchor, in pixels of the text's own frame
    /// (x along the text, y down), for an em of `em` pixels.
    pub fn origin(&self, em: f64, anchor: Pos) -> (f64, f64) {
        let x = match anchor.h_pos {
            HPos::Left => 0.0,
            HPos::Center => -0.5 * self.width * em,
            HPos::Right => -self.width * em,
        };
        let y = match anchor.v_pos {
            VPos::Top => 0.76 * em,
            VPos::Center => 0.5 * X_HEIGHT * em,
            VPos::Bottom => -0.5 * X_HEIGHT * em,
        };
        (x, y)
    }
}

/// The size plotters lays out for `text` in `style`: its width, and an em for its height.
pub(super) fn size_of<S: BackendTextStyle>(text: &str, style: &S) -> (u32, u32) {
    let em = em(style.size());
    let width = Line::of(text).width * em;
    (width.ceil() as u32, em.round() as u32)
}

/// A vector of the text's own frame (x along the text, y down) in the page's pixels, as
/// plotters turns text (`FontTransform::transform`, in fractions of a pixel).
pub(super) fn turn(transform: &FontTransform, (x, y): (f64, f64)) -> (f64, f64) {
    match transform {
        FontTransform::None => (x, y),
        FontTransform::Rotate90 => (-y, x),
        FontTransform::Rotate180 => (-x, -y),
        FontTransform::Rotate270 => (y, -x),
    }
}
