//! Two-parameter maps: a colour per number of coexisting stable responses over x (ω_e or a
//! parameter) and a model parameter, hidden responses marked, and the fold and
//! period-doubling curves over it with their turning points.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{AxisSpec, Drawn, Legend, Marker, Style, Swatch, Units, half_step, nothing, panel};
use crate::session::results::MapView;

pub(super) fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    m: &MapView,
    units: Units,
    s: &Style,
) -> Drawn
where
    DB::ErrorType: 'static,
{
    let (nx, ny) = (m.omegas.len(), m.values.len());
    if nx == 0 || ny == 0 || m.rows.iter().all(Option::is_none) {
        return Err(nothing("no row of the map computed"));
    }
    let (hx, hy) = (half_step(&m.omegas), half_step(&m.values));
    let x_range = m.omegas[0] - hx..m.omegas[nx - 1] + hx;
    let x = match m.x.as_str() {
        "omega" => AxisSpec::omega(x_range, units),
        name => AxisSpec::new(name, x_range),
    };
    let y = AxisSpec::new(m.parameter.clone(), m.values[0] - hy..m.values[ny - 1] + hy);
    let count_color = |n: usize| s.palette.ramp(n.min(3) as f64 / 3.0);
    let mut cells = Vec::new();
    let mut hidden = Vec::new();
    for (iy, row) in m.rows.iter().enumerate() {
        let Some(row) = row else { continue };
        for (ix, cell) in row.iter().enumerate() {
            let (cx, cy) = (m.omegas[ix], m.values[iy]);
            cells.push(Rectangle::new(
                [(cx - hx, cy - hy), (cx + hx, cy + hy)],
                count_color(cell.stable).filled(),
            ));
            if cell.hidden {
                hidden.push((cx, cy));
            }
        }
    }
    let mut legend = Legend::new(s);
    for n in 0..=3 {
        let text = match n {
            3 => "3 or more stable responses".to_string(),
            1 => "1 stable response".to_string(),
            n => format!("{n} stable responses"),
        };
        legend.add(Swatch::Block(count_color(n)), text);
    }
    if !hidden.is_empty() {
        legend.add(
            Swatch::Marker(Marker::Diamond, s.palette.text, false),
            "a hidden response",
        );
    }
    let mut kinds: Vec<&str> = Vec::new();
    for curve in &m.curves {
        if !kinds.contains(&curve.kind.as_str()) {
            kinds.push(&curve.kind);
            let name = match curve.kind.as_str() {
                "fold" => "fold curve",
                _ => "period-doubling curve",
            };
            legend.add(
                Swatch::Line(curve_color(&curve.kind, s), curve.kind != "fold"),
                name,
            );
        }
    }
    if m.curves.iter().any(|c| !c.extrema.is_empty()) {
        legend.add(
            Swatch::Marker(Marker::Square, s.palette.text, true),
            "turning point",
        );
    }
    // the map takes what the legend, beside it, leaves
    let (width, height) = area.dim_in_pixel();
    let legend_width = legend.width(area) + s.pad as i32;
    let (left, right) =
        area.split_horizontally(width.saturating_sub(legend_width as u32).max(height / 2));
    let mut chart = panel(&left, &x, &y, s)?;
    chart.draw_series(cells)?;
    let mark = s.palette.background;
    chart.draw_series(
        hidden
            .iter()
            .map(|&at| Marker::Diamond.element(at, s.marker as i32, mark, false)),
    )?;
    for curve in &m.curves {
        let color = curve_color(&curve.kind, s);
        let points: Vec<(f64, f64)> = curve.points.iter().map(|p| (p[0], p[1])).collect();
        if curve.kind == "fold" {
            chart.draw_series(std::iter::once(PathElement::new(
                points,
                color.stroke_width(s.line + 1),
            )))?;
        } else {
            chart.draw_series(DashedLineSeries::new(
                points,
                (s.text / 2) as i32,
                (s.text / 3) as i32,
                color.stroke_width(s.line + 1),
            ))?;
        }
        chart.draw_series(curve.extrema.iter().map(|(_, _, at)| {
            Marker::Square.element((at[0], at[1]), s.marker as i32 + 1, color, true)
        }))?;
    }
    legend.draw(
        &right,
        (right.dim_in_pixel().0 as i32 - 2, (s.text * 4) as i32),
    )
}

/// A fold curve in orange, a period-doubling curve in purple.
fn curve_color(kind: &str, s: &Style) -> RGBColor {
    match kind {
        "fold" => s.palette.series(1),
        _ => s.palette.series(3),
    }
}
