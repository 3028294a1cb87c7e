//! `isola run`: a session's analyses headless, resumable, shardable; `isola export`: a
//! selection of a result to CSV.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::{Arc, mpsc};
use std::time::{Duration, Instant};

use clap::Args;
use isola::analysis::Progress;
use isola::jobs::JobContext;
use isola::session::Session;
use isola::session::budget::{self, Budget};
use isola::session::convergence::{self, Changes};
use isola::session::run::{Outcome, Role, Shard, run_analysis_as};
use isola::session::select::{Filter, SelectionError, export_selection, parse_filter};
use isola::session::store::ResultPaths;
use serde::Serialize;

use super::output::{Done, Output, Summary};

#[derive(Debug, Args)]
pub struct RunArgs {
    /// The session file.
    session: PathBuf,
    /// Run only this analysis.
    #[arg(long)]
    only: Option<String>,
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Compute only chunks with index ≡ I mod N (for a cluster): `--shard I/N`.
    #[arg(long, value_parser = parse_shard)]
    shard: Option<Shard>,
    /// Refuse an analysis whose worst case would take longer than this many seconds
    /// (default: a day).
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    budget: Option<f64>,
    /// Run even if over the time budget (never over the memory bound).
    #[arg(long)]
    force: bool,
    /// Be one worker of a cluster job: compute the chunks no other run has claimed until
    /// none is left, never wait for chunks claimed elsewhere (the last worker, or the job's
    /// assembly step, assembles).
    #[arg(long)]
    worker: bool,
    /// Also run each analysis at twice the resolution (twice the RK4 steps per period,
    /// Dormand–Prince tolerances / 32) and report what changed. The doubled results are kept
    /// in NAME.results/convergence.results/, never in place of the session's own.
    #[arg(long, conflicts_with_all = ["shard", "worker"])]
    convergence: bool,
}

/// A positive, finite number of seconds.
pub fn parse_seconds(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        _ => Err(format!("'{s}': a positive number of seconds")),
    }
}

pub fn parse_shard(s: &str) -> Result<Shard, String> {
    let (i, n) = s.split_once('/').ok_or("expected I/N, e.g. 0/4")?;
    let (index, count): (usize, usize) = (
        i.parse().map_err(|_| format!("'{i}' is not a number"))?,
        n.parse().map_err(|_| format!("'{n}' is not a number"))?,
    );
    if count == 0 || index >= count {
        return Err(format!("'{s}': need 0 <= I < N"));
    }
    Ok(Shard { index, count })
}

/// The analyses `--only NAME` picks (all without it); an unknown name lists the others.
pub fn selected<'a>(
    session: &'a Session,
    only: Option<&str>,
) -> anyhow::Result<Vec<&'a isola::session::AnalysisEntry>> {
    Ok(match only {
        Some(name) => vec![session.analysis(name).ok_or_else(|| {
            let names: Vec<&str> = session.analyses.iter().map(|a| a.name.as_str()).collect();
            anyhow::anyhow!(
                "no analysis '{name}' in {}: one of {}",
                session.path.display(),
                names.join(", ")
            )
        })?],
        None => session.analyses.iter().collect(),
    })
}

/// Sends tracing events to `run.log` in the session's results directory (never to the
/// terminal, where the progress bar lives).
fn log_to_file(session: &Session) -> anyhow::Result<()> {
    isola::logging::log_to(&session.results_dir().join("run.log"))
}

/// A headless run: what became of each analysis.
#[derive(Serialize)]
struct RunSummary {
    session: PathBuf,
    /// This run's shard `index` of `count`, when it was given one.
    shard: Option<ShardSummary>,
    analyses: Vec<AnalysisRun>,
    /// With --convergence: each analysis at twice the resolution, and what changed.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    convergence: Vec<ConvergenceRun>,
    /// The results this run assembled (their CSV files).
    #[serde(flatten)]
    done: Done,
}

/// `--shard I/N`.
#[derive(Serialize)]
struct ShardSummary {
    index: usize,
    count: usize,
}

