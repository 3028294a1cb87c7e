//! Chirp sweeps (Fig 3): the envelope of the response over ω_e, with the sweep the other way
//! over the same range where the session has it, and, under them, the Morlet scalogram of
//! the sweep drawn as a heat map over (ω_e, response frequency) with its colour scale and
//! the 1:1 and 1:2 lines.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{AxisSpec, Drawn, Legend, Style, Swatch, Units, fit, nothing, number, panel};
use crate::analysis::AnalysisError;
use crate::analysis::orbit::chirp_sweep::ChirpSpec;
use crate::analysis::orbit::scalogram::{Scalogram, scalogram};
use crate::session::results::ChirpView;
use crate::session::{AnalysisEntry, Session, Settings};

/// Columns of the scalogram drawn at most (the rest would share pixels).
const MAX_COLUMNS: usize = 240;
/// Colour levels of the heat map (cells of one level up a column are drawn as one).
const LEVELS: f64 = 32.0;

/// The scalogram of a chirp's response by `entry`'s settings, as the workbench computes it.
pub fn chirp_scalogram(c: &ChirpView, entry: &AnalysisEntry) -> Result<Scalogram, AnalysisError> {
    scalogram(&c.lambda, c.dt, &entry.settings.scalogram_spec())
}

/// The chirp sweep of `session` over `entry`'s ω_e range the other way (its index), with the
/// same model and otherwise the same settings: Fig 3's backward sweep of a forward one, or
/// the forward one of a backward.
pub fn reverse_sweep(session: &Session, entry: &AnalysisEntry) -> Option<usize> {
    let Settings::ChirpSweep(spec) = &entry.settings else {
        return None;
    };
    session
        .analyses
        .iter()
        .position(|other| match &other.settings {
            Settings::ChirpSweep(o) => {
                other.model == entry.model
                    && other.values == entry.values
                    && o.omega_start != o.omega_end
                    && *o
                        == ChirpSpec {
                            omega_start: spec.omega_end,
                            omega_end: spec.omega_start,
                            ..spec.clone()
                        }
            }
            _ => false,
        })
}

/// Whether the sweep runs down in ω_e.
fn is_backward(c: &ChirpView) -> bool {
    matches!((c.omega.first(), c.omega.last()), (Some(a), Some(b)) if b < a)
}

/// `forward 0→6` or `backward 6→0`: the sweep's direction and its ω_e range.
fn direction(c: &ChirpView) -> String {
    let ends = match (c.omega.first(), c.omega.last()) {
        (Some(&a), Some(&b)) => format!(" {}→{}", number(a), number(b)),
        _ => String::new(),
    };
    let way = if is_backward(c) {
        "backward"
    } else {
        "forward"
    };
    format!("{way}{ends}")
}

pub(super) fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    c: &ChirpView,
    reverse: Option<&ChirpView>,
    scalogram: Option<&Scalogram>,
    units: Units,
    s: &Style,
) -> Drawn
where
    DB::ErrorType: 'static,
{
    if c.envelope.is_empty() {
        return Err(nothing("no envelope"));
    }
    // the sweep asked for drawn last, on top of its reverse
    let sweeps: Vec<&ChirpView> = reverse
        .filter(|r| !r.envelope.is_empty())
        .into_iter()
        .chain(std::iter::once(c))
        .collect();
    let height = area.dim_in_pixel().1;
    let (top, bottom) = match scalogram {
        Some(_) => {
            let (a, b) = area.split_vertically(height * 9 / 20);
            (a, Some(b))
        }
        None => (area.clone(), None),
    };
    let omega_range = fit(sweeps.iter().flat_map(|v| v.omega.iter().copied()), 0.0);
    let peak = sweeps
        .iter()
        .flat_map(|v| v.envelope.iter().map(|e| e[1]))
        .fold(0.0f64, f64::max);
    let mut chart = panel(
        &top,
        &AxisSpec::omega(omega_range.clone(), units),
        &AxisSpec::amplitude((peak * 1.15).max(1e-3), units),
        s,
    )?;
    // forward blue, backward orange, in either figure of the pair
    let color = |sweep: &ChirpView| s.palette.series(usize::from(is_backward(sweep)));
    let mut curves = Vec::new();
    for sweep in &sweeps {
        let points: Vec<(f64, f64)> = sweep.envelope.iter().map(|e| (e[0], e[1])).collect();
        chart.draw_series(std::iter::once(PathElement::new(
            points.clone(),
            color(sweep).stroke_width(s.line + 1),
        )))?;
        curves.push(points);
    }
    // the legend reads forward, backward whichever was asked for
    let mut legend = Legend::new(s);
    let mut ordered = sweeps.clone();
    ordered.sort_by_key(|v| is_backward(v));
    for sweep in ordered {
        legend.add(Swatch::Line(color(sweep), false), direction(sweep));
    }
    legend.draw_clear_of(&chart, &curves)?;
    if let (Some(area), Some(w)) = (bottom, scalogram) {
        draw_scalogram(&area, c, w, omega_range, units, s)?;
    }
    Ok(())
}

