//! The time history of one orbit of a written model: every state sampled through the transient
//! and a few response periods, its error held within the spec's `tolerance`.
//!
//! Each sample interval's error is held by step doubling ([`Sampler`]), within its share of
//! the tolerance (1/`samples_per_period` of it: the tolerance holds for each forcing period),
//! the fine run at least 4× the classification's steps.

use std::sync::atomic::{AtomicBool, Ordering};

use serde::Serialize;

use super::written::steady_state_of;
use crate::analysis::AnalysisError;
use crate::analysis::Oscillator;
use crate::analysis::orbit::steady_state::SteadyState;
use crate::analysis::orbit::time_history::TimeHistorySpec;
use crate::model::equations::EquationSystem;
use crate::model::system::{System, Vector};
use crate::solver::Tolerance;
use crate::solver::general::{GeneralRk4, Stop};
use crate::solver::sampled::Sampler;

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
/// `max_transient_periods`) and `steady_periods` response periods after it; `cancel` is
/// seen at every sample (a recording at a tight tolerance may take seconds).
pub fn state_history(
    sys: &EquationSystem,
    spec: &TimeHistorySpec,
    cancel: &AtomicBool,
) -> Result<StateHistory, AnalysisError> {
    state_history_from(sys, &sys.grid_start([spec.dx0, spec.v0]), spec, cancel)
}

/// The same from the whole state `start` (a response's stroboscopic point with its internal
/// states, picked off a plot); `spec`'s own start is not used.
pub fn state_history_from(
    sys: &EquationSystem,
    start: &Vector,
    spec: &TimeHistorySpec,
    cancel: &AtomicBool,
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
        }) => return Err(AnalysisError::not_finite(&sys, tau, &state, &expression)),
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
    // each sample interval's share of the tolerance, which holds for a whole period
    let share = Tolerance {
        rtol: spec.tolerance.rtol / spp as f64,
        atol: spec.tolerance.atol / spp as f64,
    };
    let mut sampler = Sampler::new(sys.clone(), spp, least, MAX_STEPS_PER_PERIOD / spp, share);
    let mut x = *start;
    for j in 0..(total_periods * spp) as u64 {
        if cancel.load(Ordering::Relaxed) {
            return Err(AnalysisError::Cancelled);
        }
        let fine = sampler.interval(j, &x).map_err(|not| {
            let tau = j as f64 * period / spp as f64;
            AnalysisError::ToleranceNotMet {
                rtol: spec.tolerance.rtol,
                atol: spec.tolerance.atol,
                steps: not.steps * spp,
                per: "forcing period",
                tau,
                excess: not.excess,
            }
        })?;
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
            Some(Stop::NonFinite {
                tau,
                state,
                expression,
            }) => return Err(AnalysisError::not_finite(&sys, tau, &state, &expression)),
            None => {}
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
