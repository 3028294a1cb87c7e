//! The status bar: the keys of the focused pane, and the last message.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Widget};

use crate::tui::app::{App, Focus};
use crate::tui::keymap::Action;

pub fn draw(app: &App, area: Rect, buf: &mut Buffer) {
    let t = &app.theme;
    let k = |a: Action| app.keymap.label(a);
    let keys: Vec<(String, &str)> = if app.editing.is_some() {
        vec![("Enter".into(), "apply"), ("Esc".into(), "cancel")]
    } else {
        let mut v: Vec<(String, &str)> = match app.focus {
            Focus::Analyses => vec![("↑↓".into(), "select"), (k(Action::Run), "run")],
            Focus::Params => vec![
                ("↑↓".into(), "select"),
                (k(Action::Edit), "edit"),
                (k(Action::Run), "run"),
            ],
            Focus::Plot => vec![
                ("←→↑↓".into(), "cursor"),
                (k(Action::Edit), "orbit"),
                (k(Action::Zoom), "zoom"),
            ],
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
    let mut spans: Vec<Span> = Vec::new();
    for (key, what) in keys {
        spans.push(Span::styled(key, t.key()));
        spans.push(Span::raw(format!(" {what}  ")));
    }
    let keys_w: usize = spans.iter().map(|s| s.content.chars().count()).sum();
    let right = match &app.message {
        Some(m) => Span::styled(m.text.clone(), if m.error { t.error() } else { t.text() }),
        None => {
            let name = app
                .session
                .path
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
            Span::styled(
                format!("{name}{}", if app.modified { " [+]" } else { "" }),
                t.muted(),
            )
        }
    };
    let room = (area.width as usize).saturating_sub(keys_w);
    if right.content.chars().count() <= room {
        let pad = room - right.content.chars().count();
        spans.push(Span::raw(" ".repeat(pad)));
        spans.push(right);
        Paragraph::new(Line::from(spans)).render(area, buf);
    } else if app.message.is_some() {
        // a message matters more than the key list
        Paragraph::new(Line::from(right)).render(area, buf);
    } else {
        Paragraph::new(Line::from(spans)).render(area, buf);
    }
}
