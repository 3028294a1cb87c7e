//! The app's state and what each action does to it. Drawing is in `ui.rs`; physics only ever
//! runs in jobs that call the library.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use isola::analysis::Oscillator;
use isola::analysis::orbit::scalogram::{Scalogram, ScalogramSpec};
use isola::figure;
use isola::session::output::{Protected, check_target};
use isola::session::results::{BasinView, ChirpView, ResultStatus, ResultView};
use isola::session::run::Outcome;
use isola::session::store::ResultPaths;
use isola::session::written::ModelPoint;
use isola::session::{Session, Settings};

use super::command::{self, Command, Which};
use super::filter;
use super::jobs::{JobList, JobState, Output, Work};
use super::keymap::{Action, Keymap};
use super::line_edit::LineEdit;
use super::orbit::{self, OrbitHistory};
use super::panes::params::{self, Edit, Row, Target};
use super::plots::{self, Pick};
use super::theme::Theme;
use super::undo::{Version, Versions};
use super::watcher::{Stored, Watcher};

/// The panes that take focus, in Tab order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Focus {
    Analyses,
    Params,
    Plot,
    Jobs,
}

impl Focus {
    const ORDER: [Focus; 4] = [Focus::Analyses, Focus::Params, Focus::Plot, Focus::Jobs];

    fn step(self, by: isize) -> Focus {
        let i = Focus::ORDER.iter().position(|f| *f == self).unwrap_or(0) as isize;
        Focus::ORDER[(i + by).rem_euclid(4) as usize]
    }
}

/// A box over the panes that takes the keys while open.
#[derive(Debug, Clone, PartialEq)]
pub enum Overlay {
    Help,
    ConfirmQuit,
    /// A line of text to type: a path to save as or export to.
    Input {
        purpose: InputPurpose,
        text: LineEdit,
    },
    /// Session files to open, and folders to look in, in `dir`.
    Picker {
        dir: PathBuf,
        /// `..` and the folders first, then the session files.
        files: Vec<PathBuf>,
        /// What each is: a session's leading comment, or "folder".
        about: Vec<String>,
        selected: usize,
    },
    /// A message too long for the status bar (why a session could not be opened): any key
    /// closes it.
    Notice {
        title: String,
        text: String,
    },
    /// The kinds of analysis, to add one (`a`).
    KindPicker {
        selected: usize,
    },
    /// A question before something that cannot be undone: `y` does it.
    Confirm {
        question: String,
        then: Confirmed,
    },
}

