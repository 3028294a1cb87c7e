//! What the end-to-end tests share: a pseudo-terminal of their own, and the workbench
//! spawned in it as its controlling terminal.

use std::fs::File;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::os::unix::process::CommandExt;
use std::process::{Child, Command, Stdio};
use std::sync::Mutex;

/// Held while a terminal is opened and its workbench spawned: a terminal opened while
/// another test spawns must not leak into that child (it would hold the terminal open).
static SPAWNING: Mutex<()> = Mutex::new(());

/// A pseudo-terminal pair (master, slave) of `cols × rows`, both close-on-exec.
pub fn open_pty(cols: u16, rows: u16) -> (OwnedFd, OwnedFd) {
    let (mut master, mut slave) = (0, 0);
    let size = libc::winsize {
        ws_row: rows,
        ws_col: cols,
        ws_xpixel: 0,
        ws_ypixel: 0,
    };
    // SAFETY: valid out-pointers; no name or termios asked for.
    let rc = unsafe {
        libc::openpty(
            &mut master,
            &mut slave,
            std::ptr::null_mut(),
            std::ptr::null(),
            &size,
        )
    };
    assert_eq!(rc, 0, "openpty: {}", std::io::Error::last_os_error());
    for fd in [master, slave] {
        // SAFETY: fcntl on a descriptor just opened.
        assert_eq!(
            unsafe { libc::fcntl(fd, libc::F_SETFD, libc::FD_CLOEXEC) },
            0
        );
    }
    // SAFETY: openpty returned two open descriptors that nothing else owns.
    unsafe { (OwnedFd::from_raw_fd(master), OwnedFd::from_raw_fd(slave)) }
}

/// `command` spawned with `slave` as its controlling terminal (a session of its own).
pub fn spawn_on(mut command: Command, slave: &OwnedFd) -> Child {
    let tty = || File::from(slave.try_clone().unwrap());
    let slave_fd = slave.as_raw_fd();
    command
        .env("TERM", "xterm-256color")
        .stdin(Stdio::from(tty()))
        .stdout(Stdio::from(tty()))
        .stderr(Stdio::from(tty()));
    // SAFETY: only async-signal-safe calls between fork and exec.
    unsafe {
        command.pre_exec(move || {
            if libc::setsid() < 0 || libc::ioctl(slave_fd, libc::TIOCSCTTY, 0) < 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    command.spawn().unwrap()
}

/// `command` spawned in a new `cols × rows` terminal: the child, the master end, and the
/// slave end (drop it to leave the terminal to the child alone).
#[allow(dead_code)] // (not every test binary that shares this module uses it)
pub fn spawn_in_pty(command: Command, cols: u16, rows: u16) -> (Child, File, OwnedFd) {
    let _one_at_a_time = SPAWNING.lock().unwrap_or_else(|e| e.into_inner());
    let (master, slave) = open_pty(cols, rows);
    let child = spawn_on(command, &slave);
    (child, File::from(master), slave)
}

/// A written model at its default values, from its `[model]` table's text.
pub fn written(model: &str) -> isola::model::equations::EquationSystem {
    let text = format!("schema = 1\n{model}");
    isola::session::written::WrittenModel::read(&text)
        .unwrap()
        .system(&Default::default())
        .unwrap()
}

/// The `isola` binary run with `args`, to its end.
pub fn isola(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_isola"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// The one JSON document a successful `isola ARGS` prints.
pub fn json(args: &[&str]) -> serde_json::Value {
    let out = isola(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}
