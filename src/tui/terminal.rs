//! The terminal in raw mode on the alternate screen, and its restoration: on drop, on a panic
//! of the UI thread, and on SIGINT, SIGQUIT, SIGTERM or SIGHUP (the loop sees which and
//! returns, and the process exits with 128 + the signal's number). A worker's panic is logged,
//! never printed over the screen.

use std::io::{Stdout, stdout};
use std::mem::ManuallyDrop;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use crossterm::execute;
use crossterm::terminal::{
    EnterAlternateScreen, LeaveAlternateScreen, disable_raw_mode, enable_raw_mode,
};
use ratatui::Terminal;
use ratatui::backend::CrosstermBackend;

/// Owns the terminal while the TUI runs; dropping it gives the terminal back.
pub struct TerminalGuard {
    /// Never dropped: ratatui's drop prints to stderr, and panics, when the terminal is gone
    /// (a hang-up); [`restore`] shows the cursor instead.
    pub terminal: ManuallyDrop<Terminal<CrosstermBackend<Stdout>>>,
}

impl TerminalGuard {
    /// Takes the terminal: raw mode, the alternate screen, and the mouse if `mouse`.
    pub fn enter(mouse: bool) -> anyhow::Result<Self> {
        install_panic_hook();
        enable_raw_mode()?;
        if let Err(e) = execute!(stdout(), EnterAlternateScreen) {
            restore();
            return Err(e.into());
        }
        if mouse && let Err(e) = execute!(stdout(), crossterm::event::EnableMouseCapture) {
            restore();
            return Err(e.into());
        }
        let mut terminal = Terminal::new(CrosstermBackend::new(stdout()))?;
        terminal.hide_cursor()?;
        // cleared without `Terminal::clear`, which asks the terminal where its cursor is: a
        // terminal that never answers (a bare pty, some multiplexers) would stall the start
        execute!(
            stdout(),
            crossterm::terminal::Clear(crossterm::terminal::ClearType::All)
        )?;
        Ok(TerminalGuard {
            terminal: ManuallyDrop::new(terminal),
        })
    }
}

impl Drop for TerminalGuard {
    fn drop(&mut self) {
        restore();
    }
}

/// Gives the mouse back, leaves the alternate screen and raw mode (harmless if already done).
pub fn restore() {
    let _ = disable_raw_mode();
    let _ = execute!(
        stdout(),
        crossterm::event::DisableMouseCapture,
        LeaveAlternateScreen,
        crossterm::cursor::Show
    );
}

/// On a panic of the UI thread: log it, restore the terminal, then print the message as usual.
/// On a worker's panic (the job turns it into an error): log it only.
fn install_panic_hook() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if std::thread::current().name() == Some("main") {
            // logged too: the terminal it is printed on may be gone
            tracing::error!("panic: {info}");
            restore();
            default(info);
        } else {
            tracing::error!(thread = ?std::thread::current().name(), "panic: {info}");
        }
    }));
}

/// The signals that end the workbench cleanly.
const SIGNALS: [i32; 4] = [
    signal_hook::consts::SIGINT,
    signal_hook::consts::SIGQUIT,
    signal_hook::consts::SIGTERM,
    signal_hook::consts::SIGHUP,
];

/// Holds the number of the last of SIGINT, SIGQUIT, SIGTERM or SIGHUP received (0: none).
pub fn termination_signal() -> anyhow::Result<Arc<AtomicUsize>> {
    let received = Arc::new(AtomicUsize::new(0));
    for signal in SIGNALS {
        signal_hook::flag::register_usize(signal, received.clone(), signal as usize)?;
    }
    Ok(received)
}

/// The main loop's heartbeat, read by the watchdog: the loop counts its turns, and says when
/// it has seen the signal and is quitting (its jobs saving what they finished).
#[derive(Clone, Default)]
pub struct LoopBeat(Arc<AtomicU64>);

impl LoopBeat {
    const QUITTING: u64 = u64::MAX;

    /// One more turn of the loop.
    pub fn turn(&self) {
        let _ = self
            .0
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |n| {
                (n != Self::QUITTING).then_some(n + 1)
            });
    }

    /// The loop saw the signal and is quitting: it may take the whole grace period.
    pub fn quitting(&self) {
        self.0.store(Self::QUITTING, Ordering::Relaxed);
    }

    fn read(&self) -> u64 {
        self.0.load(Ordering::Relaxed)
    }
}

