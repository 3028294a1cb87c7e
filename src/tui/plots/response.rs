//! Frequency response (Fig 4/5) and stepped sweeps: amplitude over ω_e, a glyph and colour per
//! response type, hidden responses highlighted (outlined glyphs, the theme's hidden colour),
//! and each subharmonic branch's ω range annotated.

use ratatui::style::{Modifier, Style};
use ratatui::text::{Line, Span};

use super::frame::{Axis, Layer, XyPlot, legend_item};
use super::{PlotContext, PointCursor};
use isola::figure::short_type;
use isola::session::results::{ContinuedView, ResponsePoint, branches};

/// The glyph of a response type: filled when reached by a sweep, outlined when hidden.
pub fn glyph(response_type: &str, hidden: bool) -> &'static str {
    let key = response_type.split_whitespace().next().unwrap_or("");
    match (key, hidden) {
        ("1:1", false) => "•",
        ("1:1", true) => "○",
        ("1:2", false) => "◆",
        ("1:2", true) => "◇",
        ("2:1", false) => "▲",
        ("2:1", true) => "△",
        ("1:3", false) => "■",
        ("1:3", true) => "□",
        (_, false) => "+",
        (_, true) => "×",
    }
}

/// Amplitude over ω_e of `points`, joined by a line in sweep order if `joined`, with
/// `continued` branches drawn over them (a hunt's; these then replace the brute-force
/// branches' lines in the footer).
pub fn plot(
    points: &[ResponsePoint],
    continued: &[ContinuedView],
    omega_range: (f64, f64),
    joined: bool,
    ctx: &PlotContext,
) -> XyPlot {
    let theme = ctx.theme;
    let top = points
        .iter()
        .filter_map(|p| p.amplitude)
        .chain(
            continued
                .iter()
                .flat_map(|b| b.points.iter().map(|p| p.amplitude)),
        )
        .fold(0.0f64, f64::max);
    let mut plot = XyPlot::new(
        Axis::new(ctx.omega_axis(), omega_range.0, omega_range.1),
        Axis::new(ctx.of_output("amplitude"), 0.0, (top * 1.2).max(0.01)),
    );
    plot.axis_style = theme.muted();
    plot.cursor_style = theme.cursor();
    if joined {
        plot.layers.push(Layer::Curve {
            points: points
                .iter()
                .map(|p| (p.omega, p.amplitude.unwrap_or(f64::NAN)))
                .collect(),
            color: theme.muted,
        });
    }
    // one layer per (type, hidden), 1:1 first so subharmonics are drawn over it
    let mut groups: Vec<(String, bool)> = points
        .iter()
        .filter(|p| p.amplitude.is_some())
        .map(|p| (p.response_type.clone(), p.hidden == Some(true)))
        .collect();
    groups.sort_by_key(|(t, h)| (t != "1:1", *h, t.clone()));
    groups.dedup();
    for (t, hidden) in &groups {
        let style = if *hidden {
            theme.hidden()
        } else {
            Style::default().fg(theme.type_color(t))
        };
        plot.layers.push(Layer::Glyphs {
            points: points
                .iter()
                .filter(|p| &p.response_type == t && (p.hidden == Some(true)) == *hidden)
                .filter_map(|p| Some((p.omega, p.amplitude?)))
                .collect(),
            glyph: glyph(t, *hidden),
            style,
        });
    }
    // subharmonic branches: a bar over their ω range and a label
    let branches = branches(points);
    let annotated: Vec<_> = branches
        .iter()
        .filter(|b| b.is_subharmonic() && b.omega_max > b.omega_min)
        .collect();
    for b in &annotated {
        let style = if b.hidden {
            theme.hidden()
        } else {
            Style::default().fg(theme.type_color(&b.response_type))
        };
        let t = short_type(&b.response_type);
        let texts = if b.hidden {
            vec![
                format!("{t} isola, hidden"),
                format!("{t} hidden"),
                t.into(),
            ]
        } else if b.partly_hidden {
            vec![
                format!("{t} partly hidden"),
                format!("{t} partly"),
                t.into(),
            ]
        } else {
            vec![format!("{t} reached by a sweep"), t.into()]
        };
        plot.layers.push(Layer::Range {
            x0: b.omega_min,
            x1: b.omega_max,
            y: b.peak_amplitude * 1.12,
            texts,
            style,
        });
    }
    // legend: the types present
    let mut legend: Vec<Span> = Vec::new();
    let mut types: Vec<&str> = groups.iter().map(|(t, _)| t.as_str()).collect();
    types.sort_by_key(|t| short_type(t).to_string());
    types.dedup();
    for t in types {
        legend.extend(legend_item(
            glyph(t, false),
            Style::default().fg(theme.type_color(t)),
            short_type(t),
        ));
    }
    // the outlined glyph of each type drawn hidden: ○ for a hidden 1:1, ◇ for a 1:2
    let mut outlined: Vec<&str> = groups
        .iter()
        .filter(|(_, hidden)| *hidden)
        .map(|(t, _)| glyph(t, true))
        .collect();
    outlined.sort_unstable();
    outlined.dedup();
    if !outlined.is_empty() {
        legend.extend(legend_item(&outlined.concat(), theme.hidden(), "hidden"));
    }
    // responses without an amplitude (collisions, non-periodic) are counted, not drawn
    let mut without: Vec<(&str, usize)> = Vec::new();
    for p in points.iter().filter(|p| p.amplitude.is_none()) {
        match without.iter_mut().find(|(t, _)| *t == p.response_type) {
            Some((_, n)) => *n += 1,
            None => without.push((&p.response_type, 1)),
        }
    }
    for (t, n) in without {
        legend.push(Span::styled(
            format!("{} at {n} {}  ", short_type(t), ctx.omega()),
            theme.muted(),
        ));
    }
    plot.footer.push(Line::from(legend));
    if !continued.is_empty() {
        super::continued::overlay(
            &mut plot,
            continued,
            super::continued::XAxis::Omega,
            ctx.omega(),
            ctx,
        );
    }
    for b in annotated.into_iter().filter(|_| continued.is_empty()) {
        plot.footer.push(Line::from(Span::styled(
            format!(
                "{} {} {:.2}–{:.2}{} peak {:.3}{}",
                short_type(&b.response_type),
                ctx.omega(),
                b.omega_min,
                b.omega_max,
                ctx.device.map_or(String::new(), |d| format!(
                    " ({:.1}–{:.1} Hz)",
                    d.hz(b.omega_min),
                    d.hz(b.omega_max)
                )),
                b.peak_amplitude,
                if b.hidden {
                    " hidden"
                } else if b.partly_hidden {
                    " partly hidden"
                } else {
                    ""
                }
            ),
            if b.hidden {
                theme.hidden()
            } else {
                theme.text()
            },
        )));
    }
    let cursor = PointCursor::new(points);
    if let Some(p) = cursor.point(ctx.cursor) {
        plot.cursor = p.amplitude.map(|a| (p.omega, a));
        plot.footer.insert(0, readout(p, ctx));
    }
    plot
}

