//! The session file and what is written beside it: reload on change, save, export, figures
//! and the file picker.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use isola::figure;
use isola::session::Session;
use isola::session::output::{Protected, check_target};
use isola::session::results::ResultStatus;
use isola::session::store::ResultPaths;

use super::{App, Confirmed, ExportRequest, InputPurpose, Overlay};
use crate::tui::command;
use crate::tui::line_edit::LineEdit;

impl App {
    /// Notices, once a second, an edit of the session file made outside the workbench (an
    /// editor, git): with no unsaved edits here it is loaded (`u` undoes that); with some,
    /// it is said with what to do, and `s` asks before replacing it.
    pub(super) fn watch_session_file(&mut self) {
        if self.last_disk_check.elapsed() >= Duration::from_secs(1) {
            self.last_disk_check = Instant::now();
            self.notice_session_file();
        }
    }

    /// `:reload`: the session file as on disk, asking first over unsaved edits.
    pub(super) fn reload_asking(&mut self) {
        if self.modified {
            self.overlay = Some(Overlay::Confirm {
                question: format!(
                    "drop the unsaved edits and load {} as it is on disk?",
                    file_name(&self.session.path)
                ),
                then: Confirmed::Reload,
            });
        } else {
            self.reload();
        }
    }

    /// Loads the session file as it is on disk now.
    pub(super) fn reload(&mut self) {
        self.disk_seen = disk_stamp(&self.session.path);
        match std::fs::read_to_string(&self.session.path) {
            Ok(text) if text == self.session.to_text() => {
                self.modified = text != self.saved_text;
                self.say(
                    format!("{} is as on disk", file_name(&self.session.path)),
                    false,
                );
            }
            Ok(text) => self.load_disk_text(text),
            Err(e) => self.say(
                format!("{} not reloaded: {e}", self.session.path.display()),
                true,
            ),
        }
    }

    /// The session replaced by `text`, its file's as now on disk: an undoable change, the
    /// selected analysis kept where it still is; a text that does not load is said, and the
    /// session shown stays.
    pub(super) fn load_disk_text(&mut self, text: String) {
        let name = file_name(&self.session.path);
        match Session::parse(&self.session.path, &text) {
            Ok(session) => {
                let before = self.version(format!("the reload of {name}"));
                let selected = self
                    .session
                    .analyses
                    .get(self.selected)
                    .map(|e| e.name.clone());
                self.session = session;
                self.versions.remember(before);
                self.selected = selected
                    .and_then(|n| self.session.analyses.iter().position(|e| e.name == n))
                    .unwrap_or(0);
                self.saved_text = self.session.to_text();
                self.modified = false;
                self.editing = None;
                self.reload_session_state();
                self.say(
                    format!("reloaded {name}: it changed on disk (u undoes)"),
                    false,
                );
                self.bring_back_kept();
            }
            Err(e) => self.say(
                format!(
                    "{name} changed on disk but does not load ({e}); s asks before replacing it"
                ),
                true,
            ),
        }
    }

    /// Saves the session (as `path`), asking first if its own file changed on disk since it
    /// was opened or saved (another editor's changes would be lost).
    pub(super) fn save(&mut self, path: Option<PathBuf>) {
        let path = path.unwrap_or_else(|| self.session.path.clone());
        let on_disk = std::fs::read_to_string(&path).ok();
        if same_file(&path, &self.session.path) && on_disk.is_some_and(|t| t != self.saved_text) {
            self.overlay = Some(Overlay::Confirm {
                question: format!(
                    "{} changed on disk since it was opened or saved: replace it with this \
                     session, losing those changes? (n: :save FILE writes elsewhere)",
                    path.display()
                ),
                then: Confirmed::SaveAs(path),
            });
            return;
        }
        self.save_over(path);
    }

    /// Writes the session to `path`, whatever is there.
    pub(super) fn save_over(&mut self, path: PathBuf) {
        let old_dir = self.session.results_dir();
        match self.session.save_as(&path) {
            Ok(()) => {
                self.modified = false;
                self.saved_text = self.session.to_text();
                self.disk_seen = disk_stamp(&self.session.path);
                let carried = self.carry_results(&old_dir);
                self.reload_session_state();
                self.say(format!("saved {}{carried}", path.display()), false);
            }
            Err(e) => self.say(format!("not saved: {e}"), true),
        }
    }

