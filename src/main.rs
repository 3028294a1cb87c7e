//! `isola`: the command-line and terminal front ends of the library.

mod cli;
#[cfg(feature = "tui")]
mod tui;

fn main() -> std::process::ExitCode {
    // a closed pipe (`isola hunt | head`) ends the process quietly, as for other Unix tools,
    // instead of a panic on the next print
    #[cfg(unix)]
    // SAFETY: restoring the default disposition of SIGPIPE before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    cli::run()
}
