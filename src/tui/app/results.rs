//! Results: the stored ones read back, the previews, and the jobs that compute them.

use std::time::{Duration, Instant};

use isola::session::results::{ResultStatus, ResultView};
use isola::session::store::ResultPaths;
use isola::session::{AnalysisEntry, Settings};

use super::{App, Focus, Preview};
use crate::tui::command::Which;
use crate::tui::jobs::{JobState, Work};
use crate::tui::plots;

impl App {
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
        let entry = &self.session.analyses[i];
        let has_one = isola::session::preview::available(&entry.settings);
        if !has_one
            || self.status_of(i) == ResultStatus::Complete
            || self.kept_result(entry).is_some()
        {
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

    /// The fingerprint of `entry`'s settings now, if a result of them is kept from before
    /// (replaced by other settings').
    fn kept_result(&self, entry: &AnalysisEntry) -> Option<String> {
        let paths = ResultPaths::new(&self.session, &entry.name);
        let fingerprint = self.session.fingerprint(entry);
        isola::session::store::earlier::is_kept(&paths, &fingerprint).then_some(fingerprint)
    }

    /// Brings back the result of each analysis whose settings now have one kept from before
    /// (after an undo, an edit back to them, the session file changed back on disk): a job
    /// that computes nothing (a kept result that fails its checks is said, not recomputed).
    pub(super) fn bring_back_kept(&mut self) {
        let kept: Vec<(String, String)> = (self.session.analyses.iter())
            .filter(|entry| self.active_job(&entry.name).is_none())
            .filter_map(|entry| Some((entry.name.clone(), self.kept_result(entry)?)))
            .collect();
        if kept.is_empty() {
            return;
        }
        for (name, fingerprint) in kept {
            let id = self.jobs.push(
                format!("{name} (kept result)"),
                Work::BringBack {
                    session: self.snapshot.clone(),
                    name: name.clone(),
                },
            );
            self.run_fingerprints.insert(id, (name, fingerprint));
        }
        self.tick();
    }

    pub fn status_of(&self, i: usize) -> ResultStatus {
        self.stored
            .get(i)
            .map_or(ResultStatus::Missing, |r| r.status)
    }

    /// Closes the picked orbit once the selected analysis' settings (or model) differ from
    /// those it was integrated on: it would be drawn, exported and figured as theirs.
    pub(super) fn close_orbit_of_other_settings(&mut self) {
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
    pub(super) fn poll_results(&mut self, now: bool) {
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
    pub(super) fn take_results(&mut self) {
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

    /// Runs the analyses `which` names.
    pub(super) fn run_which(&mut self, which: Which) {
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
    pub(super) fn cancel_job(&mut self) {
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
}
