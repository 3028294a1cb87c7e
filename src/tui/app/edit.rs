//! Editing the session: parameters, `:` commands, analyses added and removed, undo and redo.

use std::sync::Arc;

use crossterm::event::{KeyCode, KeyEvent};
use isola::session::Session;
use isola::session::results::ResultStatus;
use isola::session::store::ResultPaths;

use super::{App, Confirmed, ExportRequest, Overlay};
use crate::tui::command::{self, Command};
use crate::tui::keymap::Action;
use crate::tui::panes::params::{self, Edit, Target};
use crate::tui::theme::Theme;
use crate::tui::undo::Version;

impl App {
    /// The session as it is now, to remember before an edit.
    pub(super) fn version(&self, what: String) -> Version {
        Version {
            text: self.session.to_text(),
            selected: self.selected,
            what,
        }
    }

    pub(super) fn undo(&mut self) {
        let now = self.version(String::new());
        match self.versions.undo(now) {
            Some(back) => self.go_to_version(back, "undid"),
            None => self.say("nothing to undo", false),
        }
    }

    pub(super) fn redo(&mut self) {
        let now = self.version(String::new());
        match self.versions.redo(now) {
            Some(forward) => self.go_to_version(forward, "redid"),
            None => self.say("nothing to redo", false),
        }
    }

    /// The session replaced by `version` (as text, comments and all), the view kept where it
    /// can be.
    fn go_to_version(&mut self, version: Version, did: &str) {
        match Session::parse(&self.session.path, &version.text) {
            Ok(session) => {
                self.session = session;
                self.selected = version.selected;
                self.modified = version.text != self.saved_text;
                self.reload_session_state();
                self.say(format!("{did} {}", version.what), false);
                self.bring_back_kept();
            }
            // a version is a text this session had: it parses, unless the schema changed
            Err(e) => self.say(format!("cannot {did}: {e}"), true),
        }
    }

    /// Runs a command line (`:`); what it did or why it could not goes to the status bar.
    pub fn execute(&mut self, line: &str) {
        let command = match command::parse(line) {
            Ok(c) => c,
            Err(e) => return self.say(e, true),
        };
        match command {
            Command::Run(which) => self.run_which(which),
            Command::Add { kind, name } => {
                let before = self.version(format!("add {kind} {name}"));
                let result = self.session.add_analysis(&kind, &name);
                self.after_structure_edit(result, before, format!("added {name} ({kind})"));
            }
            Command::Duplicate { name } | Command::Rename { name }
                if self.has_stored_result(&name) =>
            {
                self.say(
                    format!(
                        "{name} has a result on disk (in {}), which that would replace: give \
                         another name, or remove its files first",
                        self.session.results_dir().display()
                    ),
                    true,
                );
            }
            Command::Duplicate { name } => {
                let old = self.selected_name();
                let before = self.version(format!("dup {name}"));
                let result = self.session.duplicate_analysis(self.selected, &name);
                let carried = self.carry_result(result.is_ok(), &old, &name);
                self.after_structure_edit(result, before, format!("copied as {name}{carried}"));
            }
            Command::Rename { name } => {
                let (index, old) = (self.selected, self.selected_name());
                let before = self.version(format!("rename {old} to {name}"));
                let result = self.session.rename_analysis(index, &name).map(|()| index);
                let carried = self.carry_result(result.is_ok(), &old, &name);
                self.after_structure_edit(result, before, format!("renamed {name}{carried}"));
            }
            Command::Delete { name } => {
                let index = match &name {
                    Some(n) => self.session.analysis_index(n),
                    None => (!self.session.analyses.is_empty()).then_some(self.selected),
                };
                let Some(index) = index else {
                    return self.say(format!("no analysis {}", name.unwrap_or_default()), true);
                };
                let name = self.session.analyses[index].name.clone();
                self.overlay = Some(Overlay::Confirm {
                    question: format!("delete {name} from the session? (its results stay on disk)"),
                    then: Confirmed::Delete(index, name),
                });
            }
            Command::Set { field, value } => self.set_field(&field, &value, false),
            Command::Override { field, value } => self.set_field(&field, &value, true),
            Command::Select { name } => match self.session.analysis_index(&name) {
                Some(i) => self.select(i),
                None => self.say(format!("no analysis {name}"), true),
            },
            Command::Save(None) => self.save(None),
            Command::Save(Some(path)) => self.save_as_asking(path),
            Command::Open(path) => self.open_asking(path),
            Command::Reload => self.reload_asking(),
            Command::Export {
                path,
                table,
                filters,
            } => {
                let orbit = self.picked.as_ref().is_some_and(|p| p.history.is_some());
                if orbit || self.status_of(self.selected) == ResultStatus::Complete {
                    self.export_asking(ExportRequest {
                        path,
                        table,
                        filters,
                    });
                } else {
                    self.say("no complete result to export (r runs it)", true);
                }
            }
            Command::Goto { at, hz } => self.goto(at, hz),
            Command::Theme(name) => {
                let themes = crate::tui::config::config_dir().map(|d| d.join("themes"));
                match Theme::load(&name, self.theme.mode, themes.as_deref()) {
                    Ok(theme) => {
                        self.theme = theme;
                        self.say(format!("theme {name}"), false);
                    }
                    Err(e) => self.say(format!("{e:#}"), true),
                }
            }
            Command::Key(action) => self.act(action),
            Command::Compare(None) => {
                self.compare = None;
                self.say("comparison off", false);
            }
            Command::Compare(Some(name)) => match self.session.analysis_index(&name) {
                None => self.say(format!("no analysis {name}"), true),
                Some(i) if i == self.selected => self.say(
                    format!("{name} is the one shown: select another first"),
                    true,
                ),
                Some(_) => {
                    self.say(format!("{name} drawn muted under this plot"), false);
                    self.compare = Some(name);
                    self.poll_results(true);
                }
            },
            Command::Figure(path) => self.write_figure(Some(path)),
            Command::Help => self.open_help(),
            Command::Quit => self.act(Action::Quit),
        }
    }

