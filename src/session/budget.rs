//! A run's budget: an analysis whose worst case would take longer than the time budget is
//! refused with its estimate and the settings to change (`--force` overrides that); one whose
//! result would not fit in memory is refused always, so that a run never aborts half-way.

use crate::analysis::cost::{self, Cost};
use crate::model::ParamError;

use super::schema::{AnalysisEntry, Session, Settings};
use super::written::ModelPoint;

/// Integration steps per second and thread assumed for estimates (the RK4 lanes run at
/// 1.6e7 to 1.8e8 per core on the reference machine; slack orbits are the slow end).
pub const STEPS_PER_SECOND: f64 = 2e7;

/// The time budget when none is given: a day of worst-case computing.
pub const DEFAULT_SECONDS: f64 = 86_400.0;

/// The longest a chunk may take in the worst case (about a minute in a typical one, whose
/// trajectories settle some fifty times sooner than their `max_forcing_periods`).
pub const CHUNK_SECONDS: f64 = 3600.0;

/// What a run may spend.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Budget {
    /// Wall seconds of the worst case on `threads` threads.
    pub seconds: f64,
    /// Bytes of memory (half of this machine's).
    pub bytes: f64,
    pub threads: usize,
    /// Run even if over the time budget (never over the memory bound).
    pub force: bool,
}

/// An analysis over its budget.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BudgetError {
    #[error(
        "analysis '{name}' could take up to {} on {threads} threads (worst case: {}), more than \
         the budget of {}: make the settings named smaller, or give a larger --budget or --force",
        duration(*seconds), factors.join(" × "), duration(*budget)
    )]
    Time {
        name: String,
        seconds: f64,
        threads: usize,
        budget: f64,
        factors: Vec<String>,
    },
    #[error(
        "one chunk of analysis '{name}' could take up to {} on a thread (worst case), more than \
         {}: a kill would lose all of it; make it smaller ({}), or give --force",
        duration(*seconds), duration(CHUNK_SECONDS), factors.join(" × ")
    )]
    Chunk {
        name: String,
        seconds: f64,
        factors: Vec<String>,
    },
    #[error(
        "analysis '{name}' would need {} of memory for its result ({}), more than {} (half of \
         this machine's): make the settings named smaller (--force does not override this)",
        size(*bytes), factors.join(", "), size(*bound)
    )]
    Memory {
        name: String,
        bytes: f64,
        bound: f64,
        factors: Vec<String>,
    },
    #[error(
        "analysis '{name}' would write about {} of chunks ({}), and {folder} has {} free: make \
         the settings named smaller or free some space",
        size(*bytes), factors.join(", "), size(*free)
    )]
    Disk {
        name: String,
        bytes: f64,
        free: f64,
        folder: String,
        factors: Vec<String>,
    },
    #[error("{0}")]
    Setting(ParamError),
}

/// Bytes free for this user in the folder at `path` (its nearest existing ancestor), if known.
pub fn free_space(path: &std::path::Path) -> Option<f64> {
    use std::os::unix::ffi::OsStrExt;
    let existing = path.ancestors().find(|p| p.is_dir())?;
    let c = std::ffi::CString::new(existing.as_os_str().as_bytes()).ok()?;
    // SAFETY: a zeroed statvfs is a valid out-value; `c` is a NUL-terminated path.
    let mut s: libc::statvfs = unsafe { std::mem::zeroed() };
    (unsafe { libc::statvfs(c.as_ptr(), &mut s) } == 0)
        .then_some(s.f_bavail as f64 * s.f_frsize as f64)
}

/// Seconds as a person reads them: `40 s`, `5 min`, `2.5 h`, `3 days`.
pub fn duration(seconds: f64) -> String {
    if seconds < 120.0 {
        format!("{seconds:.0} s")
    } else if seconds < 7200.0 {
        format!("{:.0} min", seconds / 60.0)
    } else if seconds < 172_800.0 {
        format!("{:.1} h", seconds / 3600.0)
    } else {
        format!("{:.0} days", seconds / 86_400.0)
    }
}

fn size(bytes: f64) -> String {
    if bytes < 1e9 {
        format!("{:.0} MB", bytes / 1e6)
    } else {
        format!("{:.1} GB", bytes / 1e9)
    }
}

