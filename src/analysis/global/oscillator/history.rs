//! The time history of one orbit of a written model: every state sampled through the transient
//! and a few response periods, its error held within the spec's `tolerance`.
//!
//! Each sample interval is integrated twice from the same state, with N and 2N RK4 steps, and
//! N doubled until the two agree: the 2N run's error is about a fifteenth of their difference
//! (RK4 is of fourth order, and the general engine keeps it across kinks), and it must be
//! within the interval's share of `atol + rtol·|x|` in every state (1/`samples_per_period`
//! of it: the tolerance holds for each forcing period). The 2N run is recorded and the next interval
//! starts from its end; where the estimate is far inside the tolerance, N is halved again
//! (2N never below 4× the classification's steps). Steps are refined only where the orbit
//! needs them: near a singular kink (`sqrt` at its branch's end), not over the whole period.

use std::collections::BTreeMap;

use serde::Serialize;

use super::written::{not_finite, steady_state_of};
use crate::analysis::AnalysisError;
use crate::analysis::Oscillator;
use crate::analysis::orbit::steady_state::SteadyState;
use crate::analysis::orbit::time_history::TimeHistorySpec;
use crate::model::equations::EquationSystem;
use crate::model::system::{Mode, System, Vector};
use crate::solver::Tolerance;
use crate::solver::general::{GeneralRk4, Stop};

/// Most RK4 steps per forcing period a recording takes to meet its tolerance.
pub const MAX_STEPS_PER_PERIOD: usize = 1 << 20;

/// One sample: τ, the whole state, the amplitude's output.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StateSample {
    pub tau: f64,
    pub state: Vec<f64>,
    pub output: f64,
    /// On the steady response (after the transient).
    pub steady: bool,
}

/// A written model's recorded orbit and its classification.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StateHistory {
    /// The state names, in the samples' order.
    pub states: Vec<String>,
    pub samples: Vec<StateSample>,
    pub steady_state: SteadyState,
    /// τ where the steady part begins.
    pub steady_from: f64,
    /// The collision that ended the orbit, if one did: the last sample is where it was met
    /// (at the end of the step that met it).
    pub collision: Option<HistoryCollision>,
}

/// A collision that ended a recorded orbit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HistoryCollision {
    pub tau: f64,
    /// The condition met, as `model.collision[i] = \`text\``.
    pub condition: String,
}

/// Records the orbit of `sys` from the grid offset (`dx0`, `v0`): the transient (at most
/// `max_transient_periods`) and `steady_periods` response periods after it.
pub fn state_history(
    sys: &EquationSystem,
    spec: &TimeHistorySpec,
) -> Result<StateHistory, AnalysisError> {
    state_history_from(sys, &sys.grid_start([spec.dx0, spec.v0]), spec)
}

