//! Background jobs: each analysis runs on its own rayon pool, publishes its progress, honours
//! a cancel flag, and turns a worker's panic into an error of the job. (Partial results reach
//! a viewer through the results store's chunks, not through the job.)

use std::panic::AssertUnwindSafe;
use std::sync::Arc;
use std::thread::JoinHandle;

pub use crate::analysis::Progress;

/// Why a job produced no result.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum JobError {
    #[error("cancelled")]
    Cancelled,
    #[error("a worker panicked: {0}")]
    Panicked(String),
    #[error("{0}")]
    Failed(String),
}

/// The cores of this machine (1 if unknown).
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The worker count for `threads` (0: one per core); more threads than cores is an error, since
/// they would only take the machine from everyone else.
pub fn worker_count(threads: usize) -> Result<usize, JobError> {
    let cores = cores();
    match threads {
        0 => Ok(cores),
        n if n <= cores => Ok(n),
        n => Err(JobError::Failed(format!(
            "--threads {n}: this machine has {cores} cores; give at most {cores} (0: one per core)"
        ))),
    }
}

/// What a running analysis sees: its pool and its progress.
pub struct JobContext {
    pub pool: rayon::ThreadPool,
    pub progress: Arc<Progress>,
}

/// How the workers share the machine with whoever else runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Priority {
    /// As the process that starts them.
    Normal,
    /// Lowered (nice +10 on Linux), so that an interactive thread beside them — the
    /// workbench reading keys — always gets a core at once.
    Background,
}

/// Lowers the calling thread's priority (Linux sets nice per thread).
fn lower_this_thread() {
    #[cfg(target_os = "linux")]
    // SAFETY: setpriority has no memory effects; 0 names the calling thread on Linux.
    unsafe {
        libc::setpriority(libc::PRIO_PROCESS, 0, 10);
    }
}

impl JobContext {
    /// A context with its own pool of `threads` workers (0: one per core).
    pub fn new(threads: usize, progress: Arc<Progress>) -> Result<Self, JobError> {
        Self::with_priority(threads, Priority::Normal, progress)
    }

    /// A context whose workers run at `priority`.
    pub fn with_priority(
        threads: usize,
        priority: Priority,
        progress: Arc<Progress>,
    ) -> Result<Self, JobError> {
        let mut builder = rayon::ThreadPoolBuilder::new()
            .num_threads(worker_count(threads)?)
            .thread_name(|i| format!("isola-worker-{i}"));
        if priority == Priority::Background {
            builder = builder.start_handler(|_| lower_this_thread());
        }
        let pool = builder
            .build()
            .map_err(|e| JobError::Failed(e.to_string()))?;
        Ok(JobContext { pool, progress })
    }

    /// Runs `f` on the pool; a panic anywhere in it becomes [`JobError::Panicked`].
    pub fn run<T: Send>(&self, f: impl FnOnce() -> T + Send) -> Result<T, JobError> {
        std::panic::catch_unwind(AssertUnwindSafe(|| self.pool.install(f))).map_err(|e| {
            let msg = e
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| e.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            JobError::Panicked(msg)
        })
    }

    /// `Err(Cancelled)` once the cancel flag is set.
    pub fn check_cancel(&self) -> Result<(), JobError> {
        if self.progress.is_cancelled() {
            Err(JobError::Cancelled)
        } else {
            Ok(())
        }
    }
}

/// A job running on a background thread.
pub struct Job<T> {
    pub progress: Arc<Progress>,
    handle: JoinHandle<Result<T, JobError>>,
}

impl<T: Send + 'static> Job<T> {
    /// Starts `work` on a new thread with a pool of `threads` workers.
    pub fn spawn(
        threads: usize,
        work: impl FnOnce(&JobContext) -> Result<T, JobError> + Send + 'static,
    ) -> Result<Self, JobError> {
        Self::spawn_with(threads, Priority::Normal, work)
    }

    /// [`Job::spawn`] with workers at `priority`.
    pub fn spawn_with(
        threads: usize,
        priority: Priority,
        work: impl FnOnce(&JobContext) -> Result<T, JobError> + Send + 'static,
    ) -> Result<Self, JobError> {
        let progress = Arc::new(Progress::new(0));
        let ctx = JobContext::with_priority(threads, priority, progress.clone())?;
        let handle = std::thread::Builder::new()
            .name("isola-job".into())
            .spawn(move || ctx.run(|| work(&ctx)).and_then(|r| r))
            .map_err(|e| JobError::Failed(e.to_string()))?;
        Ok(Job { progress, handle })
    }

    pub fn is_finished(&self) -> bool {
        self.handle.is_finished()
    }

    pub fn cancel(&self) {
        self.progress.cancel();
    }

    /// Waits for the result.
    pub fn join(self) -> Result<T, JobError> {
        self.handle
            .join()
            .unwrap_or_else(|_| Err(JobError::Panicked("job thread".into())))
    }
}
