//! A written model evaluated on `L` trajectories at once: each instruction of its tapes over
//! `L` lanes, so that the dispatch is paid once per `L` values and the arithmetic vectorises.

use std::sync::Arc;

use super::EquationSystem;
use super::build::Compiled;
#[cfg(target_arch = "x86_64")]
use super::native_step;
use super::tape::Registers;
use super::time_table::{GridTime, TimeTable};
use crate::model::system::{END_SWITCHES, GridStep, MAX_DIM, Mode};

/// `L` lanes of state: `x[i][l]` is state i of lane l.
pub type LaneVectors<const L: usize> = [[f64; L]; MAX_DIM];
/// The model's first [`END_SWITCHES`] switching values in `L` lanes, a row each.
pub type LaneSwitching<const L: usize> = [[f64; L]; END_SWITCHES];

/// Each lane's step length and the times of its step's middle and end.
#[derive(Debug, Clone, Copy)]
pub struct LaneTimes<const L: usize> {
    pub h: [f64; L],
    pub t_half: [f64; L],
    pub t_end: [f64; L],
}

impl<const L: usize> LaneTimes<L> {
    /// `step`'s times in every lane.
    pub fn of(step: &GridStep) -> Self {
        LaneTimes {
            h: [step.h; L],
            t_half: [step.t_half; L],
            t_end: [step.t_end; L],
        }
    }
}

/// A written model's registers for `L` lanes, at one set of parameter values.
#[derive(Debug, Clone)]
pub struct EquationLanes<const L: usize> {
    inner: Arc<Compiled>,
    values: Vec<[f64; L]>,
    time_slot: Option<u32>,
    stamp: u32,
    table: Option<Arc<TimeTable>>,
}

impl<const L: usize> EquationLanes<L> {
    /// Lanes of `sys` (its constants and parameter-fixed values in every lane).
    pub fn new(sys: &EquationSystem) -> Self {
        let regs: &Registers = sys.registers();
        EquationLanes {
            inner: sys.model().inner.clone(),
            values: regs.values.iter().map(|&v| [v; L]).collect(),
            time_slot: regs.time_slot,
            stamp: regs.stamp,
            table: regs.table.clone(),
        }
    }

