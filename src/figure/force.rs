//! Static force curves (Fig 2): the net force f_II − f_I over Δλ, one curve per pre-stretch
//! and voltage.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{AxisSpec, Drawn, Legend, Style, Swatch, fit, nothing, panel};
use crate::model::Device;
use crate::session::results::ForceView;

pub(super) fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    f: &ForceView,
    device: Option<&Device>,
    s: &Style,
) -> Drawn
where
    DB::ErrorType: 'static,
{
    let points = || f.curves.iter().flat_map(|c| c.2.iter());
    if points().next().is_none() {
        return Err(nothing("no force curve"));
    }
    let mut x = AxisSpec::new("offset Δλ", fit(points().map(|p| p[0]), 0.02));
    if let Some(d) = device {
        x = x.with_physical("Δλ·L₁ (mm)", |dx| dx * d.l1 * 1e3);
    }
    let y = AxisSpec::new("net force f_II − f_I", fit(points().map(|p| p[1]), 0.08));
    let mut chart = panel(area, &x, &y, s)?;
    // the zero of force: where a curve crosses it is an equilibrium
    let span = x.range.clone();
    chart.draw_series(std::iter::once(PathElement::new(
        vec![(span.start, 0.0), (span.end, 0.0)],
        s.palette.muted.stroke_width(1),
    )))?;
    let mut legend = Legend::new(s);
    for (i, (lambda_p, phi_i, curve)) in f.curves.iter().enumerate() {
        let color = s.palette.series(i);
        chart.draw_series(std::iter::once(PathElement::new(
            curve.iter().map(|p| (p[0], p[1])).collect::<Vec<_>>(),
            color.stroke_width(s.line + 1),
        )))?;
        legend.add(
            Swatch::Line(color, false),
            format!("λ_p {lambda_p}, φ_I {phi_i}"),
        );
    }
    let curves: Vec<Vec<(f64, f64)>> = f
        .curves
        .iter()
        .map(|c| c.2.iter().map(|p| (p[0], p[1])).collect())
        .collect();
    legend.draw_clear_of(&chart, &curves)
}
