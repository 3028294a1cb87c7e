//! The real binary in a real terminal, with nothing but cargo: a pseudo-terminal of 80×24 of
//! this process' own, read through a terminal emulator (`vt100`). The workbench opens an
//! example session, runs a small frequency response, reads the plot and the job pane off the
//! screen, quits, and the terminal is given back (main screen, cursor shown); the work of a
//! session made in the workbench survives it; closing the terminal ends it.

use crate::common;

use std::fs::File;
use std::io::{Read, Write};
use std::os::fd::AsRawFd;
use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The workbench in a pseudo-terminal: what it draws goes through a terminal emulator.
struct Pty {
    child: Child,
    /// The terminal's keyboard end (`None` once the terminal is closed).
    keyboard: Option<File>,
    screen: Arc<Mutex<vt100::Parser>>,
    /// Tells the thread reading the screen to let go of the terminal.
    stop: Arc<std::sync::atomic::AtomicBool>,
    reader: Option<std::thread::JoinHandle<()>>,
}

impl Pty {
    /// `isola tui SESSION` in a new 80×24 terminal, its state and config in `home`.
    fn start(session: &Path, home: &Path) -> Pty {
        let mut command = Command::new(env!("CARGO_BIN_EXE_isola"));
        command
            .arg("tui")
            .arg(session)
            .env("XDG_STATE_HOME", home)
            .env("XDG_CONFIG_HOME", home);
        let (child, keyboard, slave) = common::spawn_in_pty(command, 80, 24);
        // only the workbench holds the terminal's far end now: reads end when it exits
        drop(slave);
        let mut display = keyboard.try_clone().unwrap();
        let screen = Arc::new(Mutex::new(vt100::Parser::new(24, 80, 0)));
        let fed = screen.clone();
        let stop = Arc::new(std::sync::atomic::AtomicBool::new(false));
        let stopping = stop.clone();
        let reader = std::thread::spawn(move || {
            let mut buf = [0u8; 8192];
            let fd = display.as_raw_fd();
            while !stopping.load(std::sync::atomic::Ordering::Relaxed) {
                let mut poll = libc::pollfd {
                    fd,
                    events: libc::POLLIN,
                    revents: 0,
                };
                // SAFETY: one valid pollfd.
                if unsafe { libc::poll(&mut poll, 1, 20) } <= 0 {
                    continue;
                }
                match display.read(&mut buf) {
                    Ok(0) | Err(_) => break,
                    Ok(n) => fed.lock().unwrap().process(&buf[..n]),
                }
            }
        });
        Pty {
            child,
            keyboard: Some(keyboard),
            screen,
            stop,
            reader: Some(reader),
        }
    }

    /// Closes the terminal (every descriptor of its master end): it hangs up under the
    /// workbench, as when a terminal window is closed.
    fn hang_up(&mut self) {
        self.stop.store(true, std::sync::atomic::Ordering::Relaxed);
        if let Some(reader) = self.reader.take() {
            reader.join().unwrap();
        }
        self.keyboard = None;
    }

    /// The screen's text, a line per row.
    fn screen(&self) -> String {
        self.screen.lock().unwrap().screen().contents()
    }

    /// Types `text` (`\r` is Enter, `\x1b` Escape, `\x7f` Backspace).
    fn keys(&mut self, text: &str) {
        let keyboard = self.keyboard.as_mut().expect("the terminal is open");
        keyboard.write_all(text.as_bytes()).unwrap();
        keyboard.flush().unwrap();
    }

    /// Types `:`, waits for the command line, types `line` and Enter.
    fn command(&mut self, line: &str) {
        self.keys(":");
        self.wait_for("the command line", |s| s.contains("Command"));
        self.keys(line);
        self.keys("\r");
    }

    /// Waits until the screen satisfies `ok` (20 s at most), and returns it.
    fn wait_for(&self, what: &str, ok: impl Fn(&str) -> bool) -> String {
        let start = Instant::now();
        loop {
            let screen = self.screen();
            if ok(&screen) {
                return screen;
            }
            assert!(
                start.elapsed() < Duration::from_secs(20),
                "timed out waiting for {what}; the screen:\n{screen}"
            );
            std::thread::sleep(Duration::from_millis(30));
        }
    }

    /// Waits for the workbench to exit (10 s at most); its exit code.
    fn exit_code(&mut self) -> Option<i32> {
        let start = Instant::now();
        loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                return status.code();
            }
            assert!(
                start.elapsed() < Duration::from_secs(10),
                "the workbench did not exit"
            );
            std::thread::sleep(Duration::from_millis(30));
        }
    }
}