/// Bytes of memory on this machine (`MemTotal` of `/proc/meminfo`), if known.
pub fn machine_memory() -> Option<f64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}

impl Budget {
    /// The budget for `threads` threads on this machine: `seconds` of worst-case time (the
    /// default if `None`) and half its memory (4 GB if unknown).
    pub fn on_this_machine(threads: usize, seconds: Option<f64>, force: bool) -> Budget {
        Budget {
            seconds: seconds.unwrap_or(DEFAULT_SECONDS),
            bytes: machine_memory().map_or(4e9, |m| 0.5 * m),
            threads: threads.max(1),
            force,
        }
    }

    /// Refuses `cost` for analysis `name` if it is over the budget.
    pub fn check(&self, name: &str, cost: &Cost) -> Result<(), BudgetError> {
        if cost.bytes > self.bytes {
            return Err(BudgetError::Memory {
                name: name.into(),
                bytes: cost.bytes,
                bound: self.bytes,
                factors: cost.memory.clone(),
            });
        }
        let rate = STEPS_PER_SECOND * self.threads as f64;
        let seconds = cost.steps / rate;
        if seconds > self.seconds && !self.force {
            return Err(BudgetError::Time {
                name: name.into(),
                seconds,
                threads: self.threads,
                budget: self.seconds,
                factors: cost.factors.clone(),
            });
        }
        // a chunk runs on one thread (a family's member or a map's row on all: this errs safe)
        let chunk = cost.chunk_steps() / STEPS_PER_SECOND;
        if chunk > CHUNK_SECONDS && cost.chunk.is_some() && !self.force {
            return Err(BudgetError::Chunk {
                name: name.into(),
                seconds: chunk,
                factors: cost.factors.clone(),
            });
        }
        Ok(())
    }
}

/// The worst-case cost of `entry` in `session`.
pub fn cost_of(session: &Session, entry: &AnalysisEntry) -> Result<Cost, BudgetError> {
    let point = session.point(Some(entry)).map_err(BudgetError::Setting)?;
    let omega = match &point {
        ModelPoint::BuiltIn(p) => p.omega(),
        ModelPoint::Written(sys) => sys.omega(),
    };
    match &entry.settings {
        Settings::ForceCurve(s) => Ok(cost::force(s)),
        Settings::TimeHistory(s) => cost::time_history(s, omega),
        Settings::ChirpSweep(s) => cost::chirp(s),
        Settings::SteppedSweep(s) => cost::stepped(&s.omega, &s.steady),
        Settings::FrequencyResponse(s) => cost::response(s, None),
        Settings::Basin(s) => cost::basin(s, omega),
        Settings::Family(s) => cost::family(s),
        Settings::Continuation(s) => cost::continuation(&s.continuation, &s.steady, omega),
        Settings::Hunt(s) => cost::hunt(s),
        Settings::Map(s) => cost::map(s, omega),
    }
    .map_err(BudgetError::Setting)
}

/// Checks every analysis of `entries` against `budget`, and the chunks they would write
/// against the free space beside the session, before any starts.
pub fn check_all<'a>(
    session: &Session,
    entries: impl IntoIterator<Item = &'a AnalysisEntry>,
    budget: &Budget,
) -> Result<(), BudgetError> {
    let folder = session.results_dir();
    let free = free_space(&folder);
    for entry in entries {
        let cost = cost_of(session, entry)?;
        // one trajectory, or a sweep from each ω's state to the next, runs on one thread
        let serial = matches!(
            entry.settings,
            Settings::TimeHistory(_) | Settings::ChirpSweep(_) | Settings::SteppedSweep(_)
        );
        let budget = Budget {
            threads: if serial { 1 } else { budget.threads },
            ..*budget
        };
        budget.check(&entry.name, &cost)?;
        if let Some(free) = free.filter(|&f| cost.disk > f) {
            return Err(BudgetError::Disk {
                name: entry.name.clone(),
                bytes: cost.disk,
                free,
                folder: folder.display().to_string(),
                factors: cost.memory.clone(),
            });
        }
    }
    Ok(())
}
