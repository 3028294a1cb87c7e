//! `isola status`: where each analysis of a session stands, readable while runs (here or on
//! the nodes of a cluster) compute it: the stored result, and the chunks done, claimed and
//! missing, by host, with rates.

use std::path::{Path, PathBuf};
use std::time::{Instant, SystemTime};

use clap::Args;
use isola::session::Session;
use isola::session::run::survey_of;
use isola::session::store::survey::{HostWork, Survey, host_of};
use isola::session::store::{self, ResultPaths};
use serde::Serialize;

use super::output::{Done, Output, Summary};

#[derive(Debug, Args)]
pub struct StatusArgs {
    /// The session file.
    session: PathBuf,
    /// Only this analysis.
    #[arg(long)]
    only: Option<String>,
    /// Exit with status 1 unless every analysis shown has a complete, verified, current result.
    #[arg(long)]
    verify: bool,
}

/// Where each analysis of a session stands.
#[derive(Serialize)]
struct StatusSummary<'a> {
    session: &'a Path,
    analyses: Vec<AnalysisStatus>,
    #[serde(flatten)]
    done: Done,
}

/// One analysis: its stored result and, unless that is complete and current, its chunks.
#[derive(Serialize)]
struct AnalysisStatus {
    name: String,
    kind: &'static str,
    #[serde(flatten)]
    result: Stored,
    /// Unless the result is current: one of these settings is kept from before (replaced by
    /// other settings'), which a run brings back without computing.
    kept: bool,
    chunks: Option<Chunks>,
}

/// The state of an analysis's stored result.
#[derive(Serialize)]
#[serde(tag = "result", rename_all = "snake_case")]
enum Stored {
    /// Complete, verified and current.
    Complete { files: usize, assembled_by: String },
    /// Computed for other settings, device or numerics.
    Stale,
    /// No usable result, and why.
    #[serde(rename = "none")]
    Missing { reason: String },
}

/// The chunks of an unfinished analysis, by host, with the rates they are done at.
#[derive(Serialize)]
struct Chunks {
    total: usize,
    done: usize,
    claimed: usize,
    missing: usize,
    /// Chunk files that fail their checks (they will be recomputed).
    damaged: usize,
    hosts: Vec<Host>,
    /// All hosts together (none before any host has worked), and the seconds to go at that
    /// rate (while chunks are missing).
    chunks_per_minute: Option<f64>,
    seconds_left: Option<f64>,
}

/// One host's part of the work.
#[derive(Serialize)]
struct Host {
    host: String,
    done: usize,
    claimed: usize,
    chunks_per_minute: f64,
    /// Compute seconds per chunk done (none before its first).
    seconds_per_chunk: Option<f64>,
}

impl Chunks {
    fn of(s: &Survey) -> Self {
        let hosts = s.by_host(SystemTime::now());
        Chunks {
            total: s.chunks,
            done: s.done.len(),
            claimed: s.claimed.len(),
            missing: s.missing(),
            damaged: s.bad.len(),
            chunks_per_minute: (!hosts.is_empty()).then(|| HostWork::total_per_minute(&hosts)),
            // a time to go only while some run computes (claims chunks)
            seconds_left: (s.seconds_left(&hosts))
                .filter(|_| s.missing() > 0 && !s.claimed.is_empty()),
            hosts: hosts
                .into_iter()
                .map(|h| Host {
                    seconds_per_chunk: (h.done > 0).then(|| h.seconds / h.done as f64),
                    host: h.host,
                    done: h.done,
                    claimed: h.claimed,
                    chunks_per_minute: h.per_minute,
                })
                .collect(),
        }
    }

    /// Prints the chunks' lines of the text summary.
    fn print_text(&self) {
        say!(
            "  chunks: {} of {} done, {} claimed, {} missing{}",
            self.done,
            self.total,
            self.claimed,
            self.missing,
            if self.damaged == 0 {
                String::new()
            } else {
                format!(" ({} damaged, to be recomputed)", self.damaged)
            }
        );
        if self.hosts.is_empty() {
            return;
        }
        say!(
            "  {:<24} {:>6} {:>8} {:>11} {:>9}",
            "host",
            "done",
            "claimed",
            "chunks/min",
            "s/chunk"
        );
        for h in &self.hosts {
            let per_chunk = h
                .seconds_per_chunk
                .map_or("-".into(), |s| format!("{s:.2}"));
            say!(
                "  {:<24} {:>6} {:>8} {:>11.1} {per_chunk:>9}",
                h.host,
                h.done,
                h.claimed,
                h.chunks_per_minute
            );
        }
        if let (Some(left), Some(rate)) = (self.seconds_left, self.chunks_per_minute) {
            say!("  at {rate:.1} chunks/min: about {left:.0} s to go");
        } else if self.missing > 0 && self.claimed == 0 {
            say!("  nothing computing it now: isola run resumes it");
        }
    }
}

pub fn run(args: &StatusArgs, out: Output) -> anyhow::Result<()> {
    let started = Instant::now();
    let session = Session::load(&args.session)?;
    let mut analyses = Vec::new();
    for entry in super::run::selected(&session, args.only.as_deref())? {
        let paths = ResultPaths::new(&session, &entry.name);
        let fingerprint = session.fingerprint(entry);
        let stored = || match store::verified(&paths) {
            Ok(m) if m.fingerprint == fingerprint => Stored::Complete {
                files: m.files.len(),
                assembled_by: host_of(&m.assembled_by).to_string(),
            },
            Ok(_) => Stored::Stale,
            Err(why) => Stored::Missing {
                reason: why.to_string(),
            },
        };
        let mut status = AnalysisStatus {
            name: entry.name.clone(),
            kind: entry.settings.kind(),
            result: stored(),
            kept: false,
            chunks: None,
        };
        if !matches!(status.result, Stored::Complete { .. }) {
            let survey = survey_of(&session, entry);
            // a run may have committed the result (and begun to remove its chunks) meanwhile
            status.result = stored();
            if !matches!(status.result, Stored::Complete { .. }) {
                status.chunks = Some(Chunks::of(&survey));
                status.kept = store::earlier::is_kept(&paths, &fingerprint);
            }
        }
        analyses.push(status);
    }
    let incomplete: Vec<&str> = analyses
        .iter()
        .filter(|a| a.chunks.is_some())
        .map(|a| a.name.as_str())
        .collect();
    let verify = (args.verify && !incomplete.is_empty())
        .then(|| anyhow::anyhow!("no complete, current result for {}", incomplete.join(", ")));
    out.report(&StatusSummary {
        session: &args.session,
        analyses,
        done: Done {
            elapsed_seconds: started.elapsed().as_secs_f64(),
            ..Done::default()
        },
    })?;
    verify.map_or(Ok(()), Err)
}

impl Summary for StatusSummary<'_> {
    fn print_text(&self) {
        for a in &self.analyses {
            let result = match &a.result {
                Stored::Complete {
                    files,
                    assembled_by,
                } => format!("complete, verified ({files} files, assembled by {assembled_by})"),
                Stored::Stale => {
                    "stale (computed for other settings, device or numerics)".to_string()
                }
                Stored::Missing { reason } => format!("none ({reason})"),
            };
            say!("{} ({}): result {result}", a.name, a.kind);
            if a.kept {
                say!("  a result of these settings is kept from before: isola run brings it back");
            }
            if let Some(chunks) = &a.chunks {
                chunks.print_text();
            }
        }
    }
}