    /// Takes `sys`'s table of its forcing, if it has another (after [`System::tabulate`]).
    ///
    /// [`System::tabulate`]: crate::model::system::System::tabulate
    #[inline]
    pub fn follow_table(&mut self, sys: &EquationSystem) {
        let theirs = &sys.registers().table;
        let same = match (&self.table, theirs) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        };
        if !same {
            self.table = theirs.clone();
        }
    }

    /// Loads the lanes' times and states into their registers, and the time-only nodes
    /// (see [`EquationLanes::load_time`]).
    #[inline(always)]
    fn load(&mut self, tau: &[f64; L], x: &LaneVectors<L>) {
        self.load_time(tau, None);
        for &(i, slot) in &self.inner.field_io.states {
            self.values[slot as usize] = x[i as usize];
        }
    }

    /// Loads the lanes' times, and the time-only nodes unless every lane's were last
    /// computed at its time: from the table where it has every lane's time, else computed
    /// (see [`Registers::load_time`]). `at`: the grid time every running lane is at, if the
    /// integrator knows it (one row for all of them, as each lane's time would find).
    #[inline(always)]
    fn load_time(&mut self, tau: &[f64; L], at: Option<GridTime>) {
        if let Some(slot) = self.time_slot {
            self.values[slot as usize] = *tau;
            let stamp = &mut self.values[self.stamp as usize];
            if (0..L).any(|l| stamp[l].to_bits() != tau[l].to_bits()) {
                *stamp = *tau;
                if let Some(at) = at
                    && let Some(table) = self.table.as_deref()
                    && let Some(row) = table.row_at(at)
                {
                    for (&s, &value) in table.slots().iter().zip(row) {
                        self.values[s as usize] = [value; L];
                    }
                    return;
                }
                let rows = self.table.as_deref().and_then(|table| {
                    let mut rows: [&[f64]; L] = [&[]; L];
                    for (row, &t) in rows.iter_mut().zip(tau) {
                        *row = table.row(t)?;
                    }
                    Some((table, rows))
                });
                match rows {
                    Some((table, rows)) => {
                        for (j, &s) in table.slots().iter().enumerate() {
                            self.values[s as usize] = std::array::from_fn(|l| rows[l][j]);
                        }
                    }
                    None => {
                        self.inner.time_tape.run_lanes(&mut self.values, &[0; L]);
                    }
                }
            }
        }
    }

    /// dx/dτ of every lane on its own mode into `dx`; returns the modes the switching
    /// functions' signs select (see [`crate::model::system::System::field`]). `at`: the grid
    /// time every running lane's τ is on, if known (see [`Self::load_time`]).
    #[inline]
    pub fn field(
        &mut self,
        tau: &[f64; L],
        at: Option<GridTime>,
        x: &LaneVectors<L>,
        modes: &[Mode; L],
        dx: &mut LaneVectors<L>,
    ) -> [Mode; L] {
        self.load_time(tau, at);
        let c = &*self.inner;
        c.field_tape
            .run_field_lanes(&mut self.values, modes, &c.field_io, x, dx)
    }

    /// Every lane's plain RK4 step by the model's compiled code (see
    /// [`crate::model::system::System::compiled_step`]): each lane's end and derivative
    /// there into `end` and `dx`, its switching values there into `switching`; returns each
    /// lane's mode bits seen to differ, whether it collided and the mode bits its end saw.
    /// Every lane is at step `phase` of a period of `steps_per_period`; `times` are each
    /// lane's. `None` where there is no such code.
    #[allow(clippy::too_many_arguments)]
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub fn compiled_step(
        &mut self,
        phase: usize,
        steps_per_period: usize,
        times: &LaneTimes<L>,
        x: &LaneVectors<L>,
        k1: &LaneVectors<L>,
        modes: &[Mode; L],
        end: &mut LaneVectors<L>,
        dx: &mut LaneVectors<L>,
        switching: &mut LaneSwitching<L>,
    ) -> Option<([Mode; L], [bool; L], [Mode; L])> {
        native_step::run(
            &self.inner,
            self.values.as_flattened(),
            self.table.as_deref(),
            [phase, steps_per_period],
            times,
            [x.as_flattened(), k1.as_flattened()],
            modes,
            [end.as_flattened_mut(), dx.as_flattened_mut()],
            switching.as_flattened_mut(),
        )
    }

    /// Whether each lane has met a collision condition, or one has no truth value there.
    pub fn collided(&mut self, tau: &[f64; L], x: &LaneVectors<L>) -> [bool; L] {
        if self.inner.collisions.is_empty() {
            return [false; L];
        }
        self.load(tau, x);
        let (c, values) = (&*self.inner, &mut self.values);
        c.collision_tape.run_lanes_free(values);
        let mut hit = [false; L];
        for cond in &c.collisions {
            let stops = cond.stops(&|id| values[id as usize]);
            (0..L).for_each(|l| hit[l] |= stops[l]);
        }
        hit
    }

    /// The amplitude's output and its rate in every lane, on each lane's mode.
    pub fn output(
        &mut self,
        tau: &[f64; L],
        x: &LaneVectors<L>,
        modes: &[Mode; L],
    ) -> ([f64; L], [f64; L]) {
        self.load(tau, x);
        let c = &*self.inner;
        // as [`super::EquationSystem`]'s output: the output's own kinks by their signs
        let own = c.output_tape.switch_mask & !c.field_tape.switch_mask;
        if own == 0 {
            c.output_tape.run_lanes(&mut self.values, modes);
        } else {
            let free = c.output_tape.run_lanes_free(&mut self.values);
            let modes: [Mode; L] = std::array::from_fn(|l| (modes[l] & !own) | (free[l] & own));
            c.output_tape.run_lanes(&mut self.values, &modes);
        }
        (
            self.values[c.output[0] as usize],
            self.values[c.output[1] as usize],
        )
    }
}
