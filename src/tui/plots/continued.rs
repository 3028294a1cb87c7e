//! Continued branches: stable arcs as solid lines, unstable ones dashed in the muted colour,
//! folds and period doublings marked; drawn over a hunt's brute-force responses, or alone
//! for a continuation.

use ratatui::style::Style;
use ratatui::text::{Line, Span};

use super::PlotContext;
use super::frame::{Axis, Layer, XyPlot, legend_item};
use isola::session::results::{ContinuationView, ContinuedPoint, ContinuedView};

/// Glyph of a located fold.
const FOLD: &str = "✕";
/// Glyph of a located period doubling.
const PERIOD_DOUBLING: &str = "⊗";
/// Dash and gap lengths of an unstable arc, as fractions of the plot's diagonal.
const DASH: f64 = 0.035;
const GAP: f64 = 0.03;

/// The response type a branch of period k is drawn as (`1:k`).
fn type_of(b: &ContinuedView) -> String {
    format!("1:{}", b.period)
}

/// What the x axis of continued branches is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum XAxis {
    /// The drive's frequency ω_e (a hunt: over the brute-force responses).
    Omega,
    /// The continuation's parameter.
    Parameter,
}

impl XAxis {
    /// The x of a point with this `parameter` and `omega`.
    fn of(self, parameter: f64, omega: f64) -> f64 {
        match self {
            XAxis::Omega => omega,
            XAxis::Parameter => parameter,
        }
    }
}

/// Adds `branches` to `plot` against `x`, with the legend and one line per branch in the
/// footer.
pub fn overlay(
    plot: &mut XyPlot,
    branches: &[ContinuedView],
    x: XAxis,
    x_name: &str,
    ctx: &PlotContext,
) {
    let theme = ctx.theme;
    let scale = (plot.x.max - plot.x.min, plot.y.max - plot.y.min);
    for b in branches {
        let color = theme.type_color(&type_of(b));
        let xy: Vec<(f64, f64, bool)> = b
            .points
            .iter()
            .map(|p| (x.of(p.parameter, p.omega), p.amplitude, p.stable))
            .collect();
        let mut stable = Vec::new();
        let mut unstable_runs: Vec<Vec<(f64, f64)>> = Vec::new();
        let mut in_run = false;
        for w in xy.windows(2) {
            let (a, c) = (w[0], w[1]);
            // a segment between points of different stability passes a fold: draw it unstable
            if a.2 && c.2 {
                stable.extend([(a.0, a.1), (c.0, c.1), (f64::NAN, f64::NAN)]);
                in_run = false;
            } else {
                if !in_run {
                    unstable_runs.push(vec![(a.0, a.1)]);
                    in_run = true;
                }
                let run = unstable_runs.last_mut().expect("a run was started");
                run.push((c.0, c.1));
            }
        }
        let unstable: Vec<(f64, f64)> = unstable_runs
            .iter()
            .flat_map(|run| dashes(run, scale))
            .collect();
        plot.layers.push(Layer::Curve {
            points: unstable,
            color: theme.muted,
        });
        plot.layers.push(Layer::Curve {
            points: stable,
            color,
        });
        for (kind, glyph) in [("fold", FOLD), ("period-doubling", PERIOD_DOUBLING)] {
            let at: Vec<(f64, f64)> = b
                .bifurcations
                .iter()
                .filter(|f| f.kind.ends_with(kind))
                .map(|f| (x.of(f.parameter, f.omega), f.amplitude))
                .collect();
            if !at.is_empty() {
                plot.layers.push(Layer::Glyphs {
                    points: at,
                    glyph,
                    style: theme.key(),
                });
            }
        }
    }
    if branches.is_empty() {
        return;
    }
    let mut legend = vec![
        Span::styled("━", theme.text()),
        Span::raw(" stable  "),
        Span::styled("┄", theme.muted()),
        Span::raw(" unstable  "),
    ];
    legend.extend(legend_item(FOLD, theme.key(), "fold"));
    legend.extend(legend_item(PERIOD_DOUBLING, theme.key(), "period doubling"));
    plot.footer.push(Line::from(legend));
    for b in branches {
        plot.footer.push(describe(b, x, x_name, ctx));
    }
}

