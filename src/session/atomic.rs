//! Files written whole or not at all: a temporary file with a random name beside the target,
//! fsync, rename, fsync of the folder.

use std::io::Write;
use std::path::Path;
use std::time::{Duration, SystemTime};

/// Writes `bytes` to `path` atomically: readers see the old file or the new one, never a
/// half-written one, and a crash before the rename leaves the old file intact. The temporary
/// (`.NAME.XXXXXX.tmp`, random, so writers on other hosts or in other PID namespaces never
/// collide) is removed on error; one left by a killed writer is removed by
/// [`remove_stale_temporaries`].
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_atomic_unsynced(path, bytes)?;
    sync_dir(folder_of(path));
    Ok(())
}

/// The folder `path` is in.
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// [`write_atomic`] without the fsync of the folder after the rename: the new name is durable
/// only once [`sync_dir`] has run on the folder (once after the last of many files).
pub fn write_atomic_unsynced(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::os::unix::fs::PermissionsExt;
    let dir = folder_of(path);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut tmp = tempfile::Builder::new()
        .prefix(&format!(".{name}."))
        .suffix(".tmp")
        // the usual mode under the user's umask, not tempfile's private 0600
        .permissions(std::fs::Permissions::from_mode(0o666))
        .tempfile_in(dir)
        // said of the folder the user named, not of the temporary's random name
        .map_err(|e| {
            let why = if dir.is_dir() {
                format!("cannot write in folder {}: {}", dir.display(), e.kind())
            } else {
                format!("no folder {}", dir.display())
            };
            std::io::Error::new(e.kind(), why)
        })?;
    tmp.write_all(bytes)?;
    tmp.as_file().sync_all()?;
    tmp.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// Makes renames and removals in `dir` durable (best effort: some file systems refuse).
pub fn sync_dir(dir: &Path) {
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

/// True for the name of a temporary that [`write_atomic`] makes (`.NAME.XXXXXX.tmp`).
pub fn is_temporary(file_name: &str) -> bool {
    file_name.starts_with('.') && file_name.ends_with(".tmp")
}

/// True for the name of a temporary that [`write_atomic`] makes for a file whose name starts
/// with `stem` (`stem` = `basin` matches `.basin.csv.XXXXXX.tmp`).
pub fn is_temporary_of(file_name: &str, stem: &str) -> bool {
    is_temporary(file_name)
        && file_name[1..]
            .strip_prefix(stem)
            .is_some_and(|rest| rest.starts_with('.'))
}

/// Removes the temporaries of files named `stem…` in `dir` that were last written more than
/// `older_than` ago (a live writer writes its temporary in one go, within seconds). Returns
/// how many were removed.
pub fn remove_stale_temporaries(dir: &Path, stem: &str, older_than: Duration) -> usize {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    let now = SystemTime::now();
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        if !is_temporary_of(&name, stem) {
            continue;
        }
        let old = entry
            .metadata()
            .and_then(|m| m.modified())
            .is_ok_and(|t| now.duration_since(t).unwrap_or_default() >= older_than);
        if old && std::fs::remove_file(entry.path()).is_ok() {
            tracing::info!(file = %entry.path().display(), "stale temporary removed");
            removed += 1;
        }
    }
    removed
}
