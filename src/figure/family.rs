//! Families (Fig 7–12): each member's frequency response over ω_e, a colour per member and
//! a marker per response type, hidden responses outlined.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{
    AxisSpec, Drawn, Legend, Marker, Style, Swatch, Units, fit, nothing, panel, short_type,
};
use crate::session::results::FamilyView;

pub(super) fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    f: &FamilyView,
    units: Units,
    s: &Style,
) -> Drawn
where
    DB::ErrorType: 'static,
{
    let points = || f.members.iter().flat_map(|(_, pts)| pts.iter());
    if points().all(|p| p.amplitude.is_none()) {
        return Err(nothing("no periodic response in the family"));
    }
    let top = points().filter_map(|p| p.amplitude).fold(0.0f64, f64::max);
    let x = AxisSpec::omega(fit(points().map(|p| p.omega), 0.02), units);
    let mut chart = panel(area, &x, &AxisSpec::amplitude(top * 1.25, units), s)?;
    let mut legend = Legend::new(s);
    let r = s.marker as i32;
    let mut types: Vec<&str> = Vec::new();
    let mut any_hidden = false;
    for (i, (value, pts)) in f.members.iter().enumerate() {
        let color = s.palette.series(i);
        chart.draw_series(pts.iter().filter_map(|p| {
            let hidden = p.hidden == Some(true);
            any_hidden |= hidden;
            if !types.contains(&p.response_type.as_str()) && p.amplitude.is_some() {
                types.push(&p.response_type);
            }
            Some(Marker::of(&p.response_type).element((p.omega, p.amplitude?), r, color, !hidden))
        }))?;
        legend.add(Swatch::Block(color), format!("{} = {value}", f.parameter));
    }
    types.sort_by_key(|t| short_type(t).to_string());
    for t in types {
        legend.add(
            Swatch::Marker(Marker::of(t), s.palette.text, true),
            short_type(t),
        );
    }
    if any_hidden {
        legend.add(
            Swatch::Marker(Marker::Circle, s.palette.text, false),
            "hidden: no sweep reaches it",
        );
    }
    let markers: Vec<Vec<(f64, f64)>> = points()
        .filter_map(|p| Some(vec![(p.omega, p.amplitude?)]))
        .collect();
    legend.draw_clear_of(&chart, &markers)
}
