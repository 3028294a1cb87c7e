//! Basins of attraction (Fig 6): the grid of initial states as an image, a colour per
//! attractor, and a legend of each attractor's type, amplitude and share of the cells.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{AxisSpec, Drawn, Legend, Style, Swatch, Units, half_step, nothing, panel, short_type};
use crate::session::results::{AttractorRow, BasinView};

/// The colour of attractor `a`: its response type's, unless another attractor has the same
/// type (then a series colour of its own); collisions grey.
fn attractor_color(b: &BasinView, a: &AttractorRow, s: &Style) -> RGBColor {
    let short = short_type(&a.response_type);
    if short == "collision" {
        return s.palette.muted;
    }
    let same = b
        .attractors
        .iter()
        .filter(|o| short_type(&o.response_type) == short)
        .count();
    match same {
        1 => s.palette.response_type(&a.response_type),
        _ => s.palette.series(4 + a.id),
    }
}

pub(super) fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    b: &BasinView,
    units: Units,
    s: &Style,
) -> Drawn
where
    DB::ErrorType: 'static,
{
    let (n_dx, n_v) = (b.dx.len(), b.v.len());
    if n_dx == 0 || n_v == 0 || b.labels.iter().all(Option::is_none) {
        return Err(nothing("no cell of the basin computed"));
    }
    let (hx, hv) = (half_step(&b.dx), half_step(&b.v));
    let x_range = b.dx[0] - hx..b.dx[n_dx - 1] + hx;
    let v_range = b.v[0] - hv..b.v[n_v - 1] + hv;
    let (mut x, mut y) = match units.names {
        Some(names) => {
            let [x, v] = names.grid.clone().map(|n| format!("initial Δ{n}"));
            (AxisSpec::new(x, x_range), AxisSpec::new(v, v_range))
        }
        None => (
            AxisSpec::new("initial offset Δλ₀", x_range),
            AxisSpec::new("initial velocity v₀", v_range),
        ),
    };
    if let Some(d) = units.device {
        let (l1, seconds) = (d.l1, d.time_scale());
        x = x.with_physical("Δλ₀·L₁ (mm)", |dx| dx * l1 * 1e3);
        y = y.with_physical("velocity (m/s)", |v| v * l1 / seconds);
    }
    let colors: Vec<(usize, RGBColor)> = b
        .attractors
        .iter()
        .map(|a| (a.id, attractor_color(b, a, s)))
        .collect();
    let color_of = |id: usize| {
        colors
            .iter()
            .find(|(i, _)| *i == id)
            .map_or(s.palette.text, |(_, c)| *c)
    };
    // one rectangle per run of equal cells up a column: thousands, not tens of thousands
    let mut cells = Vec::new();
    for i in 0..n_dx {
        let column = &b.labels[i * n_v..(i + 1) * n_v];
        let mut start = 0;
        while start < n_v {
            let label = column[start];
            let mut end = start + 1;
            while end < n_v && column[end] == label {
                end += 1;
            }
            if let Some(id) = label {
                cells.push(Rectangle::new(
                    [
                        (b.dx[i] - hx, b.v[start] - hv),
                        (b.dx[i] + hx, b.v[end - 1] + hv),
                    ],
                    color_of(id).filled(),
                ));
            }
            start = end;
        }
    }
    let mut legend = Legend::new(s);
    for a in &b.attractors {
        let amplitude = a.amplitude.map_or(String::new(), |x| format!(", A {x:.3}"));
        legend.add(
            Swatch::Block(color_of(a.id)),
            format!(
                "{}{amplitude}: {:.1} %",
                short_type(&a.response_type),
                100.0 * a.fraction
            ),
        );
    }
    // the map takes what the legend leaves
    let (width, height) = area.dim_in_pixel();
    let legend_width = legend.width(area) + s.pad as i32;
    let (left, right) =
        area.split_horizontally(width.saturating_sub(legend_width as u32).max(height / 2));
    let mut chart = panel(&left, &x, &y, s)?;
    chart.draw_series(cells)?;
    let top = (s.text * 4) as i32;
    legend.draw(&right, (right.dim_in_pixel().0 as i32 - 2, top))
}
