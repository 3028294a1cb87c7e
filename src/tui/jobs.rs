//! The TUI's jobs: a session's analyses run one at a time (each takes every core) through the
//! same checkpointed path as `isola run`; orbits picked off a plot and scalograms run at once.

use std::sync::Arc;
use std::time::{Duration, Instant};

use isola::analysis::Progress;
use isola::analysis::orbit::scalogram::{Scalogram, ScalogramSpec, scalogram};
use isola::analysis::orbit::time_history::TimeHistorySpec;
use isola::jobs::{Job, JobError, Priority};
use isola::session::Session;
use isola::session::budget::{self, Budget};
use isola::session::preview;
use isola::session::results::{HistoryView, ResultView};

use super::orbit::{OrbitHistory, OrbitModel, integrate};
use isola::session::run::{Outcome, Shard, bring_back, run_analysis};

/// What a job computes.
pub enum Work {
    /// Analysis `name` of a session (a snapshot taken when it was queued).
    Analysis { session: Arc<Session>, name: String },
    /// One orbit, from a point picked on a plot.
    Orbit {
        model: OrbitModel,
        spec: TimeHistorySpec,
    },
    /// The scalogram of a chirp's response.
    Scalogram {
        lambda: Vec<f64>,
        dt: f64,
        spec: ScalogramSpec,
    },
    /// The coarse first picture of analysis `name` (a basin or a frequency response).
    Preview { session: Arc<Session>, name: String },
    /// The result of analysis `name`'s settings kept from before, brought back (nothing
    /// computed: it starts at once, beside a running analysis).
    BringBack { session: Arc<Session>, name: String },
}

/// What a finished job gives back.
pub enum Output {
    Analysis(Outcome),
    /// An orbit, and its view with the steady part summarised.
    Orbit {
        history: Box<OrbitHistory>,
        view: Box<HistoryView>,
    },
    Scalogram(Scalogram),
    /// A coarse picture, for the settings of this fingerprint.
    Preview {
        fingerprint: String,
        view: Box<ResultView>,
    },
}

#[derive(Debug, Clone, PartialEq)]
pub enum JobState {
    Queued,
    Running,
    Done { seconds: f64 },
    Cancelled,
    Failed(String),
}

/// A job as the job pane shows it.
pub struct JobEntry {
    pub id: usize,
    pub label: String,
    /// The analysis it computes, for analysis jobs.
    pub analysis: Option<String>,
    pub state: JobState,
    pub progress: Arc<Progress>,
    /// A preview: analyses wait for it (it is short, and drawn first).
    pub preview: bool,
    /// It computes (all but a result brought back): analyses wait for one another.
    computes: bool,
    /// Of a session closed since (its label names it).
    aside: bool,
    started: Option<Instant>,
    work: Option<Work>,
    job: Option<Job<Output>>,
    /// (time, done, open steps) samples of the last few seconds, for the rates.
    samples: Vec<(Instant, usize, usize)>,
}

impl JobEntry {
    /// Work units per second over the last few seconds.
    pub fn rate(&self) -> Option<f64> {
        self.per_second(|s| s.1)
    }

    /// Steps of unknown-length work (continuation points) per second.
    pub fn step_rate(&self) -> Option<f64> {
        self.per_second(|s| s.2)
    }

    /// How fast the `count` of the samples grew over the last few seconds.
    fn per_second(&self, count: impl Fn(&(Instant, usize, usize)) -> usize) -> Option<f64> {
        let (first, last) = (self.samples.first()?, self.samples.last()?);
        let dt = last.0.duration_since(first.0).as_secs_f64();
        (dt > 0.2).then(|| (count(last) - count(first)) as f64 / dt)
    }

    /// Seconds left at the current rate.
    pub fn eta(&self) -> Option<f64> {
        let (done, total) = self.progress.get();
        let rate = self.rate()?;
        (rate > 0.0 && total >= done).then(|| (total - done) as f64 / rate)
    }

    pub fn is_active(&self) -> bool {
        matches!(self.state, JobState::Queued | JobState::Running)
    }
}

