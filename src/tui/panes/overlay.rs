//! Boxes over the panes: help, the quit question, a path to type, session files to open.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph, Widget, Wrap};

use crate::tui::app::{App, InputPurpose, Overlay};
use crate::tui::command::{COMMANDS, KIND_ABOUT};
use crate::tui::config;
use crate::tui::keymap::Action;
use crate::tui::panes::ellipsis;

/// The help's width with one column of keys (its notes wrap to it).
const HELP_WIDTH: u16 = 74;

/// A line of a list to choose from: a name, then what it is, muted; highlighted if selected.
fn choice(name: String, about: String, selected: bool, app: &App) -> Line<'static> {
    let line = Line::from(vec![
        Span::raw(name),
        Span::styled(about, app.theme.muted()),
    ]);
    if selected {
        line.style(app.theme.selected())
    } else {
        line
    }
}

/// What Tab found to fit, in at most `width` cells (`+N` for those left out); `None` if
/// nothing or one thing did.
fn tab_choices(choices: &[String], width: usize) -> Option<String> {
    if choices.len() < 2 {
        return None;
    }
    let mut line = String::from("Tab:");
    for (i, choice) in choices.iter().enumerate() {
        let more = format!("  +{}", choices.len() - i);
        let room = if i + 1 == choices.len() {
            0
        } else {
            more.chars().count()
        };
        if line.chars().count() + 2 + choice.chars().count() + room > width {
            line.push_str(&more);
            break;
        }
        line.push_str("  ");
        line.push_str(choice);
    }
    Some(line)
}

/// A box of `w × h` centred in `area` (clipped to it).
fn centred(area: Rect, w: u16, h: u16) -> Rect {
    let (w, h) = (w.min(area.width), h.min(area.height));
    Rect::new(
        area.x + (area.width - w) / 2,
        area.y + (area.height - h) / 2,
        w,
        h,
    )
}

