//! Running and queued jobs: a gauge, the rate, the time left; `c` cancels.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph, Widget};

use crate::tui::app::{App, Focus};
use crate::tui::jobs::JobState;

/// The width of a running job's readouts after its bar.
const TAIL_W: usize = 28;

/// `12.3k/s`.
fn rate_text(r: f64) -> String {
    if r >= 1e6 {
        format!("{:.1}M/s", r / 1e6)
    } else if r >= 1e3 {
        format!("{:.1}k/s", r / 1e3)
    } else {
        format!("{r:.0}/s")
    }
}

fn seconds_text(s: f64) -> String {
    if s >= 60.0 {
        format!("{}m{:02}s", (s / 60.0) as u64, (s % 60.0) as u64)
    } else {
        format!("{s:.1}s")
    }
}

/// The first job shown in `h` rows: newest at the bottom, the selected one in sight.
fn first_shown(app: &App, h: usize) -> usize {
    let n = app.jobs.entries.len();
    let skip = n.saturating_sub(h).min(app.job_row);
    if app.job_row >= skip + h {
        app.job_row + 1 - h
    } else {
        skip
    }
}

/// The job on each row of the pane drawn in `area`, top down.
pub fn shown(app: &App, area: Rect) -> Vec<usize> {
    let h = area.height.saturating_sub(2) as usize;
    let skip = first_shown(app, h);
    (skip..app.jobs.entries.len()).take(h).collect()
}

pub fn draw(app: &App, area: Rect, buf: &mut Buffer) {
    let t = &app.theme;
    let focused = app.focus == Focus::Jobs;
    let active = app.jobs.entries.iter().filter(|e| e.is_active()).count();
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(t.border(focused))
        .title(format!(" Jobs ({active} active) "));
    let inner = block.inner(area);
    block.render(area, buf);
    let w = inner.width as usize;
    let h = inner.height as usize;
    let skip = first_shown(app, h);
    let lines: Vec<Line> = app
        .jobs
        .entries
        .iter()
        .enumerate()
        .skip(skip)
        .take(h)
        .map(|(i, e)| {
            // a running job's label gives room to its gauge; another's takes what its
            // state leaves (a failed job's reason is cut first); `…` where it is cut
            let gauge_label_w = (w / 3).clamp(8, 24);
            let label_w = match &e.state {
                JobState::Running => gauge_label_w,
                JobState::Failed(_) => (w / 2).clamp(8, 40),
                state => w
                    .saturating_sub(state_text(state).chars().count() + 1)
                    .clamp(8.min(w), 72),
            }
            // padded no narrower than a running job's, so that the states line up
            .min(e.label.chars().count().max(gauge_label_w));
            let label = super::ellipsis(&e.label, label_w);
            let mut spans = vec![Span::raw(format!("{label:<label_w$} "))];
            match &e.state {
                JobState::Running if e.progress.in_open_phase() => {
                    // work of unknown length (continuation points): counted, no fraction
                    // as wide as a gauge's readouts, so the bar keeps its width between phases
                    let tail = format!(
                        "{:<TAIL_W$}",
                        format!(
                            " {:>6} points {:>9}",
                            e.progress.open_steps(),
                            e.step_rate().map_or(String::new(), rate_text),
                        )
                    );
                    let bar_w = w.saturating_sub(label_w + 1 + tail.chars().count()).max(4);
                    // a block that moves a cell per step: alive, and no percentage
                    let at = e.progress.open_steps() % bar_w;
                    spans.push(Span::styled("░".repeat(at), t.muted()));
                    spans.push(Span::styled("█", t.ok()));
                    spans.push(Span::styled("░".repeat(bar_w - at - 1), t.muted()));
                    spans.push(Span::raw(tail));
                }
                JobState::Running => {
                    let f = e.progress.fraction();
                    // the readouts padded to fixed widths, so the bar keeps its width
                    let tail = format!(
                        "{:<TAIL_W$}",
                        format!(
                            " {:>3.0}% {:>9} {:<12}",
                            f * 100.0,
                            e.rate().map_or(String::new(), rate_text),
                            e.eta()
                                .map_or(String::new(), |s| format!("eta {}", seconds_text(s)))
                        )
                    );
                    let bar_w = w.saturating_sub(label_w + 1 + tail.chars().count()).max(4);
                    let full = ((f * bar_w as f64) as usize).min(bar_w);
                    spans.push(Span::styled("█".repeat(full), t.ok()));
                    spans.push(Span::styled("░".repeat(bar_w - full), t.muted()));
                    spans.push(Span::raw(tail));
                }
                state => {
                    let style = match state {
                        JobState::Done { .. } => t.ok(),
                        JobState::Cancelled => t.warn(),
                        JobState::Failed(_) => t.error(),
                        _ => t.muted(),
                    };
                    spans.push(Span::styled(state_text(state), style));
                }
            }
            let mut line = Line::from(spans);
            if focused && i == app.job_row {
                line = line.style(t.selected());
            }
            line
        })
        .collect();
    if lines.is_empty() {
        let run = app.keymap.label(crate::tui::keymap::Action::Run);
        Paragraph::new(Line::styled(
            format!("no jobs: {run} runs the selected analysis"),
            t.muted(),
        ))
        .render(inner, buf);
    } else {
        Paragraph::new(lines).render(inner, buf);
    }
}

/// What a job not running says of itself.
fn state_text(state: &JobState) -> String {
    match state {
        JobState::Queued => "queued".into(),
        JobState::Done { seconds } => format!("✓ done in {}", seconds_text(*seconds)),
        JobState::Cancelled => "✗ cancelled".into(),
        JobState::Failed(why) => format!("✗ {why}"),
        JobState::Running => String::new(),
    }
}
