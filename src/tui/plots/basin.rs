//! Basins of attraction (Fig 6): a colour per attractor over (Δλ, v), a legend with each
//! attractor's share of the cells, and glyphs instead of colours on a monochrome terminal.

use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};

use super::PlotContext;
use super::frame::Axis;
use super::heatmap::{HeatMap, Paint};
use crate::tui::theme::Theme;
use isola::figure::short_type;
use isola::session::results::BasinView;

/// Glyphs for attractors 0, 1, 2... when there is no colour.
const GLYPHS: [&str; 8] = ["·", "█", "▒", "░", "▓", "#", "+", "o"];

/// Colour of attractor `id`: its type's colour, or a series colour when an earlier attractor
/// already has that type.
fn attractor_color(b: &BasinView, id: usize, theme: &Theme) -> Color {
    let t = &b.attractors[id].response_type;
    if b.attractors[..id].iter().any(|a| &a.response_type == t) {
        theme.series(id + 2)
    } else {
        theme.type_color(t)
    }
}

fn glyph(id: usize) -> &'static str {
    GLYPHS[id % GLYPHS.len()]
}

/// Draws the basin with the cursor's cell marked and read out; the cells not computed yet
/// show `previous` (the settings before, or a coarse preview, on the same grid, with what it
/// is called) faded.
pub fn draw(
    b: &BasinView,
    previous: Option<(&BasinView, &str)>,
    lambda_p: f64,
    ctx: &PlotContext,
    area: ratatui::layout::Rect,
    buf: &mut ratatui::buffer::Buffer,
) {
    let theme = ctx.theme;
    let (nx, nv) = (b.dx.len(), b.v.len());
    let label = |ix: usize, iy: usize| b.labels.get(ix * nv + iy).copied().flatten();
    let colors: Vec<Color> = (0..b.attractors.len())
        .map(|id| attractor_color(b, id, theme))
        .collect();
    let previous = previous.filter(|(p, _)| p.dx == b.dx && p.v == b.v && !theme.monochrome);
    let faded_label = previous.map(|(_, label)| label);
    let previous = previous.map(|(p, _)| p);
    let faded: Vec<Color> = previous.map_or(Vec::new(), |p| {
        (0..p.attractors.len())
            .map(|id| theme.dim(attractor_color(p, id, theme)))
            .collect()
    });
    let earlier = |ix: usize, iy: usize| {
        let l = previous?.labels.get(ix * nv + iy).copied().flatten()?;
        faded.get(l).copied()
    };
    let color_of = |ix: usize, iy: usize| match label(ix, iy) {
        Some(l) => colors.get(l).copied(),
        None => earlier(ix, iy),
    };
    let glyph_of = |ix: usize, iy: usize| label(ix, iy).map_or(" ", glyph);
    let paint = if theme.monochrome {
        Paint::Glyphs(&glyph_of)
    } else {
        Paint::Colors(&color_of)
    };
    let (cx, cy) = (
        ctx.cursor.0.min(nx.saturating_sub(1)),
        ctx.cursor.1.min(nv.saturating_sub(1)),
    );
    let mut footer = Vec::new();
    if let (Some(dx), Some(v)) = (b.dx.get(cx), b.v.get(cy)) {
        let target = label(cx, cy).and_then(|l| b.attractors.get(l));
        let mut spans = vec![
            Span::styled("▸ ", theme.key()),
            Span::raw(format!(
                "{}  → {}",
                match ctx.grid() {
                    None => format!("Δλ {dx:+.3} (λ_I {:.3})  v {v:+.3}", lambda_p + dx),
                    Some([a, b]) => format!("{a} {dx:+.3}  {b} {v:+.3} (from the origin)"),
                },
                target.map_or("not computed".into(), |a| format!(
                    "{} {}",
                    short_type(&a.response_type),
                    a.amplitude
                        .map_or(String::new(), |x| format!("A\u{a0}{x:.4}"))
                ))
            )),
        ];
        if ctx.pickable {
            spans.push(Span::styled(
                "  Enter: orbit",
                theme.muted().add_modifier(Modifier::ITALIC),
            ));
        }
        footer.push(Line::from(spans));
    }
    let items: Vec<Vec<Span>> = b
        .attractors
        .iter()
        .map(|a| {
            let swatch = if theme.monochrome {
                Span::raw(glyph(a.id).repeat(2))
            } else {
                Span::styled("██", Style::default().fg(colors[a.id]))
            };
            vec![
                swatch,
                Span::raw(format!(
                    " {}{} {:.1}%  ",
                    short_type(&a.response_type),
                    a.amplitude.map_or(String::new(), |x| format!(" A {x:.3}")),
                    a.fraction * 100.0
                )),
            ]
        })
        .collect();
    // as many entries a line as fit the plot's width, so none is cut off
    let mut line: Vec<Span> = Vec::new();
    for item in items {
        let width: usize = item.iter().map(Span::width).sum();
        let used: usize = line.iter().map(Span::width).sum();
        // (each entry ends in two spaces, which may fall off the edge)
        if !line.is_empty() && used + width.saturating_sub(2) > area.width as usize {
            footer.push(Line::from(std::mem::take(&mut line)));
        }
        line.extend(item);
    }
    if !line.is_empty() {
        footer.push(Line::from(line));
    }
    let done = b.labels.iter().filter(|l| l.is_some()).count();
    if done < b.labels.len() {
        footer.push(super::previous::so_far(
            done,
            b.labels.len(),
            "cells",
            faded_label,
            theme,
        ));
    }
    let (x_label, y_label) = match ctx.grid() {
        None => ("Δλ".to_string(), "v (per τ)".to_string()),
        Some([a, b]) => (format!("Δ{a}"), format!("Δ{b}")),
    };
    let map = HeatMap {
        x: Axis::new(
            x_label,
            b.dx.first().copied().unwrap_or(-1.0),
            b.dx.last().copied().unwrap_or(1.0),
        ),
        y: Axis::new(
            y_label,
            b.v.first().copied().unwrap_or(-1.0),
            b.v.last().copied().unwrap_or(1.0),
        ),
        nx,
        ny: nv,
        paint,
        cursor: Some((cx, cy)),
        marks: Vec::new(),
        axis_style: theme.muted(),
        cursor_style: theme.cursor(),
        footer,
    };
    ratatui::widgets::Widget::render(map, area, buf);
}
