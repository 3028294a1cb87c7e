//! Parameter families (Fig 7–12): every member's frequency response overlaid, a colour per
//! member, and the subharmonic branches of the member under the cursor.

use ratatui::style::Style;
use ratatui::text::{Line, Span};

use super::frame::{Axis, Layer, XyPlot, legend_item};
use super::{PlotContext, PointCursor, response};
use isola::session::results::{FamilyView, branches};

pub fn plot(f: &FamilyView, ctx: &PlotContext) -> XyPlot {
    let theme = ctx.theme;
    let all = || f.members.iter().flat_map(|(_, pts)| pts.iter());
    let top = all().filter_map(|p| p.amplitude).fold(0.0f64, f64::max);
    let mut plot = XyPlot::new(
        Axis::fit(ctx.omega_axis(), all().map(|p| p.omega), 0.0),
        Axis::new(ctx.of_output("amplitude"), 0.0, (top * 1.1).max(0.01)),
    );
    plot.axis_style = theme.muted();
    plot.cursor_style = theme.cursor();
    let mut legend: Vec<Span> = vec![Span::raw(format!("{}: ", f.parameter))];
    for (i, (value, points)) in f.members.iter().enumerate() {
        let color = theme.series(i);
        plot.layers.push(Layer::Points {
            points: points
                .iter()
                .filter_map(|p| Some((p.omega, p.amplitude?)))
                .collect(),
            color,
        });
        legend.extend(legend_item(
            "■",
            Style::default().fg(color),
            &value.to_string(),
        ));
    }
    let cursor = PointCursor::tagged(
        f.members
            .iter()
            .flat_map(|(v, pts)| pts.iter().map(move |p| (Some(*v), p))),
    );
    if let Some(p) = cursor.point(ctx.cursor) {
        plot.cursor = p.amplitude.map(|a| (p.omega, a));
        let member = cursor.member(ctx.cursor).unwrap_or(f64::NAN);
        let mut line = response::readout(p, ctx);
        line.spans
            .insert(1, Span::raw(format!("{} {member}  ", f.parameter)));
        plot.footer.push(line);
        if let Some((_, points)) = f.members.iter().find(|(v, _)| *v == member) {
            let subharmonic: Vec<String> = branches(points)
                .iter()
                .filter(|b| b.is_subharmonic())
                .map(|b| b.describe())
                .collect();
            plot.footer.push(Line::styled(
                if subharmonic.is_empty() {
                    "no subharmonic branch".to_string()
                } else {
                    subharmonic.join("; ")
                },
                theme.text(),
            ));
        }
    }
    plot.footer.push(Line::from(legend));
    plot
}
