//! Continued branches: amplitude over the continuation parameter, stable arcs solid and
//! unstable arcs dashed, folds and period doublings marked; also drawn over a hunt's
//! frequency response.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{
    AxisSpec, Chart, Drawn, Legend, Marker, Polylines, Style, Swatch, Units, fit, nothing, panel,
};
use crate::session::results::{ContinuationView, ContinuedView};

/// What a branch of period `k` is, for its colour and legend: `1:k`.
fn branch_type(b: &ContinuedView) -> String {
    format!("1:{}", b.period)
}

/// The marker of a bifurcation kind: a fold a square, a period doubling a triangle, a
/// Neimark–Sacker point or a branch point a cross.
fn bifurcation_marker(kind: &str) -> Marker {
    match kind {
        "fold" => Marker::Square,
        "period-doubling" | "parent-period-doubling" => Marker::Triangle,
        _ => Marker::Cross,
    }
}

/// The branches as polylines (x the parameter, or ω_e if `by_omega`), where a legend must
/// not cover them.
pub(super) fn curves(branches: &[ContinuedView], by_omega: bool) -> Polylines {
    branches
        .iter()
        .map(|b| {
            b.points
                .iter()
                .map(|p| (if by_omega { p.omega } else { p.parameter }, p.amplitude))
                .collect()
        })
        .collect()
}

/// Draws `branches` on `chart` with x the continuation parameter (`by_omega`: ω_e instead),
/// and adds their entries to `legend`.
pub(super) fn overlay<DB: DrawingBackend>(
    chart: &mut Chart<DB>,
    branches: &[ContinuedView],
    by_omega: bool,
    legend: &mut Legend,
    s: &Style,
) -> Drawn
where
    DB::ErrorType: 'static,
{
    let x_of = |parameter: f64, omega: f64| if by_omega { omega } else { parameter };
    let mut kinds: Vec<&str> = Vec::new();
    let mut any_unstable = false;
    for b in branches {
        let color = s.palette.response_type(&branch_type(b));
        // runs of equal stability, each sharing its end point with the next
        let mut start = 0;
        while start + 1 < b.points.len() {
            let stable = b.points[start].stable;
            let mut end = start + 1;
            while end + 1 < b.points.len() && b.points[end].stable == stable {
                end += 1;
            }
            let run: Vec<(f64, f64)> = b.points[start..=end]
                .iter()
                .map(|p| (x_of(p.parameter, p.omega), p.amplitude))
                .collect();
            if stable {
                chart.draw_series(std::iter::once(PathElement::new(
                    run,
                    color.stroke_width(s.line + 1),
                )))?;
            } else {
                any_unstable = true;
                chart.draw_series(DashedLineSeries::new(
                    run,
                    (s.text / 2) as i32,
                    (s.text / 3) as i32,
                    color.stroke_width(s.line),
                ))?;
            }
            start = end;
        }
        for f in &b.bifurcations {
            if !kinds.contains(&f.kind.as_str()) {
                kinds.push(&f.kind);
            }
            chart.draw_series(std::iter::once(bifurcation_marker(&f.kind).element(
                (x_of(f.parameter, f.omega), f.amplitude),
                s.marker as i32 + 2,
                s.palette.text,
                false,
            )))?;
        }
    }
    let mut periods: Vec<usize> = branches.iter().map(|b| b.period).collect();
    periods.sort_unstable();
    periods.dedup();
    for k in periods {
        let verdicts: Vec<&str> = branches
            .iter()
            .filter(|b| b.period == k)
            .map(|b| b.verdict.as_str())
            .collect();
        legend.add(
            Swatch::Line(s.palette.response_type(&format!("1:{k}")), false),
            format!("1:{k} branch, stable ({})", verdicts.join(", ")),
        );
    }
    if any_unstable {
        legend.add(Swatch::Line(s.palette.muted, true), "unstable");
    }
    for kind in kinds {
        let name = match kind {
            "fold" => "fold",
            "period-doubling" => "period doubling",
            "parent-period-doubling" => "period doubling of the parent",
            "neimark-sacker" => "Neimark–Sacker",
            "branch-point" => "branch point",
            other => other,
        };
        legend.add(
            Swatch::Marker(bifurcation_marker(kind), s.palette.text, false),
            name,
        );
    }
    Ok(())
}

/// The figure of a continuation: every branch over the continuation parameter.
pub(super) fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    c: &ContinuationView,
    units: Units,
    s: &Style,
) -> Drawn
where
    DB::ErrorType: 'static,
{
    let points = || c.branches.iter().flat_map(|b| b.points.iter());
    if points().next().is_none() {
        return Err(nothing("no continued branch"));
    }
    let by_omega = c.parameter == "omega";
    let x_range = fit(points().map(|p| p.parameter), 0.04);
    let x = match by_omega {
        true => AxisSpec::omega(x_range, units),
        false => AxisSpec::new(c.parameter.clone(), x_range),
    };
    let top = points().map(|p| p.amplitude).fold(0.0f64, f64::max);
    let y = AxisSpec::amplitude((top * 1.15).max(1e-3), units);
    let mut chart = panel(area, &x, &y, s)?;
    let mut legend = Legend::new(s);
    overlay(&mut chart, &c.branches, false, &mut legend, s)?;
    legend.draw_clear_of(&chart, &curves(&c.branches, false))
}