/// What a confirmation does when the answer is yes.
#[derive(Debug, Clone, PartialEq)]
pub enum Confirmed {
    /// Open this session, dropping unsaved edits.
    Open(PathBuf),
    /// Load the session's own file again, dropping unsaved edits.
    Reload,
    /// Save the session over this existing file (or its own, changed on disk).
    SaveAs(PathBuf),
    /// Export over this existing file.
    Export(ExportRequest),
    /// Delete analysis number `0` (called `1`) from the session.
    Delete(usize, String),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InputPurpose {
    SaveAs,
    Export,
    Open,
    /// A command line (`:`).
    Command,
    /// The filter (`/`), applied as it is typed.
    Filter,
    /// The name of a new analysis of kind `KINDS[i]`.
    NewName(usize),
}

/// An orbit picked off a plot, being computed or shown.
pub struct Picked {
    pub label: String,
    pub job: usize,
    /// The fingerprint of the analysis' settings it was integrated on: closed when they
    /// change.
    pub fingerprint: String,
    /// The orbit's time history, once integrated, and its view.
    pub history: Option<Box<OrbitHistory>>,
    pub view: Option<ResultView>,
    /// Its own cursor: the plot's is kept for when the orbit is closed.
    pub cursor: (usize, usize),
    pub summary: Option<String>,
}

/// What `e` or `:export` writes: the picked orbit if one is shown, else the selected result
/// (its companion `table` and only the rows passing `filters`, if given).
#[derive(Debug, Clone, PartialEq)]
pub struct ExportRequest {
    pub path: PathBuf,
    pub table: Option<String>,
    pub filters: Vec<isola::session::select::Filter>,
}

/// A line in the status bar.
#[derive(Debug, Clone, PartialEq)]
pub struct Message {
    pub text: String,
    pub error: bool,
}

pub struct App {
    pub session: Session,
    /// The session as jobs and the result reader see it, taken again after each change.
    snapshot: Arc<Session>,
    /// Edits not saved yet.
    pub modified: bool,
    pub selected: usize,
    pub focus: Focus,
    pub overlay: Option<Overlay>,
    pub param_rows: Vec<Row>,
    pub param_row: usize,
    /// The text being typed into the selected parameter.
    pub editing: Option<LineEdit>,
    /// What fits the word Tab completed in the line being typed, where more than one thing
    /// does (shown under it until the next key).
    pub tab_choices: Vec<String>,
    pub param_error: Option<String>,
    /// What is stored of each analysis' result, as the watcher last read it.
    pub stored: Vec<Stored>,
    watcher: Watcher,
    pub jobs: JobList,
    pub job_row: usize,
    pub cursor: (usize, usize),
    pub picked: Option<Picked>,
    /// Scalograms by analysis name, each with what it was computed from, and the job
    /// computing one (with the same).
    scalograms: HashMap<String, (u64, Scalogram)>,
    scalogram_jobs: HashMap<usize, (String, u64)>,
    /// Coarse first pictures by analysis name, and the job computing one.
    previews: HashMap<String, Preview>,
    preview_jobs: HashMap<usize, String>,
    /// Each analysis job's analysis and the fingerprint of the settings it computes.
    run_fingerprints: HashMap<usize, (String, String)>,
    pub show_scalogram: bool,
    pub zoom: bool,
    /// The user moved the plot cursor since the view was first drawn.
    cursor_moved: bool,
    /// How far the help overlay is scrolled down, in lines.
    pub help_scroll: u16,
    /// The pane that had the keys before the plot was zoomed, to give them back after.
    focus_before_zoom: Option<Focus>,
    /// The view held on the plot (`f`) while results keep coming in.
    pub frozen: Option<Arc<ResultView>>,
    /// The analysis whose result is drawn muted under the selected one's (`:compare`).
    pub compare: Option<String>,
    /// Only analyses and parameters whose names contain this are listed (`/`).
    pub filter: String,
    /// The session's text as last opened or saved: an undo back to it is no edit.
    saved_text: String,
    /// The session file's modification time and length when last looked at, and when.
    disk_seen: Option<(std::time::SystemTime, u64)>,
    last_disk_check: Instant,
    /// The mouse is the workbench's (config `mouse = false` leaves it to the terminal).
    pub mouse: bool,
    /// Where panes and plots were on the last frame, for the mouse.
    pub layout: std::cell::RefCell<super::mouse::Layout>,
    versions: Versions,
    pub message: Option<Message>,
    pub theme: Theme,
    pub keymap: Keymap,
    pub should_quit: bool,
    /// The process' exit status when the app quits (130 after Ctrl-C, 128 + a signal's number).
    pub exit_status: u8,
    /// Something changed since the last frame.
    pub dirty: bool,
    last_poll: Instant,
    last_full_poll: Instant,
}

impl App {
    pub fn new(session: Session, theme: Theme, keymap: Keymap, threads: usize) -> Self {
        let mut app = App {
            snapshot: Arc::new(session.clone()),
            stored: Vec::new(),
            tab_choices: Vec::new(),
            watcher: Watcher::start(),
            session,
            modified: false,
            selected: 0,
            focus: Focus::Analyses,
            overlay: None,
            param_rows: Vec::new(),
            param_row: 0,
            editing: None,
            param_error: None,
            jobs: JobList::new(threads),
            job_row: 0,
            cursor: (0, 0),
            picked: None,
            scalograms: HashMap::new(),
            scalogram_jobs: HashMap::new(),
            previews: HashMap::new(),
            preview_jobs: HashMap::new(),
            run_fingerprints: HashMap::new(),
            show_scalogram: false,
            zoom: false,
            help_scroll: 0,
            cursor_moved: false,
            focus_before_zoom: None,
            frozen: None,
            compare: None,
            filter: String::new(),
            saved_text: String::new(),
            disk_seen: None,
            last_disk_check: Instant::now(),
            mouse: true,
            layout: Default::default(),
            versions: Versions::default(),
            message: None,
            theme,
            keymap,
            should_quit: false,
            exit_status: 0,
            dirty: true,
            last_poll: Instant::now(),
            last_full_poll: Instant::now(),
        };
        app.saved_text = app.session.to_text();
        app.disk_seen = disk_stamp(&app.session.path);
        app.reload_session_state();
        app
    }

    /// After a session is opened or replaced: readers, rows and cursor from scratch.
    fn reload_session_state(&mut self) {
        let before = std::mem::replace(&mut self.snapshot, Arc::new(self.session.clone()));
        let read = std::mem::take(&mut self.stored);
        // an analysis unchanged (its name, fingerprint and results folder) keeps what was read
        // of its result until the readers read it again: a save or an edit of another
        // analysis does not flash "not run"
        let now = &self.snapshot;
        let same_folder = before.results_dir() == now.results_dir();
        self.stored = now
            .analyses
            .iter()
            .map(|entry| {
                before
                    .analyses
                    .iter()
                    .position(|e| e.name == entry.name)
                    .filter(|&i| {
                        same_folder
                            && before.fingerprint(&before.analyses[i]) == now.fingerprint(entry)
                    })
                    .and_then(|i| read.get(i).cloned())
                    .unwrap_or_default()
            })
            .collect();
        self.selected = self
            .selected
            .min(self.session.analyses.len().saturating_sub(1));
        self.refresh_rows();
        // the readers keep what they read: ask for it all again, changed or not
        self.last_poll = Instant::now();
        self.last_full_poll = Instant::now();
        let all = (0..self.session.analyses.len()).collect();
        self.watcher.poll_all(&self.snapshot, all);
        self.reset_cursor();
    }

