//! Draws the whole app: analyses and parameters on the left, the plot and the jobs on the
//! right, the status bar below; overlays on top. Below the minimum size, a message instead.

use ratatui::Frame;
use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph, Widget, Wrap};

use super::app::{App, Focus, Overlay};
use super::jobs::JobState;
use super::panes::{self, params::ParamsPane};
use super::plots::{self, PlotContext};
use isola::session::Settings;
use isola::session::budget;
use isola::session::results::{ResultStatus, ResultView};
use isola::session::store::survey::{HostWork, Survey};

/// The smallest terminal the layout is drawn in.
pub const MIN_WIDTH: u16 = 60;
pub const MIN_HEIGHT: u16 = 18;

pub fn draw(frame: &mut Frame, app: &App) {
    let area = frame.area();
    let buf = frame.buffer_mut();
    if area.width < MIN_WIDTH || area.height < MIN_HEIGHT {
        let mut text = format!(
            "isola needs a terminal of at least {MIN_WIDTH}×{MIN_HEIGHT}; this one is {}×{}.\nEnlarge it, or press q to quit.",
            area.width, area.height
        );
        // the one question that can be asked here must be seen
        if app.overlay == Some(Overlay::ConfirmQuit) {
            text.push_str("\n\nJobs are running or edits are unsaved. Quit? y / n");
        }
        Paragraph::new(text)
            .wrap(Wrap { trim: true })
            .style(app.theme.text())
            .render(area, buf);
        return;
    }
    let status_h = panes::status::height(app, area.width);
    let [body, status] =
        Layout::vertical([Constraint::Min(1), Constraint::Length(status_h)]).areas(area);
    let mut layout = super::mouse::Layout::default();
    if app.zoom {
        draw_plot(app, body, buf);
        layout.plot = body;
    } else {
        let left_w = (body.width * 2 / 5).clamp(28, 44);
        let [left, right] =
            Layout::horizontal([Constraint::Length(left_w), Constraint::Min(20)]).areas(body);
        let list_h = (app.session.analyses.len() as u16 + 2).clamp(3, (left.height / 3).max(3));
        let [list, params] =
            Layout::vertical([Constraint::Length(list_h), Constraint::Min(3)]).areas(left);
        let jobs_h = if right.height >= 30 { 7 } else { 5 };
        let [plot, jobs] =
            Layout::vertical([Constraint::Min(8), Constraint::Length(jobs_h)]).areas(right);
        panes::analyses::draw(app, list, buf);
        // the rows the filter lists, and the selected one among them
        let visible = app.visible_rows();
        let rows: Vec<&panes::params::Row> = visible.iter().map(|&i| &app.param_rows[i]).collect();
        let filtered = rows.len() < app.param_rows.len();
        let pane = ParamsPane {
            rows: &rows,
            selected: visible
                .iter()
                .position(|&i| i == app.param_row)
                .unwrap_or(usize::MAX),
            filter: filtered.then_some(app.filter.trim()),
            editing: app.editing.as_ref(),
            error: app.param_error.as_deref(),
            focused: app.focus == Focus::Params,
            theme: &app.theme,
        };
        layout.param_rows = pane
            .shown(params)
            .into_iter()
            .map(|r| r.and_then(|r| visible.get(r).copied()))
            .collect();
        pane.render(params, buf);
        draw_plot(app, plot, buf);
        panes::jobs::draw(app, jobs, buf);
        layout.analysis_rows = panes::analyses::shown(app, list);
        layout.job_rows = panes::jobs::shown(app, jobs);
        (layout.analyses, layout.params, layout.plot, layout.jobs) = (list, params, plot, jobs);
    }
    layout.frames = plots::frame::take_drawn();
    *app.layout.borrow_mut() = layout;
    panes::status::draw(app, status, buf);
    if let Some(overlay) = &app.overlay {
        panes::overlay::draw(app, overlay, body, buf);
    }
}

