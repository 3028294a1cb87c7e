//! `isola`: the command-line and terminal front ends of the library.

mod cli;
#[cfg(feature = "tui")]
mod tui;

fn main() -> std::process::ExitCode {
    cli::run()
}
