//! `isola run`: a session's analyses headless, resumable, shardable; `isola export`: a
//! selection of a result to CSV.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::Context;
use clap::Args;
use isola::analysis::Progress;
use isola::jobs::JobContext;
use isola::session::Session;
use isola::session::budget::{self, Budget};
use isola::session::output::{Protected, check_target};
use isola::session::run::{Outcome, Role, Shard, run_analysis_as};
use isola::session::store::{self, ResultPaths};

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

pub fn run(args: &RunArgs) -> anyhow::Result<()> {
    let session = Session::load(&args.session)?;
    log_to_file(&session)?;
    tracing::info!(session = %args.session.display(), "run started");
    let entries = selected(&session, args.only.as_deref())?;
    let shard = args.shard.unwrap_or(Shard::ALL);
    let threads = isola::jobs::worker_count(args.threads)?;
    let budget = Budget::on_this_machine(threads, args.budget, args.force);
    budget::check_all(&session, entries.iter().copied(), &budget)?;
    let total_started = Instant::now();
    for entry in entries {
        let progress = Arc::new(Progress::new(0));
        let (ctx, _rx) = JobContext::<()>::new(args.threads, progress.clone())?;
        let done = Arc::new(AtomicBool::new(false));
        let reporter = spawn_reporter(entry.name.clone(), progress.clone(), done.clone());
        let started = Instant::now();
        let role = Role {
            shard,
            worker: args.worker,
        };
        let outcome = ctx.run(|| run_analysis_as(&session, entry, role, &progress));
        done.store(true, Ordering::Relaxed);
        let _ = reporter.join();
        let outcome = outcome??;
        let csv = ResultPaths::new(&session, &entry.name).csv;
        match outcome {
            Outcome::UpToDate => println!("{}: up to date ({})", entry.name, csv.display()),
            Outcome::Completed {
                chunks_computed,
                seconds,
                assembled_here,
            } => println!(
                "{}: done in {:.2} s ({} chunks computed now, {:.2} s in all; {}) → {}",
                entry.name,
                started.elapsed().as_secs_f64(),
                chunks_computed,
                seconds,
                if assembled_here {
                    "assembled here"
                } else {
                    "assembled by another run"
                },
                csv.display()
            ),
            Outcome::ShardDone {
                chunks_computed,
                missing,
            } if shard == Shard::ALL => println!(
                "{}: this run computed {} chunks; {} chunks still missing (other runs have them)",
                entry.name, chunks_computed, missing
            ),
            Outcome::ShardDone {
                chunks_computed,
                missing,
            } => println!(
                "{}: shard {}/{} computed {} chunks; {} chunks still missing",
                entry.name, shard.index, shard.count, chunks_computed, missing
            ),
        }
    }
    println!(
        "session done in {:.2} s",
        total_started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// A progress bar on a terminal; a plain line every 10 s otherwise (nohup, batch jobs).
fn spawn_reporter(
    name: String,
    progress: Arc<Progress>,
    done: Arc<AtomicBool>,
) -> std::thread::JoinHandle<()> {
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
            while !done.load(Ordering::Relaxed) {
                let (d, t) = progress.get();
                bar.set_length(t as u64);
                bar.set_position(d as u64);
                if progress.in_open_phase() {
                    bar.set_message(format!("{name}: {} points", progress.open_steps()));
                }
                std::thread::sleep(Duration::from_millis(100));
            }
            bar.finish_and_clear();
        } else {
            let started = Instant::now();
            let mut last = Instant::now();
            while !done.load(Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(100));
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
    /// A companion table instead of the main result: `attractors` (basin), `responses`
    /// (family) or `branches` (hunt).
    #[arg(long, value_parser = ["attractors", "responses", "branches"])]
    table: Option<String>,
    /// Keep rows where COLUMN OP VALUE holds (OP: = != < <= > >=); repeat to combine.
    #[arg(long = "where", value_name = "COLUMN OP VALUE")]
    filters: Vec<String>,
    /// Where to write the selection.
    #[arg(long)]
    csv: PathBuf,
}

/// One `--where` condition.
#[derive(Debug, PartialEq)]
struct Filter {
    column: String,
    op: &'static str,
    value: String,
    /// The value as a number, if it is one.
    number: Option<f64>,
}

/// `COLUMN OP VALUE`, OP one of `= == != < <= > >=`; an ordering needs a number.
fn parse_filter(s: &str) -> anyhow::Result<Filter> {
    let usage = "expected COLUMN OP VALUE with OP one of = != < <= > >= (e.g. \"omega>=3.5\")";
    let at = s
        .find(['<', '>', '=', '!'])
        .ok_or_else(|| anyhow::anyhow!("--where '{s}': no operator; {usage}"))?;
    let (column, rest) = (s[..at].trim(), &s[at..]);
    let op = ["<=", ">=", "!=", "==", "=", "<", ">"]
        .into_iter()
        .find(|op| rest.starts_with(op))
        .ok_or_else(|| anyhow::anyhow!("--where '{s}': '!' alone is no operator; {usage}"))?;
    let value = rest[op.len()..].trim();
    if column.is_empty() {
        anyhow::bail!("--where '{s}': no column before '{op}'; {usage}");
    }
    if value.is_empty() || value.starts_with(['<', '>', '=', '!']) {
        anyhow::bail!("--where '{s}': '{value}' is not a value; {usage}");
    }
    let number = value.parse::<f64>().ok().filter(|x| x.is_finite());
    if matches!(op, "<" | "<=" | ">" | ">=") && number.is_none() {
        anyhow::bail!(
            "--where '{s}': '{op}' compares numbers and '{value}' is not a finite number"
        );
    }
    Ok(Filter {
        column: column.to_string(),
        op: if op == "==" { "=" } else { op },
        value: value.to_string(),
        number,
    })
}

impl Filter {
    /// True if `cell` passes: numbers compare as numbers (an empty or text cell never passes
    /// an ordering), text compares exactly.
    fn keeps(&self, cell: &str) -> bool {
        use std::cmp::Ordering as O;
        let order = match (cell.parse::<f64>(), self.number) {
            (Ok(a), Some(b)) => a.partial_cmp(&b),
            (_, Some(_)) if matches!(self.op, "<" | "<=" | ">" | ">=") => None,
            _ => Some(cell.cmp(self.value.as_str())),
        };
        matches!(
            (self.op, order),
            ("=", Some(O::Equal))
                | ("!=", Some(O::Less | O::Greater))
                | ("<", Some(O::Less))
                | ("<=", Some(O::Less | O::Equal))
                | (">", Some(O::Greater))
                | (">=", Some(O::Greater | O::Equal))
        )
    }
}

pub fn export(args: &ExportArgs) -> anyhow::Result<()> {
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
    let paths = ResultPaths::new(&session, &entry.name);
    let target = check_target(
        &args.csv,
        &Protected::session(&session.path, &session.results_dir()),
    )?;
    let fingerprint = session.fingerprint(entry);
    let not_current = |why: String| {
        anyhow::anyhow!(
            "{}: no current result ({why}); run `isola run {} --only {}` first",
            entry.name,
            args.session.display(),
            entry.name
        )
    };
    let source = match &args.table {
        Some(table) => paths.csv.with_extension(format!("{table}.csv")),
        None => paths.csv.clone(),
    };
    let kept = store::with_verified(&paths, |m| -> anyhow::Result<usize> {
        if m.fingerprint != fingerprint {
            return Err(not_current(
                "the stored one was computed for other settings, device or numerics".into(),
            ));
        }
        let name = source.file_name().unwrap_or_default().to_string_lossy();
        if !m.files.iter().any(|f| f.name == name) {
            anyhow::bail!(
                "{}: a {} has no {} table",
                entry.name,
                entry.settings.kind(),
                args.table.as_deref().unwrap_or("main")
            );
        }
        let mut reader =
            csv::Reader::from_path(&source).with_context(|| source.display().to_string())?;
        let headers = reader.headers()?.clone();
        let columns: Vec<usize> = filters
            .iter()
            .map(|f| {
                headers.iter().position(|h| h == f.column).ok_or_else(|| {
                    anyhow::anyhow!(
                        "--where: no column '{}'; columns: {}",
                        f.column,
                        headers.iter().collect::<Vec<_>>().join(", ")
                    )
                })
            })
            .collect::<anyhow::Result<_>>()?;
        let mut kept = 0;
        let mut bytes = Vec::new();
        {
            let mut w = csv::Writer::from_writer(&mut bytes);
            w.write_record(&headers)?;
            for row in reader.records() {
                let row = row?;
                if filters.iter().zip(&columns).all(|(f, &c)| f.keeps(&row[c])) {
                    w.write_record(&row)?;
                    kept += 1;
                }
            }
            w.flush()?;
        }
        target.write(&bytes)?;
        Ok(kept)
    })
    .map_err(|why| not_current(why.to_string()))??;
    println!(
        "wrote {} rows of {} to {}",
        kept,
        entry.name,
        args.csv.display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn where_is_parsed_strictly() {
        let f = parse_filter("omega >= 3.5").unwrap();
        assert_eq!(
            (f.column.as_str(), f.op, f.number),
            ("omega", ">=", Some(3.5))
        );
        assert_eq!(parse_filter("omega==3.7").unwrap().op, "=");
        assert!(parse_filter("ratio=1:2").unwrap().keeps("1:2"));
        for bad in [
            "omega<abc",
            "omega",
            "=3",
            "omega=",
            "omega=<3",
            "omega!3",
            "a<nan",
            "a>inf",
        ] {
            assert!(parse_filter(bad).is_err(), "{bad}");
        }
        let f = parse_filter("amplitude_stretch>0.1").unwrap();
        assert!(f.keeps("0.2") && !f.keeps("0.05") && !f.keeps(""));
        let f = parse_filter("branch!=3").unwrap();
        assert!(f.keeps("4") && !f.keeps("3.0") && f.keeps(""));
    }
}