    /// A name for a new analysis of `kind` no analysis has: `basin`, else `basin2`, ...
    pub(super) fn unused_name(&self, kind: &str) -> String {
        let short = kind.split('_').next().unwrap_or(kind);
        (1..)
            .map(|n| {
                if n == 1 {
                    short.to_string()
                } else {
                    format!("{short}{n}")
                }
            })
            .find(|name| self.session.analysis(name).is_none())
            .expect("some number is free")
    }

    fn selected_name(&self) -> String {
        self.session
            .analyses
            .get(self.selected)
            .map_or(String::new(), |e| e.name.clone())
    }

    /// Whether a result of an analysis named `name` is stored (complete, or the manifest
    /// of one): a copy or a rename onto that name would replace it.
    fn has_stored_result(&self, name: &str) -> bool {
        let paths = ResultPaths::in_dir(&self.session.results_dir(), name);
        paths.manifest.exists() || paths.csv.exists()
    }

    /// After a copy or a rename (if `done`): the stored result of analysis `from`, and the
    /// results kept for its earlier settings, copied as `to`'s, so the copy starts with them
    /// (and the session file on disk, which may still name `from`, keeps its own). Says what
    /// became of them, to end the status message.
    fn carry_result(&self, done: bool, from: &str, to: &str) -> String {
        if !done {
            return String::new();
        }
        let dir = self.session.results_dir();
        let (from, to) = (
            ResultPaths::in_dir(&dir, from),
            ResultPaths::in_dir(&dir, to),
        );
        let carried = isola::session::store::copy::carry(&from, &to);
        let kept = kept_words(carried.kept);
        match (carried.result, kept) {
            (Ok(true), None) => ", with its result".into(),
            (Ok(true), Some(kept)) => format!(", with its result and {kept}"),
            (Ok(false), None) => String::new(),
            (Ok(false), Some(kept)) => format!(", with {kept}"),
            (Err(e), kept) => {
                tracing::warn!(error = %format!("{e:#}"), "result not copied");
                let kept = kept.map_or(String::new(), |k| format!(", with {k}"));
                format!(" (its result not copied: {e:#}){kept}")
            }
        }
    }

    /// Selects analysis `i`, as moving to it in the list does.
    pub(super) fn select(&mut self, i: usize) {
        self.selected = i;
        self.frozen = None;
        self.param_error = None;
        self.refresh_rows();
        self.poll_results(true);
        self.reset_cursor();
        self.show_scalogram = false;
    }

    /// After an analysis was added, copied, renamed or deleted: the new session shown with
    /// analysis `Ok(index)` selected, or the error said and nothing changed.
    fn after_structure_edit(
        &mut self,
        result: Result<usize, isola::session::SessionError>,
        before: Version,
        done: String,
    ) {
        match result {
            Ok(index) => {
                self.versions.remember(before);
                self.modified = true;
                self.selected = index;
                self.reload_session_state();
                self.say(done, false);
            }
            Err(e) => self.say(params::error_line(&e), true),
        }
    }

    pub(super) fn delete_analysis(&mut self, index: usize, name: &str) {
        let before = self.version(format!("delete {name}"));
        let result = self
            .session
            .delete_analysis(index)
            .map(|()| index.min(self.session.analyses.len().saturating_sub(1)));
        self.after_structure_edit(result, before, format!("deleted {name}"));
    }