/// A finished job's output, handed to the app once.
pub struct Finished {
    pub id: usize,
    pub analysis: Option<String>,
    pub result: Result<Output, JobError>,
}

/// The jobs of this TUI session, newest last.
pub struct JobList {
    pub entries: Vec<JobEntry>,
    threads: usize,
    next_id: usize,
}

impl JobList {
    pub fn new(threads: usize) -> Self {
        JobList {
            entries: Vec::new(),
            threads,
            next_id: 0,
        }
    }

    /// Queues work; analyses wait for the one before them, other work starts at once.
    pub fn push(&mut self, label: String, work: Work) -> usize {
        let id = self.next_id;
        self.next_id += 1;
        let analysis = match &work {
            Work::Analysis { name, .. } | Work::BringBack { name, .. } => Some(name.clone()),
            _ => None,
        };
        let preview = matches!(work, Work::Preview { .. });
        let computes = !matches!(work, Work::BringBack { .. });
        self.entries.push(JobEntry {
            id,
            label,
            analysis,
            state: JobState::Queued,
            progress: Arc::new(Progress::new(0)),
            preview,
            computes,
            aside: false,
            started: None,
            work: Some(work),
            job: None,
            samples: Vec::new(),
        });
        // keep the pane short: forget old finished jobs beyond the last 20
        while self.entries.len() > 20 {
            match self.entries.iter().position(|e| !e.is_active()) {
                Some(i) => {
                    self.entries.remove(i);
                }
                None => break,
            }
        }
        id
    }

    /// Marks this session's jobs as another session's (`file`, as a message names it), once
    /// that session is closed for another: they run on, saving into its results folder, and
    /// their rows and messages name it, so that none is taken for an analysis of the same name
    /// in the session now open.
    pub fn set_aside(&mut self, file: &str) {
        for e in self.entries.iter_mut().filter(|e| !e.aside) {
            e.aside = true;
            e.label = format!("{file}: {}", e.label);
            if let Some(name) = &mut e.analysis {
                *name = format!("{file}: {name}");
            }
        }
    }

    pub fn any_active(&self) -> bool {
        self.entries.iter().any(JobEntry::is_active)
    }

    /// A preview is queued or running: worth polling for more often than once a frame.
    pub fn preview_active(&self) -> bool {
        self.entries.iter().any(|e| e.preview && e.is_active())
    }

    /// Asks job `id` to stop (a queued job is dropped at once).
    pub fn cancel(&mut self, id: usize) {
        if let Some(e) = self.entries.iter_mut().find(|e| e.id == id) {
            match &e.job {
                Some(job) => job.cancel(),
                None if e.state == JobState::Queued => {
                    e.work = None;
                    e.state = JobState::Cancelled;
                }
                None => {}
            }
        }
    }

    pub fn cancel_all(&mut self) {
        let ids: Vec<usize> = self.entries.iter().map(|e| e.id).collect();
        for id in ids {
            self.cancel(id);
        }
    }

