//! The session's analyses, each with the state of its stored result.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph, Widget};

use crate::tui::app::{App, Focus};
use isola::session::results::ResultStatus;

/// A mark for a result's state: complete, partial, stale, or none.
pub fn status_mark(status: ResultStatus) -> (&'static str, &'static str) {
    match status {
        ResultStatus::Complete => ("✓", "done"),
        ResultStatus::Partial { .. } => ("◐", "partial"),
        ResultStatus::Stale => ("~", "stale"),
        ResultStatus::Missing => ("·", "not run"),
    }
}

/// The analysis on each row of the pane drawn in `area`, top down.
pub fn shown(app: &App, area: Rect) -> Vec<usize> {
    let h = area.height.saturating_sub(2) as usize;
    let visible = app.visible_analyses();
    let at = visible.iter().position(|&i| i == app.selected).unwrap_or(0);
    let skip = (at + 1).saturating_sub(h);
    visible.into_iter().skip(skip).take(h).collect()
}

pub fn draw(app: &App, area: Rect, buf: &mut Buffer) {
    let t = &app.theme;
    let focused = app.focus == Focus::Analyses;
    let inner = Block::default().borders(Borders::ALL).inner(area);
    let h = inner.height as usize;
    let visible = app.visible_analyses();
    let n = visible.len();
    let at = visible.iter().position(|&i| i == app.selected).unwrap_or(0);
    let skip = (at + 1).saturating_sub(h);
    let (above, below) = (skip, n.saturating_sub(skip + h));
    // what is out of sight is counted on the borders
    let mut block = Block::default()
        .borders(Borders::ALL)
        .border_style(t.border(focused))
        .title(if n < app.session.analyses.len() {
            format!(" Analyses /{} ", app.filter.trim())
        } else {
            " Analyses ".to_string()
        });
    if above > 0 {
        block = block.title(Line::styled(format!(" ↑ {above} more "), t.muted()).right_aligned());
    }
    if below > 0 {
        block = block
            .title_bottom(Line::styled(format!(" ↓ {below} more "), t.muted()).right_aligned());
    }
    block.render(area, buf);
    let lines: Vec<Line> = visible
        .iter()
        .map(|&i| (i, &app.session.analyses[i]))
        .skip(skip)
        .take(h)
        .map(|(i, a)| {
            let status = app.status_of(i);
            let (mark, _) = status_mark(status);
            let style = match status {
                ResultStatus::Complete => t.ok(),
                ResultStatus::Stale => t.warn(),
                _ => t.muted(),
            };
            let mut line = Line::from(vec![
                Span::styled(format!("{mark} "), style),
                Span::raw(a.name.clone()),
                Span::styled(
                    format!(" {}", a.settings.kind().replace('_', " ")),
                    t.muted(),
                ),
            ]);
            if i == app.selected {
                line = line.style(if focused {
                    t.selected()
                } else {
                    t.selected().add_modifier(ratatui::style::Modifier::DIM)
                });
            }
            line
        })
        .collect();
    Paragraph::new(lines).render(inner, buf);
}