/// Work under way on an analysis, here or on other hosts, as the plot title says it, in
/// `width` cells: `40/99 chunks · computing on node1 (4), node2 (4) · 12/min, about 5 min
/// left`, or as much of it as fits (the parts after the count go first). `here`: a job of
/// this workbench computes it, which holds no chunk between chunks nor after the last (a
/// map's curves).
fn work_state(work: &Survey, width: usize, here: bool) -> String {
    let count = format!("{}/{} chunks", work.done.len(), work.chunks);
    let hosts = work.by_host(std::time::SystemTime::now());
    let busy: Vec<String> = hosts
        .iter()
        .filter(|h| h.claimed > 0)
        .map(|h| format!("{} ({})", h.host, h.claimed))
        .collect();
    if busy.is_empty() {
        let what = if here {
            "computing here"
        } else {
            "nothing computing"
        };
        return format!("{count} · {what}");
    }
    let mut candidates = Vec::new();
    let on = format!("{count} · computing on {}", busy.join(", "));
    let rate = HostWork::total_per_minute(&hosts);
    let left = work.seconds_left(&hosts).map(budget::duration);
    if let Some(left) = &left {
        candidates.push(format!("{on} · {rate:.0}/min, about {left} left"));
        candidates.push(format!("{on} · about {left} left"));
    }
    candidates.push(on);
    if let Some(left) = &left {
        candidates.push(format!("{count} · about {left} left"));
    }
    candidates.push(count);
    let fits = |s: &String| s.chars().count() <= width;
    let last = candidates.pop().expect("the count");
    candidates.into_iter().find(fits).unwrap_or(last)
}