/// The same from the whole state `start` (a response's stroboscopic point with its internal
/// states, picked off a plot); `spec`'s own start is not used.
pub fn state_history_from(
    sys: &EquationSystem,
    start: &Vector,
    spec: &TimeHistorySpec,
) -> Result<StateHistory, AnalysisError> {
    spec.validate()?;
    let grid = sys.model().grid();
    let mut sys = sys.clone();
    let steady = steady_state_of(&mut sys, start, grid, &spec.steady)?;
    let k = steady.period.unwrap_or(1);
    let transient = steady.transient_periods.min(spec.max_transient_periods);
    let total_periods = transient + spec.steady_periods * k;
    let period = sys.period();
    let steady_from = transient as f64 * period;
    let dim = sys.dim();
    let spp = spec.samples_per_period;
    let sample = |sys: &mut EquationSystem, tau: f64, x: &Vector, mode| StateSample {
        tau,
        state: x[..dim].to_vec(),
        output: sys.output(tau, x, mode).0,
        steady: tau >= steady_from - 1e-9,
    };
    let mut samples = Vec::with_capacity(total_periods * spp + 1);
    let first = GeneralRk4::with_steps(&sys, spp).start(&mut sys, &start[..dim]);
    samples.push(sample(&mut sys, 0.0, &first.x, first.mode));
    let mut collision = None;
    match first.stop {
        Some(Stop::NonFinite {
            tau,
            state,
            expression,
        }) => return Err(not_finite(&sys, tau, &state, &expression)),
        Some(Stop::Collision { tau, state }) => {
            let condition = sys.collision_met(tau, &state).unwrap_or_default();
            collision = Some(HistoryCollision { tau, condition });
        }
        None => {}
    }
    // nothing more to record after a collision at the start
    let total_periods = if collision.is_some() {
        0
    } else {
        total_periods
    };
    // the coarse run's steps per sample: twice the classification's steps, the fine run's four
    // times, to begin with
    let least = (2 * spec.steady.resolution.steps_for(period)).div_ceil(spp);
    let most = MAX_STEPS_PER_PERIOD / spp;
    let mut per_sample = least;
    // each sample interval's share of the tolerance, which holds for a whole period
    let share = Tolerance {
        rtol: spec.tolerance.rtol / spp as f64,
        atol: spec.tolerance.atol / spp as f64,
    };
    // one system per step length: each keeps its forcing's table
    let mut systems = Systems {
        model: sys.clone(),
        by_steps: BTreeMap::new(),
    };
    let mut x = *start;
    for j in 0..(total_periods * spp) as u64 {
        let mut coarse = systems.interval(per_sample, spp, j, &x);
        let (fine, excess) = loop {
            let fine = systems.interval(2 * per_sample, spp, j, &x);
            if let Some(Stop::NonFinite {
                tau,
                state,
                expression,
            }) = &fine.stop
            {
                return Err(not_finite(&sys, *tau, state, expression));
            }
            let excess = error_excess(&coarse, &fine, dim, share);
            if excess <= 1.0 {
                break (fine, excess);
            }
            if 2 * per_sample >= most {
                return Err(AnalysisError::ToleranceNotMet {
                    rtol: spec.tolerance.rtol,
                    atol: spec.tolerance.atol,
                    steps: 2 * per_sample * spp,
                    tau: j as f64 * period / spp as f64,
                    excess,
                });
            }
            per_sample *= 2;
            coarse = fine;
        };
        if let Some((tau, state, mode)) = &fine.end {
            samples.push(sample(&mut sys, *tau, state, *mode));
            x = *state;
        }
        match fine.stop {
            Some(Stop::Collision { tau, state }) => {
                let condition = sys.collision_met(tau, &state).unwrap_or_default();
                let mode = sys.mode_at(tau, &state) & sys.switch_mask();
                samples.push(sample(&mut sys, tau, &state, mode));
                collision = Some(HistoryCollision { tau, condition });
                break;
            }
            Some(Stop::NonFinite { .. }) => unreachable!("returned as an error above"),
            None => {}
        }
        // far inside the tolerance (the coarse run's error, 16 times the fine one's, within
        // a tenth of it): half the steps will do for the next interval
        if 16.0 * excess < 0.1 && per_sample / 2 >= least {
            per_sample /= 2;
        }
    }
    Ok(StateHistory {
        states: sys.model().states().to_vec(),
        samples,
        steady_state: steady,
        steady_from,
        collision,
    })
}

impl HistoryCollision {
    /// In words, for the user: where and how the orbit ended.
    pub fn describe(&self) -> String {
        format!(
            "the orbit met a collision at τ = {:.6} ({}): its time history ends there",
            self.tau, self.condition
        )
    }
}

/// One sample interval of a recording: its end sample (τ, state, piece), unless it stopped
/// first, and what stopped it.
struct IntervalRun {
    end: Option<(f64, Vector, Mode)>,
    stop: Option<Stop>,
}

/// The model, and a copy of it per step length used (its forcing tabulated for that length).
struct Systems {
    model: EquationSystem,
    by_steps: BTreeMap<usize, EquationSystem>,
}

impl Systems {
    /// Sample interval `j` (from τ = j·T/`spp`) from `x`, at `per_sample` steps.
    fn interval(&mut self, per_sample: usize, spp: usize, j: u64, x: &Vector) -> IntervalRun {
        let n = per_sample * spp;
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
        IntervalRun {
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
fn error_excess(coarse: &IntervalRun, fine: &IntervalRun, dim: usize, tol: Tolerance) -> f64 {
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
