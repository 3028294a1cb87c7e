//! Where isola's events go: a log file, never the terminal, where progress bars and the
//! workbench live. Set up once per process by the command line and the workbench alike.

use std::path::Path;

use anyhow::Context;

/// Sends tracing events to the file `path` (appended; its folder made if needed), and logs
/// this build and the instruction set its hot loops run on.
pub fn log_to(path: &Path) -> anyhow::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("results folder {}", dir.display()))?;
    }
    let file = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .with_context(|| format!("log file {}", path.display()))?;
    let _ = tracing_subscriber::fmt()
        .with_writer(std::sync::Mutex::new(file))
        .with_ansi(false)
        .with_max_level(tracing::Level::INFO)
        .try_init();
    let isa = crate::solver::isa::chosen().name();
    tracing::info!("isola {} on {isa} instructions", crate::BUILD);
    Ok(())
}