/// Watches, on a thread of its own, for the terminal going away (a hang-up: the SSH link or
/// the tmux pane closed, which some terminals report only as end of input) and raises
/// `terminate`. The loop then quits; if it has not turned within 500 ms of `terminate` (it is
/// blocked reading the dead terminal) or has not returned within 3 s, this restores what it
/// can and exits, so that no orphan is left on a dead terminal. Finished chunks are already
/// on disk.
pub fn spawn_watchdog(terminate: Arc<AtomicUsize>, beat: LoopBeat) -> anyhow::Result<()> {
    std::thread::Builder::new()
        .name("isola-watchdog".into())
        .spawn(move || {
            let mut raised: Option<(Instant, u64)> = None;
            loop {
                std::thread::sleep(Duration::from_millis(50));
                if terminal_hung_up() {
                    let _ = terminate.compare_exchange(
                        0,
                        signal_hook::consts::SIGHUP as usize,
                        Ordering::Relaxed,
                        Ordering::Relaxed,
                    );
                }
                let signal = terminate.load(Ordering::Relaxed);
                if signal == 0 {
                    continue;
                }
                let (at, turns) = *raised.get_or_insert_with(|| (Instant::now(), beat.read()));
                let (blocked, give_up) = gives_up(turns, beat.read(), at.elapsed());
                if give_up {
                    tracing::warn!(
                        blocked,
                        "the terminal is gone and the loop did not return: exiting"
                    );
                    restore();
                    std::process::exit(128 + signal as i32);
                }
            }
        })?;
    Ok(())
}

/// Whether the watchdog gives up on the loop, `since` the signal was seen with the loop at
/// `turns` and now at `now`, and whether because the loop is blocked. A quitting loop may take
/// the grace period, even if it said so before the watchdog saw the signal.
fn gives_up(turns: u64, now: u64, since: Duration) -> (bool, bool) {
    let blocked = now != LoopBeat::QUITTING && now == turns && since > Duration::from_millis(500);
    (blocked, blocked || since > Duration::from_secs(3))
}

/// Whether a terminal operation failed because the terminal hung up (the loop may meet the
/// dead terminal before the watchdog does): then the hang-up is raised as SIGHUP and the loop
/// quits as on the signal. Any other failure is returned.
pub fn gone(result: std::io::Result<()>, terminate: &AtomicUsize) -> std::io::Result<bool> {
    match result {
        Ok(()) => Ok(false),
        Err(_) if terminal_hung_up() => {
            let _ = terminate.compare_exchange(
                0,
                signal_hook::consts::SIGHUP as usize,
                Ordering::Relaxed,
                Ordering::Relaxed,
            );
            Ok(true)
        }
        Err(e) => Err(e),
    }
}

/// True when standard input, the terminal, has hung up.
fn terminal_hung_up() -> bool {
    let mut fd = libc::pollfd {
        fd: 0,
        events: libc::POLLIN,
        revents: 0,
    };
    // SAFETY: one valid pollfd, no timeout.
    let ready = unsafe { libc::poll(&mut fd, 1, 0) };
    ready > 0 && fd.revents & (libc::POLLHUP | libc::POLLERR | libc::POLLNVAL) != 0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_watchdog_gives_up_on_a_blocked_loop_at_once_and_on_a_quitting_one_after_its_grace() {
        let ms = Duration::from_millis;
        // the loop has not turned since the signal: blocked after 500 ms, not before
        assert_eq!(gives_up(7, 7, ms(400)), (false, false));
        assert_eq!(gives_up(7, 7, ms(600)), (true, true));
        // it turned, or it is quitting (also if it said so first): the 3 s grace
        for (turns, now) in [
            (7, 9),
            (7, LoopBeat::QUITTING),
            (LoopBeat::QUITTING, LoopBeat::QUITTING),
        ] {
            assert_eq!(gives_up(turns, now, ms(2900)), (false, false));
            assert_eq!(gives_up(turns, now, ms(3100)), (false, true));
        }
    }
}
