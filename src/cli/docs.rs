//! `isola completions SHELL` and `isola man`: shell completions and a man page, generated from
//! the same clap definitions as the commands themselves.

use clap::{Args, CommandFactory};

#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell to complete for.
    shell: clap_complete::Shell,
}

/// Writes the completion script for the shell to stdout (e.g. `isola completions bash >
/// ~/.local/share/bash-completion/completions/isola`).
pub fn completions(args: &CompletionsArgs) -> anyhow::Result<()> {
    let mut command = super::Cli::command();
    clap_complete::generate(args.shell, &mut command, "isola", &mut std::io::stdout());
    Ok(())
}

/// Writes the man page (roff) to stdout (e.g. `isola man > ~/.local/share/man/man1/isola.1`).
pub fn man() -> anyhow::Result<()> {
    clap_mangen::Man::new(super::Cli::command()).render(&mut std::io::stdout())?;
    Ok(())
}