/// The plot pane: the selected analysis' view, or the picked orbit.
fn draw_plot(app: &App, area: Rect, buf: &mut Buffer) {
    // only this plot's data areas are kept for the mouse
    let _ = plots::frame::take_drawn();
    let t = &app.theme;
    let entry = app.session.analyses.get(app.selected);
    let name = entry.map_or("", |e| e.name.as_str());
    let status = app.status_of(app.selected);
    let work = app.stored.get(app.selected).and_then(|s| s.work.as_deref());
    let state = match (status, work) {
        (ResultStatus::Complete, _) => "done".to_string(),
        // the title's room: the pane's width, less borders, spaces and the name
        (_, Some(work)) => work_state(
            work,
            (area.width as usize).saturating_sub(name.chars().count() + 8),
            app.active_job(name) == Some(&JobState::Running),
        ),
        (ResultStatus::Partial { done, total }, None) => format!("{done}/{total} chunks"),
        (ResultStatus::Stale, None) => "stale: model or settings changed".into(),
        (ResultStatus::Missing, None) => "not run".into(),
    };
    let title = match &app.picked {
        // what the orbit is (its type and amplitude) whole; where it came from cut to fit
        Some(p) => {
            let summary = p.summary.as_deref().unwrap_or("integrating…");
            let room = (area.width as usize).saturating_sub(summary.chars().count() + 7);
            format!(" {} · {summary} ", panes::ellipsis(&p.label, room))
        }
        None if app.frozen.is_some() => {
            let key = app.keymap.label(super::keymap::Action::Freeze);
            format!(" {name} · held ({key} resumes) · {state} ")
        }
        None => format!(" {name} · {state} "),
    };
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(t.border(app.focus == Focus::Plot))
        .title(Span::styled(
            title,
            if status == ResultStatus::Stale {
                t.warn()
            } else {
                t.text()
            },
        ));
    let inner = block.inner(area);
    block.render(area, buf);
    let device = app.session.device();
    let ctx = PlotContext {
        theme: t,
        device: app.session.written.is_none().then_some(&device),
        names: (app.session.written.as_ref()).map(|w| isola::figure::AxisNames::of(&w.model)),
        cursor: app.cursor,
        pickable: app.pick_blocked().is_none(),
    };
    if let Some(p) = &app.picked {
        match &p.view {
            Some(ResultView::History(h)) => plots::history::draw(
                h,
                Some(Line::styled("Esc: back to the plot", t.muted())),
                &PlotContext {
                    cursor: p.cursor,
                    ..ctx
                },
                inner,
                buf,
            ),
            _ => {
                Paragraph::new(Line::styled("integrating the orbit…", t.muted())).render(inner, buf)
            }
        }
        return;
    }
    let Some(view) = app.view() else {
        let run = app.keymap.label(super::keymap::Action::Run);
        let text = match app.stored.get(app.selected).and_then(|r| r.error.clone()) {
            Some(e) => Line::styled(e, t.error()),
            None => Line::styled(format!("no result yet: {run} runs {name}"), t.muted()),
        };
        Paragraph::new(text)
            .wrap(Wrap { trim: true })
            .render(inner, buf);
        return;
    };
    let lambda_p = entry
        .and_then(|e| app.session.params(Some(e)).ok())
        .map_or(1.0, |p| p.lambda_p());
    // the previous settings' complete result under a partial one until it completes, or a
    // compared analysis' result
    let underlay = app.underlay();
    let previous = underlay.as_ref().map(|(v, label)| (*v, label.as_str()));
    let with_previous = |mut plot: plots::frame::XyPlot| {
        if let Some((view, label)) = &underlay {
            plots::previous::beneath(&mut plot, view, label, t);
        }
        plot
    };
    match view {
        ResultView::Response(points) => {
            let range = match entry.map(|e| &e.settings) {
                Some(Settings::FrequencyResponse(s)) => (s.omega.min, s.omega.max),
                _ => (0.0, 6.0),
            };
            with_previous(plots::response::plot(points, &[], range, false, &ctx))
                .render(inner, buf);
        }
        ResultView::Hunt(h) => {
            let range = match entry.map(|e| &e.settings) {
                Some(Settings::Hunt(s)) => (s.response.omega.min, s.response.omega.max),
                _ => (0.0, 6.0),
            };
            with_previous(plots::response::plot(
                &h.responses,
                &h.continued,
                range,
                false,
                &ctx,
            ))
            .render(inner, buf);
        }
        ResultView::Continuation(c) => plots::continued::plot(c, &ctx).render(inner, buf),
        ResultView::Map(m) => {
            let previous = match previous {
                Some((ResultView::Map(p), label)) => Some((p, label)),
                _ => None,
            };
            plots::map::draw(m, previous, &ctx, inner, buf)
        }
        ResultView::Stepped(points) => {
            let (lo, hi) = points
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                    (a.min(p.omega), b.max(p.omega))
                });
            plots::response::plot(points, &[], (lo, hi), true, &ctx).render(inner, buf);
        }
        ResultView::Basin(b) => {
            let previous = match previous {
                Some((ResultView::Basin(p), label)) => Some((p, label)),
                _ => None,
            };
            plots::basin::draw(b, previous, lambda_p, &ctx, inner, buf)
        }
        ResultView::History(h) => plots::history::draw(h, None, &ctx, inner, buf),
        ResultView::Force(f) => plots::force::plot(f, &ctx).render(inner, buf),
        ResultView::Family(f) => with_previous(plots::family::plot(f, &ctx)).render(inner, buf),
        ResultView::Chirp(c) => {
            if app.show_scalogram {
                match app.scalogram(name, c) {
                    Some(s) => plots::sweep::scalogram(c, s, &ctx, inner, buf),
                    None => Paragraph::new(Line::styled("computing the scalogram…", t.muted()))
                        .render(inner, buf),
                }
            } else {
                let group = app.sweep_group();
                let sweeps: Vec<plots::sweep::Sweep> = group
                    .iter()
                    .filter_map(|(i, v)| match v {
                        ResultView::Chirp(c) => Some(plots::sweep::Sweep {
                            name: app.session.analyses[*i].name.as_str(),
                            view: c,
                            selected: *i == app.selected,
                        }),
                        _ => None,
                    })
                    .collect();
                plots::sweep::envelopes(&sweeps, &ctx).render(inner, buf);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With no chunk claimed, the title says whether this workbench computes the analysis:
    /// between chunks, and in a map's curves after its last row, no chunk is held.
    #[test]
    fn a_title_says_computing_here_while_a_job_here_holds_no_chunk() {
        let work = Survey {
            chunks: 23,
            ..Survey::default()
        };
        assert_eq!(work_state(&work, 80, true), "0/23 chunks · computing here");
        assert_eq!(
            work_state(&work, 80, false),
            "0/23 chunks · nothing computing"
        );
    }
}
