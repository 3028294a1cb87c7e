//! The results store: what `isola run` and the workbench keep beside a session, built for
//! many writers (threads, processes, shards on the nodes of a cluster) on one shared folder.
//!
//! Layout, for analysis `A` of `sessions/NAME.toml`:
//! - `NAME.results/A.csv` (and companions such as `A.attractors.csv`): the result;
//! - `NAME.results/A.manifest.json`: written last, only for a complete result: fingerprint,
//!   numerics, build, and a SHA-256 of every file of the result (see [`manifest`]);
//! - `NAME.results/A.lock`: held shared to read the result, exclusive to replace it;
//! - `NAME.results/A.earlier/FINGERPRINT/`: complete results of earlier settings, kept to be
//!   brought back when the settings come back (see [`earlier`]);
//! - `NAME.results/A.chunks/FINGERPRINT/`: the work under way for one fingerprint:
//!   - `000012.json`: a finished, self-describing chunk (see [`chunk`]);
//!   - `000012.claim`: locked by whoever computes chunk 12 (`host pid N` inside);
//!   - `active.lock`: held shared by every run taking part, so the folder is removed only
//!     when no run uses it;
//!   - `assemble.lock`: held by the one run that assembles the result;
//!   - `staging/`: the result's files before they are moved into place.
//!
//! Every check failing ends in recomputing or in an error naming the file, never in a result
//! that is used without being verified.

pub mod chunk;
pub mod copy;
pub mod earlier;
pub mod finite;
pub mod lock;
pub mod manifest;
pub mod saver;
pub mod survey;

use std::path::{Path, PathBuf};
use std::time::Duration;

use chunk::{ChunkError, ChunkId, Decoded, Payload};
use lock::{Lock, Mode};
use manifest::{Manifest, StoredFile, Unverified};
use saver::ChunkSaver;

/// Where analysis `name`'s files live.
#[derive(Debug, Clone)]
pub struct ResultPaths {
    /// `NAME.results/`.
    pub dir: PathBuf,
    pub name: String,
    /// The main result file, `A.csv`.
    pub csv: PathBuf,
    pub manifest: PathBuf,
    pub lock: PathBuf,
    /// `A.chunks/`, one folder per fingerprint under it.
    pub chunks: PathBuf,
}

impl ResultPaths {
    /// The paths of analysis `name` in the results folder `dir`.
    pub fn in_dir(dir: &Path, name: &str) -> Self {
        ResultPaths {
            dir: dir.to_path_buf(),
            name: name.to_string(),
            csv: dir.join(format!("{name}.csv")),
            manifest: dir.join(format!("{name}.manifest.json")),
            lock: dir.join(format!("{name}.lock")),
            chunks: dir.join(format!("{name}.chunks")),
        }
    }

    /// The work folder of `fingerprint`.
    pub fn work_dir(&self, fingerprint: &str) -> PathBuf {
        self.chunks.join(fingerprint)
    }

    /// Chunk `i`'s file in the work folder of `fingerprint`.
    pub fn chunk(&self, fingerprint: &str, i: usize) -> PathBuf {
        self.work_dir(fingerprint).join(chunk_name(i))
    }
}

/// `000012.json`.
pub fn chunk_name(i: usize) -> String {
    format!("{i:06}.json")
}

fn io_at(path: &Path) -> impl Fn(std::io::Error) -> anyhow::Error + '_ {
    move |e| anyhow::anyhow!("{}: {e}", path.display())
}

/// The verified manifest of the stored result, read under the shared lock so that a result
/// being replaced is never half-read.
pub fn verified(paths: &ResultPaths) -> Result<Manifest, Unverified> {
    with_verified(paths, Manifest::clone)
}

/// Runs `read` on the verified stored result while holding the shared lock, so that no run
/// replaces the files while they are read.
pub fn with_verified<R>(
    paths: &ResultPaths,
    read: impl FnOnce(&Manifest) -> R,
) -> Result<R, Unverified> {
    if !paths.dir.is_dir() {
        return Err(Unverified::Missing);
    }
    let _read = match Lock::acquire(&paths.lock, Mode::Shared) {
        Ok(lock) => Some(lock),
        // a folder no one may write to (results copied read-only): nothing can change it
        Err(e) if read_only(&e) && !paths.lock.exists() => None,
        Err(e) => {
            return Err(Unverified::Unreadable {
                file: paths.lock.display().to_string(),
                why: e.to_string(),
            });
        }
    };
    let m = verified_unlocked(paths)?;
    Ok(read(&m))
}

