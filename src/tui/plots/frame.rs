//! An x–y plot with ticked, labelled axes: Braille curves and points, glyphs for typed points,
//! text annotations, and a cursor. Every plot view builds one of these.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::Widget;
use ratatui::widgets::canvas::{Canvas, Context, Points};

/// One axis: its range and name with unit.
#[derive(Debug, Clone)]
pub struct Axis {
    pub name: String,
    pub min: f64,
    pub max: f64,
}

impl Axis {
    pub fn new(name: impl Into<String>, min: f64, max: f64) -> Self {
        let (min, max) = if max > min {
            (min, max)
        } else if max == min {
            (
                min - 0.5 * min.abs().max(1e-3),
                max + 0.5 * max.abs().max(1e-3),
            )
        } else {
            (max, min)
        };
        Axis {
            name: name.into(),
            min,
            max,
        }
    }

    /// The range of `values` with a margin, or [0, 1] with none.
    pub fn fit(name: impl Into<String>, values: impl Iterator<Item = f64>, margin: f64) -> Self {
        let (lo, hi) = values
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
        if lo > hi {
            return Axis::new(name, 0.0, 1.0);
        }
        let pad = (hi - lo) * margin;
        Axis::new(name, lo - pad, hi + pad)
    }
}

/// What is drawn inside the axes.
pub enum Layer {
    /// Braille dots.
    Points {
        points: Vec<(f64, f64)>,
        color: Color,
    },
    /// Braille dots joined in order (gaps where a point is NaN).
    Curve {
        points: Vec<(f64, f64)>,
        color: Color,
    },
    /// A glyph at each point.
    Glyphs {
        points: Vec<(f64, f64)>,
        glyph: &'static str,
        style: Style,
    },
    /// A bracket `├─ text ─┤` over [x0, x1] at height y: a range named on the plot by the
    /// first of `texts` that fits.
    Range {
        x0: f64,
        x1: f64,
        y: f64,
        texts: Vec<String>,
        style: Style,
    },
}

/// A plot: axes, layers, an optional cursor, and text lines below.
pub struct XyPlot {
    pub x: Axis,
    pub y: Axis,
    pub layers: Vec<Layer>,
    pub cursor: Option<(f64, f64)>,
    pub cursor_style: Style,
    pub axis_style: Style,
    pub footer: Vec<Line<'static>>,
}

/// About `n` round tick values (1, 2 or 5 × 10^k apart) inside [min, max], at least two
/// when the range is not empty.
pub fn ticks(min: f64, max: f64, n: usize) -> Vec<f64> {
    let span = max - min;
    if span.is_nan() || span <= 0.0 || n == 0 {
        return vec![min];
    }
    let in_range = |step: f64| -> Vec<f64> {
        let first = (min / step - 1e-9).ceil();
        (0..=n + 1)
            .map(|i| (first + i as f64) * step)
            .take_while(|t| *t <= max + step * 1e-9)
            .map(|t| if t.abs() < step * 1e-9 { 0.0 } else { t })
            .collect()
    };
    // 10^e exactly as a division for e < 0, so that 0.01 × 9 is 0.09
    let e = (span / n as f64).log10().floor() as i32;
    let scaled = |m: f64| {
        if e < 0 {
            m / 10f64.powi(-e)
        } else {
            m * 10f64.powi(e)
        }
    };
    // round steps from the largest that gives at most n ticks down, until two fit
    let steps = [10.0, 5.0, 2.0, 1.0, 0.5, 0.2, 0.1].map(scaled);
    let first = steps
        .iter()
        .rposition(|s| span / s <= n as f64)
        .unwrap_or(0);
    steps[first..]
        .iter()
        .map(|&s| in_range(s))
        .find(|t| t.len() >= 2)
        .unwrap_or_else(|| in_range(steps[steps.len() - 1]))
}

/// A tick label with as few digits as the step needs.
pub fn tick_label(t: f64, step: f64) -> String {
    let decimals = if step >= 1.0 {
        0
    } else {
        (-step.log10()).ceil() as usize
    };
    format!("{t:.decimals$}")
}