    /// After saving as another file: the stored results in `old_dir` copied into the new
    /// session's results folder, so nothing computed is left behind. Says how many.
    fn carry_results(&self, old_dir: &Path) -> String {
        let new_dir = self.session.results_dir();
        if same_file(old_dir, &new_dir) || !old_dir.is_dir() {
            return String::new();
        }
        let (mut copied, mut failed, mut kept) = (0, Vec::new(), 0);
        for entry in &self.session.analyses {
            let from = ResultPaths::in_dir(old_dir, &entry.name);
            let to = ResultPaths::in_dir(&new_dir, &entry.name);
            let carried = isola::session::store::copy::carry(&from, &to);
            kept += carried.kept;
            match carried.result {
                Ok(true) => copied += 1,
                Ok(false) => {}
                Err(e) => {
                    tracing::warn!(error = %format!("{e:#}"), "result not copied");
                    failed.push(entry.name.clone());
                }
            }
        }
        let results = |n: usize| format!("{n} result{}", if n == 1 { "" } else { "s" });
        match (copied, failed.is_empty(), super::edit::kept_words(kept)) {
            (0, true, None) => String::new(),
            (0, true, Some(kept)) => format!(" with {kept}"),
            (n, true, None) => format!(" with {}", results(n)),
            (n, true, Some(kept)) => format!(" with {} and {kept}", results(n)),
            (n, false, _) => format!(
                " with {n} result(s); not copied (see the log): {}",
                failed.join(", ")
            ),
        }
    }

    pub(super) fn export_prompt(&mut self) {
        if let Some(p) = self.picked.as_ref().filter(|p| p.history.is_some()) {
            let path = self.beside_session(&p.label, "csv");
            self.overlay = Some(Overlay::Input {
                purpose: InputPurpose::Export,
                text: LineEdit::new(path.display().to_string()),
            });
            return;
        }
        let Some(entry) = self.session.analyses.get(self.selected) else {
            return;
        };
        if self.status_of(self.selected) != ResultStatus::Complete {
            self.say(
                format!("{}: no complete result to export (r runs it)", entry.name),
                true,
            );
            return;
        }
        let path = self.beside_session(&entry.name, "csv");
        self.overlay = Some(Overlay::Input {
            purpose: InputPurpose::Export,
            text: LineEdit::new(path.display().to_string()),
        });
    }

