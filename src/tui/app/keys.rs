//! What each key does: the panes' keys, the plot cursor and the overlays' keys.

use std::path::Path;

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

use super::files::list_dir;
use super::{App, Confirmed, ExportRequest, Focus, InputPurpose, Overlay};
use crate::tui::command;
use crate::tui::filter;
use crate::tui::jobs::JobState;
use crate::tui::keymap::Action;
use crate::tui::line_edit::LineEdit;
use crate::tui::panes::params::Target;
use crate::tui::plots;

impl App {
    pub fn handle_key(&mut self, key: KeyEvent) {
        self.dirty = true;
        if key.code == KeyCode::Char('c') && key.modifiers.contains(KeyModifiers::CONTROL) {
            self.quit_now();
            self.exit_status = 130; // as a shell reports an interrupted program
            return;
        }
        if self.overlay.is_some() {
            self.overlay_key(key);
            return;
        }
        if self.editing.is_some() {
            self.edit_key(key);
            return;
        }
        let Some(action) = self.keymap.action(&key) else {
            return;
        };
        self.message = None;
        self.act(action);
    }

    pub(super) fn act(&mut self, action: Action) {
        match action {
            Action::Quit => {
                if self.jobs.any_active() || self.modified {
                    self.overlay = Some(Overlay::ConfirmQuit);
                } else {
                    self.should_quit = true;
                }
            }
            Action::Help => self.open_help(),
            // a zoomed plot is the only pane on screen: it keeps the keys
            Action::FocusNext if !self.zoom => self.focus = self.focus.step(1),
            Action::FocusPrev if !self.zoom => self.focus = self.focus.step(-1),
            Action::FocusNext | Action::FocusPrev => {}
            Action::Up => self.move_by(0, -1),
            Action::Down => self.move_by(0, 1),
            Action::Left => self.move_by(-1, 0),
            Action::Right => self.move_by(1, 0),
            Action::FastUp => self.move_by(0, -10),
            Action::FastDown => self.move_by(0, 10),
            Action::FastLeft => self.move_by(-10, 0),
            Action::FastRight => self.move_by(10, 0),
            Action::Edit => self.enter(),
            Action::Back => {
                if self.picked.take().is_none() {
                    self.set_zoom(false);
                }
            }
            Action::Run => self.run_selected(),
            Action::CancelJob => self.cancel_job(),
            Action::Save => self.save(None),
            Action::SaveAs => {
                self.overlay = Some(Overlay::Input {
                    purpose: InputPurpose::SaveAs,
                    text: LineEdit::new(self.session.path.display().to_string()),
                })
            }
            Action::Open => self.open_picker(),
            Action::Export => self.export_prompt(),
            Action::Zoom => self.set_zoom(!self.zoom),
            Action::Scalogram => self.toggle_scalogram(),
            Action::Command => {
                self.overlay = Some(Overlay::Input {
                    purpose: InputPurpose::Command,
                    text: LineEdit::default(),
                })
            }
            Action::Add => self.overlay = Some(Overlay::KindPicker { selected: 0 }),
            Action::Figure => self.write_figure(None),
            Action::Undo => self.undo(),
            Action::Redo => self.redo(),
            Action::Freeze => self.toggle_freeze(),
            Action::Filter => {
                self.overlay = Some(Overlay::Input {
                    purpose: InputPurpose::Filter,
                    text: LineEdit::new(self.filter.clone()),
                })
            }
        }
    }

    /// Moves the plot cursor (the picked orbit's, if one is shown) to the point nearest `at`
    /// (`hz`: the first coordinate is a frequency in Hz, converted to ω_e).
    pub(super) fn goto(&mut self, mut at: Vec<f64>, hz: bool) {
        if hz {
            at[0] = self.session.device().omega_from_hz(at[0]);
        }
        match self.place_cursor(&at) {
            Some(()) => self.focus = Focus::Plot,
            None => self.say("no point to go to on this plot", true),
        }
    }

    /// The plot cursor (the picked orbit's, if one is shown) on the point nearest `at`, in
    /// the view's coordinates; `None` if the view has no such point.
    pub(super) fn place_cursor(&mut self, at: &[f64]) -> Option<()> {
        match &mut self.picked {
            Some(p) => p.cursor = plots::cursor_near(p.view.as_ref()?, p.cursor, at)?,
            None => {
                self.cursor = plots::cursor_near(self.view()?, self.cursor, at)?;
                self.cursor_moved = true;
            }
        }
        Some(())
    }

    /// Holds the plot's view as it is (results keep coming in, the title says so), or lets it
    /// follow them again.
    fn toggle_freeze(&mut self) {
        if self.frozen.take().is_some() {
            self.say("plot follows the results again", false);
        } else if let Some(view) = self.stored.get(self.selected).and_then(|s| s.view.clone()) {
            self.frozen = Some(view);
            let key = self.keymap.label(Action::Freeze);
            self.say(format!("plot held: {key} resumes"), false);
        } else {
            self.say("nothing drawn to hold", true);
        }
    }

