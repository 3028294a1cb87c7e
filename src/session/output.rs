//! Where a user-chosen output (`--csv FILE`, an export) may go, checked before any work starts:
//! a regular file is replaced atomically (through a symbolic link, the file it points to), a
//! FIFO or character device (`/dev/stdout`, `/dev/null`) is written through and never
//! replaced, anything else is refused; so are the session file and its stored results.

use std::io::Write;
use std::path::{Path, PathBuf};

/// A temporary of a user's output older than this was left by a killed writer (a live one
/// writes its temporary in one go).
const STALE_AFTER: std::time::Duration = std::time::Duration::from_secs(600);

/// Why an output cannot go where it was asked to.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("{path}: is a directory; give a file name")]
    Directory { path: PathBuf },
    #[error(
        "{path}: is a {what}; isola writes only to a regular file, a FIFO or a character device"
    )]
    Special { path: PathBuf, what: &'static str },
    #[error("{path}: folder {folder} does not exist")]
    NoFolder { path: PathBuf, folder: PathBuf },
    #[error("{path}: folder {folder} is not writable")]
    ReadOnly { path: PathBuf, folder: PathBuf },
    #[error("{path}: would overwrite {what}; choose another file")]
    Protected { path: PathBuf, what: String },
    #[error("{path}: {error}")]
    Io {
        path: PathBuf,
        error: std::io::Error,
    },
}

/// A checked output: what to do when the bytes are ready.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum OutputTarget {
    /// Replace (or create) this regular file atomically.
    File(PathBuf),
    /// Write through to this FIFO or character device.
    Stream(PathBuf),
}

/// Files an output must not replace: a session file and the results folder beside it.
#[derive(Debug, Clone, Default)]
pub struct Protected {
    files: Vec<(PathBuf, String)>,
    folders: Vec<(PathBuf, String)>,
}

impl Protected {
    /// Nothing protected (outputs of commands that have no session).
    pub fn none() -> Self {
        Protected::default()
    }

    /// The session file at `session` and its results folder `results`.
    pub fn session(session: &Path, results: &Path) -> Self {
        let mut p = Protected::default();
        if let Ok(s) = session.canonicalize() {
            p.files
                .push((s, format!("the session {}", session.display())));
        }
        if let Ok(r) = results.canonicalize() {
            p.folders
                .push((r, format!("a stored result in {}", results.display())));
        }
        p
    }

    fn check(&self, path: &Path, resolved: &Path) -> Result<(), OutputError> {
        let hit = self
            .files
            .iter()
            .find(|(f, _)| f == resolved)
            .or_else(|| self.folders.iter().find(|(d, _)| resolved.starts_with(d)));
        match hit {
            Some((_, what)) => Err(OutputError::Protected {
                path: path.to_path_buf(),
                what: what.clone(),
            }),
            None => Ok(()),
        }
    }
}

/// Checks that `path` can take an output, before anything is computed.
pub fn check_target(path: &Path, protected: &Protected) -> Result<OutputTarget, OutputError> {
    use std::os::unix::fs::FileTypeExt;
    let io = |error| OutputError::Io {
        path: path.to_path_buf(),
        error,
    };
    match std::fs::metadata(path) {
        Ok(meta) => {
            // exists (a symbolic link is followed to what it names)
            let resolved = path.canonicalize().map_err(io)?;
            let kind = meta.file_type();
            if kind.is_dir() {
                return Err(OutputError::Directory {
                    path: path.to_path_buf(),
                });
            }
            if kind.is_fifo() || kind.is_char_device() {
                return Ok(OutputTarget::Stream(resolved));
            }
            if !kind.is_file() {
                let what = if kind.is_socket() {
                    "socket"
                } else if kind.is_block_device() {
                    "block device"
                } else {
                    "special file"
                };
                return Err(OutputError::Special {
                    path: path.to_path_buf(),
                    what,
                });
            }
            protected.check(path, &resolved)?;
            writable_folder(path, resolved.parent().unwrap_or(Path::new("/")))?;
            Ok(OutputTarget::File(resolved))
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            if std::fs::symlink_metadata(path).is_ok() {
                // a dangling link: replacing it would silently drop the link
                return Err(OutputError::Special {
                    path: path.to_path_buf(),
                    what: "symbolic link to nothing",
                });
            }
            let folder = match path.parent() {
                Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
                _ => PathBuf::from("."),
            };
            if !folder.is_dir() {
                return Err(OutputError::NoFolder {
                    path: path.to_path_buf(),
                    folder,
                });
            }
            let resolved = folder
                .canonicalize()
                .map_err(io)?
                .join(path.file_name().ok_or_else(|| OutputError::Directory {
                    path: path.to_path_buf(),
                })?);
            protected.check(path, &resolved)?;
            writable_folder(path, &folder)?;
            Ok(OutputTarget::File(resolved))
        }
        Err(e) => Err(io(e)),
    }
}

fn writable_folder(path: &Path, folder: &Path) -> Result<(), OutputError> {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(folder.as_os_str().as_bytes()).map_err(|_| {
        OutputError::NoFolder {
            path: path.to_path_buf(),
            folder: folder.to_path_buf(),
        }
    })?;
    // SAFETY: `c` is a valid NUL-terminated path for the duration of the call.
    let ok = unsafe { libc::access(c.as_ptr(), libc::W_OK | libc::X_OK) } == 0;
    if ok {
        Ok(())
    } else {
        Err(OutputError::ReadOnly {
            path: path.to_path_buf(),
            folder: folder.to_path_buf(),
        })
    }
}

impl OutputTarget {
    /// Writes `bytes` there: atomically for a file, straight through for a stream.
    pub fn write(&self, bytes: &[u8]) -> Result<(), OutputError> {
        match self {
            OutputTarget::File(path) => {
                super::atomic::write_atomic(path, bytes).map_err(|error| OutputError::Io {
                    path: path.clone(),
                    error,
                })?;
                // temporaries of this file left by a writer killed long ago
                if let (Some(dir), Some(name)) = (path.parent(), path.file_name()) {
                    let name = name.to_string_lossy();
                    super::atomic::remove_stale_temporaries(dir, &name, STALE_AFTER);
                }
                Ok(())
            }
            OutputTarget::Stream(path) => std::fs::OpenOptions::new()
                .write(true)
                .open(path)
                .and_then(|mut f| f.write_all(bytes))
                .map_err(|error| OutputError::Io {
                    path: path.clone(),
                    error,
                }),
        }
    }

    /// The file or stream written.
    pub fn path(&self) -> &Path {
        match self {
            OutputTarget::File(p) | OutputTarget::Stream(p) => p,
        }
    }
}

/// Writes `bytes` to `path` with the checks of [`check_target`].
pub fn write_output(path: &Path, bytes: &[u8], protected: &Protected) -> Result<(), OutputError> {
    check_target(path, protected)?.write(bytes)
}
