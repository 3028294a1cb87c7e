//! Frequency response (Fig 4/5), stepped sweeps and hunts: amplitude over ω_e, a marker and
//! colour per response type, hidden responses outlined, each subharmonic branch's ω_e range
//! annotated over it; a hunt's continued branches drawn over the responses.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{
    AxisSpec, Drawn, Legend, Marker, Style, Swatch, Units, continued, fit, nothing, panel,
};
use super::{Polylines, number, short_type};
use crate::session::results::{ContinuedView, ResponsePoint, branches};

/// Draws `points` (joined in sweep order if `joined`) over `omega_range` (or their own), with
/// a hunt's `continued` branches over them.
pub(super) fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    points: &[ResponsePoint],
    continued: &[ContinuedView],
    omega_range: Option<(f64, f64)>,
    joined: bool,
    units: Units,
    s: &Style,
) -> Drawn
where
    DB::ErrorType: 'static,
{
    if points.is_empty() {
        return Err(nothing("no response"));
    }
    let p = &s.palette;
    let x_range = match omega_range {
        Some((lo, hi)) if hi > lo => {
            let margin = 0.02 * (hi - lo);
            lo - margin..hi + margin
        }
        _ => fit(points.iter().map(|p| p.omega), 0.02),
    };
    let top = points
        .iter()
        .filter_map(|p| p.amplitude)
        .chain(
            continued
                .iter()
                .flat_map(|b| b.points.iter().map(|p| p.amplitude)),
        )
        .fold(0.0f64, f64::max);
    // headroom for the branch annotations and the legend
    let y = AxisSpec::amplitude((top * 1.4).max(1e-3), units);
    let mut chart = panel(area, &AxisSpec::omega(x_range, units), &y, s)?;
    if joined {
        let mut run: Vec<(f64, f64)> = Vec::new();
        for q in points.iter().map(|q| (q.omega, q.amplitude)) {
            match q {
                (w, Some(a)) => run.push((w, a)),
                _ => draw_run(&mut chart, &mut run, p.muted, s)?,
            }
        }
        draw_run(&mut chart, &mut run, p.muted, s)?;
    }
    // 1:1 first, so subharmonics are drawn over it
    let mut groups: Vec<(&str, bool)> = points
        .iter()
        .filter(|q| q.amplitude.is_some())
        .map(|q| (q.response_type.as_str(), q.hidden == Some(true)))
        .collect();
    groups.sort_by_key(|&(t, hidden)| (t != "1:1", hidden, t));
    groups.dedup();
    let r = s.marker as i32;
    for &(t, hidden) in &groups {
        let (marker, color) = (Marker::of(t), p.response_type(t));
        chart.draw_series(
            points
                .iter()
                .filter(|q| q.response_type == t && (q.hidden == Some(true)) == hidden)
                .filter_map(|q| Some((q.omega, q.amplitude?)))
                .map(|at| marker.element(at, r, color, !hidden)),
        )?;
    }
    let mut legend = Legend::new(s);
    let mut types: Vec<&str> = groups.iter().map(|&(t, _)| t).collect();
    types.sort_by_key(|t| short_type(t).to_string());
    types.dedup();
    for t in types {
        legend.add(
            Swatch::Marker(Marker::of(t), p.response_type(t), true),
            short_type(t),
        );
    }
    if let Some(&(t, _)) = groups.iter().find(|(_, hidden)| *hidden) {
        legend.add(
            Swatch::Marker(Marker::of(t), p.response_type(t), false),
            "hidden: no sweep reaches it",
        );
    }
    // responses without an amplitude (collisions, non-periodic) are counted, not drawn
    let mut without: Vec<(&str, usize)> = Vec::new();
    for q in points.iter().filter(|q| q.amplitude.is_none()) {
        match without.iter_mut().find(|(t, _)| *t == q.response_type) {
            Some((_, n)) => *n += 1,
            None => without.push((&q.response_type, 1)),
        }
    }
    let mut omegas: Vec<f64> = points.iter().map(|q| q.omega).collect();
    omegas.sort_by(f64::total_cmp);
    omegas.dedup();
    let of = omegas.len();
    let omega = units.omega();
    for (t, n) in without {
        legend.add(
            Swatch::None,
            format!("{}: some starts, at {n} of {of} {omega}", short_type(t)),
        );
    }
    // what the legend must not cover: every marker, and the brackets or the branches
    let mut data: Polylines = points
        .iter()
        .filter_map(|q| Some(vec![(q.omega, q.amplitude?)]))
        .collect();
    if continued.is_empty() {
        data.extend(annotate_branches(&mut chart, points, units, s)?);
    } else {
        continued::overlay(&mut chart, continued, true, &mut legend, s)?;
        data.extend(continued::curves(continued, true));
    }
    legend.draw_clear_of(&chart, &data)
}

/// Draws `run` as a line and empties it.
fn draw_run<DB: DrawingBackend>(
    chart: &mut super::Chart<DB>,
    run: &mut Vec<(f64, f64)>,
    color: RGBColor,
    s: &Style,
) -> Drawn
where
    DB::ErrorType: 'static,
{
    if run.len() > 1 {
        chart.draw_series(std::iter::once(PathElement::new(
            std::mem::take(run),
            color.stroke_width(s.line),
        )))?;
    }
    run.clear();
    Ok(())
}

/// A bracket over each subharmonic branch's ω_e range, above its peak, with its type, range
/// (and Hz) and whether a sweep reaches it; returns the brackets and the lines of their
/// texts' feet.
fn annotate_branches<DB: DrawingBackend>(
    chart: &mut super::Chart<DB>,
    points: &[ResponsePoint],
    units: Units,
    s: &Style,
) -> Result<Polylines, Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    let branches = branches(points);
    let omega = units.omega();
    let mut drawn = Vec::new();
    for b in branches
        .iter()
        .filter(|b| b.is_subharmonic() && b.omega_max > b.omega_min)
    {
        let color = s.palette.response_type(&b.response_type);
        let y = b.peak_amplitude * 1.12;
        let tick = b.peak_amplitude * 0.04;
        let bracket = vec![
            (b.omega_min, y - tick),
            (b.omega_min, y),
            (b.omega_max, y),
            (b.omega_max, y - tick),
        ];
        chart.draw_series(std::iter::once(PathElement::new(
            bracket.clone(),
            color.stroke_width(s.line),
        )))?;
        drawn.push(bracket);
        drawn.push(vec![(b.omega_min, y + tick), (b.omega_max, y + tick)]);
        let reach = if b.hidden {
            "hidden"
        } else if b.partly_hidden {
            "partly hidden"
        } else {
            "reached by a sweep"
        };
        let hz = units.device.map_or(String::new(), |d| {
            format!(
                " ({}–{} Hz)",
                number(d.hz(b.omega_min)),
                number(d.hz(b.omega_max))
            )
        });
        let text = format!(
            "{} {omega} {:.2}–{:.2}{hz}, {reach}",
            short_type(&b.response_type),
            b.omega_min,
            b.omega_max
        );
        chart.draw_series(std::iter::once(Text::new(
            text,
            (0.5 * (b.omega_min + b.omega_max), y + tick / 2.0),
            s.note()
                .color(&color)
                .pos(Pos::new(HPos::Center, VPos::Bottom)),
        )))?;
    }
    Ok(drawn)
}