    /// Waits up to `limit` for cancelled jobs to stop (they save what they finished).
    pub fn wait_idle(&mut self, limit: Duration) {
        let end = Instant::now() + limit;
        while self.entries.iter().any(|e| e.job.is_some()) && Instant::now() < end {
            self.poll();
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Starts what may start, samples progress, and collects finished jobs.
    pub fn poll(&mut self) -> Vec<Finished> {
        let mut finished = Vec::new();
        let now = Instant::now();
        for e in &mut self.entries {
            if let Some(job) = &e.job {
                let (done, _) = e.progress.get();
                e.samples.push((now, done, e.progress.open_steps()));
                e.samples
                    .retain(|(t, ..)| now.duration_since(*t) < Duration::from_secs(3));
                if job.is_finished() {
                    let job = e.job.take().expect("checked");
                    let result = job.join();
                    let seconds = e.started.map_or(0.0, |s| s.elapsed().as_secs_f64());
                    e.state = match &result {
                        Ok(_) => JobState::Done { seconds },
                        Err(JobError::Cancelled) => JobState::Cancelled,
                        Err(other) => JobState::Failed(other.to_string()),
                    };
                    finished.push(Finished {
                        id: e.id,
                        analysis: e.analysis.clone(),
                        result,
                    });
                }
            }
        }
        let analysis_running = self
            .entries
            .iter()
            .any(|e| e.job.is_some() && ((e.analysis.is_some() && e.computes) || e.preview));
        let threads = self.threads;
        let mut may_start_analysis = !analysis_running;
        for e in &mut self.entries {
            if e.state != JobState::Queued {
                continue;
            }
            let is_analysis = e.analysis.is_some() && e.computes;
            if is_analysis && !may_start_analysis {
                continue;
            }
            let Some(work) = e.work.take() else { continue };
            match start(threads, work) {
                Ok(job) => {
                    e.progress = job.progress.clone();
                    e.job = Some(job);
                    e.state = JobState::Running;
                    e.started = Some(now);
                    if is_analysis || e.preview {
                        may_start_analysis = false;
                    }
                }
                Err(err) => e.state = JobState::Failed(err.to_string()),
            }
        }
        finished
    }
}

/// Workers run in the background, so that the UI thread gets a core the moment a key
/// arrives; a preview (a few tens of milliseconds) runs ahead of them at normal priority.
fn start(threads: usize, work: Work) -> Result<Job<Output>, JobError> {
    let priority = match work {
        Work::Preview { .. } | Work::BringBack { .. } => Priority::Normal,
        _ => Priority::Background,
    };
    Job::spawn_with(threads, priority, move |ctx| match work {
        Work::Analysis { session, name } => {
            let entry = session
                .analysis(&name)
                .ok_or_else(|| JobError::Failed(format!("no analysis '{name}'")))?;
            // what `isola run` would refuse, the workbench refuses too (before any work)
            let budget = Budget::on_this_machine(ctx.pool.current_num_threads(), None, false);
            budget::check_all(&session, [entry], &budget)
                .map_err(|e| JobError::Failed(e.to_string()))?;
            let outcome = run_analysis(&session, entry, Shard::ALL, &ctx.progress);
            ctx.check_cancel()?;
            outcome
                .map(Output::Analysis)
                .map_err(|e| JobError::Failed(format!("{e:#}")))
        }
        Work::BringBack { session, name } => {
            let entry = session
                .analysis(&name)
                .ok_or_else(|| JobError::Failed(format!("no analysis '{name}'")))?;
            match bring_back(&session, entry) {
                Ok(Some(outcome)) => Ok(Output::Analysis(outcome)),
                Ok(None) => Err(JobError::Failed(
                    "the result kept for these settings failed its checks and was removed: \
                     r computes it"
                        .into(),
                )),
                Err(e) => Err(JobError::Failed(format!("{e:#}"))),
            }
        }
        Work::Orbit { model, spec } => {
            ctx.progress.grow_total(1);
            let integrated = integrate(&model, &spec, ctx.progress.cancel_flag());
            ctx.check_cancel()?;
            let (h, view) = integrated.map_err(JobError::Failed)?;
            ctx.progress.add(1);
            Ok(Output::Orbit {
                history: Box::new(h),
                view: Box::new(view),
            })
        }
        Work::Scalogram { lambda, dt, spec } => {
            ctx.progress.grow_total(1);
            let s = scalogram(&lambda, dt, &spec).map_err(|e| JobError::Failed(e.to_string()))?;
            ctx.progress.add(1);
            Ok(Output::Scalogram(s))
        }
        Work::Preview { session, name } => {
            let entry = session
                .analysis(&name)
                .ok_or_else(|| JobError::Failed(format!("no analysis '{name}'")))?;
            let view = preview::coarse(&session, entry, &ctx.progress)
                .ok_or_else(|| JobError::Failed(format!("no preview of {name}")))?;
            ctx.check_cancel()?;
            let view = view.map_err(|e| JobError::Failed(format!("{e:#}")))?;
            Ok(Output::Preview {
                fingerprint: session.fingerprint(entry),
                view: Box::new(view),
            })
        }
    })
}
