//! The command line: clap definitions and one module per command.

mod basin;
mod model_args;
mod orbit;
mod output;
mod parse;
mod response;

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
    /// Basin of attraction on a grid of initial states (Fig 6).
    Basin(basin::BasinArgs),
    /// Frequency response from many initial states, with hidden responses and branches (Fig 4/5).
    Response(response::ResponseArgs),
}

/// Parses the command line and runs the command; errors go to stderr with exit code 1.
pub fn run() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Orbit(args) => orbit::run(&args),
        Command::Basin(args) => basin::run(&args),
        Command::Response(args) => response::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