pub fn draw(app: &App, overlay: &Overlay, area: Rect, buf: &mut Buffer) {
    let t = &app.theme;
    // the filter is typed on the status bar, over the lists it filters
    if let Overlay::Input {
        purpose: InputPurpose::Filter,
        ..
    } = overlay
    {
        return;
    }
    let (title, lines, w): (String, Vec<Line>, u16) = match overlay {
        Overlay::Help => {
            // every key with its command name (`:zoom` does what z does) and what it does;
            // two columns where they fit, else one, scrolled
            // the columns as wide as their longest key, name and words (a word cut or
            // wrapped into the other column is no help)
            let widest = |cells: fn(&(Action, &str, &str)) -> usize| {
                Action::ALL.iter().map(cells).max().unwrap_or(0)
            };
            let key_w = Action::ALL
                .iter()
                .map(|(a, _, _)| Span::raw(app.keymap.labels(*a)).width())
                .max()
                .unwrap_or(0)
                .max(8);
            let name_w = widest(|(_, name, _)| name.chars().count());
            let what_w = widest(|(_, _, what)| what.chars().count());
            let entry = |i: usize| -> Vec<Span> {
                Action::ALL.get(i).map_or_else(Vec::new, |(a, name, what)| {
                    vec![
                        Span::styled(format!("{:>key_w$}", app.keymap.labels(*a)), t.key()),
                        Span::styled(format!(" :{name:<name_w$}"), t.muted()),
                        Span::raw(format!(" {what:<what_w$} ")),
                    ]
                })
            };
            let entry_w = key_w + name_w + what_w + 5;
            let two_w = (2 * entry_w + 2) as u16;
            let two = area.width >= two_w;
            let mut lines: Vec<Line> = if two {
                let half = Action::ALL.len().div_ceil(2);
                (0..half)
                    .map(|i| Line::from([entry(i), entry(i + half)].concat()))
                    .collect()
            } else {
                (0..Action::ALL.len())
                    .map(|i| Line::from(entry(i)))
                    .collect()
            };
            lines.push(Line::from(vec![
                Span::styled(format!("{:>8}", "C-c"), t.key()),
                Span::raw(" quit at once (jobs cancelled, finished chunks kept)"),
            ]));
            lines.push(Line::styled(
                "commands (: then Tab completes; a key's :name above works too)",
                t.muted(),
            ));
            for (verb, args, what) in COMMANDS {
                let pad = 30usize.saturating_sub(verb.len() + args.len() + 2);
                lines.push(Line::from(vec![
                    Span::styled(format!(" :{verb}"), t.key()),
                    Span::raw(format!(" {args}{}", " ".repeat(pad))),
                    Span::styled(format!(" {what}"), t.muted()),
                ]));
            }
            lines.push(Line::styled(
                "plots: a filled glyph is reached by a sweep, an outlined one (○ ◇ △ □) is hidden; \
                 'collision': starts that left the model (a frame, a locking stretch or a written \
                 condition met), not drawn",
                t.muted(),
            ));
            lines.push(Line::styled(
                "marks: ✓ done  ◐ partial  ~ stale (model changed)  · not run",
                t.muted(),
            ));
            lines.push(Line::styled(
                format!(
                    "keys: [keys] in {}",
                    config::config_dir().map_or("(no home)".into(), |d| d
                        .join("config.toml")
                        .display()
                        .to_string())
                ),
                t.muted(),
            ));
            lines.push(Line::styled(
                format!("log: {}", config::log_path().display()),
                t.muted(),
            ));
            lines.push(Line::styled(
                format!("theme: {} (--theme, --color)", t.name),
                t.muted(),
            ));
            let w = if two {
                two_w.max(HELP_WIDTH)
            } else {
                HELP_WIDTH
            };
            (" Help (↑↓ scroll, Esc closes) ".into(), lines, w)
        }
        Overlay::ConfirmQuit => {
            let active = app.jobs.entries.iter().filter(|e| e.is_active()).count();
            let mut lines = Vec::new();
            if active > 0 {
                lines.push(Line::raw(format!(
                    "{active} job(s) running: quitting cancels them (finished chunks are kept)."
                )));
            }
            if app.modified {
                lines.push(Line::raw("The session has unsaved changes."));
            }
            lines.push(Line::styled("Quit? y / n", t.key()));
            (" Quit ".into(), lines, 60)
        }
        Overlay::Notice { title, text } => {
            let mut lines: Vec<Line> = text.lines().map(|l| Line::raw(l.to_string())).collect();
            lines.push(Line::styled("any key closes", t.muted()));
            (format!(" {title} "), lines, 76)
        }
        Overlay::KindPicker { selected } => {
            let w = area.width.min(84);
            let room = (w as usize).saturating_sub(2 + 20);
            let mut lines: Vec<Line> = KIND_ABOUT
                .iter()
                .enumerate()
                .map(|(i, (kind, about))| {
                    choice(
                        format!("{kind:<19} "),
                        ellipsis(about, room),
                        i == *selected,
                        app,
                    )
                })
                .collect();
            lines.push(Line::styled(
                "Enter: name it (settings at their defaults)   Esc: cancel",
                t.muted(),
            ));
            (" Add an analysis ".into(), lines, w)
        }
        Overlay::Confirm { question, .. } => {
            let lines = vec![
                Line::raw(question.clone()),
                Line::styled("y: yes   n / Esc: no", t.key()),
            ];
            (" Confirm ".into(), lines, 64)
        }
        Overlay::Input {
            purpose: InputPurpose::Command,
            text,
        } => {
            // what the command being typed takes and does
            let verb = text.value().split_whitespace().next().unwrap_or("");
            let hint = tab_choices(&app.tab_choices, 70).unwrap_or_else(|| {
                COMMANDS.iter().find(|(v, _, _)| *v == verb).map_or_else(
                    || {
                        "Tab: complete   Enter: run   Esc: cancel   (help lists the commands)"
                            .into()
                    },
                    |(v, args, what)| format!("{v} {args}: {what}"),
                )
            });
            let lines = vec![
                Line::from(
                    [
                        vec![Span::styled(":", t.cursor())],
                        text.spans(t.cursor(), t.selection()),
                    ]
                    .concat(),
                ),
                Line::styled(hint, t.muted()),
            ];
            (" Command ".into(), lines, 72)
        }
        Overlay::Input { purpose, text } => {
            let what = match purpose {
                InputPurpose::SaveAs => "Save session as:",
                InputPurpose::Export => "Export result to CSV file:",
                InputPurpose::NewName(_) => "Name of the new analysis:",
                InputPurpose::Open | InputPurpose::Command | InputPurpose::Filter => {
                    "Open session file:"
                }
            };
            let lines = vec![
                Line::raw(what),
                Line::from(text.spans(t.cursor(), t.selection())),
                Line::styled(
                    tab_choices(&app.tab_choices, 62).unwrap_or_else(|| {
                        match (purpose, text.is_selected()) {
                            (InputPurpose::NewName(_), true) => {
                                "Enter: ok   Esc: cancel   typing replaces it, ← → edit it"
                            }
                            (InputPurpose::NewName(_), false) => {
                                "Enter: ok   Esc: cancel   Ctrl-U: clear"
                            }
                            (_, true) => {
                                "Enter: ok   Esc: cancel   Tab: complete   typing replaces it"
                            }
                            (_, false) => "Enter: ok   Esc: cancel   Tab: complete   Ctrl-U: clear",
                        }
                        .into()
                    }),
                    t.muted(),
                ),
            ];
            (" ".into(), lines, 64)
        }
        Overlay::Picker {
            dir,
            files,
            about,
            selected,
        } => {
            let w = area.width.min(100);
            let inner = w.saturating_sub(2) as usize;
            let name_of = |f: &std::path::Path| {
                if f.ends_with("..") {
                    return "../".to_string();
                }
                let name = f
                    .file_name()
                    .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
                if f.is_dir() { format!("{name}/") } else { name }
            };
            let name_w = files
                .iter()
                .map(|f| name_of(f).chars().count())
                .max()
                .unwrap_or(0)
                .min(inner / 2);
            // a line per entry: its name and the start of what it is about
            let mut lines: Vec<Line> = files
                .iter()
                .zip(about)
                .enumerate()
                .map(|(i, (f, about))| {
                    let name: String = name_of(f).chars().take(name_w).collect();
                    let room = inner.saturating_sub(name_w + 2);
                    choice(
                        format!("{name:<name_w$}  "),
                        ellipsis(about, room),
                        i == *selected,
                        app,
                    )
                })
                .collect();
            // the selected session's whole description below the list
            if let Some(text) = about
                .get(*selected)
                .filter(|a| *a != "folder" && !a.is_empty())
            {
                lines.push(Line::raw(""));
                lines.push(Line::styled(text.clone(), t.text()));
            }
            lines.push(Line::styled(
                "Enter: open (a folder: look in it)   /: type a path   Esc: cancel",
                t.muted(),
            ));
            (format!(" Open session · {} ", dir.display()), lines, w)
        }
    };
    // rows after wrapping, so the last line (the question, the keys) is never cut off
    let inner_w = w.min(area.width).saturating_sub(2).max(1) as usize;
    let rows: usize = lines
        .iter()
        .map(|l| l.width().max(1).div_ceil(inner_w))
        .sum();
    let h = (rows as u16 + 2).min(area.height);
    let rect = centred(area, w, h);
    Clear.render(rect, buf);
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(t.border(true))
        .title(title);
    // keep the selected file visible in a long list
    let inner_h = rect.height.saturating_sub(2) as usize;
    let scroll = match overlay {
        Overlay::Picker {
            selected, files, ..
        } => {
            // the rows under the list (the selected file's description, the keys) stay
            let after = rows.saturating_sub(files.len());
            (selected + 1).saturating_sub(inner_h.saturating_sub(after)) as u16
        }
        // as far down as asked, but never past the last line
        Overlay::Help => app.help_scroll.min(rows.saturating_sub(inner_h) as u16),
        _ => 0,
    };
    Paragraph::new(lines)
        .block(block)
        .wrap(Wrap { trim: false })
        .scroll((scroll, 0))
        .render(rect, buf);
}
