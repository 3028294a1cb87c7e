//! The real binary in a real terminal: tmux at 80×24 opens an example session, runs a small
//! frequency response, reads the plot and the job pane off the screen, quits, and checks the
//! terminal was given back (main screen, cursor shown, the shell prints again).

use std::path::PathBuf;
use std::process::Command;
use std::time::{Duration, Instant};

struct Tmux {
    name: String,
}

impl Tmux {
    /// A detached 80×24 tmux session named `name` running `command`.
    fn start(name: &str, command: &str) -> Tmux {
        let tmux = Tmux {
            name: format!("{name}-{}", std::process::id()),
        };
        // a new session can be lost to a server that is exiting as another test's last
        // session closes: try again until it is there
        for _ in 0..50 {
            tmux.run(&[
                "new-session",
                "-d",
                "-s",
                &tmux.name,
                "-x",
                "80",
                "-y",
                "24",
                command,
            ]);
            let there = Command::new("tmux")
                .args(["has-session", "-t", &tmux.name])
                .status()
                .is_ok_and(|s| s.success());
            if there {
                return tmux;
            }
            std::thread::sleep(Duration::from_millis(100));
        }
        panic!("tmux would not start a session");
    }

    fn run(&self, args: &[&str]) -> String {
        let out = Command::new("tmux").args(args).output().expect("tmux runs");
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    fn screen(&self) -> String {
        self.run(&["capture-pane", "-p", "-t", &self.name])
    }

    fn keys(&self, keys: &[&str]) {
        let mut args = vec!["send-keys", "-t", &self.name];
        args.extend(keys);
        self.run(&args);
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
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

impl Drop for Tmux {
    fn drop(&mut self) {
        let _ = Command::new("tmux")
            .args(["kill-session", "-t", &self.name])
            .output();
    }
}

/// Fig 4's example session with a coarser grid, so that it runs in about a second.
fn session(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("isola-tmux-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string("sessions/fig04_response_adr06.toml")
        .unwrap()
        .replace(
            "omega = { min = 0.2, max = 6.0, points = 117 }",
            "omega = { min = 3.0, max = 6.0, points = 31 }",
        )
        .replace("points = 15 }", "points = 5 }");
    let path = dir.join("fig04.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn the_workbench_runs_a_response_in_an_80x24_terminal_and_gives_the_terminal_back() {
    if Command::new("tmux").arg("-V").output().is_err() {
        panic!("tmux is needed for this test (apt-get install tmux)");
    }
    let session = session("run");
    let state = session.with_file_name("state");
    let command = format!(
        "XDG_STATE_HOME={} {} tui {}; echo EXITED:$?; sleep 60",
        state.display(),
        env!("CARGO_BIN_EXE_isola"),
        session.display()
    );
    let tmux = Tmux::start("isola-e2e", &command);
    let screen = tmux.wait_for("the workbench", |s| {
        s.contains("Analyses") && s.contains("not run")
    });
    assert!(screen.contains("response frequency response"), "{screen}");
    assert_eq!(
        tmux.run(&["display", "-p", "-t", &tmux.name, "#{alternate_on}"])
            .trim(),
        "1"
    );
    // r runs the response; the job pane shows it done, the plot its hidden isola
    tmux.keys(&["r"]);
    let screen = tmux.wait_for("the response to finish", |s| s.contains("✓ done in"));
    let screen = if screen.contains("1:2 isola, hidden") {
        screen
    } else {
        tmux.wait_for("the plot", |s| s.contains("1:2 isola, hidden"))
    };
    assert!(screen.contains("response · done"), "{screen}");
    assert!(screen.contains("◇"), "hidden 1:2 points drawn: {screen}");
    assert!(screen.contains("Jobs (0 active)"), "{screen}");
    // nothing drawn past 80×24 (combining marks, as in c̃, take no cell)
    let width = |l: &str| {
        l.chars()
            .filter(|c| !('\u{300}'..='\u{36f}').contains(c))
            .count()
    };
    assert!(screen.lines().count() <= 24, "{screen}");
    assert!(screen.lines().all(|l| width(l) <= 80), "{screen}");
    // help opens and closes
    tmux.keys(&["?"]);
    tmux.wait_for("help", |s| s.contains("run selected analysis"));
    tmux.keys(&["Escape"]);
    tmux.wait_for("help to close", |s| !s.contains("run selected analysis"));
    // q quits (nothing runs, nothing unsaved); the shell prints on the main screen again
    tmux.keys(&["q"]);
    let screen = tmux.wait_for("the exit", |s| s.contains("EXITED:0"));
    assert!(
        !screen.contains("Analyses"),
        "the TUI is still on screen: {screen}"
    );
    assert_eq!(
        tmux.run(&["display", "-p", "-t", &tmux.name, "#{alternate_on}"])
            .trim(),
        "0"
    );
    assert_eq!(
        tmux.run(&["display", "-p", "-t", &tmux.name, "#{cursor_flag}"])
            .trim(),
        "1"
    );
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
    let unique = session("hangup");
    let command = format!("{} tui {}", env!("CARGO_BIN_EXE_isola"), unique.display());
    let tmux = Tmux::start("isola-hup", &command);
    tmux.wait_for("the workbench", |s| s.contains("Analyses"));
    let running = || {
        Command::new("pgrep")
            .args(["-f", &unique.display().to_string()])
            .output()
            .map(|o| !o.stdout.is_empty())
            .unwrap_or(false)
    };
    assert!(running());
    // the pane closes: the terminal hangs up under the workbench
    tmux.run(&["kill-session", "-t", &tmux.name]);
    let start = Instant::now();
    while running() {
        assert!(
            start.elapsed() < Duration::from_secs(8),
            "the workbench outlived its terminal"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// The work of a session made in the workbench survives it: `:add basin b2`, `:set`, `:run`,
/// `s`; the result stays drawn and exports; after quitting and reopening it is there, current.
/// Then `o` over unsaved edits and `S` over an existing file ask first.
#[test]
fn an_analysis_made_in_the_workbench_is_saved_run_and_found_again() {
    let session = session("make");
    let state = session.with_file_name("state");
    let open = || {
        format!(
            "XDG_STATE_HOME={} {} tui {}; echo EXITED:$?; sleep 60",
            state.display(),
            env!("CARGO_BIN_EXE_isola"),
            session.display()
        )
    };
    let tmux = Tmux::start("isola-make", &open());
    tmux.wait_for("the workbench", |s| s.contains("Analyses"));
    let command = |tmux: &Tmux, line: &str| {
        tmux.keys(&[":"]);
        tmux.wait_for("the command line", |s| s.contains("Command"));
        tmux.keys(&["-l", line]);
        tmux.keys(&["Enter"]);
    };
    command(&tmux, "add basin b2");
    tmux.wait_for("b2 added", |s| s.contains("added b2 (basin)"));
    command(&tmux, "set adr 1.0");
    command(&tmux, "set dx.points 21");
    command(&tmux, "set v.points 21");
    tmux.wait_for("the last edit", |s| s.contains("v.points = 21"));
    command(&tmux, "run");
    let screen = tmux.wait_for("b2 to finish", |s| s.contains("b2 · done"));
    assert!(screen.contains("1:1"), "a basin legend: {screen}");
    tmux.keys(&["s"]);
    tmux.wait_for("the save", |s| s.contains("saved"));
    let screen = tmux.wait_for("b2 still drawn", |s| s.contains("b2 · done"));
    assert!(screen.contains("✓ b2"), "{screen}");
    let csv = session.with_file_name("b2.csv");
    command(&tmux, &format!("export {}", csv.display()));
    tmux.wait_for("the export", |s| s.contains("exported"));
    assert!(std::fs::read_to_string(&csv).unwrap().lines().count() > 400);
    tmux.keys(&["q"]);
    tmux.wait_for("the exit", |s| s.contains("EXITED:0"));
    drop(tmux);
    // reopened: b2 is in the file, its result current
    let tmux = Tmux::start("isola-make2", &open());
    tmux.wait_for("the workbench", |s| s.contains("Analyses"));
    command(&tmux, "select b2");
    tmux.wait_for("b2, done", |s| s.contains("b2 · done"));
    // an unsaved edit, then o: asked first, n keeps it
    command(&tmux, "set adr 0.8");
    tmux.keys(&["o"]);
    tmux.wait_for("the picker", |s| s.contains("Open session"));
    tmux.keys(&["Enter"]);
    tmux.wait_for("the question", |s| s.contains("unsaved changes"));
    tmux.keys(&["n"]);
    tmux.wait_for("nothing done", |s| s.contains("nothing done"));
    // S onto an existing file: asked first
    let other = session.with_file_name("other.toml");
    std::fs::write(&other, "schema = 1\n").unwrap();
    tmux.keys(&["S"]);
    tmux.wait_for("save as", |s| s.contains("Save session as"));
    // the prompt holds the session's path: replace it with the other file's
    for _ in 0..session.display().to_string().chars().count() {
        tmux.keys(&["BSpace"]);
    }
    tmux.keys(&["-l", &other.display().to_string()]);
    tmux.keys(&["Enter"]);
    tmux.wait_for("the question", |s| s.contains("exists: replace it"));
    tmux.keys(&["Escape"]);
    assert_eq!(std::fs::read_to_string(&other).unwrap(), "schema = 1\n");
}
