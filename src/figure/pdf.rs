//! The PDF backend: plotters draws into a page of vector paths, and text in the shipped font,
//! embedded as a subset of its glyphs (a Type 0 font over a TrueType CIDFont, with a
//! `ToUnicode` map so the text can be searched and copied).
//!
//! A pixel of the figure is a CSS pixel on the page: 0.75 pt, so a 960 × 600 figure is a
//! 720 × 450 pt (10 × 6.25 in) page. Streams are compressed.

use std::collections::BTreeSet;
use std::convert::Infallible;

use ab_glyph::Font;
use pdf_writer::types::{
    CidFontType, FontFlags, LineCapStyle, LineJoinStyle, SystemInfo, UnicodeCmap,
};
use pdf_writer::{Content, Filter, Name, Rect, Ref, Str};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};
use subsetter::GlyphRemapper;

use super::FONT_BYTES;
use super::text::{Line, em, face, size_of, turn};

/// Points per pixel (a CSS pixel, 1/96 in).
pub(super) const PT_PER_PX: f32 = 0.75;

/// The PostScript name of the shipped font.
const FONT_NAME: &str = "DejaVuSans";

/// How circles are drawn: four cubic Béziers, each control point this far along the tangent
/// (in radii).
const KAPPA: f64 = 0.552_284_75;

type Error = DrawingErrorKind<Infallible>;

/// A figure drawn as one PDF page.
pub(super) struct Pdf {
    size: (u32, u32),
    content: Content,
    /// The glyphs used, numbered in the subset in the order of first use.
    glyphs: GlyphRemapper,
    /// The character each glyph of the subset shows (by its number there).
    chars: Vec<Option<char>>,
    /// Opacities used, in 255ths (one graphics state each).
    alphas: BTreeSet<u8>,
    /// The opacity in force.
    alpha: u8,
}

impl Pdf {
    /// An empty page of `size` pixels.
    pub fn new(size: (u32, u32)) -> Self {
        let mut content = Content::new();
        // pixels, y down, as plotters draws
        content.transform([
            PT_PER_PX,
            0.0,
            0.0,
            -PT_PER_PX,
            0.0,
            PT_PER_PX * size.1 as f32,
        ]);
        content.set_line_join(LineJoinStyle::RoundJoin);
        content.set_line_cap(LineCapStyle::RoundCap);
        Pdf {
            size,
            content,
            glyphs: GlyphRemapper::new(),
            chars: vec![None],
            alphas: BTreeSet::new(),
            alpha: u8::MAX,
        }
    }

    /// Sets the colour (and its opacity) of fills or of strokes.
    fn color(&mut self, color: BackendColor, stroke: bool) {
        let (r, g, b) = color.rgb;
        let [r, g, b] = [r, g, b].map(|c| f32::from(c) / 255.0);
        if stroke {
            self.content.set_stroke_rgb(r, g, b);
        } else {
            self.content.set_fill_rgb(r, g, b);
        }
        let alpha = (color.alpha.clamp(0.0, 1.0) * 255.0).round() as u8;
        if alpha != self.alpha {
            self.alphas.insert(alpha);
            self.content
                .set_parameters(Name(alpha_name(alpha).as_bytes()));
            self.alpha = alpha;
        }
    }

    /// Sets the stroke of `style`; `false` for a stroke of no width (nothing to draw).
    fn stroke<S: BackendStyle>(&mut self, style: &S) -> bool {
        let width = style.stroke_width();
        if width == 0 || style.color().alpha == 0.0 {
            return false;
        }
        self.color(style.color(), true);
        self.content.set_line_width(width as f32);
        true
    }

    /// A path through `points`, closed or not.
    fn path(&mut self, points: &[BackendCoord], close: bool) {
        let Some((first, rest)) = points.split_first() else {
            return;
        };
        self.content.move_to(first.0 as f32, first.1 as f32);
        for p in rest {
            self.content.line_to(p.0 as f32, p.1 as f32);
        }
        if close {
            self.content.close_path();
        }
    }

    /// The PDF file of the page.
    pub fn finish(self) -> Result<Vec<u8>, subsetter::Error> {
        let mut last = 0;
        let mut next = || {
            last += 1;
            Ref::new(last)
        };
        let (catalog, pages, page, content) = (next(), next(), next(), next());
        let mut pdf = pdf_writer::Pdf::new();
        pdf.catalog(catalog).pages(pages);
        pdf.pages(pages).kids([page]).count(1);
        let font = (self.glyphs.num_gids() > 1).then(&mut next);
        let states: Vec<(u8, Ref)> = self.alphas.iter().map(|&a| (a, next())).collect();
        {
            let mut p = pdf.page(page);
            let (w, h) = (self.size.0 as f32, self.size.1 as f32);
            p.media_box(Rect::new(0.0, 0.0, PT_PER_PX * w, PT_PER_PX * h));
            p.parent(pages);
            p.contents(content);
            let mut resources = p.resources();
            if let Some(font) = font {
                resources.fonts().pair(Name(b"F0"), font);
            }
            let mut gs = resources.ext_g_states();
            for (alpha, id) in &states {
                gs.pair(Name(alpha_name(*alpha).as_bytes()), *id);
            }
        }
        for (alpha, id) in &states {
            let a = f32::from(*alpha) / 255.0;
            pdf.ext_graphics(*id)
                .stroking_alpha(a)
                .non_stroking_alpha(a);
        }
        let stream = compress(&self.content.finish());
        pdf.stream(content, &stream).filter(Filter::FlateDecode);
        if let Some(font) = font {
            let ids = [next(), next(), next(), next()];
            embed_font(&mut pdf, font, ids, &self.glyphs, &self.chars)?;
        }
        Ok(pdf.finish())
    }
}