fn read_only(e: &std::io::Error) -> bool {
    matches!(
        e.kind(),
        std::io::ErrorKind::PermissionDenied | std::io::ErrorKind::ReadOnlyFilesystem
    )
}

fn verified_unlocked(paths: &ResultPaths) -> Result<Manifest, Unverified> {
    let m = Manifest::read(&paths.manifest)?;
    if m.analysis != paths.name {
        return Err(Unverified::Unreadable {
            file: paths.manifest.display().to_string(),
            why: format!("it is the manifest of analysis '{}'", m.analysis),
        });
    }
    m.verify_files(&paths.dir)?;
    Ok(m)
}

/// True when the stored result is complete, verified, and of `fingerprint`.
pub fn is_current(paths: &ResultPaths, fingerprint: &str) -> bool {
    verified(paths).is_ok_and(|m| m.fingerprint == fingerprint)
}

/// A run's part in the work of one fingerprint: holds `active.lock` shared until dropped.
pub struct Work {
    pub paths: ResultPaths,
    pub fingerprint: String,
    pub dir: PathBuf,
    _active: Lock,
}

impl Work {
    /// Joins (making it if needed) the work folder of `fingerprint`.
    pub fn join(paths: &ResultPaths, fingerprint: &str) -> anyhow::Result<Work> {
        let dir = paths.work_dir(fingerprint);
        for _ in 0..100 {
            std::fs::create_dir_all(&dir).map_err(io_at(&dir))?;
            let active = Lock::acquire(&dir.join("active.lock"), Mode::Shared)?;
            // the folder may have been retired while this run waited for the lock
            if active.still_at_path() {
                return Ok(Work {
                    paths: paths.clone(),
                    fingerprint: fingerprint.to_string(),
                    dir,
                    _active: active,
                });
            }
        }
        anyhow::bail!("{}: removed again and again while joining", dir.display())
    }