    fn refresh_rows(&mut self) {
        self.param_rows = params::rows(&self.session, self.selected);
        self.param_row = self.param_row.min(self.param_rows.len().saturating_sub(1));
    }

    fn reset_cursor(&mut self) {
        self.cursor = self.view().map_or((0, 0), plots::initial_cursor);
        self.cursor_moved = false;
        self.picked = None;
    }

    /// The selected analysis' result as the plot shows it (held, if frozen), if any.
    pub fn view(&self) -> Option<&ResultView> {
        if let Some(frozen) = &self.frozen {
            return Some(frozen);
        }
        self.stored
            .get(self.selected)
            .and_then(|r| r.view.as_deref())
            .or_else(|| self.preview().map(|p| &p.blank))
    }

    /// The selected analysis' coarse first picture, while it is for the current settings and
    /// no complete result is stored.
    fn preview(&self) -> Option<&Preview> {
        let entry = self.session.analyses.get(self.selected)?;
        let preview = self.previews.get(&entry.name)?;
        (self.status_of(self.selected) != ResultStatus::Complete
            && preview.fingerprint == self.session.fingerprint(entry))
        .then_some(preview)
    }

    /// Starts the coarse first picture of analysis `name` (a basin or a frequency response
    /// without a complete result), drawn under its result until that is done.
    fn start_preview(&mut self, name: &str) {
        let Some(i) = self.session.analysis_index(name) else {
            return;
        };
        let has_one = isola::session::preview::available(&self.session.analyses[i].settings);
        if !has_one || self.status_of(i) == ResultStatus::Complete {
            return;
        }
        let id = self.jobs.push(
            format!("{name} (preview)"),
            Work::Preview {
                session: self.snapshot.clone(),
                name: name.to_string(),
            },
        );
        self.preview_jobs.insert(id, name.to_string());
    }

    pub fn status_of(&self, i: usize) -> ResultStatus {
        self.stored
            .get(i)
            .map_or(ResultStatus::Missing, |r| r.status)
    }

    /// A status-bar message.
    pub fn say(&mut self, text: impl Into<String>, error: bool) {
        self.message = Some(Message {
            text: text.into(),
            error,
        });
        self.dirty = true;
    }

    /// Polls jobs and result files; called every loop turn (cheap when nothing changed).
    pub fn tick(&mut self) {
        for finished in self.jobs.poll() {
            self.dirty = true;
            // every job's entry goes when it ends (a cancelled one's too)
            let ran = self.run_fingerprints.remove(&finished.id);
            if let Some((name, source)) = self.scalogram_jobs.remove(&finished.id) {
                match finished.result {
                    Ok(Output::Scalogram(s)) => {
                        self.scalograms.insert(name, (source, s));
                    }
                    Ok(_) => {}
                    Err(e) => self.say(format!("scalogram of {name}: {e}"), true),
                }
                continue;
            }
            if let Some(name) = self.preview_jobs.remove(&finished.id) {
                match finished.result {
                    Ok(Output::Preview { fingerprint, view }) => {
                        let seconds = self.jobs.entries.iter().find(|e| e.id == finished.id);
                        if let Some(JobState::Done { seconds }) = seconds.map(|e| &e.state) {
                            tracing::info!(analysis = name, seconds, "coarse preview drawn");
                        }
                        self.previews.insert(name, Preview::new(fingerprint, *view));
                    }
                    Ok(_) | Err(isola::jobs::JobError::Cancelled) => {}
                    // the analysis itself says why it cannot run
                    Err(e) => tracing::warn!(analysis = name, "no preview: {e}"),
                }
                continue;
            }
            match (finished.result, &mut self.picked) {
                (Ok(Output::Orbit { history, view }), Some(p)) if p.job == finished.id => {
                    let s = history.steady_state();
                    p.summary = Some(format!(
                        "{} {}",
                        s.response_type(),
                        s.amplitude.map_or(String::new(), |a| format!("A {a:.4}"))
                    ));
                    p.view = Some(ResultView::History(*view));
                    p.history = Some(history);
                }
                (Err(e), Some(p)) if p.job == finished.id => {
                    p.summary = Some(format!("failed: {e}"));
                }
                (Ok(Output::Analysis(outcome)), _) => {
                    let name = finished.analysis.unwrap_or_default();
                    // settings edited during the run: what it stored is of those before
                    let edited = ran.is_some_and(|(analysis, fingerprint)| {
                        self.session
                            .analysis(&analysis)
                            .is_some_and(|e| self.session.fingerprint(e) != fingerprint)
                    });
                    let before = if edited {
                        " for the settings before the edit: stale, r runs these"
                    } else {
                        ""
                    };
                    let text = match outcome {
                        Outcome::UpToDate => format!("{name}: already up to date{before}"),
                        Outcome::Completed {
                            chunks_computed,
                            seconds,
                            assembled_here,
                            notes,
                        } => format!(
                            "{name}: done{before} ({chunks_computed} chunks now, {seconds:.1} s of computing{}){}",
                            if assembled_here {
                                ""
                            } else {
                                ", assembled by another run"
                            },
                            notes
                                .iter()
                                .map(|n| format!("; note: {n}"))
                                .collect::<String>()
                        ),
                        Outcome::ShardDone { missing, .. } => {
                            format!("{name}: {missing} chunks still missing")
                        }
                        Outcome::Superseded { .. } => format!(
                            "{name}: not stored: the session file was edited during the run"
                        ),
                    };
                    self.say(text, false);
                }
                (Err(e), _) => {
                    let name = finished.analysis.unwrap_or_else(|| "job".into());
                    self.say(
                        format!("{name}: {e}"),
                        !matches!(e, isola::jobs::JobError::Cancelled),
                    );
                }
                _ => {}
            }
            self.poll_results(true);
        }
        if self.jobs.any_active() {
            self.dirty = true; // gauges move
        }
        self.close_orbit_of_other_settings();
        self.watch_session_file();
        self.poll_results(false);
        self.take_results();
    }