/// The graphics state's name of opacity `alpha` (255ths).
fn alpha_name(alpha: u8) -> String {
    format!("A{alpha}")
}

/// `data` zlib-compressed, for a `FlateDecode` stream.
fn compress(data: &[u8]) -> Vec<u8> {
    miniz_oxide::deflate::compress_to_vec_zlib(data, 6)
}

/// Writes the Type 0 font `font` of the subset `glyphs` (showing `chars`) and, at `ids`, its
/// CIDFont, descriptor, font file and `ToUnicode` map.
fn embed_font(
    pdf: &mut pdf_writer::Pdf,
    font: Ref,
    [cid_font, descriptor, file, cmap]: [Ref; 4],
    glyphs: &GlyphRemapper,
    chars: &[Option<char>],
) -> Result<(), subsetter::Error> {
    let face = face();
    let units = face.units_per_em().unwrap_or(2048.0);
    let per_mille = |v: f32| v * 1000.0 / units;
    let old: Vec<u16> = glyphs.remapped_gids().collect();
    // a subset's name starts with a tag of six capitals, here from the glyphs it holds
    let tag: String = {
        let hash = old.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &g| {
            (h ^ u64::from(g)).wrapping_mul(0x0100_0000_01b3)
        });
        (0..6)
            .map(|k| (b'A' + (hash >> (5 * k)) as u8 % 26) as char)
            .collect()
    };
    let base = format!("{tag}+{FONT_NAME}");
    let system = SystemInfo {
        registry: Str(b"Adobe"),
        ordering: Str(b"Identity"),
        supplement: 0,
    };
    pdf.type0_font(font)
        .base_font(Name(base.as_bytes()))
        .encoding_predefined(Name(b"Identity-H"))
        .descendant_font(cid_font)
        .to_unicode(cmap);
    let widths: Vec<f32> = old
        .iter()
        .map(|&g| per_mille(face.h_advance_unscaled(ab_glyph::GlyphId(g))))
        .collect();
    {
        let mut cid = pdf.cid_font(cid_font);
        cid.subtype(CidFontType::Type2)
            .base_font(Name(base.as_bytes()))
            .system_info(system)
            .font_descriptor(descriptor)
            .cid_to_gid_map_predefined(Name(b"Identity"));
        cid.widths().consecutive(0, widths);
    }
    // the box of the glyphs held (an outline's bounds run from its top left)
    let bbox = old
        .iter()
        .filter_map(|&g| face.outline(ab_glyph::GlyphId(g)))
        .fold([f32::MAX, f32::MAX, f32::MIN, f32::MIN], |b, o| {
            let r = o.bounds;
            [
                b[0].min(r.min.x),
                b[1].min(r.max.y),
                b[2].max(r.max.x),
                b[3].max(r.min.y),
            ]
        })
        .map(per_mille);
    let cap_height = face
        .outline(face.glyph_id('H'))
        .map_or(0.73 * units, |o| o.bounds.min.y);
    pdf.font_descriptor(descriptor)
        .name(Name(base.as_bytes()))
        .flags(FontFlags::SYMBOLIC)
        .bbox(Rect::new(bbox[0], bbox[1], bbox[2], bbox[3]))
        .italic_angle(0.0)
        .ascent(per_mille(face.ascent_unscaled()))
        .descent(per_mille(face.descent_unscaled()))
        .cap_height(per_mille(cap_height))
        .stem_v(80.0)
        .font_file2(file);
    let subset = subsetter::subset(FONT_BYTES, 0, glyphs)?;
    pdf.stream(file, &compress(&subset))
        .filter(Filter::FlateDecode)
        .pair(Name(b"Length1"), subset.len() as i32);
    let mut unicode = UnicodeCmap::new(Name(b"Custom"), system);
    for (new, ch) in chars.iter().enumerate() {
        if let Some(ch) = ch {
            unicode.pair(new as u16, *ch);
        }
    }
    pdf.stream(cmap, &unicode.finish());
    Ok(())
}

impl DrawingBackend for Pdf {
    type ErrorType = Infallible;