impl Drop for Pty {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Fig 4's example session with a coarser grid (it runs in about a second), in a temporary
/// folder removed when the test ends.
fn session() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string("sessions/fig04_response_adr06.toml")
        .unwrap()
        .replace(
            "omega = { min = 0.2, max = 6.0, points = 117 }",
            "omega = { min = 3.0, max = 6.0, points = 31 }",
        )
        .replace("points = 15 }", "points = 5 }");
    let path = dir.path().join("fig04.toml");
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

#[test]
fn the_workbench_runs_a_response_in_an_80x24_terminal_and_gives_the_terminal_back() {
    let (dir, session) = session();
    let mut pty = Pty::start(&session, dir.path());
    // a frame is read as it arrives: what must be on screen is waited for, not asserted
    pty.wait_for("the workbench with the response listed", |s| {
        s.contains("Analyses") && s.contains("not run") && s.contains("response frequency response")
    });
    assert!(pty.screen.lock().unwrap().screen().alternate_screen());
    // r runs the response; the job pane shows it done, the plot its hidden isola
    pty.keys("r");
    // the result is stored complete a moment before its job (and its coarse preview's) ends
    let screen = pty.wait_for(
        "the response done, its hidden 1:2 points (◇) drawn",
        |s| {
            s.contains("Jobs (0 active)")
                && s.contains("1:2 isola, hidden")
                && s.contains("✓ done in")
                && s.contains("response · done")
                && s.contains("◇")
        },
    );
    // nothing drawn past 80×24 (combining marks, as in c̃, take no cell)
    let width = |l: &str| {
        l.chars()
            .filter(|c| !('\u{300}'..='\u{36f}').contains(c))
            .count()
    };
    assert!(screen.lines().count() <= 24, "{screen}");
    assert!(screen.lines().all(|l| width(l) <= 80), "{screen}");
    // help opens and closes
    pty.keys("?");
    pty.wait_for("help", |s| s.contains("run selected analysis"));
    pty.keys("\x1b");
    pty.wait_for("help to close", |s| !s.contains("run selected analysis"));
    // q quits (nothing runs, nothing unsaved): the main screen back, the cursor shown
    pty.keys("q");
    assert_eq!(pty.exit_code(), Some(0));
    let start = Instant::now();
    while pty.screen.lock().unwrap().screen().alternate_screen() {
        assert!(
            start.elapsed() < Duration::from_secs(5),
            "still on the alternate screen"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let parser = pty.screen.lock().unwrap();
    assert!(!parser.screen().hide_cursor(), "the cursor is hidden");
    assert!(
        !parser.screen().contents().contains("Analyses"),
        "the TUI is still on screen"
    );
    drop(parser);
    // the result was saved beside the session, as a headless run would
    assert!(
        session
            .with_file_name("fig04.results")
            .join("response.csv")
            .exists()
    );
}

#[test]
fn closing_the_terminal_leaves_no_process_behind() {
    let (dir, session) = session();
    let mut pty = Pty::start(&session, dir.path());
    pty.wait_for("the workbench", |s| s.contains("Analyses"));
    // the terminal closes: it hangs up under the workbench, which must end (with 129)
    pty.hang_up();
    let start = Instant::now();
    let status = loop {
        if let Some(status) = pty.child.try_wait().unwrap() {
            break status;
        }
        // its loop, blocked reading the dead terminal, is given up on after 0.5 s (a loop
        // that quits gets 3 s)
        assert!(
            start.elapsed() < Duration::from_millis(2500),
            "the workbench outlived its terminal"
        );
        std::thread::sleep(Duration::from_millis(50));
    };
    assert_eq!(status.code(), Some(129), "{status:?}");
}

/// The work of a session made in the workbench survives it: `:add basin b2`, `:set`, `:run`,
/// `s`; the result stays drawn and exports; after quitting and reopening it is there, current.
/// Then `o` over unsaved edits and `S` over an existing file ask first.
#[test]
fn an_analysis_made_in_the_workbench_is_saved_run_and_found_again() {
    let (dir, session) = session();
    let mut pty = Pty::start(&session, dir.path());
    pty.wait_for("the workbench", |s| s.contains("Analyses"));
    pty.command("add basin b2");
    pty.wait_for("b2 added", |s| s.contains("added b2 (basin)"));
    pty.command("set adr 1.0");
    pty.command("set dx.points 21");
    pty.command("set v.points 21");
    pty.wait_for("the last edit", |s| s.contains("v.points = 21"));
    pty.command("run");
    // the job's own message last: nothing comes after it to replace the save's
    pty.wait_for("b2's job to end", |s| s.contains("b2: done"));
    // a frame is read as it arrives: the title may be on screen before the legend
    pty.wait_for("b2 to finish, with a basin legend", |s| {
        s.contains("b2 · done") && s.contains("1:1")
    });
    pty.keys("s");
    pty.wait_for("the save", |s| s.contains("saved"));
    pty.wait_for("b2 still drawn, its result current", |s| {
        s.contains("b2 · done") && s.contains("✓ b2")
    });
    let csv = session.with_file_name("b2.csv");
    pty.command(&format!("export {}", csv.display()));
    pty.wait_for("the export", |s| s.contains("exported"));
    assert!(std::fs::read_to_string(&csv).unwrap().lines().count() > 400);
    pty.keys("q");
    assert_eq!(pty.exit_code(), Some(0));
    drop(pty);
    // reopened: b2 is in the file, its result current
    let mut pty = Pty::start(&session, dir.path());
    pty.wait_for("the workbench", |s| s.contains("Analyses"));
    pty.command("select b2");
    pty.wait_for("b2, done", |s| s.contains("b2 · done"));
    // an unsaved edit, then o: asked first, n keeps it
    pty.command("set adr 0.8");
    pty.keys("o");
    pty.wait_for("the picker", |s| s.contains("Open session"));
    pty.keys("\r");
    pty.wait_for("the question", |s| s.contains("unsaved changes"));
    pty.keys("n");
    pty.wait_for("nothing done", |s| s.contains("nothing done"));
    // S onto an existing file: asked first
    let other = session.with_file_name("other.toml");
    std::fs::write(&other, "schema = 1\n").unwrap();
    pty.keys("S");
    pty.wait_for("save as", |s| s.contains("Save session as"));
    // the prompt holds the session's path: replace it with the other file's
    let erase = "\x7f".repeat(session.display().to_string().chars().count());
    pty.keys(&erase);
    pty.keys(&other.display().to_string());
    pty.keys("\r");
    pty.wait_for("the question", |s| s.contains("exists: replace it"));
    pty.keys("\x1b");
    pty.wait_for("nothing done", |s| s.contains("nothing done"));
    assert_eq!(std::fs::read_to_string(&other).unwrap(), "schema = 1\n");
}