/// `1:2 isola  ω 3.5896–5.4439  ✕ 3.58964, 5.44387`.
fn describe(b: &ContinuedView, x: XAxis, x_name: &str, ctx: &PlotContext) -> Line<'static> {
    let (lo, hi) = b
        .points
        .iter()
        .map(|p| x.of(p.parameter, p.omega))
        .chain(b.bifurcations.iter().map(|f| x.of(f.parameter, f.omega)))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
            (lo.min(x), hi.max(x))
        });
    let mut spans = vec![Span::styled(
        format!("{} {}", type_of(b), b.verdict),
        Style::default().fg(ctx.theme.type_color(&type_of(b))),
    )];
    spans.push(Span::raw(format!("  {x_name} {lo:.4}–{hi:.4}")));
    for (kind, glyph) in [("fold", FOLD), ("period-doubling", PERIOD_DOUBLING)] {
        let at: Vec<String> = b
            .bifurcations
            .iter()
            .filter(|f| f.kind.ends_with(kind))
            .map(|f| format!("{:.5}", x.of(f.parameter, f.omega)))
            .collect();
        if !at.is_empty() {
            spans.push(Span::styled(format!("  {glyph} "), ctx.theme.key()));
            spans.push(Span::raw(at.join(", ")));
        }
    }
    Line::from(spans)
}

/// The polyline `run` cut into dashes of equal length on screen (`scale` is the plot's x and
/// y extent), the gaps as NaN points.
fn dashes(run: &[(f64, f64)], scale: (f64, f64)) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    // distance along the run where the current dash or gap ends
    let (mut drawing, mut left) = (true, DASH);
    if let Some(&first) = run.first() {
        out.push(first);
    }
    for w in run.windows(2) {
        let (a, b) = (w[0], w[1]);
        let length = (((b.0 - a.0) / scale.0).powi(2) + ((b.1 - a.1) / scale.1).powi(2)).sqrt();
        if !length.is_finite() {
            continue;
        }
        let mut done = 0.0;
        while length - done > left {
            done += left;
            let f = done / length;
            out.push((a.0 + f * (b.0 - a.0), a.1 + f * (b.1 - a.1)));
            if drawing {
                out.push((f64::NAN, f64::NAN));
            }
            (drawing, left) = if drawing { (false, GAP) } else { (true, DASH) };
        }
        left -= length - done;
        if drawing {
            out.push(b);
        }
    }
    out.push((f64::NAN, f64::NAN));
    out
}

/// A continuation alone: amplitude against its parameter, the cursor on a branch point.
pub fn plot(view: &ContinuationView, ctx: &PlotContext) -> XyPlot {
    let all = || view.branches.iter().flat_map(|b| b.points.iter());
    let mut plot = XyPlot::new(
        Axis::fit(view.parameter.as_str(), all().map(|p| p.parameter), 0.02),
        Axis::fit(ctx.of_output("amplitude"), all().map(|p| p.amplitude), 0.05),
    );
    plot.axis_style = ctx.theme.muted();
    plot.cursor_style = ctx.theme.cursor();
    overlay(
        &mut plot,
        &view.branches,
        XAxis::Parameter,
        &view.parameter,
        ctx,
    );
    if let Some(p) = point(view, ctx.cursor) {
        plot.cursor = Some((p.parameter, p.amplitude));
        plot.footer.insert(
            0,
            Line::from(vec![
                Span::styled("▸ ", ctx.theme.key()),
                Span::raw(format!(
                    "{} {:.5}  {} {:.4}{}  A {:.4}  {}",
                    view.parameter,
                    p.parameter,
                    ctx.omega(),
                    p.omega,
                    ctx.in_hz(p.omega, 2),
                    p.amplitude,
                    if p.stable { "stable" } else { "unstable" }
                )),
            ]),
        );
    }
    plot
}

/// The point under the cursor (point index along the branch, branch index).
pub fn point(view: &ContinuationView, cursor: (usize, usize)) -> Option<&ContinuedPoint> {
    let b = view.branches.get(cursor.1)?;
    b.points.get(cursor.0.min(b.points.len().checked_sub(1)?))
}
