//! One forcing period of a written model's time-only values (its forcing: `cos(omega*t)` and
//! what follows from it) tabulated at the integrator's stage times, so that the hot loop
//! does not evaluate them at every step: the written counterpart of the built-in model's
//! drive table. Only for models whose every use of t repeats with the period
//! ([`super::graph::Graph::periodic_in_time`]).

use super::tape::{Registers, Tape};

/// The time-only values at τ_k = k·h/2, k = 0..2n, over one period T = n·h; any time within
/// rounding of some k·h/2 (any period) reads row k mod 2n.
#[derive(Debug)]
pub struct TimeTable {
    /// n, the integrator's steps per period.
    steps_per_period: usize,
    half_steps: i64,
    /// 1/(2n).
    per_half_steps: f64,
    /// 2n/T: half-steps per unit of τ.
    per_half_step: f64,
    /// The registers tabulated (the time tape's roots), each row in this order.
    slots: Vec<u32>,
    rows: Vec<f64>,
}

/// A time on the table's grid given by its count: half-step `half_step` (< 2n) of a period
/// of `steps_per_period` steps, as an integrator that counts its steps knows it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GridTime {
    pub half_step: usize,
    pub steps_per_period: usize,
}

impl GridTime {
    /// `s` (≤ 2) half-steps after the start of step `phase` (< `steps_per_period`) of a
    /// period.
    pub fn in_step(phase: usize, s: usize, steps_per_period: usize) -> GridTime {
        // past the period's end at most once
        let half_step = 2 * phase + s;
        GridTime {
            half_step: if half_step >= 2 * steps_per_period {
                half_step - 2 * steps_per_period
            } else {
                half_step
            },
            steps_per_period,
        }
    }
}

/// How far, in half-steps relative to the count of half-steps since τ = 0, a time may be
/// from a grid time and still be it: a few roundings of τ = s·h and of its halves.
const GRID_TOLERANCE: f64 = 16.0 * f64::EPSILON;

/// Half-steps since τ = 0 beyond which a time is not looked up (integers stay exact).
const MAX_HALF_STEPS: f64 = 1e15;

impl TimeTable {
    /// Tabulates `time_tape` on a copy of `regs` (parameters loaded) for `n` steps per
    /// `period`.
    pub fn new(time_tape: &Tape, regs: &Registers, period: f64, n: usize) -> TimeTable {
        let half_steps = 2 * n;
        // h/2 = (T/n)/2 exactly, so that τ_2s = s·h bit for bit, as the integrator's
        let half_step = period / n as f64 / 2.0;
        let slots: Vec<u32> = time_tape.roots.clone();
        let mut r = regs.values.clone();
        let mut rows = Vec::with_capacity(half_steps * slots.len());
        for k in 0..half_steps {
            if let Some(time) = regs.time_slot {
                r[time as usize] = k as f64 * half_step;
            }
            time_tape.run_in(&mut r, 0);
            rows.extend(slots.iter().map(|&s| r[s as usize]));
        }
        TimeTable {
            steps_per_period: n,
            half_steps: half_steps as i64,
            per_half_steps: 1.0 / half_steps as f64,
            per_half_step: 1.0 / half_step,
            slots,
            rows,
        }
    }

    /// The integrator's steps per period this table is for.
    pub fn steps_per_period(&self) -> usize {
        self.steps_per_period
    }

    /// The registers a row fills, in its order.
    #[inline(always)]
    pub fn slots(&self) -> &[u32] {
        &self.slots
    }

    /// The row at grid time `at`, the row [`Self::row`] finds for any time within rounding of
    /// it; `None` if this table is of another grid.
    #[inline(always)]
    pub fn row_at(&self, at: GridTime) -> Option<&[f64]> {
        if at.steps_per_period != self.steps_per_period {
            return None;
        }
        let width = self.slots.len();
        let start = at.half_step * width;
        self.rows.get(start..start + width)
    }

    /// The row for time `t`, if `t` is a grid time (else the values must be computed).
    #[inline(always)]
    pub fn row(&self, t: f64) -> Option<&[f64]> {
        // conversions and products only: no rounding function, no division
        let q = t * self.per_half_step;
        if !(0.0..=MAX_HALF_STEPS).contains(&q) {
            return None;
        }
        // signed: one instruction each way (unsigned 64-bit conversions are several)
        let k = (q + 0.5) as i64;
        if (q - k as f64).abs() > GRID_TOLERANCE * q.max(1.0) {
            return None;
        }
        let periods = (k as f64 * self.per_half_steps) as i64;
        let mut i = k - periods * self.half_steps;
        if i < 0 {
            i += self.half_steps;
        } else if i >= self.half_steps {
            i -= self.half_steps;
        }
        let width = self.slots.len();
        let start = i as usize * width;
        Some(&self.rows[start..start + width])
    }
}
