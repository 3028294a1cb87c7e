//! Progress and cancellation shared between an analysis and whoever watches it.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Counters a viewer polls: work done of total, and the cancel flag it may set.
#[derive(Debug, Default)]
pub struct Progress {
    done: AtomicUsize,
    total: AtomicUsize,
    /// Steps of work whose amount is not known ahead (the points of a continued branch or
    /// curve): counted as they are done, never part of the fraction.
    open: AtomicUsize,
    cancel: AtomicBool,
}

impl Progress {
    pub fn new(total: usize) -> Self {
        Progress {
            total: AtomicUsize::new(total),
            ..Progress::default()
        }
    }

    /// (done, total).
    pub fn get(&self) -> (usize, usize) {
        (
            self.done.load(Ordering::Relaxed),
            self.total.load(Ordering::Relaxed),
        )
    }

    /// Fraction done in [0, 1].
    pub fn fraction(&self) -> f64 {
        let (d, t) = self.get();
        if t == 0 { 1.0 } else { d as f64 / t as f64 }
    }

    pub fn add(&self, n: usize) {
        self.done.fetch_add(n, Ordering::Relaxed);
    }

    /// One step of work of unknown length done (a continuation point).
    pub fn step(&self) {
        self.open.fetch_add(1, Ordering::Relaxed);
    }

    /// Steps of unknown-length work done so far.
    pub fn open_steps(&self) -> usize {
        self.open.load(Ordering::Relaxed)
    }

    /// True while a fraction says nothing: no work of known size announced yet (a
    /// continuation announces none), or all of it done while work of unknown length goes on
    /// (a map's curves after its rows).
    pub fn in_open_phase(&self) -> bool {
        let (done, total) = self.get();
        total == 0 || (done >= total && self.open_steps() > 0)
    }

    /// Announces `n` more units of work (an analysis made of several calls adds each one's).
    pub fn grow_total(&self, n: usize) {
        self.total.fetch_add(n, Ordering::Relaxed);
    }

    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    pub fn cancel_flag(&self) -> &AtomicBool {
        &self.cancel
    }

    pub fn is_cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
}
