//! The two-stage period test of MODEL.md §4b on a stream of stroboscopic points.

use std::collections::VecDeque;

/// Watches stroboscopic points of `N` numbers and says when, and with which period, they have
/// converged (max-norm over the `N`).
#[derive(Debug, Clone)]
pub struct PeriodDetector<const N: usize = 2> {
    history: VecDeque<[f64; N]>,
    /// The newest point's distance to the point k periods before it, for k = 1, 2, … while
    /// the history holds 2k points: the first term of each k's mismatch, measured once per
    /// point for [`Self::push`]'s precheck and [`Self::settling`] alike.
    newest_back: Vec<f64>,
    max_period: usize,
    tol_converged: f64,
    tol_match: f64,
    periods: usize,
}

/// max_i |a_i − b_i|.
#[inline]
fn distance<const N: usize>(a: &[f64; N], b: &[f64; N]) -> f64 {
    (1..N).fold((a[0] - b[0]).abs(), |m, i| m.max((a[i] - b[i]).abs()))
}

impl<const N: usize> PeriodDetector<N> {
    /// A detector of periods up to `max_period` that accepts one once its points repeat to
    /// `tol_converged`, and reports the smallest that repeats to `tol_match`.
    pub fn new(max_period: usize, tol_converged: f64, tol_match: f64) -> Self {
        PeriodDetector {
            history: VecDeque::with_capacity(2 * max_period + 1),
            newest_back: Vec::with_capacity(max_period),
            max_period,
            tol_converged,
            tol_match,
            periods: 0,
        }
    }

    /// Forcing periods seen so far.
    pub fn periods(&self) -> usize {
        self.periods
    }

    /// Takes the next point; returns the period k once some k ≤ `max_period` repeats to
    /// `tol_converged`: the smallest k that repeats to `tol_match`.
    pub fn push(&mut self, point: [f64; N]) -> Option<usize> {
        self.periods += 1;
        if self.history.len() == 2 * self.max_period {
            self.history.pop_front();
        }
        self.history.push_back(point);
        let n = self.history.len();
        let newest = &self.history[n - 1];
        self.newest_back.clear();
        self.newest_back.extend(
            (1..=self.max_period)
                .take_while(|&k| 2 * k <= n)
                .map(|k| distance(newest, &self.history[n - 1 - k])),
        );
        // cheap precheck: the newest point must be back within tol_converged of the point k
        // periods before for some k, or nothing has converged
        if !self.newest_back.iter().any(|&d| d < self.tol_converged) {
            return None;
        }
        let mut smallest_match = None;
        for k in 1..=self.newest_back.len() {
            let d = self.mismatch(k);
            if d < self.tol_match && smallest_match.is_none() {
                smallest_match = Some(k);
            }
            if d < self.tol_converged {
                return smallest_match;
            }
        }
        None
    }

    /// The smallest k whose last k points are back within `tol` of the points k periods
    /// before: the points look settled on a k-cycle (to `tol`, not yet to `tol_converged`).
    pub fn settling(&self, tol: f64) -> Option<usize> {
        (1..=self.newest_back.len())
            .find(|&k| self.newest_back[k - 1] < tol && self.mismatch(k) < tol)
    }

    /// max over the last k points of the distance to the point k periods earlier.
    fn mismatch(&self, k: usize) -> f64 {
        self.mismatch_back(k, 0)
    }

    /// The same, `back` points earlier.
    fn mismatch_back(&self, k: usize, back: usize) -> f64 {
        let h = &self.history;
        let n = h.len() - back;
        (0..k)
            .map(|j| distance(&h[n - 1 - j], &h[n - 1 - j - k]))
            .fold(0.0, f64::max)
    }
}