    /// After the filter changed: the selection moved onto what is listed.
    fn apply_filter(&mut self, text: String) {
        self.filter = text;
        let analyses = self.visible_analyses();
        if !analyses.contains(&self.selected)
            && let Some(&first) = analyses.first()
        {
            self.select(first);
        }
        let rows = self.visible_rows();
        if !rows.contains(&self.param_row)
            && let Some(&first) = rows.first()
        {
            self.param_row = first;
        }
    }

    /// Opens the help at its top.
    pub(super) fn open_help(&mut self) {
        self.help_scroll = 0;
        self.overlay = Some(Overlay::Help);
    }

    /// Zooms the plot to the whole window (it takes the keys) or back (the keys go back to the
    /// pane that had them).
    fn set_zoom(&mut self, on: bool) {
        if on == self.zoom {
            return;
        }
        if on {
            self.focus_before_zoom = Some(self.focus);
            self.focus = Focus::Plot;
        } else if let Some(focus) = self.focus_before_zoom.take() {
            self.focus = focus;
        }
        self.zoom = on;
    }

    pub(super) fn move_by(&mut self, dx: isize, dy: isize) {
        match self.focus {
            Focus::Analyses => {
                let visible = self.visible_analyses();
                if let Some(next) = filter::step(&visible, self.selected, dy.signum())
                    && next != self.selected
                {
                    self.select(next);
                }
            }
            Focus::Params => {
                let visible = self.visible_rows();
                if let Some(next) = filter::step(&visible, self.param_row, dy) {
                    self.param_row = next;
                    self.param_error = None;
                }
            }
            Focus::Plot => {
                // on a plot, ↑ means up the axis
                if let Some(p) = &mut self.picked {
                    if let Some(view) = &p.view {
                        p.cursor = plots::move_cursor(view, p.cursor, dx, -dy);
                    }
                } else if let Some(view) = self.view() {
                    self.cursor = plots::move_cursor(view, self.cursor, dx, -dy);
                    self.cursor_moved = true;
                }
            }
            Focus::Jobs => {
                let n = self.jobs.entries.len();
                if n > 0 && dy != 0 {
                    self.job_row = (self.job_row as isize + dy).clamp(0, n as isize - 1) as usize;
                }
            }
        }
    }

    /// Enter: edit the parameter, or pick the point under the cursor.
    fn enter(&mut self) {
        match self.focus {
            Focus::Params => {
                if let Some(row) = self.param_rows.get(self.param_row) {
                    if let Target::Derived(why) = row.target {
                        // nothing to type into: say what to edit instead
                        self.param_error = Some(format!("{}: {why}", row.label));
                    } else {
                        // every digit: Enter on it untouched changes nothing
                        self.editing = Some(LineEdit::replacing(row.exact.clone()));
                        self.param_error = None;
                    }
                }
            }
            Focus::Plot => self.pick(),
            Focus::Analyses => self.focus = Focus::Plot,
            // a failed job's whole error, which the pane and the status bar cut
            Focus::Jobs => {
                if let Some(entry) = self.jobs.entries.get(self.job_row)
                    && let JobState::Failed(why) = &entry.state
                {
                    self.overlay = Some(Overlay::Notice {
                        title: format!("{} failed", entry.label),
                        text: why.clone(),
                    });
                }
            }
        }
    }

