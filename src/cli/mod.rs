//! The command line: clap definitions and one module per command.

/// `println!` that does not panic when stdout fails (a full disk behind `> log`): the
/// command's work goes on and it ends with the error ([`output::print_line`]).
macro_rules! say {
    () => {
        $crate::cli::output::print_line(format_args!(""))
    };
    ($($arg:tt)*) => {
        $crate::cli::output::print_line(format_args!($($arg)*))
    };
}

mod basin;
mod continue_cmd;
mod docs;
mod family;
mod figure;
mod force;
mod hunt;
mod map;
mod model_args;
mod model_cmd;
mod orbit;
mod output;
mod parse;
mod reproduce;
mod response;
mod run;
mod slurm;
mod start_ranges;
mod status;
mod sweep;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use output::Output;

/// isola: nonlinear dynamics of antagonistic pure-shear dielectric elastomer actuators.
#[derive(Debug, Parser)]
#[command(name = "isola", version = isola::BUILD, about)]
struct Cli {
    /// Print the command's summary as one JSON document on one line of stdout, with the
    /// files written and the seconds taken, and nothing else there (errors stay on stderr).
    /// Not with --quiet, nor for the workbench; completions and man ignore it.
    #[arg(long, global = true, conflicts_with = "quiet")]
    json: bool,
    /// Print nothing but errors: no summary, no progress. Not with --json.
    #[arg(long, short, global = true)]
    quiet: bool,
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Integrate one orbit to its steady state and classify it.
    Orbit(orbit::OrbitArgs),
    /// Static force curves f_II − f_I against Δλ (Fig 2).
    Force(force::ForceArgs),
    /// The model's derived quantities: the drive's E_a, E_b, E_c, the static equilibrium
    /// under the mean drive and the natural frequency ω₀ about it.
    Model(model_cmd::ModelCmdArgs),
    /// Frequency sweep: a chirp with its envelope and scalogram, or stepped (Fig 3).
    Sweep(sweep::SweepArgs),
    /// Basin of attraction on a grid of initial states (Fig 6).
    Basin(basin::BasinArgs),
    /// Frequency response from many initial states, with hidden responses and branches (Fig 4/5).
    Response(response::ResponseArgs),
    /// A frequency response per value of one parameter (Fig 7–12).
    Family(family::FamilyArgs),
    /// Continue the branch through one response in ω or a model parameter, with Floquet
    /// stability, folds and period doublings.
    Continue(continue_cmd::ContinueArgs),
    /// Find the subharmonic branches of a frequency response and continue each: isola or
    /// attached, its folds, period doublings, stable and unstable arcs.
    Hunt(hunt::HuntArgs),
    /// How many stable responses coexist over ω and one model parameter, where hidden
    /// responses are, with the fold and period-doubling curves.
    Map(map::MapArgs),
    /// The paper's claims, each beside what isola computes, with its precision and a
    /// verdict (agrees, differs, imprecise).
    Reproduce(reproduce::ReproduceArgs),
    /// Run a session's analyses headless; resumes after a crash, can be sharded.
    Run(run::RunArgs),
    /// Export a selection of a session's result to CSV.
    Export(run::ExportArgs),
    /// A publication figure (SVG or PNG) of one analysis of a session, computed first if
    /// its stored result is not current.
    Figure(figure::FigureArgs),
    /// One self-contained HTML page of a session: each analysis' figure and tables.
    Report(figure::ReportArgs),
    /// Where each analysis of a session stands: its result, and the chunks done, claimed and
    /// missing, by host, with rates (while runs compute it, here or on a cluster).
    Status(status::StatusArgs),
    /// Write (and with --submit, submit) a Slurm job array that computes a session's analyses
    /// on many nodes, and a job that assembles and verifies them.
    Slurm(slurm::SlurmArgs),
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell).
    Completions(docs::CompletionsArgs),
    /// Print the man page (roff).
    Man,
    /// The terminal workbench (also what a bare `isola` opens).
    #[cfg(feature = "tui")]
    Tui(crate::tui::TuiArgs),
}