/// One analysis of the run: its outcome, the seconds it took here and its result's CSV file.
#[derive(Serialize)]
struct AnalysisRun {
    name: String,
    kind: &'static str,
    #[serde(flatten)]
    outcome: RunOutcome,
    seconds: f64,
    csv: PathBuf,
    #[serde(skip)]
    shard: Shard,
}

/// [`Outcome`] as the summary reports it.
#[derive(Serialize)]
#[serde(tag = "outcome", rename_all = "snake_case")]
enum RunOutcome {
    /// Its result was already complete, verified and current.
    UpToDate,
    /// The result of these settings kept from before is the stored result again.
    BroughtBack { compute_seconds: f64 },
    /// Complete now; `compute_seconds` on every host, assembly included.
    Completed {
        chunks_computed: usize,
        compute_seconds: f64,
        assembled_here: bool,
        /// What the user should know about the result (a map's window that cuts a branch).
        #[serde(skip_serializing_if = "Vec::is_empty")]
        notes: Vec<String>,
    },
    /// This shard's chunks are done; others are still missing.
    ShardDone {
        chunks_computed: usize,
        missing: usize,
    },
    /// Computed but not stored: the session was edited during the run, and the stored result
    /// is of its settings now.
    Superseded { chunks_computed: usize },
}

impl From<Outcome> for RunOutcome {
    fn from(outcome: Outcome) -> Self {
        match outcome {
            Outcome::UpToDate => RunOutcome::UpToDate,
            Outcome::BroughtBack { seconds } => RunOutcome::BroughtBack {
                compute_seconds: seconds,
            },
            Outcome::Superseded { chunks_computed } => RunOutcome::Superseded { chunks_computed },
            Outcome::Completed {
                chunks_computed,
                seconds,
                assembled_here,
                notes,
            } => RunOutcome::Completed {
                chunks_computed,
                compute_seconds: seconds,
                assembled_here,
                notes,
            },
            Outcome::ShardDone {
                chunks_computed,
                missing,
            } => RunOutcome::ShardDone {
                chunks_computed,
                missing,
            },
        }
    }
}

pub fn run(args: &RunArgs, out: Output) -> anyhow::Result<()> {
    let session = Session::load(&args.session)?;
    log_to_file(&session)?;
    tracing::info!(session = %args.session.display(), "run started");
    let entries = selected(&session, args.only.as_deref())?;
    let threads = isola::jobs::worker_count(args.threads)?;
    let budget = Budget::on_this_machine(threads, args.budget, args.force);
    budget::check_all(&session, entries.iter().copied(), &budget)?;
    let doubled = if args.convergence {
        let doubled = convergence::at_twice_the_resolution(&session)?;
        let twins = entries.iter().filter_map(|e| doubled.analysis(&e.name));
        budget::check_all(&doubled, twins, &budget)?;
        Some(doubled)
    } else {
        None
    };
    let total_started = Instant::now();
    let mut analyses = Vec::new();
    let mut compared = Vec::new();
    let mut done = Done::default();
    for entry in entries {
        let analysis = run_one(&session, entry, args, out, &entry.name)?;
        if analysis.assembled_here() {
            done.wrote.push(analysis.csv.clone());
        }
        out.show(&analysis);
        if let Some(doubled) = &doubled {
            let twin = doubled
                .analysis(&entry.name)
                .expect("the doubled session has the same analyses");
            let twice = run_one(doubled, twin, args, out, &format!("{} ×2", entry.name))?;
            if twice.assembled_here() {
                done.wrote.push(twice.csv.clone());
            }
            let view = |s: &Session, e| {
                convergence::stored_view(s, e)
                    .ok_or_else(|| anyhow::anyhow!("{}: no complete result to compare", e.name))
            };
            let run = ConvergenceRun {
                name: entry.name.clone(),
                kind: entry.settings.kind(),
                resolution: entry.settings.resolution_in_words(),
                doubled: twin.settings.resolution_in_words(),
                seconds: twice.seconds,
                csv: twice.csv,
                changes: convergence::compare(&view(&session, entry)?, &view(doubled, twin)?),
            };
            out.show(&run);
            compared.push(run);
        }
        analyses.push(analysis);
    }
    done.elapsed_seconds = total_started.elapsed().as_secs_f64();
    out.report(&RunSummary {
        session: args.session.clone(),
        shard: args.shard.map(|s| ShardSummary {
            index: s.index,
            count: s.count,
        }),
        analyses,
        convergence: compared,
        done,
    })
}