/// The scalogram over (ω_e, ω_r), magnitudes on a square-root scale so the weaker
/// subharmonic lines still show, with a colour bar on the right.
fn draw_scalogram<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    c: &ChirpView,
    w: &Scalogram,
    omega_range: std::ops::Range<f64>,
    units: Units,
    s: &Style,
) -> Drawn
where
    DB::ErrorType: 'static,
{
    let (nx, ny) = (w.times.len(), w.frequencies.len());
    let omega = units.omega();
    if nx == 0 || ny < 2 {
        return Err(nothing("an empty scalogram"));
    }
    let forcing = w.forcing(&c.omega);
    let peak = w
        .magnitude
        .iter()
        .flatten()
        .fold(0.0f64, |a, &b| a.max(b))
        .max(1e-30);
    let level =
        |iy: usize, ix: usize| ((w.magnitude[iy][ix] / peak).sqrt() * LEVELS).round() / LEVELS;
    let width = area.dim_in_pixel().0;
    let bar_width = s.text * 6;
    let (map_area, bar_area) = area.split_horizontally(width - bar_width);
    let (f0, f1) = (w.frequencies[0], w.frequencies[ny - 1]);
    let df = 0.5 * (f1 - f0) / (ny - 1) as f64;
    let mut chart = panel(
        &map_area,
        // without Hz: the envelope's axis above gives them
        &AxisSpec::omega(
            omega_range.clone(),
            Units {
                device: None,
                ..units
            },
        ),
        &AxisSpec::new("response frequency ωᵣ", f0 - df..f1 + df),
        s,
    )?;
    let stride = nx.div_ceil(MAX_COLUMNS).max(1);
    let mut cells = Vec::new();
    let columns: Vec<usize> = (0..nx).step_by(stride).collect();
    for (k, &ix) in columns.iter().enumerate() {
        let here = forcing[ix];
        let next = forcing[columns.get(k + 1).copied().unwrap_or(nx - 1)];
        let (x0, x1) = (here.min(next), here.max(next));
        let mut start = 0;
        while start < ny {
            let l = level(start, ix);
            let mut end = start + 1;
            while end < ny && level(end, ix) == l {
                end += 1;
            }
            cells.push(Rectangle::new(
                [
                    (x0, w.frequencies[start] - df),
                    (x1, w.frequencies[end - 1] + df),
                ],
                s.palette.ramp(l).filled(),
            ));
            start = end;
        }
    }
    chart.draw_series(cells)?;
    // where a 1:1 and a 1:2 response would show
    let white = s.palette.background;
    for (ratio, name) in [
        (1.0, format!("ωᵣ = {omega}")),
        (0.5, format!("ωᵣ = {omega}/2")),
    ] {
        let ends = [omega_range.start, omega_range.end].map(|x| (x, ratio * x));
        chart.draw_series(DashedLineSeries::new(
            ends,
            (s.text / 2) as i32,
            (s.text / 2) as i32,
            white.mix(0.8).stroke_width(1),
        ))?;
        // labelled near the right end, where the two lines are far apart
        let x = omega_range.start + 0.97 * (omega_range.end - omega_range.start);
        let y = (ratio * x).min(f1 - 2.0 * df);
        chart.draw_series(std::iter::once(Text::new(
            name,
            (x, y + df),
            s.note()
                .color(&white)
                .pos(Pos::new(HPos::Right, VPos::Bottom)),
        )))?;
    }
    colour_bar(&bar_area, s)
}

/// The heat map's colour scale: |W| over its peak, drawn on the square-root scale.
fn colour_bar<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, s: &Style) -> Drawn
where
    DB::ErrorType: 'static,
{
    let h = area.dim_in_pixel().1;
    let (top, bottom) = (
        (s.pad + s.text) as i32,
        h as i32 - (s.text * 3 + s.pad) as i32,
    );
    let (x0, x1) = (s.pad as i32, (s.pad + s.text) as i32);
    let steps = 64;
    for k in 0..steps {
        let y = |k: i32| bottom - (bottom - top) * k / steps;
        area.draw(&Rectangle::new(
            [(x0, y(k + 1)), (x1, y(k))],
            s.palette.ramp(k as f64 / (steps - 1) as f64).filled(),
        ))?;
    }
    area.draw(&Rectangle::new(
        [(x0, top), (x1, bottom)],
        s.palette.text.stroke_width(1),
    ))?;
    // labels at magnitudes 0, 0.25 and 1 (√ of them up the bar)
    for m in [0.0, 0.25, 1.0f64] {
        let y = bottom - ((bottom - top) as f64 * m.sqrt()) as i32;
        area.draw(&Text::new(
            number(m),
            (x1 + 4, y),
            s.note()
                .color(&s.palette.text)
                .pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
    }
    area.draw(&Text::new(
        "|W|/peak",
        (x0, top - 2),
        s.note().pos(Pos::new(HPos::Left, VPos::Bottom)),
    ))
    .map_err(Into::into)
}
