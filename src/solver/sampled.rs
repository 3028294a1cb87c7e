//! A trajectory of a [`System`] recorded at equal sample intervals by the general engine's
//! RK4, each interval's error held within a tolerance by step doubling.
//!
//! Each sample interval is integrated twice from the same state, with N and 2N RK4 steps, and
//! N doubled until the two agree: the 2N run's error is about a fifteenth of their difference
//! (RK4 is of fourth order, and the general engine keeps it across kinks), and it must be
//! within `atol + rtol·|x|` in every state. The 2N run is recorded and the next interval
//! starts from its end; where the estimate is far inside the tolerance, N is halved again
//! (never below the least allowed). Steps are refined only where the trajectory needs them
//! (near a singular kink, `sqrt` at its branch's end), not over the whole record.

use std::collections::BTreeMap;

use crate::model::system::{Mode, System, Vector};
use crate::solver::Tolerance;
use crate::solver::general::{GeneralRk4, Stop};

/// Records a trajectory of `S`, one sample interval at a time.
#[derive(Debug, Clone)]
pub struct Sampler<S: System> {
    model: S,
    /// A copy of the model per step length used (its forcing tabulated for that length).
    by_steps: BTreeMap<usize, S>,
    samples_per_period: usize,
    least: usize,
    most: usize,
    /// The coarse run's steps per sample interval.
    per_sample: usize,
    tolerance: Tolerance,
}

/// One sample interval: its end sample (τ, state, piece), unless the trajectory stopped
/// first, and what stopped it.
#[derive(Debug, Clone)]
pub struct Interval {
    pub end: Option<(f64, Vector, Mode)>,
    pub stop: Option<Stop>,
}

/// A sample interval whose tolerance was not met at the most steps allowed: the fine run's
/// steps per sample interval and its error estimate over the tolerance.
#[derive(Debug, Clone, Copy)]
pub struct NotMet {
    pub steps: usize,
    pub excess: f64,
}

impl<S: System> Sampler<S> {
    /// Samples `samples_per_period` times per [`System::period`] of `sys`, each interval's
    /// error within `tolerance`, the coarse run at `least` to `most`/2 steps per interval.
    pub fn new(
        sys: S,
        samples_per_period: usize,
        least: usize,
        most: usize,
        tolerance: Tolerance,
    ) -> Self {
        Sampler {
            model: sys,
            by_steps: BTreeMap::new(),
            samples_per_period,
            least,
            most,
            per_sample: least,
            tolerance,
        }
    }

    /// Sample interval `j` (from τ = j·T/`samples_per_period`) from `x`: the fine run's
    /// interval, at once where its stop is a value that is not finite.
    pub fn interval(&mut self, j: u64, x: &Vector) -> Result<Interval, NotMet> {
        let dim = self.model.dim();
        let mut coarse = self.run(self.per_sample, j, x);
        let (fine, excess) = loop {
            let fine = self.run(2 * self.per_sample, j, x);
            if matches!(fine.stop, Some(Stop::NonFinite { .. })) {
                return Ok(fine);
            }
            let excess = error_excess(&coarse, &fine, dim, self.tolerance);
            if excess <= 1.0 {
                break (fine, excess);
            }
            if 2 * self.per_sample >= self.most {
                return Err(NotMet {
                    steps: 2 * self.per_sample,
                    excess,
                });
            }
            self.per_sample *= 2;
            coarse = fine;
        };
        // far inside the tolerance (the coarse run's error, 16 times the fine one's, within
        // a tenth of it): half the steps will do for the next interval
        if 16.0 * excess < 0.1 && self.per_sample / 2 >= self.least {
            self.per_sample /= 2;
        }
        Ok(fine)
    }

    /// Interval `j` from `x` at `per_sample` steps.
    fn run(&mut self, per_sample: usize, j: u64, x: &Vector) -> Interval {
        let n = per_sample * self.samples_per_period;
        let sys = self.by_steps.entry(n).or_insert_with(|| self.model.clone());
        let rk = GeneralRk4::with_steps(sys, n);
        let dim = sys.dim();
        let mut traj = rk.start_at(sys, &x[..dim], j * per_sample as u64);
        for _ in 0..per_sample {
            if traj.stop.is_some() {
                break;
            }
            rk.advance_step(sys, &mut traj);
        }
        Interval {
            end: traj
                .stop
                .is_none()
                .then(|| (rk.tau(traj.steps), traj.x, traj.mode)),
            stop: traj.stop,
        }
    }
}

/// The fine run's error estimated from its difference to the coarse one (a fifteenth of it),
/// over the tolerance: the largest over the states at the interval's end. Infinite where the
/// coarse run stopped on a value that is not finite and the fine one did not; 0 where either
/// stopped on a collision (the fine run's is taken).
fn error_excess(coarse: &Interval, fine: &Interval, dim: usize, tol: Tolerance) -> f64 {
    if matches!(coarse.stop, Some(Stop::NonFinite { .. })) {
        return f64::INFINITY;
    }
    let (Some((_, c, _)), Some((_, f, _))) = (&coarse.end, &fine.end) else {
        return 0.0;
    };
    (0..dim)
        .map(|i| {
            let scale = tol.atol + tol.rtol * c[i].abs().max(f[i].abs());
            (f[i] - c[i]).abs() / 15.0 / scale
        })
        .fold(0.0, f64::max)
}
