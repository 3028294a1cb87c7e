//! Force curves (Fig 2): f_II − f_I against Δλ, one colour per (λ_p, φ_I).

use ratatui::style::Style;
use ratatui::text::{Line, Span};

use super::PlotContext;
use super::frame::{Axis, Layer, XyPlot, legend_item};
use isola::session::results::ForceView;

pub fn plot(f: &ForceView, ctx: &PlotContext) -> XyPlot {
    let theme = ctx.theme;
    let all = || f.curves.iter().flat_map(|c| c.2.iter());
    let mut plot = XyPlot::new(
        Axis::fit("Δλ", all().map(|p| p[0]), 0.0),
        Axis::fit("force f_II − f_I (non-dim)", all().map(|p| p[1]), 0.05),
    );
    plot.axis_style = theme.muted();
    plot.cursor_style = theme.cursor();
    let mut legend: Vec<Span> = Vec::new();
    for (i, (lambda_p, phi, points)) in f.curves.iter().enumerate() {
        let color = theme.series(i);
        plot.layers.push(Layer::Curve {
            points: points.iter().map(|p| (p[0], p[1])).collect(),
            color,
        });
        legend.extend(legend_item(
            "━",
            Style::default().fg(color),
            &format!("λp {lambda_p} φ {phi}"),
        ));
    }
    let curve = ctx.cursor.1.min(f.curves.len().saturating_sub(1));
    if let Some((lambda_p, phi, points)) = f.curves.get(curve)
        && let Some(p) = points.get(ctx.cursor.0.min(points.len().saturating_sub(1)))
    {
        plot.cursor = Some((p[0], p[1]));
        plot.footer.push(Line::from(vec![
            Span::styled("▸ ", theme.key()),
            Span::raw(format!(
                "λp {lambda_p} φ {phi}: Δλ {:+.4}  f {:+.5}  (↑↓ curve)",
                p[0], p[1]
            )),
        ]));
    }
    plot.footer.push(Line::from(legend));
    plot
}