    /// Notices, once a second, an edit of the session file made outside the workbench (an
    /// editor, git): with no unsaved edits here it is loaded (`u` undoes that); with some,
    /// it is said with what to do, and `s` asks before replacing it.
    fn watch_session_file(&mut self) {
        if self.last_disk_check.elapsed() >= Duration::from_secs(1) {
            self.last_disk_check = Instant::now();
            self.notice_session_file();
        }
    }

    /// [`App::watch_session_file`]'s look at the file, now.
    pub(super) fn notice_session_file(&mut self) {
        let stamp = disk_stamp(&self.session.path);
        if stamp == self.disk_seen {
            return; // unchanged (or never saved)
        }
        if stamp.is_none() {
            // deleted (or moved away): what is shown is the only copy, unsaved
            self.disk_seen = None;
            self.modified = true;
            self.say(
                format!(
                    "{} was deleted on disk: s writes it again",
                    file_name(&self.session.path)
                ),
                true,
            );
            return;
        }
        self.disk_seen = stamp;
        match std::fs::read_to_string(&self.session.path) {
            Ok(text) if text == self.saved_text => {
                // as loaded again (a repaired edit, a restored file): no warning stands
                if self
                    .message
                    .as_ref()
                    .is_some_and(|m| m.text.contains("on disk"))
                {
                    self.message = None;
                }
                self.modified = self.session.to_text() != self.saved_text;
            }
            Ok(_) if self.modified => self.say(
                format!(
                    "{} changed on disk: :reload loads it (dropping your unsaved edits), \
                     s asks before replacing it",
                    file_name(&self.session.path)
                ),
                true,
            ),
            Ok(text) => self.load_disk_text(text),
            Err(e) => tracing::warn!(error = %e, "the session file changed but is not read"),
        }
    }

    /// `:reload`: the session file as on disk, asking first over unsaved edits.
    fn reload_asking(&mut self) {
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
    fn reload(&mut self) {
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
    fn load_disk_text(&mut self, text: String) {
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
            }
            Err(e) => self.say(
                format!(
                    "{name} changed on disk but does not load ({e}); s asks before replacing it"
                ),
                true,
            ),
        }
    }

    /// Closes the picked orbit once the selected analysis' settings (or model) differ from
    /// those it was integrated on: it would be drawn, exported and figured as theirs.
    fn close_orbit_of_other_settings(&mut self) {
        let Some(p) = &self.picked else { return };
        let current = self
            .session
            .analyses
            .get(self.selected)
            .map(|e| self.session.fingerprint(e));
        if current.as_ref() != Some(&p.fingerprint) {
            self.picked = None;
            self.dirty = true;
            self.say(
                "closed the orbit: it was of the settings before the edit",
                false,
            );
        }
    }

    /// Asks for new result files to be read: the selected analysis' every 200 ms, all every
    /// 2 s (or now), unless the last poll is still being answered.
    fn poll_results(&mut self, now: bool) {
        let due = now || self.last_poll.elapsed() >= Duration::from_millis(200);
        if !due || (!now && self.watcher.busy()) {
            return;
        }
        self.last_poll = Instant::now();
        let all = now || self.last_full_poll.elapsed() >= Duration::from_secs(2);
        if all {
            self.last_full_poll = Instant::now();
        }
        let which: Vec<usize> = (0..self.session.analyses.len())
            .filter(|&i| all || i == self.selected || self.is_sweep_partner(i))
            .collect();
        self.watcher.poll(&self.snapshot, which);
    }

