//! The terminal workbench: `isola` or `isola tui [SESSION]`. A synchronous loop: wait up to
//! 50 ms for a key, poll jobs and result files, redraw if something changed: at once after a
//! key, at most 20 times a second for background progress (ratatui sends only the cells that
//! differ, which spares an SSH link).

pub mod app;
pub mod command;
pub mod config;
pub mod filter;
pub mod jobs;
pub mod keymap;
pub mod line_edit;
pub mod mouse;
pub mod orbit;
pub mod panes;
pub mod plots;
pub mod terminal;
pub mod theme;
pub mod ui;
pub mod undo;
pub mod watcher;

#[cfg(test)]
mod tests;

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use clap::Args;
use crossterm::event::{self, Event, KeyEventKind};
use isola::session::Session;

use app::App;
use keymap::Keymap;
use theme::{ColorMode, Theme};

#[derive(Debug, Args, Default)]
pub struct TuiArgs {
    /// The session to open (none: pick one from ./sessions, over an untitled session).
    pub session: Option<PathBuf>,
    /// Theme: dark, light, mono, or a theme file (default: the config's, else dark).
    #[arg(long)]
    pub theme: Option<String>,
    /// Colours: auto (from COLORTERM, TERM and NO_COLOR), truecolor, 256, 16 or none.
    #[arg(long, value_enum)]
    pub color: Option<ColorMode>,
    /// Config file (default: $XDG_CONFIG_HOME/isola/config.toml).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Worker threads for analyses (0: one per core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
}

/// The session a bare `isola` starts with; saved only when the user saves it.
const UNTITLED: &str = r#"# A new session: edit the model and settings, r runs an analysis, s saves.
schema = 1
description = "untitled"

[model]
adr = 0.6
e_a = 0.04

[[analysis]]
name = "response"
kind = "frequency_response"
[analysis.settings]
omega = { min = 0.2, max = 6.0, points = 117 }

[[analysis]]
name = "basin"
kind = "basin"
model = { omega = 3.7 }

[[analysis]]
name = "orbit"
kind = "time_history"
model = { omega = 3.7 }
"#;

/// Everything but the terminal: config, theme, keys and session, as the app starts.
pub fn build_app(args: &TuiArgs) -> anyhow::Result<App> {
    let config = config::Config::load(args.config.as_deref())?;
    let mode = match (args.color, config.color.as_deref()) {
        (Some(m), _) => m,
        (None, Some(s)) => <ColorMode as clap::ValueEnum>::from_str(s, true).map_err(|_| {
            anyhow::anyhow!("config color = \"{s}\": one of auto, truecolor, 256, 16, none")
        })?,
        (None, None) => ColorMode::Auto,
    }
    .resolve(|k| std::env::var(k).ok());
    let theme_name = args
        .theme
        .clone()
        .or(config.theme.clone())
        .unwrap_or_else(|| "dark".into());
    let themes_dir = config::config_dir().map(|d| d.join("themes"));
    let theme = Theme::load(&theme_name, mode, themes_dir.as_deref())?;
    let keymap = Keymap::with_overrides(&config.keys).map_err(anyhow::Error::msg)?;
    // without a session: an untitled one, beside the example sessions if there are some
    let examples = Path::new("sessions");
    let session = match &args.session {
        Some(path) => Session::load(path)?,
        None if examples.is_dir() => Session::parse(&examples.join("untitled.toml"), UNTITLED)?,
        None => Session::parse(Path::new("untitled.toml"), UNTITLED)?,
    };
    let mut app = App::new(session, theme, keymap, args.threads);
    app.mouse = config.mouse.unwrap_or(true);
    if args.session.is_none() && examples.is_dir() {
        app.open_picker_in(examples);
    }
    Ok(app)
}

/// Runs the TUI until the user quits or a signal asks it to; returns the exit status (0, or
/// 128 + the signal's number: 130 after Ctrl-C or SIGINT, 131 SIGQUIT, 143 SIGTERM, 129 SIGHUP).
pub fn run(args: &TuiArgs) -> anyhow::Result<u8> {
    use std::io::IsTerminal;
    if !(std::io::stdin().is_terminal() && std::io::stdout().is_terminal()) {
        anyhow::bail!(
            "the workbench needs a terminal, and stdin or stdout is not one; run it in a \
             terminal, or headless: `isola run SESSION` computes a session's analyses, \
             `isola status SESSION` shows them, `isola --help` lists the rest"
        );
    }
    // nothing may write to the screen while the TUI runs
    isola::logging::log_to(&config::log_path())?;
    let mut app = build_app(args)?;
    tracing::info!(session = %app.session.path.display(), "tui started");
    let terminate = terminal::termination_signal()?;
    let beat = terminal::LoopBeat::default();
    terminal::spawn_watchdog(terminate.clone(), beat.clone())?;
    let mut guard = terminal::TerminalGuard::enter(app.mouse)?;
    let frame_time = Duration::from_millis(50);
    let mut last_draw = Instant::now() - frame_time;
    let mut key_pressed = false;
    loop {
        beat.turn();
        let signal = terminate.load(Ordering::Relaxed);
        if signal != 0 && !app.should_quit {
            tracing::info!(signal, "signal: quitting");
            beat.quitting();
            app.quit_now();
            app.exit_status = 128 + signal as u8;
        }
        if app.should_quit {
            break;
        }
        // a key is answered at once; background updates at most every frame_time
        if app.dirty && (key_pressed || last_draw.elapsed() >= frame_time) {
            let drawn = guard.terminal.draw(|f| ui::draw(f, &app)).map(drop);
            if terminal::gone(drawn, &terminate)? {
                continue;
            }
            app.dirty = false;
            last_draw = Instant::now();
        }
        key_pressed = false;
        // a preview is drawn the moment it is done, not at the next frame
        let wait = if app.jobs.preview_active() {
            Duration::from_millis(5)
        } else {
            frame_time
                .saturating_sub(last_draw.elapsed())
                .max(Duration::from_millis(5))
        };
        let polled = event::poll(wait);
        let ready = matches!(polled, Ok(true));
        if terminal::gone(polled.map(drop), &terminate)? {
            continue;
        }
        if ready {
            let read = match event::read() {
                Ok(read) => read,
                Err(e) => {
                    terminal::gone(Err(e), &terminate)?;
                    continue;
                }
            };
            match read {
                Event::Key(key) if key.kind == KeyEventKind::Press => {
                    app.handle_key(key);
                    key_pressed = true;
                }
                Event::Mouse(mouse) => {
                    app.handle_mouse(mouse);
                    key_pressed = true;
                }
                Event::Resize(..) => {
                    if terminal::gone(guard.terminal.autoresize(), &terminate)? {
                        continue;
                    }
                    app.dirty = true;
                    key_pressed = true;
                }
                _ => {}
            }
        }
        app.tick();
    }
    drop(guard);
    tracing::info!(status = app.exit_status, "tui quit");
    Ok(app.exit_status)
}
