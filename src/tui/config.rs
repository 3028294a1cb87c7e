//! The user's config file, `$XDG_CONFIG_HOME/isola/config.toml` (or `~/.config/isola/...`):
//!
//! ```toml
//! theme = "light"          # dark, light, mono, or a theme file
//! color = "256"            # auto, truecolor, 256, 16, none
//! mouse = false            # leave the mouse to the terminal (to select text)
//! [keys]
//! run = ["r", "f5"]
//! ```

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::Context;
use serde::Deserialize;

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    pub theme: Option<String>,
    pub color: Option<String>,
    /// Clicks and the wheel go to the workbench (the default), or stay with the terminal.
    pub mouse: Option<bool>,
    #[serde(default)]
    pub keys: BTreeMap<String, Vec<String>>,
}

/// isola's folder under the user's config home, if there is a home.
pub fn config_dir() -> Option<PathBuf> {
    std::env::var_os("XDG_CONFIG_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config")))
        .map(|d| d.join("isola"))
}

/// Where the TUI's log goes: `$XDG_STATE_HOME/isola/tui.log` (or `~/.local/state/...`, or the
/// temporary folder).
pub fn log_path() -> PathBuf {
    std::env::var_os("XDG_STATE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".local/state")))
        .unwrap_or_else(std::env::temp_dir)
        .join("isola")
        .join("tui.log")
}

impl Config {
    /// Reads `path`, or the default file if there is one; no file is an empty config.
    pub fn load(path: Option<&Path>) -> anyhow::Result<Config> {
        let path = match path {
            Some(p) => p.to_path_buf(),
            None => match config_dir().map(|d| d.join("config.toml")) {
                Some(p) if p.is_file() => p,
                _ => return Ok(Config::default()),
            },
        };
        let text =
            std::fs::read_to_string(&path).with_context(|| format!("config {}", path.display()))?;
        toml::from_str(&text).with_context(|| format!("config {}", path.display()))
    }
}
