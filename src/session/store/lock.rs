//! Advisory file locks: `flock(2)` through `std::fs::File::lock`, released when the lock is
//! dropped or its process dies (also by `kill -9`), so a dead writer never holds anything.
//!
//! On Linux, `flock` on NFS is carried out as a whole-file POSIX lock that the NFS client
//! forwards to the server (NLM for NFSv3, the protocol's own locks for NFSv4), so the locks
//! hold across the nodes of a cluster sharing the directory; see the README for Lustre, GPFS
//! and BeeGFS. A file system that refuses locks is an error, never a silent run without them.

use std::fs::{File, OpenOptions, TryLockError};
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// A held lock; released on drop.
#[derive(Debug)]
pub struct Lock {
    file: File,
    path: PathBuf,
}

/// Shared (many holders) or exclusive (one holder).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    Shared,
    Exclusive,
}

fn open(path: &Path) -> io::Result<File> {
    OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(path)
        .or_else(|e| match e.kind() {
            // a lock file in a folder shared read-only (by its permissions or its mount): a
            // shared lock still works
            io::ErrorKind::PermissionDenied | io::ErrorKind::ReadOnlyFilesystem => File::open(path),
            _ => Err(e),
        })
}

/// The error for a lock that could not be taken, naming the file and what to do.
fn lock_error(path: &Path, error: io::Error) -> io::Error {
    let hint = match error.raw_os_error() {
        Some(libc::ENOLCK | libc::ENOSYS | libc::EOPNOTSUPP) => {
            ": this file system does not support file locks (NFSv3 needs lockd, Lustre the \
             `flock` mount option; see README, Cluster)"
        }
        _ => "",
    };
    io::Error::new(
        error.kind(),
        format!("cannot lock {}: {error}{hint}", path.display()),
    )
}

impl Lock {
    /// Waits until the lock on `path` (made if missing) is granted.
    pub fn acquire(path: &Path, mode: Mode) -> io::Result<Lock> {
        let file = open(path).map_err(|e| lock_error(path, e))?;
        match mode {
            Mode::Shared => file.lock_shared(),
            Mode::Exclusive => file.lock(),
        }
        .map_err(|e| lock_error(path, e))?;
        Ok(Lock {
            file,
            path: path.to_path_buf(),
        })
    }

    /// The lock on `path` if it is free now; `None` if another holder has it.
    pub fn try_acquire(path: &Path, mode: Mode) -> io::Result<Option<Lock>> {
        let file = open(path).map_err(|e| lock_error(path, e))?;
        let attempt = match mode {
            Mode::Shared => file.try_lock_shared(),
            Mode::Exclusive => file.try_lock(),
        };
        match attempt {
            Ok(()) => Ok(Some(Lock {
                file,
                path: path.to_path_buf(),
            })),
            Err(TryLockError::WouldBlock) => Ok(None),
            Err(TryLockError::Error(e)) => Err(lock_error(path, e)),
        }
    }

    /// True while `path` still names the locked file (it may have been removed or replaced
    /// while this process waited for the lock).
    pub fn still_at_path(&self) -> bool {
        use std::os::unix::fs::MetadataExt;
        match (self.file.metadata(), std::fs::metadata(&self.path)) {
            (Ok(held), Ok(named)) => held.dev() == named.dev() && held.ino() == named.ino(),
            _ => false,
        }
    }

    /// Replaces the lock file's text (who holds it, for `isola status` and for people).
    pub fn describe(&mut self, text: &str) -> io::Result<()> {
        self.file.set_len(0)?;
        use std::io::Seek;
        self.file.seek(io::SeekFrom::Start(0))?;
        self.file.write_all(text.as_bytes())
    }
}

/// This host's name, for provenance and claims.
pub fn host_name() -> String {
    let mut buf = [0u8; 256];
    // SAFETY: the buffer is valid for its length; gethostname writes at most that many bytes.
    let rc = unsafe { libc::gethostname(buf.as_mut_ptr().cast(), buf.len()) };
    if rc != 0 {
        return "unknown".into();
    }
    let end = buf.iter().position(|&b| b == 0).unwrap_or(buf.len());
    String::from_utf8_lossy(&buf[..end]).into_owned()
}

/// Who is writing: `host pid N` (the pid alone is not unique across hosts or PID namespaces).
pub fn holder() -> String {
    format!("{} pid {}", host_name(), std::process::id())
}