/// Parses the command line and runs the command; errors go to stderr with exit code 1.
pub fn run() -> ExitCode {
    let cli = Cli::parse();
    if let Err(e) = isola::solver::isa::choose() {
        return finish(Err(e.into()));
    }
    let out = Output::new(cli.json, cli.quiet);
    let Some(command) = cli.command else {
        return open_workbench(out);
    };
    let result = match command {
        Command::Orbit(args) => orbit::run(&args, out),
        Command::Figure(args) => figure::run(&args, out),
        Command::Report(args) => figure::report(&args, out),
        Command::Basin(args) => basin::run(&args, out),
        Command::Response(args) => response::run(&args, out),
        Command::Force(args) => force::run(&args, out),
        Command::Model(args) => model_cmd::run(&args, out),
        Command::Sweep(args) => sweep::run(&args, out),
        Command::Family(args) => family::run(&args, out),
        Command::Continue(args) => continue_cmd::run(&args, out),
        Command::Hunt(args) => hunt::run(&args, out),
        Command::Map(args) => map::run(&args, out),
        Command::Reproduce(args) => reproduce::run(&args, out),
        Command::Run(args) => run::run(&args, out),
        Command::Export(args) => run::export(&args, out),
        Command::Status(args) => status::run(&args, out),
        Command::Slurm(args) => slurm::run(&args, out),
        Command::Completions(args) => docs::completions(&args),
        Command::Man => docs::man(),
        #[cfg(feature = "tui")]
        Command::Tui(args) => return tui(&args, out),
    };
    finish(result)
}

/// The workbench, refused with --json or --quiet: it draws on the terminal, it prints no
/// summary.
#[cfg(feature = "tui")]
fn tui(args: &crate::tui::TuiArgs, out: Output) -> ExitCode {
    if out != Output::Text {
        return finish(Err(anyhow::anyhow!(
            "the workbench takes neither --json nor --quiet; they are for the headless \
             commands (isola run, orbit, ...)"
        )));
    }
    finish_with(crate::tui::run(args))
}

#[cfg(feature = "tui")]
fn open_workbench(out: Output) -> ExitCode {
    tui(&crate::tui::TuiArgs::default(), out)
}

#[cfg(not(feature = "tui"))]
fn open_workbench(_: Output) -> ExitCode {
    finish(Err(anyhow::anyhow!(
        "this isola was built without the terminal workbench (feature `tui`); see --help"
    )))
}

/// The exit status a command returned, or 1 with its error on stderr.
#[cfg(feature = "tui")]
fn finish_with(result: anyhow::Result<u8>) -> ExitCode {
    match result {
        Ok(status) => ExitCode::from(status),
        Err(e) => finish(Err(e)),
    }
}

/// Checks every output path a command was given (`--csv` and the like) before any work
/// starts, so that a path that cannot take the output fails at once, not after the run.
fn check_outputs<'a>(
    paths: impl IntoIterator<Item = Option<&'a std::path::Path>>,
) -> anyhow::Result<()> {
    for path in paths.into_iter().flatten() {
        isola::session::output::check_target(path, &isola::session::output::Protected::none())?;
    }
    Ok(())
}

/// Refuses a command whose result would not fit in memory (the estimate of
/// [`isola::analysis::cost`]), before it starts; the time is the user's to spend.
fn check_memory(
    what: &str,
    cost: Result<isola::analysis::cost::Cost, isola::model::ParamError>,
) -> anyhow::Result<()> {
    let budget = isola::session::budget::Budget::on_this_machine(1, None, true);
    budget.check(what, &cost?)?;
    Ok(())
}

fn finish(result: anyhow::Result<()>) -> ExitCode {
    // the work is done (and saved); a summary that could not be printed is still an error
    let result = result.and_then(|()| match output::stdout_failure() {
        Some(e) => Err(anyhow::anyhow!("writing the summary to stdout failed: {e}")),
        None => Ok(()),
    });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // stderr may be gone too (a closed terminal): the status still tells
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
