//! Chunk files written on a thread of their own, so that the threads computing chunks never
//! wait for the disk: each file's two fsyncs (the file's and its folder's) took 0.5 ms on a
//! local disk, far longer on a cluster's network file system, and a thread waiting for them
//! leaves its core idle.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{Sender, channel};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use anyhow::Context;

use super::lock::Lock;
use crate::session::atomic::{is_temporary, is_temporary_of, sync_dir, write_atomic_unsynced};

/// One chunk's file to write, and the claim that keeps other runs off the chunk until it is
/// written.
struct Job {
    path: PathBuf,
    bytes: Vec<u8>,
    /// Held until the job is dropped, after its folder's fsync.
    _claim: Lock,
    /// What the chunk is, for an error.
    context: String,
}

/// Writes chunk files atomically ([`crate::session::atomic::write_atomic`]) in the order
/// given, each claim released once its file is in place and its name durable. The first
/// failure is kept: [`Self::healthy`] reports it to the threads computing, so that they stop,
/// and [`Self::finish`] returns it.
pub struct ChunkSaver {
    jobs: Option<Sender<Job>>,
    thread: Option<JoinHandle<()>>,
    failure: Arc<Mutex<Option<anyhow::Error>>>,
}

impl ChunkSaver {
    /// Starts the writing thread for the chunks of folder `dir`. The temporaries found there
    /// now were left by killed writers; each is removed before its chunk is written (under
    /// the chunk's claim, so that no live writer's is), and the folder is read only this once
    /// (reading it for every chunk took seconds for the 1 957 chunks of a 1001 × 1001 basin).
    pub fn start(dir: &Path) -> anyhow::Result<Self> {
        let mut leftovers: Vec<PathBuf> = std::fs::read_dir(dir)
            .map(|entries| {
                entries
                    .flatten()
                    .filter(|e| is_temporary(&e.file_name().to_string_lossy()))
                    .map(|e| e.path())
                    .collect()
            })
            .unwrap_or_default();
        let dir = dir.to_path_buf();
        let (jobs, received) = channel::<Job>();
        let failure: Arc<Mutex<Option<anyhow::Error>>> = Arc::default();
        let failed = Arc::clone(&failure);
        let thread = std::thread::Builder::new()
            .name("chunk-saver".into())
            .spawn(move || {
                // the chunks queued meanwhile in one go: each file written and renamed, then
                // one fsync of the folder for all their renames before their claims go
                while let Ok(first) = received.recv() {
                    let batch: Vec<Job> =
                        std::iter::once(first).chain(received.try_iter()).collect();
                    for job in &batch {
                        remove_leftovers(&mut leftovers, &job.path);
                        if let Err(e) = write(job) {
                            failed
                                .lock()
                                .expect("no panic while locked")
                                .get_or_insert(e);
                        }
                    }
                    sync_dir(&dir);
                    // the claims go
                    drop(batch);
                }
            })
            .context("starting the thread that writes chunks")?;
        Ok(ChunkSaver {
            jobs: Some(jobs),
            thread: Some(thread),
            failure,
        })
    }

    /// Queues chunk file `path` (in the saver's folder), written under `claim`; `context`
    /// names the chunk in an error.
    pub fn save(&self, path: PathBuf, bytes: Vec<u8>, claim: Lock, context: String) {
        let job = Job {
            path,
            bytes,
            _claim: claim,
            context,
        };
        if let Some(jobs) = &self.jobs {
            // the thread only ends when `jobs` is dropped
            let _ = jobs.send(job);
        }
    }

    /// `Err` once a chunk could not be written (the disk full, the folder gone): computing
    /// more chunks would be in vain.
    pub fn healthy(&self) -> anyhow::Result<()> {
        match &*self.failure.lock().expect("no panic while locked") {
            Some(e) => Err(anyhow::anyhow!("{e:#}")),
            None => Ok(()),
        }
    }

    /// Waits until every queued chunk is written; the first failure, if any.
    pub fn finish(mut self) -> anyhow::Result<()> {
        self.wait();
        match self.failure.lock().expect("no panic while locked").take() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    fn wait(&mut self) {
        drop(self.jobs.take());
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

impl Drop for ChunkSaver {
    /// Waits for the queued chunks even on an early return: their claims are released only
    /// once they are written.
    fn drop(&mut self) {
        self.wait();
    }
}

/// Removes the temporaries among `leftovers` of the file `path` (and forgets them).
fn remove_leftovers(leftovers: &mut Vec<PathBuf>, path: &Path) {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    leftovers.retain(|tmp| {
        let name = tmp.file_name().map(|n| n.to_string_lossy().into_owned());
        if !name.is_some_and(|n| is_temporary_of(&n, &stem)) {
            return true;
        }
        if std::fs::remove_file(tmp).is_ok() {
            tracing::info!(file = %tmp.display(), "stale temporary removed");
        }
        false
    });
}

/// One chunk's file, atomically but for its folder's fsync.
fn write(job: &Job) -> anyhow::Result<()> {
    write_atomic_unsynced(&job.path, &job.bytes)
        .map_err(|e| anyhow::anyhow!("{}: {e}", job.path.display()))
        .with_context(|| job.context.clone())?;
    tracing::debug!(file = %job.path.display(), "chunk saved");
    Ok(())
}
