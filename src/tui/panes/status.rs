//! The status bar: the keys of the focused pane, and the last message.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Widget};

use crate::tui::app::{App, Focus, InputPurpose, Overlay};
use crate::tui::keymap::Action;

/// Most lines the status bar takes for a long message.
const MAX_LINES: usize = 3;

/// The status bar's height at `width` cells: one line, or up to [`MAX_LINES`] for a message
/// too long for one.
pub fn height(app: &App, width: u16) -> u16 {
    let Some(m) = &app.message else {
        return 1;
    };
    let marker = if app.modified { 4 } else { 0 };
    let room = (width as usize).saturating_sub(marker);
    super::wrap(&m.text, room).len().clamp(1, MAX_LINES) as u16
}

pub fn draw(app: &App, area: Rect, buf: &mut Buffer) {
    let t = &app.theme;
    if let Some(Overlay::Input {
        purpose: InputPurpose::Filter,
        text,
    }) = &app.overlay
    {
        let line = Line::from(
            [
                vec![Span::styled("/", t.cursor())],
                text.spans(t.cursor(), t.selection()),
                vec![Span::styled(
                    "  lists what matches · Enter: keep · Esc: clear",
                    t.muted(),
                )],
            ]
            .concat(),
        );
        Paragraph::new(line).render(area, buf);
        return;
    }
    let k = |a: Action| app.keymap.label(a);
    let keys: Vec<(String, &str)> = if let Some(edit) = &app.editing {
        let mut keys = vec![("Enter".into(), "apply"), ("Esc".into(), "cancel")];
        if edit.is_selected() {
            keys.push(("type".into(), "to replace"));
            keys.push(("←→".into(), "to edit"));
        } else {
            keys.push(("Ctrl-U".into(), "clear"));
        }
        keys
    } else {
        let mut v: Vec<(String, &str)> = match app.focus {
            Focus::Analyses => vec![("↑↓".into(), "select"), (k(Action::Run), "run")],
            Focus::Params => vec![
                ("↑↓".into(), "select"),
                (k(Action::Edit), "edit"),
                (k(Action::Run), "run"),
            ],
            Focus::Plot => {
                let mut keys = vec![("←→↑↓".into(), "cursor")];
                // offered where the point under the cursor has an orbit to integrate
                if app.pick_blocked().is_none()
                    && app
                        .view()
                        .and_then(|v| crate::tui::plots::pick(v, app.cursor))
                        .is_some()
                {
                    keys.push((k(Action::Edit), "orbit"));
                }
                keys.push((k(Action::Zoom), "zoom"));
                keys
            }
            Focus::Jobs => vec![("↑↓".into(), "select"), (k(Action::CancelJob), "cancel")],
        };
        v.extend([
            (k(Action::FocusNext), "pane"),
            (k(Action::Save), "save"),
            (k(Action::Export), "export"),
            (k(Action::Help), "help"),
            (k(Action::Quit), "quit"),
        ]);
        v
    };
    let marker = if app.modified { " [+]" } else { "" };
    let width = area.width as usize;
    let hints = |keys: &[(String, &str)]| -> Vec<Span<'static>> {
        let mut spans = Vec::new();
        for (key, what) in keys {
            spans.push(Span::styled(key.clone(), t.key()));
            spans.push(Span::raw(format!(" {what}  ")));
        }
        spans
    };
    let cells = |spans: &[Span]| spans.iter().map(Span::width).sum::<usize>();
    let mut keys = keys;
    if let Some(m) = &app.message {
        let style = if m.error { t.error() } else { t.text() };
        let text = format!("{}{marker}", m.text);
        let spans = hints(&keys);
        if cells(&spans) + Span::raw(text.as_str()).width() <= width {
            let pad = width - cells(&spans) - Span::raw(text.as_str()).width();
            let mut line = spans;
            line.push(Span::raw(" ".repeat(pad)));
            line.push(Span::styled(m.text.clone(), style));
            line.push(Span::styled(marker, t.warn()));
            Paragraph::new(Line::from(line)).render(area, buf);
        } else {
            // a message matters more than the key list: on as many lines as the bar has
            // (`…` where they end before it), the unsaved marker after it
            let room = width.saturating_sub(marker.len());
            let mut lines = super::wrap(&m.text, room);
            let shown = (area.height as usize).max(1);
            if lines.len() > shown {
                lines.truncate(shown);
                let last = lines.pop().unwrap_or_default();
                lines.push(super::ellipsis(&format!("{last} …"), room));
            }
            let n = lines.len();
            let lines: Vec<Line> = lines
                .into_iter()
                .enumerate()
                .map(|(i, text)| {
                    let mut spans = vec![Span::styled(text, style)];
                    if i + 1 == n {
                        spans.push(Span::styled(format!(" {}", marker.trim_start()), t.warn()));
                    }
                    Line::from(spans)
                })
                .collect();
            Paragraph::new(lines).render(area, buf);
        }
        return;
    }
    let name = app
        .session
        .path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    // the key hints give way (the last before help and quit first) to the unsaved marker
    while app.modified && cells(&hints(&keys)) + marker.len() > width && keys.len() > 2 {
        keys.remove(keys.len() - 3);
    }
    let mut spans = hints(&keys);
    let room = width.saturating_sub(cells(&spans) + marker.len());
    // what the session is about, beside its name, where there is room
    let about = app.description();
    let name = if !about.is_empty() && Span::raw(name.as_str()).width() + 12 < room {
        let left = room - Span::raw(name.as_str()).width() - 3;
        format!("{} · {name}", super::ellipsis(&about, left))
    } else {
        name
    };
    let name_w = Span::raw(name.as_str()).width();
    let name = if name_w <= room {
        name
    } else if room >= 4 {
        let keep: Vec<char> = name.chars().rev().take(room - 1).collect();
        format!("…{}", keep.into_iter().rev().collect::<String>())
    } else {
        String::new()
    };
    let pad = width.saturating_sub(cells(&spans) + Span::raw(name.as_str()).width() + marker.len());
    spans.push(Span::raw(" ".repeat(pad)));
    spans.push(Span::styled(name, t.muted()));
    spans.push(Span::styled(marker, t.warn()));
    Paragraph::new(Line::from(spans)).render(area, buf);
}
