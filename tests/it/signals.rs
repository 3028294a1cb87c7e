//! The workbench in a pseudo-terminal of its own (no tmux): SIGINT, SIGQUIT, SIGTERM and
//! SIGHUP each end it with the conventional status (128 + the signal's number), the terminal
//! back in cooked mode with echo, off the alternate screen and with the cursor shown.

use crate::common;

use std::fs::File;
use std::io::Read;
use std::os::fd::{AsRawFd, OwnedFd};
use std::os::unix::process::ExitStatusExt;
use std::process::Command;
use std::time::{Duration, Instant};

fn modes(slave: &OwnedFd) -> libc::termios {
    // SAFETY: a zeroed termios is a valid out-value for tcgetattr.
    let mut t: libc::termios = unsafe { std::mem::zeroed() };
    // SAFETY: `slave` is an open terminal descriptor.
    assert_eq!(unsafe { libc::tcgetattr(slave.as_raw_fd(), &mut t) }, 0);
    t
}

/// Reads what the workbench draws until `until` appears (or `limit` passes); returns it all.
fn read_until(master: &mut File, until: &str, limit: Duration) -> String {
    let fd = master.as_raw_fd();
    let mut seen = Vec::new();
    let start = Instant::now();
    while start.elapsed() < limit {
        let mut poll = libc::pollfd {
            fd,
            events: libc::POLLIN,
            revents: 0,
        };
        // SAFETY: one valid pollfd.
        if unsafe { libc::poll(&mut poll, 1, 50) } <= 0 {
            continue;
        }
        let mut buf = [0u8; 65536];
        match master.read(&mut buf) {
            Ok(0) | Err(_) => break,
            Ok(n) => seen.extend_from_slice(&buf[..n]),
        }
        if String::from_utf8_lossy(&seen).contains(until) {
            break;
        }
    }
    String::from_utf8_lossy(&seen).into_owned()
}

#[test]
fn every_catchable_signal_restores_the_terminal_with_its_status() {
    let dir = tempfile::tempdir().unwrap();
    let session = dir.path().join("s.toml");
    std::fs::write(
        &session,
        "schema = 1\n[[analysis]]\nname = \"o\"\nkind = \"time_history\"\n",
    )
    .unwrap();
    for (signal, status) in [
        (libc::SIGINT, 130),
        (libc::SIGQUIT, 131),
        (libc::SIGTERM, 143),
        (libc::SIGHUP, 129),
    ] {
        let (master, slave) = common::open_pty(100, 30);
        let before = modes(&slave);
        assert!(before.c_lflag & libc::ECHO != 0 && before.c_lflag & libc::ICANON != 0);
        let mut command = Command::new(env!("CARGO_BIN_EXE_isola"));
        command
            .arg("tui")
            .arg(&session)
            .env("XDG_STATE_HOME", dir.path())
            .env("XDG_CONFIG_HOME", dir.path());
        let mut child = common::spawn_on(command, &slave);
        let mut screen = File::from(master);
        let drawn = read_until(&mut screen, "Analyses", Duration::from_secs(20));
        assert!(
            drawn.contains("Analyses"),
            "the workbench did not draw: {drawn:?}"
        );
        let raw = modes(&slave);
        assert!(raw.c_lflag & libc::ICANON == 0, "raw mode while it runs");
        // SAFETY: signalling our own child.
        unsafe { libc::kill(child.id() as i32, signal) };
        let rest = read_until(&mut screen, "\u{1b}[?1049l", Duration::from_secs(10));
        let exit = child.wait().unwrap();
        assert_eq!(
            exit.code(),
            Some(status),
            "signal {signal}: {exit:?} ({:?})",
            exit.signal()
        );
        let after = modes(&slave);
        assert!(
            after.c_lflag & libc::ECHO != 0 && after.c_lflag & libc::ICANON != 0,
            "signal {signal}: terminal left without echo or line mode"
        );
        assert!(
            rest.contains("\u{1b}[?1049l"),
            "signal {signal}: alternate screen not left"
        );
        assert!(
            rest.contains("\u{1b}[?25h"),
            "signal {signal}: cursor not shown"
        );
    }
}
