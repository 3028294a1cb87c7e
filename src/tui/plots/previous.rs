//! Another result drawn muted under the one shown: the complete result of the settings
//! before while the new one computes, or an analysis asked for with `:compare`, so that a
//! parameter change can be compared at a glance.

use ratatui::text::{Line, Span};

use super::frame::{Layer, XyPlot};
use crate::tui::theme::Theme;
use isola::session::results::{HuntView, ResponsePoint, ResultView};

/// The footer line that says what the muted points are.
pub fn legend(label: &str, theme: &Theme) -> Line<'static> {
    Line::from(vec![
        Span::styled("⣿", ratatui::style::Style::default().fg(theme.muted)),
        Span::styled(format!(" {label}"), theme.muted()),
    ])
}

/// The (ω, amplitude) points of a response-like view: a response, a stepped sweep, a hunt's
/// responses, every member of a family.
fn response_points(view: &ResultView) -> Option<Vec<&ResponsePoint>> {
    Some(match view {
        ResultView::Response(points)
        | ResultView::Stepped(points)
        | ResultView::Hunt(HuntView {
            responses: points, ..
        }) => points.iter().collect(),
        ResultView::Family(f) => f.members.iter().flat_map(|(_, p)| p.iter()).collect(),
        _ => return None,
    })
}

/// Draws `previous` (if it is a response-like view) in the muted colour under the layers of
/// `plot`, widening its amplitude axis to hold both; the legend calls it `label`.
pub fn beneath(plot: &mut XyPlot, previous: &ResultView, label: &str, theme: &Theme) {
    let Some(points) = response_points(previous) else {
        return;
    };
    let points: Vec<(f64, f64)> = points
        .iter()
        .filter_map(|p| Some((p.omega, p.amplitude?)))
        .collect();
    if points.is_empty() {
        return;
    }
    let top = points.iter().map(|p| p.1).fold(0.0f64, f64::max) * 1.1;
    if top > plot.y.max {
        plot.y.max = top;
    }
    plot.layers.insert(
        0,
        Layer::Points {
            points,
            color: theme.muted,
        },
    );
    // right after the readout: it says what half the points on the plot are
    let at = plot.footer.len().min(1);
    plot.footer.insert(at, legend(label, theme));
}

/// The footer line of a grid still computing: `done` of `total` `cells` so far, and, if
/// something shows faded in the rest (the previous settings' result, a coarse preview), what.
pub fn so_far(
    done: usize,
    total: usize,
    cells: &str,
    faded: Option<&str>,
    theme: &Theme,
) -> Line<'static> {
    let faded = faded.map_or(String::new(), |what| format!("; faded: {what}"));
    Line::styled(
        format!("{done} of {total} {cells} so far{faded}"),
        theme.muted(),
    )
}
