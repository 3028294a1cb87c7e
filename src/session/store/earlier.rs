//! Complete results of earlier settings, kept so that settings that come back (an undo, a
//! comparison run twice) get their result back at once instead of computing it again.
//!
//! Layout, for analysis `A`: `NAME.results/A.earlier/FINGERPRINT/` holds the result's files
//! and, written last, its `A.manifest.json`. A result replaced by one of other settings is
//! moved there; a run whose settings have a kept result moves it back. Every move happens
//! under the result's exclusive lock, and a kept result is verified (every file against its
//! manifest) only before it is brought back: a damaged one is removed, and the run computes
//! afresh.

use std::path::{Path, PathBuf};

use super::ResultPaths;
use super::lock::{Lock, Mode};
use super::manifest::Manifest;

/// Earlier results kept per analysis, the most recently replaced first.
pub const KEEP_EARLIER: usize = 4;

impl ResultPaths {
    /// `A.earlier/`, one folder per fingerprint under it.
    pub fn earlier_dir(&self) -> PathBuf {
        self.dir.join(format!("{}.earlier", self.name))
    }

    /// The folder of the kept result of `fingerprint`.
    pub fn earlier(&self, fingerprint: &str) -> PathBuf {
        self.earlier_dir().join(fingerprint)
    }
}

/// True where a result of `fingerprint` is kept (not yet verified).
pub fn is_kept(paths: &ResultPaths, fingerprint: &str) -> bool {
    is_fingerprint(fingerprint) && manifest_in(paths, &paths.earlier(fingerprint)).is_file()
}

/// The kept result of `fingerprint` moved back into place, verified, as the stored result:
/// its manifest, or `None` if none is kept (or it failed its checks, and was removed). The
/// stored result it replaces is kept in turn.
pub fn bring_back(paths: &ResultPaths, fingerprint: &str) -> anyhow::Result<Option<Manifest>> {
    if !is_kept(paths, fingerprint) {
        return Ok(None);
    }
    let _write = Lock::acquire(&paths.lock, Mode::Exclusive)?;
    let stored = Manifest::read(&paths.manifest).ok();
    if let Some(m) = &stored
        && m.fingerprint == fingerprint
        && m.verify_files(&paths.dir).is_ok()
    {
        // brought back by another run while this one waited for the lock
        return Ok(Some(m.clone()));
    }
    let from = paths.earlier(fingerprint);
    let kept = match Manifest::read(&manifest_in(paths, &from)) {
        Ok(m) if m.analysis == paths.name && m.fingerprint == fingerprint => {
            m.verify_files(&from).map(|()| m)
        }
        Ok(m) => Err(super::manifest::Unverified::Unreadable {
            file: manifest_in(paths, &from).display().to_string(),
            why: format!("it is of analysis '{}', {}", m.analysis, m.fingerprint),
        }),
        Err(e) => Err(e),
    };
    let kept = match kept {
        Ok(m) if m.files.iter().all(|f| is_plain_name(&f.name)) => m,
        Ok(_) => {
            tracing::warn!(folder = %from.display(), "kept result names a file outside its folder; removed");
            let _ = std::fs::remove_dir_all(&from);
            return Ok(None);
        }
        Err(why) => {
            tracing::warn!(folder = %from.display(), reason = %why, "kept result failed its checks; removed");
            let _ = std::fs::remove_dir_all(&from);
            return Ok(None);
        }
    };
    // the stored result aside (kept if it verifies), its manifest gone before any file moves
    match &stored {
        Some(m) if m.fingerprint != fingerprint => keep(paths, m),
        _ => remove_manifest(paths)?,
    }
    // (verified above, under this lock: a rename moves the files as they are)
    let moved_in = (|| -> anyhow::Result<()> {
        for f in &kept.files {
            let (source, target) = (from.join(&f.name), paths.dir.join(&f.name));
            let moved = std::fs::rename(&source, &target);
            moved.map_err(|e| anyhow::anyhow!("{} → {target:?}: {e}", source.display()))?;
        }
        crate::session::atomic::sync_dir(&paths.dir);
        let json = serde_json::to_vec_pretty(&kept)?;
        crate::session::atomic::write_atomic(&paths.manifest, &json)
            .map_err(|e| anyhow::anyhow!("{}: {e}", paths.manifest.display()))
    })();
    if let Err(e) = moved_in {
        // back where they were kept (its manifest still there), for a later run to try again
        for f in &kept.files {
            let _ = std::fs::rename(paths.dir.join(&f.name), from.join(&f.name));
        }
        return Err(e);
    }
    // files of the replaced result that this one does not have (another kind's tables)
    if let Some(old) = &stored {
        for f in old.files.iter().filter(|f| is_plain_name(&f.name)) {
            if !kept.files.iter().any(|n| n.name == f.name) {
                let _ = std::fs::remove_file(paths.dir.join(&f.name));
            }
        }
    }
    let _ = std::fs::remove_dir_all(&from);
    tracing::info!(analysis = %paths.name, fingerprint, "kept result brought back");
    Ok(Some(kept))
}

