//! `isola figure`: a publication figure of one analysis of a session; `isola report`: one
//! self-contained HTML page of every analysis, its figure and its tables.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use clap::{Args, ValueEnum};
use isola::analysis::Progress;
use isola::figure::{self, Format, Options, Subject, Theme};
use isola::jobs::JobContext;
use isola::session::output::{Protected, check_target};
use isola::session::results::{ResultView, current_view};
use isola::session::run::{is_current, run_analysis};
use isola::session::{AnalysisEntry, Session};
use serde::Serialize;

use super::output::{Done, Output, Summary};
use super::run::selected;

/// `--format`.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum FormatArg {
    Svg,
    Png,
    Pdf,
}

/// `--theme`.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum ThemeArg {
    Paper,
    Dark,
}

/// A figure's size in pixels (an SVG's user units).
fn parse_pixels(s: &str) -> Result<u32, String> {
    match s.parse::<u32>() {
        Ok(n) if (1..=figure::MAX_SIZE).contains(&n) => Ok(n),
        _ => Err(format!(
            "'{s}': a whole number of pixels from 1 to {}",
            figure::MAX_SIZE
        )),
    }
}

/// How the figures look, shared by `figure` and `report`.
#[derive(Debug, Args)]
struct Look {
    /// Width in pixels.
    #[arg(long, default_value_t = 960, value_parser = parse_pixels)]
    width: u32,
    /// Height in pixels.
    #[arg(long, default_value_t = 600, value_parser = parse_pixels)]
    height: u32,
    /// Colours: dark on white for papers, or light on dark for slides.
    #[arg(long, value_enum, default_value = "paper")]
    theme: ThemeArg,
    /// Worker threads for an analysis computed first (0: one per core).
    #[arg(long, default_value_t = 0)]
    threads: usize,
}

impl Look {
    fn options(&self, format: Format) -> Options {
        Options {
            format,
            width: self.width,
            height: self.height,
            theme: match self.theme {
                ThemeArg::Paper => Theme::Paper,
                ThemeArg::Dark => Theme::Dark,
            },
        }
    }
}

#[derive(Debug, Args)]
pub struct FigureArgs {
    /// The session file.
    session: PathBuf,
    /// The analysis to draw (computed first if its stored result is not current).
    #[arg(long)]
    analysis: String,
    /// File format (default: from --output's extension, else svg).
    #[arg(long, value_enum)]
    format: Option<FormatArg>,
    /// Where to write the figure (default: `SESSION-ANALYSIS.svg`, `.png` or `.pdf` beside
    /// the session file).
    #[arg(long)]
    output: Option<PathBuf>,
    #[command(flatten)]
    look: Look,
}

#[derive(Debug, Args)]
pub struct ReportArgs {
    /// The session file.
    session: PathBuf,
    /// The folder to write `SESSION.html` into (default: the session file's folder).
    #[arg(long)]
    output: Option<PathBuf>,
    #[command(flatten)]
    look: Look,
}

/// The current result of `entry`: the stored one, else computed (and stored) now.
fn view_of(
    session: &Session,
    entry: &AnalysisEntry,
    threads: usize,
    out: Output,
) -> anyhow::Result<ResultView> {
    if !is_current(session, entry) {
        if out.shows_progress() {
            eprintln!("{}: no current result, computing it", entry.name);
        }
        let progress = Arc::new(Progress::new(0));
        let ctx = JobContext::new(threads, progress.clone())?;
        ctx.run(|| run_analysis(session, entry, isola::session::run::Shard::ALL, &progress))??;
    }
    current_view(session, entry)
}

/// A chirp's scalogram, drawn under its envelope.
fn scalogram_of(
    view: &ResultView,
    entry: &AnalysisEntry,
) -> anyhow::Result<Option<isola::analysis::orbit::scalogram::Scalogram>> {
    Ok(match view {
        ResultView::Chirp(c) => Some(figure::chirp_scalogram(c, entry)?),
        _ => None,
    })
}

/// The format `--format` names, else `--output`'s extension, else SVG.
fn format_of(args: &FigureArgs) -> anyhow::Result<Format> {
    Ok(match (args.format, &args.output) {
        (Some(FormatArg::Svg), _) => Format::Svg,
        (Some(FormatArg::Png), _) => Format::Png,
        (Some(FormatArg::Pdf), _) => Format::Pdf,
        (None, Some(path)) => match path.extension().and_then(|e| e.to_str()) {
            Some(ext) => ext.parse().map_err(|_| {
                anyhow::anyhow!(
                    "--output {}: the extension '{ext}' is no figure format: one of {} (or give --format)",
                    path.display(),
                    Format::NAMES.join(", ")
                )
            })?,
            None => Format::Svg,
        },
        (None, None) => Format::Svg,
    })
}