    fn overlay_key(&mut self, key: KeyEvent) {
        let Some(overlay) = self.overlay.take() else {
            return;
        };
        // Tab's choices are shown until the next key
        self.tab_choices.clear();
        let action = self.keymap.action(&key);
        match overlay {
            Overlay::Help => {
                let scroll = match action {
                    Some(Action::Up) => Some(-1),
                    Some(Action::Down) => Some(1),
                    Some(Action::FastUp) => Some(-10),
                    Some(Action::FastDown) => Some(10),
                    _ => None,
                };
                if let Some(by) = scroll {
                    // the overlay clamps it to the last line it can show
                    self.help_scroll = self.help_scroll.saturating_add_signed(by).min(200);
                    self.overlay = Some(Overlay::Help);
                } else if !matches!(key.code, KeyCode::Esc | KeyCode::Enter | KeyCode::Char('q'))
                    && action != Some(Action::Help)
                {
                    self.overlay = Some(Overlay::Help);
                }
            }
            Overlay::ConfirmQuit => match key.code {
                KeyCode::Char('y') | KeyCode::Char('Y') => self.quit_now(),
                KeyCode::Char('n') | KeyCode::Esc => {}
                _ => self.overlay = Some(Overlay::ConfirmQuit),
            },
            Overlay::Input {
                purpose: InputPurpose::Filter,
                mut text,
            } => match key.code {
                KeyCode::Esc => self.apply_filter(String::new()),
                KeyCode::Enter => {}
                _ => {
                    if text.key(key) {
                        self.apply_filter(text.value().to_string());
                    }
                    self.overlay = Some(Overlay::Input {
                        purpose: InputPurpose::Filter,
                        text,
                    });
                }
            },
            Overlay::Input { purpose, mut text } => match key.code {
                KeyCode::Esc => {}
                KeyCode::Enter => {
                    let text = text.value();
                    let path = command::home_path(text.trim());
                    match purpose {
                        InputPurpose::SaveAs => self.save_as_asking(path),
                        InputPurpose::Export => self.export_asking(ExportRequest {
                            path,
                            table: None,
                            filters: Vec::new(),
                        }),
                        InputPurpose::Open => self.open_asking(path),
                        InputPurpose::Command => self.execute(text),
                        InputPurpose::Filter => {}
                        InputPurpose::NewName(kind) => {
                            let kind = isola::session::schema::KINDS[kind];
                            self.execute(&format!("add {kind} {}", text.trim()));
                        }
                    }
                }
                KeyCode::Tab
                    if matches!(
                        purpose,
                        InputPurpose::Command
                            | InputPurpose::Open
                            | InputPurpose::SaveAs
                            | InputPurpose::Export
                    ) =>
                {
                    // the word at the cursor is completed (whole, where the cursor is inside
                    // it), what follows it kept
                    let value = text.value().to_string();
                    let (before, after) = value.split_at(text.word_end());
                    let done = if purpose == InputPurpose::Command {
                        let names: Vec<String> = self
                            .session
                            .analyses
                            .iter()
                            .map(|a| a.name.clone())
                            .collect();
                        command::complete(before, &names, &list_dir)
                    } else {
                        command::complete_path(before, &list_dir)
                    };
                    if let Some(mut line) = done.line {
                        if line.ends_with(' ') && after.starts_with(' ') {
                            line.pop();
                        }
                        text = LineEdit::around(&line, after);
                    }
                    self.tab_choices = done.choices;
                    self.overlay = Some(Overlay::Input { purpose, text });
                }
                _ => {
                    text.key(key);
                    self.overlay = Some(Overlay::Input { purpose, text });
                }
            },
            Overlay::Picker {
                dir,
                files,
                about,
                selected,
            } => match (key.code, action) {
                (KeyCode::Esc, _) => {}
                (KeyCode::Enter, _) => match files.get(selected) {
                    // a folder: look in it (`..` kept short: the folder's own path)
                    Some(f) if f.is_dir() => {
                        let next = if f.ends_with("..") {
                            dir.canonicalize()
                                .ok()
                                .and_then(|d| d.parent().map(Path::to_path_buf))
                                .unwrap_or_else(|| f.clone())
                        } else {
                            f.clone()
                        };
                        self.open_picker_in(&next);
                    }
                    Some(f) => self.open_asking(f.clone()),
                    None => {}
                },
                (KeyCode::Char('/'), _) => {
                    self.overlay = Some(Overlay::Input {
                        purpose: InputPurpose::Open,
                        text: LineEdit::default(),
                    })
                }
                (_, Some(Action::Up | Action::Down)) => {
                    let selected = if action == Some(Action::Up) {
                        selected.saturating_sub(1)
                    } else {
                        (selected + 1).min(files.len().saturating_sub(1))
                    };
                    self.overlay = Some(Overlay::Picker {
                        dir,
                        files,
                        about,
                        selected,
                    })
                }
                _ => {
                    self.overlay = Some(Overlay::Picker {
                        dir,
                        files,
                        about,
                        selected,
                    })
                }
            },
            Overlay::KindPicker { selected } => match (key.code, action) {
                (KeyCode::Esc, _) => {}
                (KeyCode::Enter, _) => {
                    let kind = isola::session::schema::KINDS[selected];
                    self.overlay = Some(Overlay::Input {
                        purpose: InputPurpose::NewName(selected),
                        text: LineEdit::replacing(self.unused_name(kind)),
                    });
                }
                (_, Some(Action::Up)) => {
                    self.overlay = Some(Overlay::KindPicker {
                        selected: selected.saturating_sub(1),
                    })
                }
                (_, Some(Action::Down)) => {
                    let last = isola::session::schema::KINDS.len() - 1;
                    self.overlay = Some(Overlay::KindPicker {
                        selected: (selected + 1).min(last),
                    })
                }
                _ => self.overlay = Some(Overlay::KindPicker { selected }),
            },
            Overlay::Notice { .. } => {}
            Overlay::Confirm { question, then } => match key.code {
                KeyCode::Char('y') | KeyCode::Char('Y') => match then {
                    Confirmed::Open(path) => self.open(&path),
                    Confirmed::Reload => self.reload(),
                    Confirmed::SaveAs(path) => self.save_over(path),
                    Confirmed::Export(request) => self.export(&request),
                    Confirmed::Delete(index, name) => self.delete_analysis(index, &name),
                },
                KeyCode::Char('n') | KeyCode::Char('N') | KeyCode::Esc => {
                    self.say("nothing done", false)
                }
                _ => self.overlay = Some(Overlay::Confirm { question, then }),
            },
        }
    }
}
