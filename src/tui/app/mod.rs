//! The app's state and what each action does to it. Drawing is in `ui.rs`; physics only ever
//! runs in jobs that call the library. The state and its frame-by-frame upkeep are here; what
//! acts on it is in one file per concern: `keys` (what each key does), `edit` (the session's
//! parameters, commands and undo), `results` (stored results, previews and jobs), `pick` (the
//! plot's picked point and the scalogram) and `files` (reload, save, export and the picker).

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use isola::analysis::orbit::scalogram::Scalogram;
use isola::session::Session;
use isola::session::results::{BasinView, ResultView};
use isola::session::run::Outcome;

use super::filter;
use super::jobs::{JobList, JobState, Output};
use super::keymap::Keymap;
use super::line_edit::LineEdit;
use super::orbit::OrbitHistory;
use super::panes::params::{self, Row};
use super::plots;
use super::theme::Theme;
use super::undo::Versions;
use super::watcher::{Stored, Watcher};

mod edit;
mod files;
mod keys;
mod pick;
mod results;

use files::{disk_stamp, file_name};

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
        app.bring_back_kept();
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
                        Outcome::BroughtBack { seconds } => format!(
                            "{name}: its result for these settings brought back{before} \
                             (kept from before; {seconds:.1} s of computing saved)"
                        ),
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

    /// What the session is about: the leading comment of the file as last opened or saved.
    pub fn description(&self) -> String {
        isola::session::schema::description(&self.saved_text)
    }

    /// Cancels every job, waits a moment for them to save what they finished, and quits.
    pub fn quit_now(&mut self) {
        self.jobs.cancel_all();
        self.jobs.wait_idle(Duration::from_secs(2));
        self.should_quit = true;
    }
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