    /// `SESSION-TITLE.EXTENSION` beside the session file (the title's characters other than
    /// letters, digits and dots as `_`): where a figure or an export goes unless told.
    fn beside_session(&self, title: &str, extension: &str) -> PathBuf {
        let stem = self
            .session
            .path
            .file_stem()
            .map_or("session".into(), |s| s.to_string_lossy().into_owned());
        let name: String = title
            .chars()
            .map(|c| {
                if c.is_alphanumeric() || c == '.' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        self.session
            .path
            .with_file_name(format!("{stem}-{name}.{extension}"))
    }

    /// Writes what `request` asks for, atomically: the picked orbit's time history, the
    /// selected result's rows passing its filters, or the whole result (CSV, and a basin's
    /// attractor table beside it).
    pub fn export(&mut self, request: &ExportRequest) {
        let to = &request.path;
        let protected = Protected::session(&self.session.path, &self.session.results_dir());
        let result: anyhow::Result<String> =
            if let Some(history) = self.picked.as_ref().and_then(|p| p.history.as_deref()) {
                if request.table.is_some() || !request.filters.is_empty() {
                    Err(anyhow::anyhow!(
                        "an orbit is written whole: Esc closes it to export the analysis"
                    ))
                } else {
                    (history.csv_bytes(&self.session.device()))
                        .and_then(|bytes| Ok(check_target(to, &protected)?.write(&bytes)?))
                        .map(|()| format!("exported the orbit to {}", to.display()))
                }
            } else if request.table.is_some() || !request.filters.is_empty() {
                let Some(entry) = self.session.analyses.get(self.selected) else {
                    return;
                };
                isola::session::select::export_selection(
                    &self.session,
                    entry,
                    request.table.as_deref(),
                    &request.filters,
                    to,
                )
                .map(|rows| format!("exported {rows} rows to {}", to.display()))
                .map_err(anyhow::Error::from)
            } else {
                self.export_whole(to, &protected)
                    .map(|()| format!("exported {}", to.display()))
            };
        match result {
            Ok(done) => self.say(done, false),
            Err(e) => self.say(format!("export failed: {e:#}"), true),
        }
    }

    /// Writes the view shown (the picked orbit, else the selected result) as a figure: to
    /// `path`, SVG, PNG or PDF by its extension, or to `SESSION-NAME.svg` beside the session.
    pub(super) fn write_figure(&mut self, path: Option<PathBuf>) {
        let Some(entry) = self.session.analyses.get(self.selected) else {
            return;
        };
        let picked = self
            .picked
            .as_ref()
            .and_then(|p| Some((p.view.as_ref()?, &p.label)));
        // a figure is of a current result, as `isola figure` draws it: never of a stale or
        // partial one shown while its settings are computed
        let current = self.status_of(self.selected) == ResultStatus::Complete;
        // the stored result itself: a held plot (`f`) may show other settings'
        let shown = current
            .then(|| self.stored.get(self.selected)?.view.as_deref())
            .flatten();
        let Some((view, title)) = picked.or_else(|| Some((shown?, &entry.name))) else {
            let run = self.keymap.label(crate::tui::keymap::Action::Run);
            let what = match self.view() {
                Some(_) => "no current result to draw (the one shown is not complete or stale)",
                None => "no result to draw",
            };
            self.say(format!("{}: {what}; {run} runs it", entry.name), true);
            return;
        };
        let reverse = figure::reverse_sweep(&self.session, entry);
        let reverse_current = reverse.is_none_or(|i| self.status_of(i) == ResultStatus::Complete);
        if picked.is_none() && !reverse_current {
            let name = reverse.map_or("", |i| self.session.analyses[i].name.as_str());
            self.say(
                format!(
                    "{}: its reverse sweep {name} is not current; run it to draw both",
                    entry.name
                ),
                true,
            );
            return;
        }
        let path = path.unwrap_or_else(|| self.beside_session(title, "svg"));
        let written = (|| -> anyhow::Result<()> {
            let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("");
            let format: figure::Format = extension.parse()?;
            let reverse = reverse.and_then(|i| self.stored.get(i)?.view.as_deref());
            let mut subject = figure::Subject::of(
                &self.session,
                entry,
                view,
                self.scalogram_of_view(entry, view),
            )
            .with_reverse(reverse);
            subject.title = title.clone();
            let options = figure::Options {
                format,
                ..figure::Options::default()
            };
            let bytes = figure::render(&subject, &options)?;
            let protected = Protected::session(&self.session.path, &self.session.results_dir());
            Ok(check_target(&path, &protected)?.write(&bytes)?)
        })();
        match written {
            Ok(()) => self.say(format!("wrote the figure to {}", path.display()), false),
            Err(e) => self.say(format!("figure {}: {e:#}", path.display()), true),
        }
    }

    /// Copies the selected result's CSV (and a basin's attractor table) to `to`.
    fn export_whole(&self, to: &Path, protected: &Protected) -> anyhow::Result<()> {
        let Some(entry) = self.session.analyses.get(self.selected) else {
            anyhow::bail!("no analysis selected");
        };
        let paths = ResultPaths::new(&self.session, &entry.name);
        let fingerprint = self.session.fingerprint(entry);
        let copy = |from: &Path, to: &Path| -> anyhow::Result<()> {
            let target = check_target(to, protected)?;
            let bytes = std::fs::read(from)?;
            target.write(&bytes)?;
            Ok(())
        };
        // copied under the store's read lock, from a verified result of the current settings
        isola::session::store::with_verified(&paths, |m| {
            if m.fingerprint != fingerprint {
                anyhow::bail!("the stored result is of other settings");
            }
            copy(&paths.csv, to)?;
            let table = paths.csv.with_extension("attractors.csv");
            if m.files
                .iter()
                .any(|f| Some(f.name.as_str()) == table.file_name().and_then(|n| n.to_str()))
            {
                copy(&table, &to.with_extension("attractors.csv"))?;
            }
            Ok(())
        })
        .map_err(anyhow::Error::from)
        .and_then(|r| r)
    }

    pub(super) fn open_picker(&mut self) {
        let dir = self
            .session
            .path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        self.open_picker_in(&dir);
    }

    /// Lists the session files of `dir` (with what each is about) and its folders, to open
    /// one or look in another.
    pub fn open_picker_in(&mut self, dir: &Path) {
        let entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default();
        let hidden = |p: &Path| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with('.'))
        };
        // folders to browse (not a session's results), then the sessions
        let mut folders: Vec<PathBuf> = entries
            .iter()
            .filter(|p| p.is_dir() && !hidden(p) && p.extension().is_none_or(|x| x != "results"))
            .cloned()
            .collect();
        let mut sessions: Vec<PathBuf> = entries
            .into_iter()
            .filter(|p| p.is_file() && p.extension().is_some_and(|x| x == "toml"))
            .collect();
        folders.sort();
        sessions.sort();
        let parent = dir.join("..");
        let mut files = vec![parent];
        files.extend(folders);
        let first_session = files.len();
        files.extend(sessions);
        let about = files
            .iter()
            .enumerate()
            .map(|(i, f)| {
                if i < first_session {
                    return "folder".to_string();
                }
                // the leading comment is in the first few kB
                let mut head = Vec::new();
                if let Ok(file) = std::fs::File::open(f) {
                    use std::io::Read;
                    let _ = file.take(8192).read_to_end(&mut head);
                }
                isola::session::schema::description(&String::from_utf8_lossy(&head))
            })
            .collect();
        // the session open, however its path was written (`x.toml` is `./x.toml` here)
        let selected = files
            .iter()
            .position(|f| same_file(f, &self.session.path))
            .unwrap_or(first_session.min(files.len() - 1));
        self.overlay = Some(Overlay::Picker {
            dir: dir.to_path_buf(),
            files,
            about,
            selected,
        });
    }