/// The cursor's reading: ω (and Hz), amplitude, type, hidden, share.
pub fn readout(p: &ResponsePoint, ctx: &PlotContext) -> Line<'static> {
    let mut spans = vec![
        Span::styled("▸ ", ctx.theme.key()),
        Span::raw(format!(
            "{} {:.3}{}  A {}  {}",
            ctx.omega(),
            p.omega,
            // the Hz kept with its number when the footer wraps
            ctx.device.map_or(String::new(), |d| format!(
                " ({:.2}\u{a0}Hz)",
                d.hz(p.omega)
            )),
            p.amplitude.map_or("—".into(), |a| format!("{a:.4}")),
            short_type(&p.response_type)
        )),
    ];
    // a subharmonic's own frequency (1:2 at 52 Hz forcing responds at 26 Hz)
    if let (Some(k), Some(device)) = (
        p.period
            .filter(|&k| k > 1 && p.response_type.starts_with("1:")),
        ctx.device,
    ) {
        spans.push(Span::raw(format!(
            "\u{a0}at\u{a0}{:.2}\u{a0}Hz",
            device.hz(p.omega) / k as f64
        )));
    }
    if p.hidden == Some(true) {
        spans.push(Span::styled(" hidden", ctx.theme.hidden()));
    }
    if p.share > 0.0 {
        spans.push(Span::raw(format!("  {:.0}% of starts", p.share * 100.0)));
    }
    if p.start.is_some() && ctx.pickable {
        spans.push(Span::styled(
            "  Enter: orbit",
            ctx.theme.muted().add_modifier(Modifier::ITALIC),
        ));
    }
    Line::from(spans)
}
