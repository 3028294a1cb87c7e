//! Two-parameter maps: a colour per number of coexisting stable responses over ω_e and a
//! model parameter, hidden responses marked, and the fold and period-doubling curves drawn
//! over it with their turning points (where an isola is born or two folds meet).

use ratatui::style::{Modifier, Style};
use ratatui::text::{Line, Span};

use super::PlotContext;
use super::frame::Axis;
use super::heatmap::{HeatMap, Paint};
use isola::session::results::MapView;

/// Glyphs for 0, 1, 2, 3+ stable responses when there is no colour.
const COUNT_GLYPHS: [&str; 4] = [" ", "░", "▒", "▓"];
/// Hidden responses exist in this cell.
const HIDDEN: &str = "◇";
/// A point of a fold curve, of a period-doubling curve.
const FOLD_CURVE: &str = "•";
const PD_CURVE: &str = "×";

/// Draws the map with the cursor's cell read out; the rows not computed yet show `previous`
/// (the settings before, on the same grid) faded.
pub fn draw(
    m: &MapView,
    previous: Option<(&MapView, &str)>,
    ctx: &PlotContext,
    area: ratatui::layout::Rect,
    buf: &mut ratatui::buffer::Buffer,
) {
    let theme = ctx.theme;
    let (nx, ny) = (m.omegas.len(), m.values.len());
    let cell = |ix: usize, iy: usize| m.rows.get(iy)?.as_ref()?.get(ix);
    let level = |n: usize| n.min(3);
    let count_color = |n: usize| theme.ramp(level(n) as f64 / 3.0);
    let previous =
        previous.filter(|(p, _)| p.omegas == m.omegas && p.values == m.values && !theme.monochrome);
    let faded_label = previous.map(|(_, label)| label);
    let previous = previous.map(|(p, _)| p);
    let earlier = |ix: usize, iy: usize| previous?.rows.get(iy)?.as_ref()?.get(ix);
    let color_of = |ix: usize, iy: usize| match cell(ix, iy) {
        Some(c) => Some(count_color(c.stable)),
        None => earlier(ix, iy).map(|c| theme.dim(count_color(c.stable))),
    };
    let glyph_of =
        |ix: usize, iy: usize| cell(ix, iy).map_or(" ", |c| COUNT_GLYPHS[level(c.stable)]);
    let paint = if theme.monochrome {
        Paint::Glyphs(&glyph_of)
    } else {
        Paint::Colors(&color_of)
    };
    // axes reach half a cell past the first and last grid values, so marks sit on cells
    let half = |v: &[f64]| {
        if v.len() > 1 {
            0.5 * (v[v.len() - 1] - v[0]) / (v.len() - 1) as f64
        } else {
            0.5
        }
    };
    let (hx, hy) = (half(&m.omegas), half(&m.values));
    let bounds = |v: &[f64], h: f64| {
        let (a, b) = (
            v.first().copied().unwrap_or(0.0),
            v.last().copied().unwrap_or(1.0),
        );
        (a.min(b) - h, a.max(b) + h)
    };
    let (x0, x1) = bounds(&m.omegas, hx);
    let (y0, y1) = bounds(&m.values, hy);
    let mut marks = Vec::new();
    let hidden_style = theme.hidden().add_modifier(Modifier::BOLD);
    for (iy, row) in m.rows.iter().enumerate() {
        for (ix, c) in row.iter().flatten().enumerate() {
            if c.hidden {
                marks.push((m.omegas[ix], m.values[iy], HIDDEN, hidden_style));
            }
        }
    }
    let curve_style = theme.key();
    for c in &m.curves {
        let glyph = if c.kind == "fold" {
            FOLD_CURVE
        } else {
            PD_CURVE
        };
        marks.extend(c.points.iter().map(|p| (p[0], p[1], glyph, curve_style)));
    }
    let (cx, cy) = (
        ctx.cursor.0.min(nx.saturating_sub(1)),
        ctx.cursor.1.min(ny.saturating_sub(1)),
    );
    let mut footer = Vec::new();
    if let (Some(w), Some(v)) = (m.omegas.get(cx), m.values.get(cy)) {
        let reading = match cell(cx, cy) {
            Some(c) => format!(
                "{} stable{}{}",
                c.stable,
                match (&c.largest_type, c.largest_amplitude) {
                    (Some(t), Some(a)) => format!(", largest {t} A {a:.4}"),
                    _ => String::new(),
                },
                if c.hidden { ", hidden" } else { "" }
            ),
            None => "not computed".into(),
        };
        let at = if m.x == "omega" {
            format!("{} {w:.3}{}", ctx.omega(), ctx.in_hz(*w, 1))
        } else {
            format!("{} {w:.4}", m.x)
        };
        footer.push(Line::from(vec![
            Span::styled("▸ ", theme.key()),
            Span::raw(format!("{at}  {} {v:.4}: {reading}", m.parameter)),
        ]));
    }
    let mut legend: Vec<Span> = Vec::new();
    for (n, glyph) in COUNT_GLYPHS.iter().enumerate() {
        let swatch = if theme.monochrome {
            Span::raw(glyph.repeat(2))
        } else {
            Span::styled("██", Style::default().fg(count_color(n)))
        };
        legend.push(swatch);
        legend.push(Span::raw(format!(
            " {}{}  ",
            n,
            if n == 3 { "+" } else { "" }
        )));
    }
    legend.push(Span::styled(HIDDEN, hidden_style));
    legend.push(Span::raw(" hidden  "));
    if !m.curves.is_empty() {
        legend.push(Span::styled(FOLD_CURVE, curve_style));
        legend.push(Span::raw(" fold  "));
        legend.push(Span::styled(PD_CURVE, curve_style));
        legend.push(Span::raw(" period doubling"));
    }
    footer.push(Line::from(legend));
    let x_name = if m.x == "omega" {
        ctx.omega()
    } else {
        m.x.as_str()
    };
    let turning: Vec<String> = m
        .curves
        .iter()
        .flat_map(|c| {
            c.extrema
                .iter()
                .filter(|e| e.1 == m.parameter)
                .map(move |e| {
                    format!(
                        "1:{} {} {} {} {:.4} at {} {:.3}",
                        c.period, c.kind, e.0, m.parameter, e.2[1], x_name, e.2[0]
                    )
                })
        })
        .collect();
    if !turning.is_empty() {
        footer.push(Line::styled(turning.join("; "), theme.text()));
    }
    let done = m.rows.iter().filter(|r| r.is_some()).count();
    if done < m.rows.len() {
        footer.push(super::previous::so_far(
            done,
            m.rows.len(),
            "rows",
            faded_label,
            theme,
        ));
    }
    let map = HeatMap {
        // the forcing frequency as the model names it (ω_e, or a written model's parameter)
        x: Axis::new(
            if m.x == "omega" {
                ctx.omega_axis()
            } else {
                m.x.as_str()
            },
            x0,
            x1,
        ),
        y: Axis::new(m.parameter.as_str(), y0, y1),
        nx,
        ny,
        paint,
        cursor: Some((cx, cy)),
        marks,
        axis_style: theme.muted(),
        cursor_style: theme.cursor(),
        footer,
    };
    ratatui::widgets::Widget::render(map, area, buf);
}
