//! The command line: clap definitions and one module per command.

mod model_args;
mod orbit;

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
}

/// Parses the command line and runs the command; errors go to stderr with exit code 1.
pub fn run() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Orbit(args) => orbit::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
