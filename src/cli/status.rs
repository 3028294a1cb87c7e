//! `isola status`: where each analysis of a session stands, readable while runs (here or on
//! the nodes of a cluster) compute it: the stored result, and the chunks done, claimed and
//! missing, by host, with rates.

use std::path::PathBuf;
use std::time::SystemTime;

use clap::Args;
use isola::session::Session;
use isola::session::run::survey_of;
use isola::session::store::survey::{HostWork, Survey, host_of};
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

pub fn run(args: &StatusArgs) -> anyhow::Result<()> {
    let session = Session::load(&args.session)?;
    let mut incomplete = Vec::new();
    for entry in super::run::selected(&session, args.only.as_deref())? {
        let paths = ResultPaths::new(&session, &entry.name);
        let fingerprint = session.fingerprint(entry);
        let result = || match store::verified(&paths) {
            Ok(m) if m.fingerprint == fingerprint => Ok(format!(
                "complete, verified ({} files, assembled by {})",
                m.files.len(),
                host_of(&m.assembled_by)
            )),
            Ok(_) => Err("stale (computed for other settings, device or numerics)".to_string()),
            Err(why) => Err(format!("none ({why})")),
        };
        let (kind, name) = (entry.settings.kind(), &entry.name);
        let not_current = match result() {
            Ok(complete) => {
                println!("{name} ({kind}): result {complete}");
                continue;
            }
            Err(why) => why,
        };
        let survey = survey_of(&session, entry);
        // a run may have committed the result (and begun to remove its chunks) meanwhile
        if let Ok(complete) = result() {
            println!("{name} ({kind}): result {complete}");
            continue;
        }
        incomplete.push(name.clone());
        println!("{name} ({kind}): result {not_current}");
        print_survey(&survey);
    }
    if args.verify && !incomplete.is_empty() {
        anyhow::bail!("no complete, current result for {}", incomplete.join(", "));
    }
    Ok(())
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
    let hosts = s.by_host(SystemTime::now());
    if hosts.is_empty() {
        return;
    }
    println!(
        "  {:<24} {:>6} {:>8} {:>11} {:>9}",
        "host", "done", "claimed", "chunks/min", "s/chunk"
    );
    for h in &hosts {
        let per_chunk = if h.done > 0 {
            format!("{:.2}", h.seconds / h.done as f64)
        } else {
            "-".into()
        };
        println!(
            "  {:<24} {:>6} {:>8} {:>11.1} {per_chunk:>9}",
            h.host, h.done, h.claimed, h.per_minute
        );
    }
    if let Some(left) = s.seconds_left(&hosts).filter(|_| s.missing() > 0) {
        let rate = HostWork::total_per_minute(&hosts);
        println!("  at {rate:.1} chunks/min: about {left:.0} s to go");
    }
}