    fn get_size(&self) -> (u32, u32) {
        self.size
    }

    fn ensure_prepared(&mut self) -> Result<(), Error> {
        Ok(())
    }

    fn present(&mut self) -> Result<(), Error> {
        Ok(())
    }

    fn draw_pixel(&mut self, point: BackendCoord, color: BackendColor) -> Result<(), Error> {
        self.color(color, false);
        self.content
            .rect(point.0 as f32, point.1 as f32, 1.0, 1.0)
            .fill_nonzero();
        Ok(())
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), Error> {
        if self.stroke(style) {
            self.path(&[from, to], false);
            self.content.stroke();
        }
        Ok(())
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), Error> {
        let (x, y) = (upper_left.0 as f32, upper_left.1 as f32);
        let (w, h) = (
            (bottom_right.0 - upper_left.0) as f32,
            (bottom_right.1 - upper_left.1) as f32,
        );
        if fill {
            if style.color().alpha == 0.0 {
                return Ok(());
            }
            self.color(style.color(), false);
            self.content.rect(x, y, w, h).fill_nonzero();
        } else if self.stroke(style) {
            self.content.rect(x, y, w, h).stroke();
        }
        Ok(())
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), Error> {
        let points: Vec<BackendCoord> = path.into_iter().collect();
        if points.len() > 1 && self.stroke(style) {
            self.path(&points, false);
            self.content.stroke();
        }
        Ok(())
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), Error> {
        if fill {
            self.color(style.color(), false);
        } else if !self.stroke(style) {
            return Ok(());
        }
        let (cx, cy, r) = (center.0 as f64, center.1 as f64, radius as f64);
        let k = KAPPA * r;
        let c = &mut self.content;
        let at = |x: f64, y: f64| ((cx + x) as f32, (cy + y) as f32);
        let (x, y) = at(r, 0.0);
        c.move_to(x, y);
        // a quarter at a time: from (r, 0) by the tangent to (0, r), and so on round
        for [(ax, ay), (bx, by), (ex, ey)] in [
            [(r, k), (k, r), (0.0, r)],
            [(-k, r), (-r, k), (-r, 0.0)],
            [(-r, -k), (-k, -r), (0.0, -r)],
            [(k, -r), (r, -k), (r, 0.0)],
        ] {
            let (a, b, e) = (at(ax, ay), at(bx, by), at(ex, ey));
            c.cubic_to(a.0, a.1, b.0, b.1, e.0, e.1);
        }
        c.close_path();
        if fill {
            c.fill_nonzero();
        } else {
            c.stroke();
        }
        Ok(())
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), Error> {
        let points: Vec<BackendCoord> = vert.into_iter().collect();
        if points.len() > 2 && style.color().alpha > 0.0 {
            self.color(style.color(), false);
            self.path(&points, true);
            self.content.fill_nonzero();
        }
        Ok(())
    }

    fn estimate_text_size<S: BackendTextStyle>(
        &self,
        text: &str,
        style: &S,
    ) -> Result<(u32, u32), Error> {
        Ok(size_of(text, style))
    }

    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), Error> {
        if style.color().alpha == 0.0 || text.is_empty() {
            return Ok(());
        }
        let em = em(style.size());
        let line = Line::of(text);
        let transform = style.transform();
        let (dx, dy) = turn(&transform, line.origin(em, style.anchor()));
        // the text's x along its direction, its y up (the page's y is down)
        let along = turn(&transform, (1.0, 0.0));
        let up = turn(&transform, (0.0, -1.0));
        let matrix = [
            along.0,
            along.1,
            up.0,
            up.1,
            pos.0 as f64 + dx,
            pos.1 as f64 + dy,
        ];
        let mut shown = Vec::with_capacity(2 * line.glyphs.len());
        // runs of glyphs between kerned pairs, each kern an adjustment (in 1000ths of an em)
        let mut runs: Vec<(f32, Vec<u8>)> = Vec::new();
        for g in &line.glyphs {
            let new = self.glyphs.remap(g.glyph.0);
            let slot = usize::from(new);
            if self.chars.len() <= slot {
                self.chars.resize(slot + 1, None);
            }
            self.chars[slot].get_or_insert(g.ch);
            if g.kern != 0.0 && !shown.is_empty() {
                runs.push(((-1000.0 * g.kern) as f32, std::mem::take(&mut shown)));
            }
            shown.extend(new.to_be_bytes());
        }
        self.color(style.color(), false);
        let c = &mut self.content;
        c.begin_text();
        c.set_font(Name(b"F0"), em as f32);
        c.set_text_matrix(matrix.map(|v| v as f32));
        {
            let mut positioned = c.show_positioned();
            let mut items = positioned.items();
            for (adjust, glyphs) in &runs {
                items.show(Str(glyphs));
                items.adjust(*adjust);
            }
            items.show(Str(&shown));
        }
        c.end_text();
        Ok(())
    }
}