    /// Takes what the watcher has read.
    fn take_results(&mut self) {
        let mut selected_changed = false;
        for (index, name, stored) in self.watcher.updates() {
            if self
                .session
                .analyses
                .get(index)
                .is_none_or(|e| e.name != name)
            {
                continue; // the session changed since the poll
            }
            let selected = index == self.selected;
            selected_changed |= selected;
            let first = self.stored[index].view.is_none();
            let finished = self.stored[index].status != ResultStatus::Complete
                && stored.status == ResultStatus::Complete;
            self.stored[index] = stored;
            self.dirty = true;
            if selected && self.picked.is_none() {
                if first {
                    // a first view: the cursor starts at its default point
                    self.cursor = self.view().map_or((0, 0), plots::initial_cursor);
                    self.cursor_moved = false;
                } else if finished {
                    // the final view replacing the live one: a cursor the user moved stays
                    // where it was (kept inside the view); one never moved goes to the final
                    // view's default point
                    if let Some(view) = self.view() {
                        self.cursor = if self.cursor_moved {
                            plots::move_cursor(view, self.cursor, 0, 0)
                        } else {
                            plots::initial_cursor(view)
                        };
                    }
                }
            }
        }
        if selected_changed {
            // a new result of the chirp shown: its scalogram is computed again
            self.ensure_scalogram();
        }
    }

    /// Waits until every poll asked for is answered (10 s at most): for tests, and for a
    /// command that must know what is stored (`run stale`).
    pub fn sync_results(&mut self) {
        let start = Instant::now();
        while self.watcher.busy() && start.elapsed() < Duration::from_secs(10) {
            self.take_results();
            std::thread::sleep(Duration::from_millis(2));
        }
        self.take_results();
    }

    /// Analysis `i` is a chirp drawn with the selected one.
    fn is_sweep_partner(&self, i: usize) -> bool {
        let a = &self.session.analyses;
        matches!(
            (
                a.get(i).map(|e| &e.settings),
                a.get(self.selected).map(|e| &e.settings)
            ),
            (Some(Settings::ChirpSweep(_)), Some(Settings::ChirpSweep(_)))
        ) && a[i].model == a[self.selected].model
    }

    /// The chirps drawn together with the selected one (same model), with their views: a
    /// partner's only while it is of its current settings (a stale one is not drawn beside).
    pub fn sweep_group(&self) -> Vec<(usize, &ResultView)> {
        (0..self.session.analyses.len())
            .filter(|&i| {
                i == self.selected
                    || (self.is_sweep_partner(i) && self.status_of(i) != ResultStatus::Stale)
            })
            .filter_map(|i| Some((i, self.stored.get(i)?.view.as_deref()?)))
            .collect()
    }

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

