//! The command line: clap definitions and one module per command.

mod basin;
mod continue_cmd;
mod family;
mod force;
mod model_args;
mod orbit;
mod parse;
mod response;
mod run;
mod start_ranges;
mod sweep;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// isola: nonlinear dynamics of antagonistic pure-shear dielectric elastomer actuators.
#[derive(Debug, Parser)]
#[command(name = "isola", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Integrate one orbit to its steady state and classify it.
    Orbit(orbit::OrbitArgs),
    /// Static force curves f_II − f_I against Δλ (Fig 2).
    Force(force::ForceArgs),
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
    /// Run a session's analyses headless; resumes after a crash, can be sharded.
    Run(run::RunArgs),
    /// Export a selection of a session's result to CSV.
    Export(run::ExportArgs),
}

/// Parses the command line and runs the command; errors go to stderr with exit code 1.
pub fn run() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Orbit(args) => orbit::run(&args),
        Command::Basin(args) => basin::run(&args),
        Command::Response(args) => response::run(&args),
        Command::Force(args) => force::run(&args),
        Command::Sweep(args) => sweep::run(&args),
        Command::Family(args) => family::run(&args),
        Command::Continue(args) => continue_cmd::run(&args),
        Command::Run(args) => run::run(&args),
        Command::Export(args) => run::export(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