    pub fn id(&self, index: usize, chunks: usize) -> ChunkId<'_> {
        ChunkId {
            fingerprint: &self.fingerprint,
            index,
            chunks,
        }
    }

    pub fn chunk_path(&self, i: usize) -> PathBuf {
        self.dir.join(chunk_name(i))
    }

    fn claim_path(&self, i: usize) -> PathBuf {
        self.dir.join(format!("{i:06}.claim"))
    }

    /// Chunk `i` if its file exists and passes every check; `Err` says why it does not.
    pub fn read_chunk<T: Payload>(
        &self,
        i: usize,
        chunks: usize,
        content: impl FnOnce(&T) -> Result<(), String>,
    ) -> Result<Option<Decoded<T>>, ChunkError> {
        self.chunk_bytes(i)?
            .map(|bytes| chunk::decode(&bytes, &self.id(i, chunks), content))
            .transpose()
    }

    /// The seconds chunk `i` took if its file exists and passes every check but its
    /// payload's parse ([`chunk::check`]); `Err` says why it does not.
    pub fn check_chunk(&self, i: usize, chunks: usize) -> Result<Option<f64>, ChunkError> {
        self.chunk_bytes(i)?
            .map(|bytes| chunk::check(&bytes, &self.id(i, chunks)))
            .transpose()
    }

    /// Chunk `i`'s file, `None` if there is none.
    fn chunk_bytes(&self, i: usize) -> Result<Option<Vec<u8>>, ChunkError> {
        match std::fs::read(self.chunk_path(i)) {
            Ok(bytes) => Ok(Some(bytes)),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(ChunkError::BadPayload(e.to_string())),
        }
    }

    /// Claims chunk `i` if no one else has; `None` if someone is computing it.
    pub fn try_claim(&self, i: usize) -> anyhow::Result<Option<Lock>> {
        let claim = Lock::try_acquire(&self.claim_path(i), Mode::Exclusive)?;
        Ok(claim.map(|mut c| {
            let _ = c.describe(&lock::holder());
            c
        }))
    }

    /// Waits for the claim on chunk `i` (polling, so that `cancelled` is seen); `None` if
    /// cancelled.
    pub fn claim(&self, i: usize, cancelled: &dyn Fn() -> bool) -> anyhow::Result<Option<Lock>> {
        wait_for(|| self.try_claim(i), cancelled)
    }

    /// Moves chunk `i`'s file aside ([`Self::reject`]) if `check` still fails under its claim;
    /// nothing if another run holds the claim (it is computing the chunk again).
    pub fn reject_if_still_bad<R>(
        &self,
        i: usize,
        check: impl FnOnce() -> Result<R, ChunkError>,
    ) -> anyhow::Result<()> {
        if let Some(_claim) = self.try_claim(i)?
            && let Err(why) = check()
        {
            self.reject(i, &why);
        }
        Ok(())
    }

    /// Moves an unusable chunk file aside (`000012.json.rejected`, for inspection), logging
    /// why; only while holding its claim, so that a good file just written is never moved.
    pub fn reject(&self, i: usize, why: &ChunkError) {
        let path = self.chunk_path(i);
        tracing::warn!(file = %path.display(), reason = %why, "chunk rejected; recomputing");
        let aside = path.with_extension("json.rejected");
        if std::fs::rename(&path, &aside).is_err() {
            let _ = std::fs::remove_file(&path);
        }
    }

    /// Chunk `i`'s file contents, for [`Self::save_chunk`]; `Err` names the non-finite number
    /// a chunk may not hold.
    pub fn encode_chunk<T: Payload>(
        &self,
        i: usize,
        chunks: usize,
        value: &T,
        seconds: f64,
    ) -> anyhow::Result<Vec<u8>> {
        chunk::encode(&self.id(i, chunks), value, seconds)
            .map_err(|found| anyhow::anyhow!("{found}"))
    }

    /// Queues chunk `i`'s file on `saver`, to be written atomically under `claim`, which is
    /// released once it is; `context` names the chunk in an error.
    pub fn save_chunk(
        &self,
        saver: &ChunkSaver,
        i: usize,
        bytes: Vec<u8>,
        claim: Lock,
        context: String,
    ) {
        saver.save(self.chunk_path(i), bytes, claim, context);
    }

    /// Waits for the right to assemble the result; `None` if cancelled.
    pub fn assembler(&self, cancelled: &dyn Fn() -> bool) -> anyhow::Result<Option<Lock>> {
        let path = self.dir.join("assemble.lock");
        wait_for(|| Ok(Lock::try_acquire(&path, Mode::Exclusive)?), cancelled)
    }

    /// An empty staging folder for the result's files (call as the assembler).
    pub fn staging(&self) -> anyhow::Result<PathBuf> {
        let staging = self.dir.join("staging");
        if staging.exists() {
            std::fs::remove_dir_all(&staging).map_err(io_at(&staging))?;
        }
        std::fs::create_dir_all(&staging).map_err(io_at(&staging))?;
        Ok(staging)
    }

    /// Moves the staged `files` into the results folder and writes the manifest last, under
    /// the result's exclusive lock; returns the manifest. The files are checksummed in
    /// staging and checked again in place before the manifest says "complete". A stored
    /// result of other settings that `current` says the session now wants (edited while this
    /// ran, and computed since) is kept, and this one not stored: `None`.
    pub fn commit(
        &self,
        files: &[PathBuf],
        manifest: Manifest,
        current: &dyn Fn() -> Option<String>,
    ) -> anyhow::Result<Option<Manifest>> {
        let mut manifest = manifest;
        manifest.files = files
            .iter()
            .map(|f| StoredFile::of(f).map_err(io_at(f)))
            .collect::<anyhow::Result<_>>()?;
        let dir = &self.paths.dir;
        let _write = Lock::acquire(&self.paths.lock, Mode::Exclusive)?;
        let previous = Manifest::read(&self.paths.manifest).ok();
        if let Some(old) = &previous
            && old.fingerprint != manifest.fingerprint
            && current().as_ref() == Some(&old.fingerprint)
        {
            tracing::info!(analysis = %self.paths.name, current = %old.fingerprint,
                "not stored: the session's settings now are those of the stored result");
            earlier::keep_computed(&self.paths, files, &manifest);
            return Ok(None);
        }
        // a result of other settings is kept aside, its manifest gone first
        if let Some(old) = &previous
            && old.fingerprint != manifest.fingerprint
        {
            earlier::keep(&self.paths, old);
        }
        // the manifest goes first, so no old manifest vouches for half-replaced files
        match std::fs::remove_file(&self.paths.manifest) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(io_at(&self.paths.manifest)(e));
            }
            _ => {}
        }
        super::atomic::sync_dir(dir);
        for (staged, record) in files.iter().zip(&manifest.files) {
            let target = dir.join(&record.name);
            std::fs::rename(staged, &target).map_err(io_at(&target))?;
        }
        super::atomic::sync_dir(dir);
        for record in &manifest.files {
            record
                .verify(dir)
                .map_err(|e| anyhow::anyhow!("result not written as computed: {e}"))?;
        }
        let json = serde_json::to_vec_pretty(&manifest)?;
        super::atomic::write_atomic(&self.paths.manifest, &json)
            .map_err(io_at(&self.paths.manifest))?;
        // files of the previous result that this one does not have (another kind's tables)
        if let Some(old) = previous {
            for f in old.files {
                if !manifest.files.iter().any(|n| n.name == f.name) {
                    let _ = std::fs::remove_file(dir.join(&f.name));
                }
            }
        }
        super::atomic::remove_stale_temporaries(dir, &self.paths.name, Duration::ZERO);
        tracing::info!(
            analysis = %self.paths.name,
            fingerprint = %self.fingerprint,
            files = manifest.files.len(),
            "result committed"
        );
        Ok(Some(manifest))
    }

    /// Leaves the work; if the result of this fingerprint is now complete, removes the work
    /// folders that no run uses any more ([`remove_unused_work`]).
    pub fn retire(self) {
        let Work {
            paths,
            fingerprint,
            _active,
            ..
        } = self;
        drop(_active);
        if is_current(&paths, &fingerprint) {
            remove_unused_work(&paths, &fingerprint);
        }
    }
}

