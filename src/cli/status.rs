//! `isola status`: where each analysis of a session stands, readable while runs (here or on
//! the nodes of a cluster) compute it: the stored result, and the chunks done, claimed and
//! missing, by host, with rates.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::{Duration, SystemTime};

use clap::Args;
use isola::session::Session;
use isola::session::run::survey_of;
use isola::session::store::survey::{Survey, host_of};
use isola::session::store::{self, ResultPaths};

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

/// Rates are taken over the chunks saved in this last stretch of time.
const RATE_WINDOW: Duration = Duration::from_secs(300);

pub fn run(args: &StatusArgs) -> anyhow::Result<()> {
    let session = Session::load(&args.session)?;
    let mut incomplete = Vec::new();
    for entry in super::run::selected(&session, args.only.as_deref())? {
        let paths = ResultPaths::new(&session, &entry.name);
        let fingerprint = session.fingerprint(entry);
        let result = match store::verified(&paths) {
            Ok(m) if m.fingerprint == fingerprint => format!(
                "complete, verified ({} files, assembled by {})",
                m.files.len(),
                host_of(&m.assembled_by)
            ),
            Ok(_) => "stale (computed for other settings, device or numerics)".into(),
            Err(why) => format!("none ({why})"),
        };
        let current = result.starts_with("complete");
        if !current {
            incomplete.push(entry.name.clone());
        }
        println!(
            "{} ({}): result {result}",
            entry.name,
            entry.settings.kind()
        );
        if current {
            continue;
        }
        print_survey(&survey_of(&session, entry));
    }
    if args.verify && !incomplete.is_empty() {
        anyhow::bail!("no complete, current result for {}", incomplete.join(", "));
    }
    Ok(())
}

/// One host's part.
#[derive(Default)]
struct Host {
    done: usize,
    claimed: usize,
    seconds: f64,
    recent: Vec<SystemTime>,
}

fn print_survey(s: &Survey) {
    println!(
        "  chunks: {} of {} done, {} claimed, {} missing{}",
        s.done.len(),
        s.chunks,
        s.claimed.len(),
        s.missing(),
        if s.bad.is_empty() {
            String::new()
        } else {
            format!(" ({} damaged, to be recomputed)", s.bad.len())
        }
    );
    let now = SystemTime::now();
    let mut hosts: BTreeMap<String, Host> = BTreeMap::new();
    for d in &s.done {
        let h = hosts.entry(d.host.clone()).or_default();
        h.done += 1;
        h.seconds += d.seconds;
        if now.duration_since(d.saved).unwrap_or_default() <= RATE_WINDOW {
            h.recent.push(d.saved);
        }
    }
    for (_, holder) in &s.claimed {
        hosts
            .entry(host_of(holder).to_string())
            .or_default()
            .claimed += 1;
    }
    if hosts.is_empty() {
        return;
    }
    println!(
        "  {:<24} {:>6} {:>8} {:>11} {:>9}",
        "host", "done", "claimed", "chunks/min", "s/chunk"
    );
    let mut total_rate = 0.0;
    for (name, h) in &hosts {
        let rate = rate_per_minute(&h.recent, now);
        total_rate += rate;
        let per_chunk = if h.done > 0 {
            format!("{:.2}", h.seconds / h.done as f64)
        } else {
            "-".into()
        };
        println!(
            "  {name:<24} {:>6} {:>8} {:>11.1} {per_chunk:>9}",
            h.done, h.claimed, rate
        );
    }
    if total_rate > 0.0 && s.missing() > 0 {
        println!(
            "  at {total_rate:.1} chunks/min: about {:.0} s to go",
            60.0 * s.missing() as f64 / total_rate
        );
    }
}

/// Chunks a minute over those saved in the last [`RATE_WINDOW`] (0 if none).
fn rate_per_minute(saved: &[SystemTime], now: SystemTime) -> f64 {
    let Some(first) = saved.iter().min() else {
        return 0.0;
    };
    let span = now
        .duration_since(*first)
        .unwrap_or_default()
        .max(Duration::from_secs(1))
        .min(RATE_WINDOW);
    saved.len() as f64 * 60.0 / span.as_secs_f64()
}
