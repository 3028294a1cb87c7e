//! A time history and its phase path side by side (stacked when narrow): the transient
//! muted, the steady state in colour.

use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Direction, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::Widget;

use super::PlotContext;
use super::frame::{Axis, Layer, XyPlot};
use isola::session::results::HistoryView;

/// At most this many points per series are drawn (the rest would share pixels).
const MAX_POINTS: usize = 4000;

fn thin<T: Copy>(values: impl ExactSizeIterator<Item = T>) -> Vec<T> {
    let stride = values.len().div_ceil(MAX_POINTS).max(1);
    values.step_by(stride).collect()
}

/// Draws `h`, with `heading` (what the orbit is) as the first footer line.
pub fn draw(
    h: &HistoryView,
    heading: Option<Line<'static>>,
    ctx: &PlotContext,
    area: Rect,
    buf: &mut Buffer,
) {
    let theme = ctx.theme;
    let n = h.tau.len();
    let i = ctx.cursor.0.min(n.saturating_sub(1));
    let steady_color = theme.type_color("1:1");
    let split = |pred: bool| -> Vec<usize> { (0..n).filter(|&k| h.steady[k] == pred).collect() };
    let (transient, steady) = (split(false), split(true));
    let series = |idx: &[usize], f: &dyn Fn(usize) -> (f64, f64)| thin(idx.iter().map(|&k| f(k)));
    let [x_name, v_name] = h.states.clone().unwrap_or(["λ_I".into(), "v".into()]);
    let mut footer = Vec::new();
    if let Some(line) = heading {
        footer.push(line);
    }
    if n > 0 {
        // a written model's time is its own: no seconds of the paper's device
        let seconds = ctx.device.map_or(String::new(), |d| {
            format!(" ({:.4} s)", d.seconds(h.tau[i]))
        });
        footer.push(Line::from(vec![
            Span::styled("▸ ", theme.key()),
            Span::raw(format!(
                "{} {:.2}{seconds}  {x_name} {:.4}  {v_name} {:+.4}{}",
                ctx.time(),
                h.tau[i],
                h.lambda[i],
                h.v[i],
                if h.steady[i] {
                    "  steady"
                } else {
                    "  transient"
                }
            )),
        ]));
    }
    if let Some(tau) = h.collision {
        footer.push(Line::from(Span::styled(
            format!(
                "ended by a collision at {} {tau:.4}: nothing recorded after it",
                ctx.time()
            ),
            theme.error(),
        )));
    }
    if let Some(s) = &h.summary {
        let period = match (s.period_forcing_periods, ctx.device) {
            // a subharmonic's own frequency beside the forcing's
            (Some(1), Some(device)) => format!("1:1 at {:.2} Hz", device.hz(s.omega)),
            (Some(k), Some(device)) => format!(
                "1:{k}, {:.2} Hz (forcing {:.2} Hz)",
                device.hz(s.omega) / k as f64,
                device.hz(s.omega)
            ),
            (Some(k), None) => format!("1:{k}"),
            (None, _) => "no period within the record".into(),
        };
        let slack = s.slack.map_or(String::new(), |[i, ii]| {
            format!(
                "  slack: I {:.0}%, II {:.0}% of the time",
                i * 100.0,
                ii * 100.0
            )
        });
        footer.push(Line::from(vec![
            Span::styled("steady ", theme.muted()),
            Span::raw(format!("{period}  A {:.4}{slack}", s.amplitude)),
        ]));
    }
    // one plot of (x, y) over the samples: the transient muted, the steady part in colour
    let plot = |x_name: &str, x: &[f64], y_name: &str, y: &[f64], x_margin: f64| {
        let mut p = XyPlot::new(
            Axis::fit(x_name, x.iter().copied(), x_margin),
            Axis::fit(y_name, y.iter().copied(), 0.05),
        );
        p.layers.push(Layer::Points {
            points: series(&transient, &|k| (x[k], y[k])),
            color: theme.muted,
        });
        p.layers.push(Layer::Curve {
            points: series(&steady, &|k| (x[k], y[k])),
            color: steady_color,
        });
        p.cursor = (n > 0).then(|| (x[i], y[i]));
        p.axis_style = theme.muted();
        p.cursor_style = theme.cursor();
        p
    };
    let time = plot(ctx.time(), &h.tau, &x_name, &h.lambda, 0.0);
    let phase = plot(&x_name, &h.lambda, &v_name, &h.v, 0.05);
    let footer = super::frame::wrap_footer(&footer, area.width, (area.height / 3).max(1) as usize);
    let footer_rows = footer.len() as u16;
    let [plots, foot] =
        Layout::vertical([Constraint::Min(4), Constraint::Length(footer_rows)]).areas(area);
    let direction = if plots.width >= 2 * plots.height + 20 {
        Direction::Horizontal
    } else {
        Direction::Vertical
    };
    let halves = Layout::default()
        .direction(direction)
        .constraints([Constraint::Percentage(55), Constraint::Percentage(45)])
        .split(plots);
    time.render(halves[0], buf);
    phase.render(halves[1], buf);
    for (k, line) in footer.iter().enumerate() {
        buf.set_line(foot.x, foot.y + k as u16, line, foot.width);
    }
}