/// The results kept for `from`'s earlier settings copied as `to`'s (a copied or renamed
/// analysis, a session saved as another file), so that they come back for it too: each
/// verified against its manifest, its files copied under `to`'s names and checked, its
/// manifest written last, oldest first (so they stay in the order they were kept). One that
/// fails its checks, is of other numerics, or is kept for `to` already, is not copied; one
/// whose copy fails is removed (and logged). Returns how many were copied.
pub fn copy_kept(from: &ResultPaths, to: &ResultPaths) -> anyhow::Result<usize> {
    let Ok(entries) = std::fs::read_dir(from.earlier_dir()) else {
        return Ok(0);
    };
    // (another session's results folder may not be there yet)
    std::fs::create_dir_all(&to.dir).map_err(|e| anyhow::anyhow!("{}: {e}", to.dir.display()))?;
    let _read = Lock::acquire(&from.lock, Mode::Shared)?;
    let _write = Lock::acquire(&to.lock, Mode::Exclusive)?;
    let mut found: Vec<(std::time::SystemTime, PathBuf, Manifest)> = Vec::new();
    for entry in entries.flatten() {
        let folder = entry.path();
        let manifest = manifest_in(from, &folder);
        let Ok(m) = Manifest::read(&manifest) else {
            continue;
        };
        let copyable = m.analysis == from.name
            && folder.file_name().is_some_and(|f| *f == *m.fingerprint)
            && is_fingerprint(&m.fingerprint)
            && m.numerics == crate::analysis::NUMERICS_VERSION
            && m.files.iter().all(|f| is_plain_name(&f.name))
            && !is_kept(to, &m.fingerprint)
            && m.verify_files(&folder).is_ok();
        if let (true, Ok(written)) = (
            copyable,
            std::fs::metadata(&manifest).and_then(|m| m.modified()),
        ) {
            found.push((written, folder, m));
        }
    }
    found.sort_by_key(|(written, ..)| *written);
    let mut copied = 0;
    for (_, folder, kept) in found {
        let target = to.earlier(&kept.fingerprint);
        let done = (|| -> anyhow::Result<()> {
            std::fs::create_dir_all(&target)?;
            let mut m = kept.clone();
            m.analysis = to.name.clone();
            for f in &mut m.files {
                let name = super::copy::renamed(&f.name, &from.name, &to.name);
                std::fs::copy(folder.join(&f.name), target.join(&name))?;
                f.name = name;
            }
            m.verify_files(&target)
                .map_err(|why| anyhow::anyhow!("changed while being copied: {why}"))?;
            crate::session::atomic::sync_dir(&target);
            let json = serde_json::to_vec_pretty(&m)?;
            crate::session::atomic::write_atomic(&manifest_in(to, &target), &json)
                .map_err(|e| anyhow::anyhow!("{e}"))
        })();
        match done {
            Ok(()) => copied += 1,
            Err(e) => {
                tracing::warn!(folder = %target.display(), error = %format!("{e:#}"), "kept result not copied");
                let _ = std::fs::remove_dir_all(&target);
            }
        }
    }
    prune(to);
    Ok(copied)
}

/// Moves the stored result of manifest `stored` (to be replaced) aside as a kept result
/// (its files are verified if it is ever brought back); a manifest of another analysis, or
/// naming a file outside the folder, is only removed, as a replacement does. Call under the
/// exclusive lock. Its manifest is gone from the results folder either way.
pub(super) fn keep(paths: &ResultPaths, stored: &Manifest) {
    let keepable = stored.analysis == paths.name
        && is_fingerprint(&stored.fingerprint)
        && stored.files.iter().all(|f| is_plain_name(&f.name));
    if remove_manifest(paths).is_err() || !keepable {
        return;
    }
    let files: Vec<PathBuf> = stored
        .files
        .iter()
        .map(|f| paths.dir.join(&f.name))
        .collect();
    put(paths, stored, &files, "replaced result");
}

