//! `isola`: the command-line and terminal front ends of the library.

mod cli;

fn main() -> std::process::ExitCode {
    cli::run()
}
