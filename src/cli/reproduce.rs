//! `isola reproduce`: the paper's claims, each beside what isola computes, with a verdict.

use std::time::Instant;

use clap::Args;
use isola::analysis::Progress;
use isola::jobs::JobContext;
use isola::reproduce::{Claim, Mode, reproduce};
use serde::Serialize;

use super::output::{Done, Output, Summary};

#[derive(Debug, Args)]
pub struct ReproduceArgs {
    /// Coarser grids of starts for the brute-force parts (about 20 s on two cores); the
    /// continuation-based locations are computed exactly as in the full run.
    #[arg(long)]
    quick: bool,
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    threads: usize,
}

/// Every claim, and how many agree, differ or are imprecise.
#[derive(Serialize)]
struct ReproduceSummary {
    mode: Mode,
    claims: Vec<Claim>,
    agrees: usize,
    differs: usize,
    imprecise: usize,
    #[serde(flatten)]
    done: Done,
}

pub fn run(args: &ReproduceArgs, out: Output) -> anyhow::Result<()> {
    let mode = if args.quick { Mode::Quick } else { Mode::Full };
    let progress = std::sync::Arc::new(Progress::new(0));
    let ctx = JobContext::new(args.threads, progress.clone())?;
    let started = Instant::now();
    let claims = ctx.run(|| {
        reproduce(mode, &progress, |c| {
            if out.shows_progress() {
                eprintln!(
                    "[{:6.1} s] {:<22} {}",
                    started.elapsed().as_secs_f64(),
                    c.id,
                    c.verdict.as_str()
                );
            }
        })
    })??;
    let count = |v: isola::reproduce::Verdict| claims.iter().filter(|c| c.verdict == v).count();
    out.report(&ReproduceSummary {
        mode,
        agrees: count(isola::reproduce::Verdict::Agrees),
        differs: count(isola::reproduce::Verdict::Differs),
        imprecise: count(isola::reproduce::Verdict::Imprecise),
        claims,
        done: Done {
            elapsed_seconds: started.elapsed().as_secs_f64(),
            ..Done::default()
        },
    })
}

/// `text` cut into lines of at most `width` characters at spaces.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > width {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

impl Summary for ReproduceSummary {
    fn print_text(&self) {
        say!(
            "{} claims of the paper checked ({} mode) in {:.1} s: {} agree, {} differ, {} imprecise",
            self.claims.len(),
            match self.mode {
                Mode::Quick => "quick",
                Mode::Full => "full",
            },
            self.done.elapsed_seconds,
            self.agrees,
            self.differs,
            self.imprecise
        );
        say!();
        say!(
            "{:<22} {:<10} {:>22}  figure",
            "claim",
            "verdict",
            "isola ± precision"
        );
        for c in &self.claims {
            say!(
                "{:<22} {:<10} {:>22}  {}",
                c.id,
                c.verdict.as_str(),
                format!("{} ± {:.1e}", significant(c.value), c.precision),
                c.figure
            );
        }
        for c in &self.claims {
            say!();
            say!("{} [{}] — {}", c.id, c.figure, c.verdict.as_str());
            let field = |label: &str, text: &str| {
                for (i, line) in wrap(text, 84).iter().enumerate() {
                    say!("  {:<9} {line}", if i == 0 { label } else { "" });
                }
            };
            field("paper", c.paper);
            field("isola", &c.isola);
            let mut value = format!(
                "{} ± {:.1e} ({})",
                significant(c.value),
                c.precision,
                c.precision_from
            );
            if let (Some(p), Some(d)) = (c.paper_value, c.difference) {
                value.push_str(&format!("; paper {}, difference {d:+.4}", significant(p)));
            }
            field("value", &value);
            field("note", &c.note);
        }
    }
}

/// A value with enough digits for its size: counts as integers, the rest to 6 significant
/// digits (more where it is located to better: the folds and limits).
fn significant(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e6 {
        format!("{x:.0}")
    } else if x.abs() >= 1.0 {
        format!("{x:.9}")
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    } else {
        format!("{x:.9}")
    }
}