    fn act(&mut self, action: Action) {
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
    fn goto(&mut self, mut at: Vec<f64>, hz: bool) {
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
    fn place_cursor(&mut self, at: &[f64]) -> Option<()> {
        match &mut self.picked {
            Some(p) => p.cursor = plots::cursor_near(p.view.as_ref()?, p.cursor, at)?,
            None => {
                self.cursor = plots::cursor_near(self.view()?, self.cursor, at)?;
                self.cursor_moved = true;
            }
        }
        Some(())
    }

    /// A click on `target`: its pane focused, its row selected, the plot cursor on the point.
    pub(super) fn click(&mut self, target: super::mouse::Target) {
        use super::mouse::Target;
        match target {
            Target::Analysis(i) => {
                self.focus = Focus::Analyses;
                if i != self.selected {
                    self.select(i);
                }
            }
            Target::Param(i) => {
                self.focus = Focus::Params;
                self.param_row = i;
                self.param_error = None;
            }
            Target::Job(i) => {
                self.focus = Focus::Jobs;
                self.job_row = i;
            }
            Target::Point(x, y) => {
                self.focus = Focus::Plot;
                let _ = self.place_cursor(&[x, y]);
            }
            Target::Pane(pane) => self.focus = pane,
            Target::Nothing => {}
        }
    }

    /// The wheel over `pane`: its selection (or the plot cursor) moved by `by`.
    pub(super) fn scroll(&mut self, pane: Focus, by: isize) {
        let focus = std::mem::replace(&mut self.focus, pane);
        self.move_by(0, by);
        // the wheel scrolls what it is over without taking the keys from another pane
        self.focus = focus;
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

    /// The session as it is now, to remember before an edit.
    fn version(&self, what: String) -> Version {
        Version {
            text: self.session.to_text(),
            selected: self.selected,
            what,
        }
    }

    fn undo(&mut self) {
        let now = self.version(String::new());
        match self.versions.undo(now) {
            Some(back) => self.go_to_version(back, "undid"),
            None => self.say("nothing to undo", false),
        }
    }

    fn redo(&mut self) {
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
            }
            // a version is a text this session had: it parses, unless the schema changed
            Err(e) => self.say(format!("cannot {did}: {e}"), true),
        }
    }

    /// What is drawn muted under the selected analysis' plot, and what it is called: the
    /// coarse first picture of the current settings, or the previous settings' complete
    /// result, while a partial one of the current settings is shown; else the compared
    /// analysis' result.
    pub fn underlay(&self) -> Option<(&ResultView, String)> {
        if let Some(preview) = self.preview() {
            return Some((&preview.picture, "a coarse preview, until done".into()));
        }
        let stored = self.stored.get(self.selected)?;
        if matches!(stored.status, ResultStatus::Partial { .. })
            && let Some(previous) = stored.previous.as_deref()
        {
            return Some((previous, "the previous settings, until done".into()));
        }
        let name = self.compare.as_ref()?;
        let i = self.session.analysis_index(name)?;
        let view = self.stored.get(i)?.view.as_deref()?;
        (i != self.selected).then(|| (view, name.clone()))
    }

    /// The analyses listed: those matching the filter (all, if none does or there is none).
    pub fn visible_analyses(&self) -> Vec<usize> {
        let names: Vec<String> = self
            .session
            .analyses
            .iter()
            .map(|a| format!("{} {}", a.name, a.settings.kind()))
            .collect();
        filter::matching(&self.filter, &names)
    }

    /// The parameter rows listed: those matching the filter (all, if none does).
    pub fn visible_rows(&self) -> Vec<usize> {
        let labels: Vec<String> = self.param_rows.iter().map(|r| r.label.clone()).collect();
        filter::matching(&self.filter, &labels)
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
    fn open_help(&mut self) {
        self.help_scroll = 0;
        self.overlay = Some(Overlay::Help);
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
                let themes = super::config::config_dir().map(|d| d.join("themes"));
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

    /// What the session is about: the leading comment of the file as last opened or saved.
    pub fn description(&self) -> String {
        isola::session::schema::description(&self.saved_text)
    }

    /// A name for a new analysis of `kind` no analysis has: `basin`, else `basin2`, ...
    fn unused_name(&self, kind: &str) -> String {
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

    /// After a copy or a rename (if `done`): the stored result of analysis `from` copied as
    /// `to`'s, so the copy starts with it (and the session file on disk, which may still name
    /// `from`, keeps its own). Says what became of it, to end the status message.
    fn carry_result(&self, done: bool, from: &str, to: &str) -> String {
        if !done {
            return String::new();
        }
        let dir = self.session.results_dir();
        let from = ResultPaths::in_dir(&dir, from);
        match isola::session::store::copy::copy_result(&from, &ResultPaths::in_dir(&dir, to)) {
            Ok(true) => ", with its result".into(),
            Ok(false) => String::new(),
            Err(e) => {
                tracing::warn!(error = %format!("{e:#}"), "result not copied");
                format!(" (its result not copied: {e:#})")
            }
        }
    }

    /// Selects analysis `i`, as moving to it in the list does.
    fn select(&mut self, i: usize) {
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

    fn delete_analysis(&mut self, index: usize, name: &str) {
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

    /// Runs the analyses `which` names.
    fn run_which(&mut self, which: Which) {
        let indices: Vec<usize> = match which {
            Which::Selected => vec![self.selected],
            Which::All => (0..self.session.analyses.len()).collect(),
            Which::Stale => {
                // what the stored results are now, not what was last read of them
                self.sync_results();
                (0..self.session.analyses.len())
                    .filter(|&i| self.status_of(i) != ResultStatus::Complete)
                    .collect()
            }
            Which::Named(name) => match self.session.analysis_index(&name) {
                Some(i) => vec![i],
                None => return self.say(format!("no analysis {name}"), true),
            },
        };
        if indices.is_empty() {
            return self.say("every result is current: nothing to run", false);
        }
        let selected = self.selected;
        for &i in &indices {
            self.selected = i;
            self.run_selected();
        }
        self.selected = selected;
        if indices.len() > 1 {
            self.say(format!("{} analyses queued", indices.len()), false);
        }
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

    fn move_by(&mut self, dx: isize, dy: isize) {
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

    fn edit_key(&mut self, key: KeyEvent) {
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
            }
            Err(e) => self.param_error = Some(params::error_line(&e)),
        }
    }

    /// The state of this workbench's job on analysis `name`, while it waits or runs (one at
    /// a time: `r` refuses a second).
    pub fn active_job(&self, name: &str) -> Option<&JobState> {
        self.jobs
            .entries
            .iter()
            .find(|e| e.is_active() && e.analysis.as_deref() == Some(name))
            .map(|e| &e.state)
    }

    /// Queues the selected analysis.
    pub fn run_selected(&mut self) {
        let Some(entry) = self.session.analyses.get(self.selected) else {
            return;
        };
        let name = entry.name.clone();
        if self.active_job(&name).is_some() {
            self.say(format!("{name} is already running"), true);
            return;
        }
        // the preview first: the analysis waits the few tens of milliseconds it takes
        let fingerprint = self.snapshot.fingerprint(entry);
        self.start_preview(&name);
        let id = self.jobs.push(
            name.clone(),
            Work::Analysis {
                session: self.snapshot.clone(),
                name: name.clone(),
            },
        );
        self.run_fingerprints
            .insert(id, (name.clone(), fingerprint));
        self.job_row = self.jobs.entries.len() - 1;
        self.tick();
        // started at once if nothing else ran (after its preview, a few tens of milliseconds);
        // otherwise it waits its turn
        let ahead = self
            .jobs
            .entries
            .iter()
            .filter(|e| e.is_active() && !e.preview && e.analysis.as_deref() != Some(name.as_str()))
            .count();
        let running = ahead == 0
            || self.jobs.entries.iter().any(|e| {
                e.state == JobState::Running && e.analysis.as_deref() == Some(name.as_str())
            });
        if running {
            self.say(format!("{name}: running"), false);
        } else {
            self.say(format!("{name}: queued after {ahead} job(s)"), false);
        }
    }

    /// Cancels the job under the cursor in the job pane, or else the selected analysis' job.
    fn cancel_job(&mut self) {
        let target = if self.focus == Focus::Jobs {
            self.jobs
                .entries
                .get(self.job_row)
                .filter(|e| e.is_active())
        } else {
            let name = self
                .session
                .analyses
                .get(self.selected)
                .map(|e| e.name.as_str());
            self.jobs
                .entries
                .iter()
                .rev()
                .find(|e| e.is_active() && e.analysis.as_deref() == name)
                .or_else(|| self.jobs.entries.iter().rev().find(|e| e.is_active()))
        };
        match target.map(|e| (e.id, e.label.clone())) {
            Some((id, label)) => {
                self.jobs.cancel(id);
                self.say(format!("{label}: cancelling"), false);
            }
            None => self.say("no job to cancel", false),
        }
    }

    /// Why Enter opens no orbit from the plot shown, whatever the point under the cursor: an
    /// orbit is shown already, the plot is held, or its result is of other settings (an orbit
    /// is integrated on the current settings, so it is picked from their result only). The
    /// reason, and whether it is an error; the status bar and the plot offer Enter without one.
    pub fn pick_blocked(&self) -> Option<(String, bool)> {
        use super::keymap::Action;
        if self.picked.is_some() {
            let back = self.keymap.label(Action::Back);
            Some((
                format!("an orbit is shown: {back} returns to the result"),
                false,
            ))
        } else if self.frozen.is_some() {
            let key = self.keymap.label(Action::Freeze);
            Some((
                format!("the plot is held: {key} resumes it, then pick"),
                false,
            ))
        } else if self.status_of(self.selected) == ResultStatus::Stale {
            let run = self.keymap.label(Action::Run);
            Some((
                format!("the result shown is of other settings: {run} runs these, then pick"),
                true,
            ))
        } else {
            None
        }
    }

    /// Integrates the orbit under the plot cursor.
    fn pick(&mut self) {
        if let Some((why, error)) = self.pick_blocked() {
            self.say(why, error);
            return;
        }
        let Some(view) = self.view() else { return };
        let Some(Pick {
            omega,
            member,
            start,
        }) = plots::pick(view, self.cursor)
        else {
            let why = match view {
                // a result stored before the steps kept their starts
                ResultView::Stepped(_) => {
                    "this stepped sweep was stored without its steps' starts: r runs it again, \
                     then pick"
                }
                _ => "nothing to pick here",
            };
            self.say(why, false);
            return;
        };
        let Some(entry) = self.session.analyses.get(self.selected) else {
            return;
        };
        let model = self
            .session
            .point(Some(entry))
            .and_then(|model| orbit::at_pick(model, &entry.settings, member, omega));
        let model = match model {
            Ok(model) => model,
            Err(e) => {
                self.say(e.to_string(), true);
                return;
            }
        };
        let omega = match &model {
            ModelPoint::BuiltIn(p) => p.omega(),
            ModelPoint::Written(sys) => sys.value_of(sys.frequency()),
        };
        let (model, spec, from) = orbit::orbit_from(model, &start);
        let label = format!("orbit ω {omega:.3} {from}");
        let job = self.jobs.push(label.clone(), Work::Orbit { model, spec });
        let fingerprint = self.session.fingerprint(entry);
        self.picked = Some(Picked {
            label,
            job,
            fingerprint,
            history: None,
            view: None,
            cursor: (0, 0),
            summary: None,
        });
        self.tick();
    }

    fn toggle_scalogram(&mut self) {
        if !matches!(self.view(), Some(ResultView::Chirp(_))) {
            self.say("the scalogram is drawn for chirp sweeps", false);
            return;
        }
        self.show_scalogram = !self.show_scalogram;
        self.ensure_scalogram();
        self.tick();
    }

    /// While the scalogram is shown, starts computing the selected chirp's if none is of
    /// the response shown and the analysis' settings, nor being computed.
    fn ensure_scalogram(&mut self) {
        if !self.show_scalogram {
            return;
        }
        let Some(ResultView::Chirp(c)) = self.view() else {
            return;
        };
        let entry = &self.session.analyses[self.selected];
        let spec = entry.settings.scalogram_spec();
        let source = scalogram_source(c, &spec);
        let name = entry.name.clone();
        let current = self
            .scalograms
            .get(&name)
            .is_some_and(|(s, _)| *s == source);
        let computing = self
            .scalogram_jobs
            .values()
            .any(|(n, s)| *n == name && *s == source);
        if !current && !computing {
            let work = Work::Scalogram {
                lambda: c.lambda.clone(),
                dt: c.dt,
                spec,
            };
            let id = self.jobs.push(format!("scalogram {name}"), work);
            self.scalogram_jobs.insert(id, (name, source));
        }
    }

    /// `entry`'s scalogram if `view` is its chirp response and one is current for it.
    fn scalogram_of_view(
        &self,
        entry: &isola::session::AnalysisEntry,
        view: &ResultView,
    ) -> Option<&Scalogram> {
        match view {
            ResultView::Chirp(c) => self.scalogram(&entry.name, c),
            _ => None,
        }
    }

    /// Analysis `name`'s scalogram, if one was computed from chirp response `c` by the
    /// analysis' current settings (never one of an earlier result).
    pub fn scalogram(&self, name: &str, c: &ChirpView) -> Option<&Scalogram> {
        let entry = self.session.analysis(name)?;
        let (source, s) = self.scalograms.get(name)?;
        (*source == scalogram_source(c, &entry.settings.scalogram_spec())).then_some(s)
    }

    /// Saves the session (as `path`), asking first if its own file changed on disk since it
    /// was opened or saved (another editor's changes would be lost).
    fn save(&mut self, path: Option<PathBuf>) {
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
    fn save_over(&mut self, path: PathBuf) {
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
        let (mut copied, mut failed) = (0, Vec::new());
        for entry in &self.session.analyses {
            let from = ResultPaths::in_dir(old_dir, &entry.name);
            let to = ResultPaths::in_dir(&new_dir, &entry.name);
            match isola::session::store::copy::copy_result(&from, &to) {
                Ok(true) => copied += 1,
                Ok(false) => {}
                Err(e) => {
                    tracing::warn!(error = %format!("{e:#}"), "result not copied");
                    failed.push(entry.name.clone());
                }
            }
        }
        match (copied, failed.is_empty()) {
            (0, true) => String::new(),
            (n, true) => format!(" with {n} result{}", if n == 1 { "" } else { "s" }),
            (n, false) => format!(
                " with {n} result(s); not copied (see the log): {}",
                failed.join(", ")
            ),
        }
    }

    fn export_prompt(&mut self) {
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
    fn write_figure(&mut self, path: Option<PathBuf>) {
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
            let run = self.keymap.label(super::keymap::Action::Run);
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

    fn open_picker(&mut self) {
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

    /// Opens `path`, asking first if that would drop unsaved edits.
    fn open_asking(&mut self, path: PathBuf) {
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
    fn save_as_asking(&mut self, path: PathBuf) {
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
    fn export_asking(&mut self, request: ExportRequest) {
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

    /// Cancels every job, waits a moment for them to save what they finished, and quits.
    pub fn quit_now(&mut self) {
        self.jobs.cancel_all();
        self.jobs.wait_idle(Duration::from_secs(2));
        self.should_quit = true;
    }
}

/// Whether `a` and `b` name the same file, however written (`x.toml`, `./x.toml`, a link);
/// two paths to nothing are the same only as written.
fn same_file(a: &Path, b: &Path) -> bool {
    a == b || matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b)
}

/// A file's modification time and length, if it is there.
fn disk_stamp(path: &Path) -> Option<(std::time::SystemTime, u64)> {
    let meta = std::fs::metadata(path).ok()?;
    Some((meta.modified().ok()?, meta.len()))
}

/// A path's last part, for a message.
fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// A coarse first picture of an analysis ([`preview::coarse`]), for the settings of its
/// fingerprint, and an empty result on its grid to draw it under before any chunk is done.
struct Preview {
    fingerprint: String,
    picture: ResultView,
    blank: ResultView,
}

impl Preview {
    fn new(fingerprint: String, picture: ResultView) -> Self {
        let blank = match &picture {
            ResultView::Basin(b) => ResultView::Basin(BasinView {
                dx: b.dx.clone(),
                v: b.v.clone(),
                labels: vec![None; b.labels.len()],
                attractors: Vec::new(),
            }),
            _ => ResultView::Response(Vec::new()),
        };
        Preview {
            fingerprint,
            picture,
            blank,
        }
    }
}

/// What a scalogram is computed from, as one number: the response's samples and their
/// interval, and the scalogram's settings. A stored scalogram is shown only while this is
/// unchanged.
fn scalogram_source(c: &ChirpView, spec: &ScalogramSpec) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::hash::DefaultHasher::new();
    c.dt.to_bits().hash(&mut h);
    for x in &c.lambda {
        x.to_bits().hash(&mut h);
    }
    let f = &spec.frequencies;
    (f.min.to_bits(), f.max.to_bits(), f.points, spec.columns).hash(&mut h);
    h.finish()
}

/// A folder's entries for Tab (`~` the home folder): each name and whether it is a folder
/// (none if unreadable).
fn list_dir(dir: &Path) -> Vec<(String, bool)> {
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