/// Work folders of other settings kept beside a complete result: an interrupted run of
/// settings since changed resumes when they come back (an undo, a comparison), and the
/// folder of settings long left does not stay for ever.
const KEEP_OTHER_SETTINGS: usize = 4;

/// Once the result of `current` is complete: removes its work folder (its work is in the
/// result), all but the [`KEEP_OTHER_SETTINGS`] most recently written of the other settings'
/// (and old-format chunks), each only if no run has joined it.
pub fn remove_unused_work(paths: &ResultPaths, current: &str) {
    let Ok(entries) = std::fs::read_dir(&paths.chunks) else {
        return;
    };
    let mut others: Vec<(std::time::SystemTime, PathBuf)> = Vec::new();
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().into_owned();
        if !path.is_dir() {
            // chunks of the unchecked format of earlier builds
            let _ = std::fs::remove_file(&path);
        } else if name.starts_with(".trash-") || name == current {
            remove_work_folder(paths, &path);
        } else {
            // chunks arrive by a rename into the folder, which sets its modification time
            let written =
                (entry.metadata().and_then(|m| m.modified())).unwrap_or(std::time::UNIX_EPOCH);
            others.push((written, path));
        }
    }
    others.sort_by_key(|(written, _)| std::cmp::Reverse(*written));
    for (_, path) in others.iter().skip(KEEP_OTHER_SETTINGS) {
        remove_work_folder(paths, path);
    }
    let _ = std::fs::remove_dir(&paths.chunks); // only if empty
}

/// Removes work folder `path` unless a run has joined it (a trash folder: whatever it holds).
fn remove_work_folder(paths: &ResultPaths, path: &Path) {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
    let Some(name) = name else { return };
    if name.starts_with(".trash-") {
        let _ = std::fs::remove_dir_all(path);
        return;
    }
    let Ok(Some(_unused)) = Lock::try_acquire(&path.join("active.lock"), Mode::Exclusive) else {
        return;
    };
    // moved away first: a run that joins now sees the folder gone and makes a new one
    let Ok(trash) = tempfile::Builder::new()
        .prefix(".trash-")
        .tempdir_in(&paths.chunks)
    else {
        return;
    };
    if std::fs::rename(path, trash.path().join(&name)).is_ok() {
        tracing::debug!(folder = %path.display(), "work folder removed");
    }
    drop(trash); // removes what was moved into it
}

/// Polls `attempt` every 20 ms until it gives a lock or `cancelled` says stop.
fn wait_for(
    mut attempt: impl FnMut() -> anyhow::Result<Option<Lock>>,
    cancelled: &dyn Fn() -> bool,
) -> anyhow::Result<Option<Lock>> {
    loop {
        if let Some(lock) = attempt()? {
            return Ok(Some(lock));
        }
        if cancelled() {
            return Ok(None);
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Seconds since 1970, for records.
pub fn unix_now() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs())
}
