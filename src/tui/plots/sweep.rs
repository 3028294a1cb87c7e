//! Chirp sweeps (Fig 3): the envelopes of the forward and backward sweeps on one plot, or the
//! selected sweep's Morlet scalogram as a heat map over (ω_e, response frequency).

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::{Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::Widget;

use super::PlotContext;
use super::frame::{Axis, Layer, XyPlot, legend_item};
use super::heatmap::{HeatMap, Paint};
use isola::analysis::orbit::scalogram::Scalogram;
use isola::session::results::ChirpView;

/// One sweep to overlay: its name, data, and whether it is the selected one.
pub struct Sweep<'a> {
    pub name: &'a str,
    pub view: &'a ChirpView,
    pub selected: bool,
}

fn direction(v: &ChirpView) -> &'static str {
    match (v.omega.first(), v.omega.last()) {
        (Some(a), Some(b)) if b < a => "←",
        _ => "→",
    }
}

/// The envelopes of `sweeps` over ω_e; the cursor walks the selected one.
pub fn envelopes(sweeps: &[Sweep], ctx: &PlotContext) -> XyPlot {
    let theme = ctx.theme;
    let all = || sweeps.iter().flat_map(|s| s.view.envelope.iter());
    let top = all().map(|e| e[1]).fold(0.0f64, f64::max);
    let mut plot = XyPlot::new(
        Axis::fit(ctx.omega_axis(), all().map(|e| e[0]), 0.0),
        Axis::new(ctx.of_output("envelope"), 0.0, (top * 1.1).max(0.01)),
    );
    plot.axis_style = theme.muted();
    plot.cursor_style = theme.cursor();
    let mut legend = Vec::new();
    for (i, s) in sweeps.iter().enumerate() {
        let color = theme.series(i);
        plot.layers.push(Layer::Curve {
            points: s.view.envelope.iter().map(|e| (e[0], e[1])).collect(),
            color,
        });
        let mut style = Style::default().fg(color);
        if s.selected {
            style = style.add_modifier(Modifier::BOLD);
        }
        legend.extend(legend_item(
            &format!("━{}", direction(s.view)),
            style,
            s.name,
        ));
    }
    if let Some(s) = sweeps.iter().find(|s| s.selected) {
        let env = &s.view.envelope;
        if let Some(e) = env.get(ctx.cursor.0.min(env.len().saturating_sub(1))) {
            plot.cursor = Some((e[0], e[1]));
            plot.footer.push(Line::from(vec![
                Span::styled("▸ ", theme.key()),
                Span::raw(format!(
                    "{}: {} {:.3}{}  envelope {:.4}",
                    s.name,
                    ctx.omega_axis(),
                    e[0],
                    ctx.in_hz(e[0], 2),
                    e[1]
                )),
                Span::styled(
                    "  w: scalogram",
                    theme.muted().add_modifier(Modifier::ITALIC),
                ),
            ]));
        }
    }
    plot.footer.push(Line::from(legend));
    plot
}

/// Shades for the scalogram without colour, low to high.
const SHADES: [&str; 5] = [" ", "░", "▒", "▓", "█"];

/// The scalogram of `sweep` (columns in time order, drawn in ω_e order).
pub fn scalogram(
    sweep: &ChirpView,
    s: &Scalogram,
    ctx: &PlotContext,
    area: Rect,
    buf: &mut Buffer,
) {
    let theme = ctx.theme;
    let forcing = s.forcing(&sweep.omega);
    let nx = s.times.len();
    let reversed = direction(sweep) == "←";
    let column = move |ix: usize| if reversed { nx - 1 - ix } else { ix };
    let peak = s
        .magnitude
        .iter()
        .flatten()
        .fold(0.0f64, |a, &b| a.max(b))
        .max(1e-30);
    // magnitudes on a square-root scale, so the weaker subharmonic lines still show
    let level = |ix: usize, iy: usize| (s.magnitude[iy][column(ix)] / peak).sqrt();
    let color = |ix: usize, iy: usize| Some(theme.ramp(level(ix, iy)));
    let glyph = |ix: usize, iy: usize| {
        SHADES[((level(ix, iy) * (SHADES.len() - 1) as f64).round() as usize).min(SHADES.len() - 1)]
    };
    let paint = if theme.monochrome {
        Paint::Glyphs(&glyph)
    } else {
        Paint::Colors(&color)
    };
    let ix = ctx.cursor.0 * nx / sweep.envelope.len().max(1);
    let ix = ix.min(nx.saturating_sub(1));
    let mut footer = Vec::new();
    if nx > 0 {
        let t = s.times[column(ix)];
        let w = forcing[column(ix)];
        let ridge = s.ridge[column(ix)];
        // no ratio while the forcing is at rest (ω_e = 0 where a sweep up starts)
        let ratio = Some(ridge / w)
            .filter(|r| w > 0.0 && r.is_finite())
            .map_or("—".to_string(), |r| format!("{r:.3}"));
        footer.push(Line::from(vec![
            Span::styled("▸ ", theme.key()),
            Span::raw(format!(
                "{} {t:.0}  {omega} {w:.3}  strongest ω_r {ridge:.3}  ω_r/{omega}\u{a0}{ratio}",
                ctx.time(),
                omega = ctx.omega_axis(),
            )),
            Span::styled(
                "  w: envelopes",
                theme.muted().add_modifier(Modifier::ITALIC),
            ),
        ]));
    }
    let (first, last) = (
        forcing.first().copied().unwrap_or(0.0),
        forcing.last().copied().unwrap_or(1.0),
    );
    let ridge_iy = if nx > 0 {
        s.frequencies
            .iter()
            .position(|&f| f >= s.ridge[column(ix)])
            .unwrap_or(0)
    } else {
        0
    };
    // the colour scale: magnitude over the peak, on the square-root scale drawn
    let mut scale = vec![Span::styled("|W|/peak ", theme.muted()), Span::raw("0 ")];
    for k in 0..=8 {
        let x = k as f64 / 8.0;
        scale.push(if theme.monochrome {
            Span::raw(
                SHADES[((x * (SHADES.len() - 1) as f64).round() as usize).min(SHADES.len() - 1)],
            )
        } else {
            Span::styled("█", Style::default().fg(theme.ramp(x)))
        });
    }
    scale.push(Span::raw(" 1"));
    scale.push(Span::styled(
        "  (√ scale: 0.25 at mid-ramp)",
        theme.muted().add_modifier(Modifier::ITALIC),
    ));
    if nx > 0 && ridge_iy < s.frequencies.len() {
        let here = level(ix, ridge_iy);
        scale.push(Span::raw(format!("  cursor {:.2}", here * here)));
    }
    footer.push(Line::from(scale));
    let map = HeatMap {
        x: Axis::new(ctx.omega_axis(), first.min(last), first.max(last)),
        y: Axis::new(
            "response ω",
            s.frequencies.first().copied().unwrap_or(0.0),
            s.frequencies.last().copied().unwrap_or(1.0),
        ),
        nx,
        ny: s.frequencies.len(),
        paint,
        cursor: Some((ix, ridge_iy)),
        marks: Vec::new(),
        axis_style: theme.muted(),
        cursor_style: theme.cursor(),
        footer,
    };
    map.render(area, buf);
}