    /// `set FIELD VALUE` on the selected analysis: FIELD as the parameter pane labels it
    /// (`ADR`, `omega.points`, `c` for `c̃`) or as the session file writes it (`adr`, `omega`,
    /// `c_tilde`); a FIELD that is none of these is answered with the names it starts.
    fn set_field(&mut self, field: &str, value: &str, own: bool) {
        // a label as typed on a keyboard: `c` for `c̃` (its combining marks dropped)
        let plain = |label: &str| -> String {
            label
                .chars()
                .filter(|c| !('\u{300}'..='\u{36f}').contains(c))
                .collect()
        };
        let rows = &self.param_rows;
        let row = rows
            .iter()
            .position(|r| {
                r.label.eq_ignore_ascii_case(field)
                    || matches!(&r.target, Target::Model { key, .. } if key == field)
            })
            .or_else(|| {
                rows.iter()
                    .position(|r| plain(&r.label).eq_ignore_ascii_case(field))
            });
        let Some(row) = row else {
            // the model's fields whose names start as typed, by the file's name and the label
            let near: Vec<String> = rows
                .iter()
                .filter_map(|r| match &r.target {
                    Target::Model { key, .. }
                        if !field.is_empty()
                            && (key.starts_with(field) || plain(&r.label).starts_with(field)) =>
                    {
                        Some(format!("{key} ({})", r.label))
                    }
                    _ => None,
                })
                .collect();
            let hint = if near.is_empty() {
                "see the Parameters pane".to_string()
            } else {
                format!("did you mean {}?", near.join(", "))
            };
            return self.say(
                format!("{field}: not a parameter of this analysis ({hint})"),
                true,
            );
        };
        if own && !matches!(self.param_rows[row].target, Target::Model { .. }) {
            return self.say(
                format!("{field}: a setting is this analysis' own already: set it"),
                true,
            );
        }
        self.param_row = row;
        self.commit_edit_in(value, own);
        if let Some(e) = self.param_error.take() {
            self.say(e, true);
        }
    }

    pub(super) fn edit_key(&mut self, key: KeyEvent) {
        let Some(text) = self.editing.as_mut() else {
            return;
        };
        match key.code {
            KeyCode::Esc => {
                self.editing = None;
                self.param_error = None;
            }
            KeyCode::Enter => {
                let text = text.value().to_string();
                let unchanged = self
                    .param_rows
                    .get(self.param_row)
                    .is_some_and(|row| row.exact == text.trim());
                if unchanged {
                    self.editing = None;
                    self.param_error = None;
                } else {
                    self.commit_edit(&text);
                }
            }
            _ => {
                text.key(key);
            }
        }
    }

    /// Applies the typed value; on error the edit stays open with the reason shown.
    pub fn commit_edit(&mut self, text: &str) {
        self.commit_edit_in(text, false);
    }

    /// [`App::commit_edit`]; `own`: a model value goes into the selected analysis' own model
    /// table, not the session's.
    fn commit_edit_in(&mut self, text: &str, own: bool) {
        let Some(row) = self.param_rows.get(self.param_row).cloned() else {
            return;
        };
        let edit = match params::parse_edit(&row, text) {
            Ok(e) => e,
            Err(e) => {
                self.param_error = Some(e);
                return;
            }
        };
        let before = self.version(format!("{} = {}", row.label, text.trim()));
        let result = match edit {
            Edit::Model { key, value } if own => {
                self.session.override_model_key(self.selected, &key, value)
            }
            Edit::Model { key, value } => {
                self.session.set_model_key(Some(self.selected), &key, value)
            }
            Edit::Setting { path, value } => {
                let path: Vec<&str> = path.iter().map(String::as_str).collect();
                self.session.set_setting(self.selected, &path, value)
            }
        };
        match result {
            Ok(()) => {
                self.versions.remember(before);
                self.snapshot = Arc::new(self.session.clone());
                self.editing = None;
                self.param_error = None;
                self.modified = true;
                self.refresh_rows();
                self.poll_results(true);
                self.say(format!("{} = {}", row.label, text.trim()), false);
                self.bring_back_kept();
            }
            Err(e) => self.param_error = Some(params::error_line(&e)),
        }
    }
}

/// `2 results of earlier settings`, or none.
pub(super) fn kept_words(kept: usize) -> Option<String> {
    match kept {
        0 => None,
        1 => Some("1 result of earlier settings".into()),
        n => Some(format!("{n} results of earlier settings")),
    }
}