    /// Opens a session in place of this one.
    pub fn open(&mut self, path: &Path) {
        match Session::load(path) {
            Ok(s) => {
                if !same_file(&s.path, &self.session.path) {
                    // the closed session's jobs run on under its name; what they would draw
                    // here (a preview, a scalogram) is not this session's
                    self.jobs.set_aside(&file_name(&self.session.path));
                    self.run_fingerprints.clear();
                    self.preview_jobs.clear();
                    self.scalogram_jobs.clear();
                    self.previews.clear();
                }
                self.session = s;
                self.modified = false;
                self.saved_text = self.session.to_text();
                self.disk_seen = disk_stamp(&self.session.path);
                self.versions.clear();
                self.frozen = None;
                self.filter.clear();
                self.selected = 0;
                self.param_row = 0;
                self.scalograms.clear();
                self.show_scalogram = false;
                self.reload_session_state();
                self.say(format!("opened {}", path.display()), false);
                self.bring_back_kept();
            }
            // the whole message, in a box: a session error names the line and the value
            Err(e) => {
                self.say(format!("not opened: {}", file_name(path)), true);
                self.overlay = Some(Overlay::Notice {
                    title: format!("{} was not opened", file_name(path)),
                    text: e.to_string(),
                });
            }
        }
    }

    /// Opens `path`, asking first if that would drop unsaved edits.
    pub(super) fn open_asking(&mut self, path: PathBuf) {
        if self.modified {
            let question = format!(
                "{} has unsaved changes: drop them and open {}?",
                file_name(&self.session.path),
                file_name(&path)
            );
            self.overlay = Some(Overlay::Confirm {
                question,
                then: Confirmed::Open(path),
            });
        } else {
            self.open(&path);
        }
    }

    /// Saves the session as `path`, asking first if that replaces another file.
    pub(super) fn save_as_asking(&mut self, path: PathBuf) {
        if path.exists() && !same_file(&path, &self.session.path) {
            self.overlay = Some(Overlay::Confirm {
                question: format!("{} exists: replace it with this session?", path.display()),
                then: Confirmed::SaveAs(path),
            });
        } else {
            self.save(Some(path));
        }
    }

    /// Exports as `request` asks, asking first if that replaces a file.
    pub(super) fn export_asking(&mut self, request: ExportRequest) {
        let whole = self.picked.is_none() && request.table.is_none() && request.filters.is_empty();
        let table = request.path.with_extension("attractors.csv");
        let existing: Vec<String> = [&request.path, &table]
            .into_iter()
            .take(if whole { 2 } else { 1 })
            .filter(|p| p.exists())
            .map(|p| p.display().to_string())
            .collect();
        if existing.is_empty() {
            self.export(&request);
        } else {
            self.overlay = Some(Overlay::Confirm {
                question: format!("{} exists: replace it?", existing.join(" and ")),
                then: Confirmed::Export(request),
            });
        }
    }
}

/// Whether `a` and `b` name the same file, however written (`x.toml`, `./x.toml`, a link);
/// two paths to nothing are the same only as written.
fn same_file(a: &Path, b: &Path) -> bool {
    a == b || matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b)
}

/// A file's modification time and length, if it is there.
pub(super) fn disk_stamp(path: &Path) -> Option<(std::time::SystemTime, u64)> {
    let meta = std::fs::metadata(path).ok()?;
    Some((meta.modified().ok()?, meta.len()))
}

/// A path's last part, for a message.
pub(super) fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// A folder's entries for Tab (`~` the home folder): each name and whether it is a folder
/// (none if unreadable).
pub(super) fn list_dir(dir: &Path) -> Vec<(String, bool)> {
    let dir = dir
        .to_str()
        .map_or_else(|| dir.to_path_buf(), command::home_path);
    std::fs::read_dir(dir).map_or_else(
        |_| Vec::new(),
        |entries| {
            entries
                .flatten()
                .filter_map(|e| Some((e.file_name().into_string().ok()?, e.path().is_dir())))
                .collect()
        },
    )
}