impl XyPlot {
    pub fn new(x: Axis, y: Axis) -> Self {
        XyPlot {
            x,
            y,
            layers: Vec::new(),
            cursor: None,
            cursor_style: Style::default(),
            axis_style: Style::default(),
            footer: Vec::new(),
        }
    }
}

/// A data area as it was last drawn: where on screen, and the axes' ranges over it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drawn {
    pub canvas: Rect,
    pub x: (f64, f64),
    pub y: (f64, f64),
}

impl Drawn {
    /// The data coordinates at the middle of terminal cell (col, row), if it is inside.
    pub fn at(&self, col: u16, row: u16) -> Option<(f64, f64)> {
        let c = self.canvas;
        if col < c.x || row < c.y || col >= c.x + c.width || row >= c.y + c.height {
            return None;
        }
        let fx = (col - c.x) as f64 / (c.width.max(2) - 1) as f64;
        let fy = (row - c.y) as f64 / (c.height.max(2) - 1) as f64;
        Some((
            self.x.0 + fx * (self.x.1 - self.x.0),
            self.y.1 - fy * (self.y.1 - self.y.0),
        ))
    }
}

thread_local! {
    /// The data areas drawn since the last [`take_drawn`]: the UI thread draws, then a mouse
    /// click is read against them.
    static DRAWN: std::cell::RefCell<Vec<Drawn>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The data areas drawn on this thread since the last call.
pub fn take_drawn() -> Vec<Drawn> {
    DRAWN.with(|d| std::mem::take(&mut *d.borrow_mut()))
}

/// The longest x axis name drawn under the y labels (a longer one ends the x labels).
const X_NAME_UNDER: u16 = 10;

/// Draws the axes of `x` and `y` (names, ticks, labels) around the data area, leaving
/// `footer` rows at the bottom, and returns the data area; `None` if there is no room.
pub fn draw_axes(
    area: Rect,
    x: &Axis,
    y: &Axis,
    footer: usize,
    s: Style,
    buf: &mut Buffer,
) -> Option<Rect> {
    // rows: y axis name, data, x axis line, x labels, footer
    let height = area.height.checked_sub(3 + footer as u16)?;
    // the labels drawn are the labels measured
    let yt = ticks(y.min, y.max, (height as usize / 3).clamp(2, 6));
    let ystep = yt.get(1).map_or(1.0, |b| b - yt[0]);
    let label_w = yt
        .iter()
        .map(|t| tick_label(*t, ystep).len())
        .max()
        .unwrap_or(1) as u16;
    // the x axis' name goes under the y labels, whose column widens for a short one (a
    // written model's `omega` read `omega2.5` against the first x label, or `1.15 1.20 omega`
    // at the axis' end like one more tick)
    let name_w = ratatui::text::Span::raw(x.name.as_str()).width() as u16;
    let label_w = if name_w <= X_NAME_UNDER {
        label_w.max(name_w)
    } else {
        label_w
    };
    let width = area.width.checked_sub(label_w + 1)?;
    if height < 3 || width < 8 {
        return None;
    }
    let canvas = Rect::new(area.x + label_w + 1, area.y + 1, width, height);
    DRAWN.with(|d| {
        d.borrow_mut().push(Drawn {
            canvas,
            x: (x.min, x.max),
            y: (y.min, y.max),
        })
    });
    let (x0, y0) = (canvas.x, canvas.y);
    buf.set_stringn(area.x, area.y, &y.name, area.width as usize, s);
    for r in 0..canvas.height {
        buf.set_string(x0 - 1, y0 + r, "│", s);
    }
    for &t in &yt {
        let row = row_of(canvas, y, t);
        let label = tick_label(t, ystep);
        buf.set_string(area.x + label_w - label.len() as u16, row, &label, s);
        buf.set_string(x0 - 1, row, "┤", s);
    }
    let axis_row = y0 + canvas.height;
    buf.set_string(x0 - 1, axis_row, "└", s);
    for c in 0..canvas.width {
        buf.set_string(x0 + c, axis_row, "─", s);
    }
    let xt = ticks(x.min, x.max, (canvas.width as usize / 10).clamp(2, 8));
    let xstep = xt.get(1).map_or(1.0, |b| b - xt[0]);
    // the x axis is always named: under the y labels if it fits there, else at the right
    // end, where tick labels make room for it
    let (name_x, labels_end) = if name_w <= label_w {
        (area.x, x0 + canvas.width)
    } else {
        let at = (x0 + canvas.width).saturating_sub(name_w);
        (at, at.saturating_sub(1))
    };
    buf.set_stringn(name_x, axis_row + 1, &x.name, area.width as usize, s);
    let mut free_from = x0;
    for &t in &xt {
        let col = col_of(canvas, x, t);
        buf.set_string(col, axis_row, "┬", s);
        let label = tick_label(t, xstep);
        let len = label.len() as u16;
        // centred on its tick, or ending at the axis' end (the last tick's label)
        let start = col
            .saturating_sub(len / 2)
            .min(labels_end.saturating_sub(len))
            .max(free_from);
        if start + len <= labels_end {
            buf.set_string(start, axis_row + 1, &label, s);
            free_from = start + label.len() as u16 + 1;
        }
    }
    Some(canvas)
}

/// The column of value `v` on axis `x` drawn over `canvas`.
pub fn col_of(canvas: Rect, x: &Axis, v: f64) -> u16 {
    let f = ((v - x.min) / (x.max - x.min)).clamp(0.0, 1.0);
    canvas.x + (f * (canvas.width - 1) as f64).round() as u16
}

/// The row of value `v` on axis `y` drawn over `canvas`.
pub fn row_of(canvas: Rect, y: &Axis, v: f64) -> u16 {
    let f = ((v - y.min) / (y.max - y.min)).clamp(0.0, 1.0);
    canvas.y + canvas.height - 1 - (f * (canvas.height - 1) as f64).round() as u16
}

/// `footer` wrapped to `width` cells at spaces, styles kept (a readout or legend too long for
/// a narrow plot goes on to the next line rather than being cut; italic hints are dropped
/// first), and at most `max_rows`
/// lines: those after are dropped, the first lines (the cursor's readout) kept.
pub fn wrap_footer(footer: &[Line<'static>], width: u16, max_rows: usize) -> Vec<Line<'static>> {
    let width = width.max(1) as usize;
    let mut out: Vec<Line<'static>> = Vec::new();
    for line in footer {
        if line.width() <= width {
            out.push(line.clone());
            continue;
        }
        // hints (italic: "Enter: orbit") give way before a line is wrapped
        let line = &Line::from(
            line.spans
                .iter()
                .filter(|s| {
                    !s.style
                        .add_modifier
                        .contains(ratatui::style::Modifier::ITALIC)
                })
                .cloned()
                .collect::<Vec<_>>(),
        )
        .style(line.style);
        if line.width() <= width {
            out.push(line.clone());
            continue;
        }
        // words, each with the spaces after it, in the styles of its spans (a word may run
        // across spans: "1:2" and " at 26 Hz" joined by no-break spaces stay together)
        let mut words: Vec<Vec<Span<'static>>> = vec![Vec::new()];
        for span in &line.spans {
            let mut rest = span.content.as_ref();
            while !rest.is_empty() {
                let word_end = rest.find(' ').unwrap_or(rest.len());
                let end = word_end + rest[word_end..].len() - rest[word_end..].trim_start().len();
                let word = words.last_mut().expect("never empty");
                word.push(Span::styled(rest[..end].to_string(), span.style));
                if end > word_end {
                    words.push(Vec::new());
                }
                rest = &rest[end..];
            }
        }
        let mut current: Vec<Span<'static>> = Vec::new();
        let mut used = 0;
        for word in words.into_iter().filter(|w| !w.is_empty()) {
            let text: String = word.iter().map(|s| s.content.as_ref()).collect();
            let w = Span::raw(text.as_str()).width();
            let bare = Span::raw(text.trim_end_matches(' ')).width();
            if used > 0 && used + bare > width {
                out.push(Line::from(std::mem::take(&mut current)).style(line.style));
                used = 0;
            }
            used += w;
            current.extend(word);
        }
        if !current.is_empty() {
            out.push(Line::from(current).style(line.style));
        }
    }
    out.truncate(max_rows);
    out
}

/// How many footer rows a plot of `height` rows may give away: half of what the axes leave
/// (the readout and legend come first in every footer, what a view found after them).
pub fn footer_room(height: u16) -> usize {
    (height.saturating_sub(3) / 2).max(1) as usize
}

/// Draws `footer` lines under the x labels of `canvas`.
pub fn draw_footer(area: Rect, canvas: Rect, footer: &[Line], buf: &mut Buffer) {
    for (i, line) in footer.iter().enumerate() {
        let row = canvas.y + canvas.height + 2 + i as u16;
        if row < area.y + area.height {
            buf.set_line(area.x, row, line, area.width);
        }
    }
}

impl Widget for XyPlot {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let s = self.axis_style;
        let footer = wrap_footer(&self.footer, area.width, footer_room(area.height));
        let Some(canvas) = draw_axes(area, &self.x, &self.y, footer.len(), s, buf) else {
            buf.set_stringn(area.x, area.y, "(too small)", area.width as usize, s);
            return;
        };
        let (xb, yb) = ([self.x.min, self.x.max], [self.y.min, self.y.max]);
        let layers = &self.layers;
        Canvas::default()
            .marker(Marker::Braille)
            .x_bounds(xb)
            .y_bounds(yb)
            .paint(|ctx| paint(ctx, layers))
            .render(canvas, buf);
        // glyphs, text and cursor go straight into cells, on the exact cell of their point
        let inside = |x: f64, y: f64| {
            x >= self.x.min && x <= self.x.max && y >= self.y.min && y <= self.y.max
        };
        for layer in layers {
            match layer {
                Layer::Glyphs {
                    points,
                    glyph,
                    style,
                } => {
                    for &(x, y) in points {
                        if inside(x, y) {
                            let (c, r) = (col_of(canvas, &self.x, x), row_of(canvas, &self.y, y));
                            buf.set_string(c, r, glyph, *style);
                        }
                    }
                }
                Layer::Range {
                    x0,
                    x1,
                    y,
                    texts,
                    style,
                } if inside(*x0, *y) => {
                    let (c0, c1) = (col_of(canvas, &self.x, *x0), col_of(canvas, &self.x, *x1));
                    let width = (c1 - c0) as usize + 1;
                    let text = texts
                        .iter()
                        .find(|t| t.chars().count() + 4 <= width)
                        .or(texts.last())
                        .map_or("", String::as_str);
                    let bracket = range_bracket(text, width);
                    let room = (canvas.x + canvas.width).saturating_sub(c0) as usize;
                    buf.set_stringn(c0, row_of(canvas, &self.y, *y), bracket, room, *style);
                }
                _ => {}
            }
        }
        if let Some((x, y)) = self.cursor
            && inside(x, y)
        {
            let (col, row) = (col_of(canvas, &self.x, x), row_of(canvas, &self.y, y));
            let cell = &mut buf[(col, row)];
            let symbol = if cell.symbol().trim().is_empty() {
                "┼".to_string()
            } else {
                cell.symbol().to_string()
            };
            cell.set_symbol(&symbol).set_style(self.cursor_style);
        }
        draw_footer(area, canvas, &footer, buf);
    }
}

fn paint(ctx: &mut Context, layers: &[Layer]) {
    for layer in layers {
        match layer {
            Layer::Points { points, color } => ctx.draw(&Points {
                coords: points,
                color: *color,
            }),
            Layer::Curve { points, color } => {
                for pair in points.windows(2) {
                    let (a, b) = (pair[0], pair[1]);
                    if a.0.is_finite() && a.1.is_finite() && b.0.is_finite() && b.1.is_finite() {
                        ctx.draw(&ratatui::widgets::canvas::Line {
                            x1: a.0,
                            y1: a.1,
                            x2: b.0,
                            y2: b.1,
                            color: *color,
                        });
                    }
                }
            }
            _ => {}
        }
    }
}

/// `├── text ──┤` exactly `width` cells wide (the text cut to fit; at least the ends).
fn range_bracket(text: &str, width: usize) -> String {
    if width < 2 {
        return "│".into();
    }
    let inner = width - 2;
    let label: String = if inner >= 4 {
        format!(" {} ", text.chars().take(inner - 2).collect::<String>())
    } else {
        String::new()
    };
    let fill = inner - label.chars().count();
    let left = fill / 2;
    format!("├{}{label}{}┤", "─".repeat(left), "─".repeat(fill - left))
}

/// A legend entry: a glyph or swatch in its style, then words.
pub fn legend_item(glyph: &str, style: Style, words: &str) -> Vec<Span<'static>> {
    vec![
        Span::styled(glyph.to_string(), style),
        Span::raw(format!(" {words}  ")),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A footer line too long for its plot: italic hints go first, then it wraps at spaces,
    /// never inside a run joined by no-break spaces, with every word kept in its style.
    #[test]
    fn a_long_footer_line_wraps_and_keeps_its_words() {
        use ratatui::style::{Modifier, Stylize};
        let line = Line::from(vec![
            Span::raw("▸ ω 3.700 (52.67\u{a0}Hz)  A 0.4156  1:2"),
            Span::raw("\u{a0}at\u{a0}26.34\u{a0}Hz"),
            Span::raw(" hidden").red(),
            Span::raw("  Enter: orbit").add_modifier(Modifier::ITALIC),
        ]);
        let text = |l: &Line| {
            l.spans
                .iter()
                .map(|s| s.content.as_ref())
                .collect::<String>()
        };
        let wrapped = wrap_footer(std::slice::from_ref(&line), 40, 9);
        assert!(wrapped.iter().all(|l| l.width() <= 40), "{wrapped:?}");
        let all: Vec<String> = wrapped.iter().map(text).collect();
        assert!(!all.concat().contains("Enter"), "{all:?}");
        assert!(
            all.iter()
                .any(|l| l.contains("1:2\u{a0}at\u{a0}26.34\u{a0}Hz")),
            "{all:?}"
        );
        let hidden = wrapped
            .iter()
            .flat_map(|l| &l.spans)
            .find(|s| s.content.contains("hidden"));
        assert_eq!(hidden.unwrap().style.fg, Some(ratatui::style::Color::Red));
        // a line that fits keeps its hint; rows past the limit are dropped, the first kept
        let short = Line::from(vec![Span::raw("A 0.4"), Span::raw(" Enter").italic()]);
        assert_eq!(
            wrap_footer(std::slice::from_ref(&short), 40, 9),
            vec![short.clone()]
        );
        let three = [short.clone(), line.clone(), line];
        let kept = wrap_footer(&three, 20, 2);
        assert_eq!((kept.len(), &kept[0]), (2, &short));
    }

    #[test]
    fn a_range_bracket_spans_its_width() {
        assert_eq!(range_bracket("1:2 isola", 15), "├─ 1:2 isola ─┤");
        assert_eq!(range_bracket("1:2 isola", 6), "├ 1: ┤");
        assert_eq!(range_bracket("x", 3), "├─┤");
        for w in 2..30 {
            assert_eq!(range_bracket("1:2 isola, hidden", w).chars().count(), w);
        }
    }

    #[test]
    fn ticks_are_round_and_inside() {
        assert_eq!(ticks(0.2, 6.0, 6), vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        assert_eq!(ticks(0.0, 0.52, 4), vec![0.0, 0.2, 0.4]);
        assert_eq!(ticks(-0.8, 0.8, 4), vec![-0.5, 0.0, 0.5]);
        assert_eq!(tick_label(0.4, 0.2), "0.4");
        assert_eq!(tick_label(3.0, 1.0), "3");
        assert_eq!(tick_label(0.05, 0.05), "0.05");
        // a narrow range still gets two ticks, labelled with the digits they need
        assert_eq!(ticks(0.0625, 0.0997, 3), vec![0.07, 0.08, 0.09]);
    }
}