/// Runs analysis `entry` of `session` through its store, with progress shown as `label`.
fn run_one(
    session: &Session,
    entry: &isola::session::AnalysisEntry,
    args: &RunArgs,
    out: Output,
    label: &str,
) -> anyhow::Result<AnalysisRun> {
    let shard = args.shard.unwrap_or(Shard::ALL);
    let progress = Arc::new(Progress::new(0));
    let ctx = JobContext::new(args.threads, progress.clone())?;
    // the reporter ends as soon as this sender is dropped, not at its next tick
    let (finished, run_ended) = mpsc::channel::<()>();
    let reporter = out
        .shows_progress()
        .then(|| spawn_reporter(label.to_string(), progress.clone(), run_ended));
    let started = Instant::now();
    let role = Role {
        shard,
        worker: args.worker,
    };
    let outcome = ctx.run(|| run_analysis_as(session, entry, role, &progress));
    drop(finished);
    if let Some(reporter) = reporter {
        let _ = reporter.join();
    }
    Ok(AnalysisRun {
        name: entry.name.clone(),
        kind: entry.settings.kind(),
        outcome: RunOutcome::from(outcome??),
        seconds: started.elapsed().as_secs_f64(),
        csv: ResultPaths::new(session, &entry.name).csv,
        shard,
    })
}

impl AnalysisRun {
    /// Whether this run assembled the result (and so wrote its files).
    fn assembled_here(&self) -> bool {
        matches!(
            self.outcome,
            RunOutcome::Completed {
                assembled_here: true,
                ..
            }
        )
    }
}

/// One analysis at twice the resolution: where its result is and what changed.
#[derive(Serialize)]
struct ConvergenceRun {
    name: String,
    kind: &'static str,
    /// The resolution of the session's result, and of the doubled run, in words.
    resolution: String,
    doubled: String,
    seconds: f64,
    csv: PathBuf,
    changes: Changes,
}

impl Summary for ConvergenceRun {
    fn print_text(&self) {
        say!(
            "{} at twice the resolution ({}; the result: {}) in {:.2} s → {}",
            self.name,
            self.doubled,
            self.resolution,
            self.seconds,
            self.csv.display()
        );
        match &self.changes {
            Changes::Basin(b) => {
                say!(
                    "  {} of {} cells changed attractor ({:.4} %); largest amplitude difference {:.2e}",
                    b.changed,
                    b.cells,
                    100.0 * b.share,
                    b.largest_amplitude_difference
                );
                print_seen("  attractors gained", &b.gained);
                print_seen("  attractors lost", &b.lost);
            }
            Changes::Responses(r) => print_responses("  ", r),
            Changes::Family { members } => {
                for m in members {
                    say!("  member {}:", m.value);
                    print_responses("    ", &m.changes);
                }
            }
            Changes::Hunt {
                responses,
                bifurcations,
            } => {
                print_responses("  ", responses);
                print_numbers(bifurcations);
            }
            Changes::Map(m) => say!(
                "  {} of {} cells changed their stable responses; largest amplitude difference {:.2e}",
                m.changed,
                m.cells,
                m.largest_amplitude_difference
            ),
            Changes::Numbers(n) => print_numbers(n),
            Changes::Nothing => say!("  nothing is integrated"),
        }
    }
}

fn print_seen(what: &str, seen: &[convergence::Seen]) {
    if seen.is_empty() {
        say!("{what}: none");
        return;
    }
    let items: Vec<String> = seen
        .iter()
        .map(|s| {
            let at = s.omega.map_or(String::new(), |w| format!(" at ω {w}"));
            let amplitude = s
                .amplitude
                .map_or(String::new(), |a| format!(" (amplitude {a:.6})"));
            format!("{}{at}{amplitude}", s.response_type)
        })
        .collect();
    say!("{what}: {}", items.join("; "));
}