/// A figure written.
#[derive(Serialize)]
struct FigureSummary {
    session: PathBuf,
    analysis: String,
    format: &'static str,
    width: u32,
    height: u32,
    #[serde(flatten)]
    done: Done,
}

impl Summary for FigureSummary {
    fn print_text(&self) {
        say!(
            "wrote the figure of {} ({}×{} {}) to {}",
            self.analysis,
            self.width,
            self.height,
            self.format,
            self.done.wrote[0].display()
        );
    }
}

pub fn run(args: &FigureArgs, out: Output) -> anyhow::Result<()> {
    let started = Instant::now();
    let format = format_of(args)?;
    let session = Session::load(&args.session)?;
    let entry = selected(&session, Some(&args.analysis))
        .map_err(|e| anyhow::anyhow!("--analysis: {e}"))?[0];
    let path = args.output.clone().unwrap_or_else(|| {
        beside(
            &args.session,
            &format!("-{}.{}", entry.name, format.extension()),
        )
    });
    let target = check_target(&path, &protected(&session))?;
    let view = view_of(&session, entry, args.look.threads, out)?;
    let scalogram = scalogram_of(&view, entry)?;
    let reverse = match figure::reverse_sweep(&session, entry) {
        Some(i) => Some(view_of(
            &session,
            &session.analyses[i],
            args.look.threads,
            out,
        )?),
        None => None,
    };
    let subject =
        Subject::of(&session, entry, &view, scalogram.as_ref()).with_reverse(reverse.as_ref());
    let options = args.look.options(format);
    target.write(&figure::render(&subject, &options)?)?;
    out.report(&FigureSummary {
        session: args.session.clone(),
        analysis: entry.name.clone(),
        format: format.extension(),
        width: options.width,
        height: options.height,
        done: Done {
            wrote: vec![path],
            elapsed_seconds: started.elapsed().as_secs_f64(),
        },
    })
}

/// The session file and its stored results: no figure or report may overwrite them.
fn protected(session: &Session) -> Protected {
    Protected::session(&session.path, &session.results_dir())
}

/// `SESSION_STEM` + `suffix` in the session file's folder.
fn beside(session: &Path, suffix: &str) -> PathBuf {
    let stem = session
        .file_stem()
        .map_or("session".into(), |s| s.to_string_lossy().into_owned());
    session.with_file_name(format!("{stem}{suffix}"))
}

/// A report written.
#[derive(Serialize)]
struct ReportSummary {
    session: PathBuf,
    analyses: usize,
    #[serde(flatten)]
    done: Done,
}

impl Summary for ReportSummary {
    fn print_text(&self) {
        say!(
            "wrote the report of {} analyses to {}",
            self.analyses,
            self.done.wrote[0].display()
        );
    }
}

pub fn report(args: &ReportArgs, out: Output) -> anyhow::Result<()> {
    let started = Instant::now();
    let session = Session::load(&args.session)?;
    let path = match &args.output {
        Some(dir) => {
            std::fs::create_dir_all(dir)
                .map_err(|e| anyhow::anyhow!("--output {}: {e}", dir.display()))?;
            dir.join(
                beside(&args.session, ".html")
                    .file_name()
                    .unwrap_or_default(),
            )
        }
        None => beside(&args.session, ".html"),
    };
    let target = check_target(&path, &protected(&session))?;
    let mut views = Vec::new();
    for entry in &session.analyses {
        let view = view_of(&session, entry, args.look.threads, out)?;
        let scalogram = scalogram_of(&view, entry)?;
        views.push((entry, view, scalogram));
    }
    let sections: Vec<figure::report::Section> = views
        .iter()
        .map(|(entry, view, scalogram)| figure::report::Section {
            subject: Subject::of(&session, entry, view, scalogram.as_ref())
                .with_reverse(figure::reverse_sweep(&session, entry).map(|i| &views[i].1)),
            entry,
        })
        .collect();
    let html = figure::report::html(&session, &sections, &args.look.options(Format::Svg))?;
    target.write(html.as_bytes())?;
    out.report(&ReportSummary {
        session: args.session.clone(),
        analyses: sections.len(),
        done: Done {
            wrote: vec![path],
            elapsed_seconds: started.elapsed().as_secs_f64(),
        },
    })
}