/// Keeps a result computed for settings the session no longer has (not stored: the stored
/// result is of its settings now), so that its work is not lost if they come back: its
/// checksummed `files` (staged, in `computed`'s order) moved in, `computed` written last.
/// Call under the exclusive lock.
pub(super) fn keep_computed(paths: &ResultPaths, files: &[PathBuf], computed: &Manifest) {
    if is_fingerprint(&computed.fingerprint)
        && computed.files.iter().all(|f| is_plain_name(&f.name))
    {
        put(
            paths,
            computed,
            files,
            "result computed for earlier settings",
        );
    }
}

/// Moves `files` into the kept folder of `m`'s fingerprint, each under its name in `m`, then
/// writes `m` there and prunes; on any failure the folder is removed (`what`: the log's
/// words for the result).
fn put(paths: &ResultPaths, m: &Manifest, files: &[PathBuf], what: &str) {
    let to = paths.earlier(&m.fingerprint);
    let moved = (|| -> std::io::Result<()> {
        if to.exists() {
            std::fs::remove_dir_all(&to)?;
        }
        std::fs::create_dir_all(&to)?;
        for (from, f) in files.iter().zip(&m.files) {
            std::fs::rename(from, to.join(&f.name))?;
        }
        crate::session::atomic::sync_dir(&to);
        let json = serde_json::to_vec_pretty(m).map_err(std::io::Error::other)?;
        crate::session::atomic::write_atomic(&manifest_in(paths, &to), &json)
    })();
    match moved {
        Ok(()) => {
            tracing::info!(analysis = %paths.name, fingerprint = %m.fingerprint, "{what} kept");
            prune(paths);
        }
        Err(e) => {
            // not kept: what was moved goes with its folder
            tracing::warn!(folder = %to.display(), error = %e, "{what} not kept");
            let _ = std::fs::remove_dir_all(&to);
        }
    }
}

/// Removes all but the [`KEEP_EARLIER`] most recently kept results, folders without a
/// readable manifest (a keep cut short), and results of other numerics (no settings of this
/// build have their fingerprint).
fn prune(paths: &ResultPaths) {
    let Ok(entries) = std::fs::read_dir(paths.earlier_dir()) else {
        return;
    };
    let mut kept: Vec<(std::time::SystemTime, PathBuf)> = Vec::new();
    for entry in entries.flatten() {
        let folder = entry.path();
        let manifest = manifest_in(paths, &folder);
        let of_this_build = Manifest::read(&manifest)
            .is_ok_and(|m| m.numerics == crate::analysis::NUMERICS_VERSION);
        match std::fs::metadata(&manifest).and_then(|m| m.modified()) {
            Ok(written) if of_this_build => kept.push((written, folder)),
            _ => {
                let _ = std::fs::remove_dir_all(&folder);
            }
        }
    }
    kept.sort_by_key(|(written, _)| std::cmp::Reverse(*written));
    for (_, folder) in kept.iter().skip(KEEP_EARLIER) {
        let _ = std::fs::remove_dir_all(folder);
    }
}

fn manifest_in(paths: &ResultPaths, folder: &Path) -> PathBuf {
    folder.join(format!("{}.manifest.json", paths.name))
}

fn remove_manifest(paths: &ResultPaths) -> anyhow::Result<()> {
    match std::fs::remove_file(&paths.manifest) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(anyhow::anyhow!("{}: {e}", paths.manifest.display()))
        }
        _ => {
            crate::session::atomic::sync_dir(&paths.dir);
            Ok(())
        }
    }
}

/// A fingerprint as this build writes them (32 hex digits): safe as a folder's name.
fn is_fingerprint(s: &str) -> bool {
    s.len() == 32 && s.bytes().all(|b| b.is_ascii_hexdigit())
}

/// A file name inside the results folder, not a path out of it.
fn is_plain_name(name: &str) -> bool {
    Path::new(name).file_name().is_some_and(|n| n == name) && name != ".."
}