fn print_responses(indent: &str, r: &convergence::ResponseChanges) {
    say!(
        "{indent}{} responses and {} other outcomes: {} gained, {} lost; largest amplitude \
         difference {:.2e}",
        r.responses,
        r.outcomes,
        r.gained.len(),
        r.lost.len(),
        r.largest_amplitude_difference
    );
    print_seen(&format!("{indent}responses gained"), &r.gained);
    print_seen(&format!("{indent}responses lost"), &r.lost);
    say!(
        "{indent}{} branches, {} with edges moved",
        r.branches,
        r.edges_moved.len()
    );
    for e in &r.edges_moved {
        say!(
            "{indent}  {}: ω {}–{} → {}–{}",
            e.response_type,
            e.omega_min[0],
            e.omega_max[0],
            e.omega_min[1],
            e.omega_max[1]
        );
    }
    print_seen(&format!("{indent}branches gained"), &r.branches_gained);
    print_seen(&format!("{indent}branches lost"), &r.branches_lost);
}

fn print_numbers(n: &convergence::NumberChanges) {
    say!(
        "  largest difference of {}: {:.2e} ({} compared, {} in one run only)",
        n.of,
        n.largest_difference,
        n.compared,
        n.unmatched
    );
}

impl Summary for AnalysisRun {
    fn print_text(&self) {
        let (name, csv) = (&self.name, self.csv.display());
        match self.outcome {
            RunOutcome::UpToDate => say!("{name}: up to date ({csv})"),
            RunOutcome::BroughtBack { compute_seconds } => say!(
                "{name}: brought back the result kept for these settings (it took \
                 {compute_seconds:.2} s to compute) → {csv}"
            ),
            RunOutcome::Superseded { chunks_computed } => say!(
                "{name}: not stored ({chunks_computed} chunks computed now): the session was \
                 edited during the run, and the result of its settings now is complete ({csv}); \
                 this one is kept, to be brought back if its settings come back"
            ),
            RunOutcome::Completed {
                chunks_computed,
                compute_seconds,
                assembled_here,
                ref notes,
            } => {
                say!(
                    "{name}: done in {:.2} s ({chunks_computed} chunks computed now, {compute_seconds:.2} s in all; {}) → {csv}",
                    self.seconds,
                    if assembled_here {
                        "assembled here"
                    } else {
                        "assembled by another run"
                    },
                );
                for note in notes {
                    say!("  note: {note}");
                }
            }
            RunOutcome::ShardDone {
                chunks_computed,
                missing,
            } if self.shard == Shard::ALL => say!(
                "{name}: this run computed {chunks_computed} chunks; {missing} chunks still missing (other runs have them)"
            ),
            RunOutcome::ShardDone {
                chunks_computed,
                missing,
            } => say!(
                "{name}: shard {}/{} computed {chunks_computed} chunks; {missing} chunks still missing",
                self.shard.index,
                self.shard.count
            ),
        }
    }
}

impl Summary for RunSummary {
    /// The analyses were shown as each finished.
    fn print_text(&self) {
        say!("session done in {:.2} s", self.done.elapsed_seconds);
    }
}

