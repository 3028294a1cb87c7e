//! A time history beside its phase path: the transient muted, the steady state in colour.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{AxisSpec, Drawn, Legend, Style, Swatch, fit, nothing, panel};
use crate::model::Device;
use crate::session::results::HistoryView;

/// Forcing periods of transient drawn before the steady part of a long record.
const TAIL_PERIODS: f64 = 8.0;

/// At most this many points per series are drawn (the rest would share pixels).
const MAX_POINTS: usize = 40_000;

/// The samples `idx` as points `f(k)`, thinned to at most [`MAX_POINTS`].
fn series(idx: &[usize], f: impl Fn(usize) -> (f64, f64)) -> Vec<(f64, f64)> {
    let stride = idx.len().div_ceil(MAX_POINTS).max(1);
    idx.iter().step_by(stride).map(|&k| f(k)).collect()
}

pub(super) fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    h: &HistoryView,
    device: Option<&Device>,
    s: &Style,
) -> Drawn
where
    DB::ErrorType: 'static,
{
    let n = h.tau.len();
    if n < 2 {
        return Err(nothing("no time history"));
    }
    let p = &s.palette;
    let [x_name, v_name] = h.states.clone().unwrap_or(["λ_I".into(), "v".into()]);
    let (transient, steady): (Vec<usize>, Vec<usize>) = (0..n).partition(|&k| !h.steady[k]);
    // the steady part starts where the transient ends: join them
    let transient: Vec<usize> = transient
        .iter()
        .copied()
        .chain(steady.first().copied())
        .collect();
    let steady_color = match h.summary.and_then(|s| s.period_forcing_periods) {
        Some(k) => p.response_type(&format!("1:{k}")),
        None => p.series(0),
    };
    // the legend in a row above the panels: a record's oscillation fills every corner
    let legend_row = (s.text + s.text / 3 + s.pad) as i32;
    let (legend_area, panels) = area.split_vertically(legend_row);
    let width = area.dim_in_pixel().0;
    let (left, right) = panels.split_horizontally(width * 3 / 5);
    // a long record is drawn from a few forcing periods before its steady part on: the
    // steady orbit, as the paper's insets show it, and the end of the transient into it
    let (first, last) = (h.tau[0], h.tau[n - 1]);
    let from = match (h.summary, steady.first()) {
        (Some(sum), Some(&k)) if sum.omega > 0.0 => {
            let period = 2.0 * std::f64::consts::PI / sum.omega;
            let span = (last - h.tau[k]).max(TAIL_PERIODS * period);
            (last - span - TAIL_PERIODS * period).max(first)
        }
        _ => first,
    };
    // a written model's time is its own t, the built-in's the dimensionless τ
    let time = if h.states.is_some() { "t" } else { "τ" };
    let name = if from > first {
        format!(
            "time {time} (the last {:.0} of {:.0})",
            last - from,
            last - first
        )
    } else {
        format!("time {time}")
    };
    let mut tau = AxisSpec::new(name, from..last);
    if let Some(d) = device {
        tau = tau.with_physical("t (s)", |t| d.seconds(t));
    }
    let faint = RGBColor(
        ((p.muted.0 as u16 + p.background.0 as u16) / 2) as u8,
        ((p.muted.1 as u16 + p.background.1 as u16) / 2) as u8,
        ((p.muted.2 as u16 + p.background.2 as u16) / 2) as u8,
    );
    let shown = |idx: &[usize]| -> Vec<usize> {
        idx.iter().copied().filter(|&k| h.tau[k] >= from).collect()
    };
    let lines = [
        (shown(&transient), faint, 1),
        (shown(&steady), steady_color, s.line + 2),
    ];
    let in_window = || (0..n).filter(|&k| h.tau[k] >= from);
    let lambda_range = fit(in_window().map(|k| h.lambda[k]), 0.08);
    let mut chart = panel(
        &left,
        &tau,
        &AxisSpec::new(&x_name, lambda_range.clone()),
        s,
    )?;
    for (idx, color, width) in &lines {
        if idx.len() > 1 {
            chart.draw_series(std::iter::once(PathElement::new(
                series(idx, |k| (h.tau[k], h.lambda[k])),
                color.stroke_width(*width),
            )))?;
        }
    }
    let mut legend = Legend::new(s);
    legend.add(Swatch::Line(faint, false), "transient");
    let steady_text = match &h.summary {
        Some(sum) => {
            let period = sum
                .period_forcing_periods
                .map_or("no period".into(), |k| format!("1:{k}"));
            let hz = match (sum.period_forcing_periods, device) {
                (Some(k), Some(d)) => format!(" at {:.2} Hz", d.hz(sum.omega) / k as f64),
                _ => String::new(),
            };
            format!("steady {period}{hz}, A {:.4}", sum.amplitude)
        }
        None => "steady".into(),
    };
    legend.add(Swatch::Line(steady_color, false), steady_text);
    if let Some(tau) = h.collision {
        legend.add(
            Swatch::Line(p.response_type("collision"), false),
            format!("ended by a collision at {time} {tau:.4}"),
        );
    }
    // from the left of the plot: past its margin and the y labels
    legend.draw_row(&legend_area, (s.pad + s.text * 4) as i32)?;
    let mut phase = panel(
        &right,
        &AxisSpec::new(&x_name, lambda_range),
        &AxisSpec::new(&v_name, fit(in_window().map(|k| h.v[k]), 0.08)),
        s,
    )?;
    for (idx, color, _) in &lines {
        if idx.len() > 1 {
            phase.draw_series(std::iter::once(PathElement::new(
                series(idx, |k| (h.lambda[k], h.v[k])),
                // a closed orbit retraced over many periods, of many short segments: stroked
                // wider than one pixel, a bitmap draws it hollow and ragged
                color.stroke_width(1),
            )))?;
        }
    }
    Ok(())
}