/// A progress bar on a terminal; a plain line every 10 s otherwise (nohup, batch jobs). It
/// ticks every 100 ms until `run_ended` disconnects, and then ends at once.
fn spawn_reporter(
    name: String,
    progress: Arc<Progress>,
    run_ended: mpsc::Receiver<()>,
) -> std::thread::JoinHandle<()> {
    let tick = move || {
        matches!(
            run_ended.recv_timeout(Duration::from_millis(100)),
            Err(mpsc::RecvTimeoutError::Timeout)
        )
    };
    std::thread::spawn(move || {
        if std::io::stderr().is_terminal() {
            let bar = indicatif::ProgressBar::new(0);
            bar.set_style(
                indicatif::ProgressStyle::with_template(
                    "{msg:12} [{bar:40}] {pos}/{len} ({percent} %) {elapsed} eta {eta}",
                )
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
                .progress_chars("=> "),
            );
            bar.set_message(name.clone());
            loop {
                let (d, t) = progress.get();
                bar.set_length(t as u64);
                bar.set_position(d as u64);
                // set at every tick, as the phase changes both ways: a response is open
                // until it announces its work
                bar.set_message(if progress.in_open_phase() {
                    format!("{name}: {} points", progress.open_steps())
                } else {
                    name.clone()
                });
                if !tick() {
                    break;
                }
            }
            bar.finish_and_clear();
        } else {
            let started = Instant::now();
            let mut last = Instant::now();
            while tick() {
                if last.elapsed() >= Duration::from_secs(10) && progress.in_open_phase() {
                    eprintln!(
                        "{name}: continuing, {} points after {:.0} s",
                        progress.open_steps(),
                        started.elapsed().as_secs_f64()
                    );
                    last = Instant::now();
                } else if last.elapsed() >= Duration::from_secs(10) {
                    let (d, t) = progress.get();
                    eprintln!(
                        "{name}: {d}/{t} ({:.0} %) after {:.0} s",
                        100.0 * progress.fraction(),
                        started.elapsed().as_secs_f64()
                    );
                    last = Instant::now();
                }
            }
        }
    })
}

#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The session file.
    session: PathBuf,
    /// The analysis whose result to export.
    #[arg(long)]
    analysis: String,
    /// A companion table instead of the main result, as its file names it (`NAME.TABLE.csv`):
    /// `attractors` or `points` (basin), `points` or `outcomes` (response), `responses`
    /// (family), `branches` (hunt), `jumps` (sweeps)...; one it lacks is named with those
    /// it has.
    #[arg(long)]
    table: Option<String>,
    /// Keep rows where COLUMN OP VALUE holds (OP: = != < <= > >=); repeat to combine.
    #[arg(long = "where", value_name = "COLUMN OP VALUE")]
    filters: Vec<String>,
    /// Where to write the selection.
    #[arg(long)]
    csv: PathBuf,
}

/// An export: the rows of a result kept by the filters, and where they went.
#[derive(Serialize)]
struct ExportSummary<'a> {
    session: &'a Path,
    analysis: &'a str,
    table: Option<&'a str>,
    filters: &'a [String],
    rows: usize,
    #[serde(flatten)]
    done: Done,
}

pub fn export(args: &ExportArgs, out: Output) -> anyhow::Result<()> {
    let started = Instant::now();
    let session = Session::load(&args.session)?;
    let entry = session.analysis(&args.analysis).ok_or_else(|| {
        let names: Vec<&str> = session.analyses.iter().map(|a| a.name.as_str()).collect();
        anyhow::anyhow!(
            "no analysis '{}' in {}: one of {}",
            args.analysis,
            args.session.display(),
            names.join(", ")
        )
    })?;
    let filters: Vec<Filter> = args
        .filters
        .iter()
        .map(|f| parse_filter(f))
        .collect::<anyhow::Result<_>>()?;
    let rows = export_selection(&session, entry, args.table.as_deref(), &filters, &args.csv)
        .map_err(|e| match e {
            SelectionError::NotCurrent(_) => anyhow::anyhow!(
                "{e}; run `isola run {} --only {}` first",
                args.session.display(),
                entry.name
            ),
            other => anyhow::Error::from(other),
        })?;
    out.report(&ExportSummary {
        session: &args.session,
        analysis: &entry.name,
        table: args.table.as_deref(),
        filters: &args.filters,
        rows,
        done: Done {
            wrote: vec![args.csv.clone()],
            elapsed_seconds: started.elapsed().as_secs_f64(),
        },
    })
}

impl Summary for ExportSummary<'_> {
    fn print_text(&self) {
        say!(
            "wrote {} rows of {} to {}",
            self.rows,
            self.analysis,
            self.done.wrote[0].display()
        );
    }
}
