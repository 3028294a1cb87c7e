//! The time history of one orbit of a written model: every state sampled through the transient
//! and a few response periods, on the general engine at four times the classification's
//! resolution.

use serde::Serialize;

use super::written::{not_finite, steady_state_of};
use crate::analysis::AnalysisError;
use crate::analysis::Oscillator;
use crate::analysis::orbit::steady_state::SteadyState;
use crate::analysis::orbit::time_history::TimeHistorySpec;
use crate::model::equations::EquationSystem;
use crate::model::system::{System, Vector};
use crate::solver::general::{GeneralRk4, Stop};

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
    // four times the classification's steps, a whole number of them per sample
    let per_sample =
        (4 * spec.steady.resolution.steps_for(period)).div_ceil(spec.samples_per_period);
    let rk = GeneralRk4::with_steps(&sys, per_sample * spec.samples_per_period);
    let dim = sys.dim();
    let mut traj = rk.start(&mut sys, &start[..dim]);
    let mut samples = Vec::with_capacity(total_periods * spec.samples_per_period + 1);
    let sample =
        |sys: &mut EquationSystem, tau: f64, x: &crate::model::system::Vector, mode| StateSample {
            tau,
            state: x[..dim].to_vec(),
            output: sys.output(tau, x, mode).0,
            steady: tau >= steady_from - 1e-9,
        };
    samples.push(sample(&mut sys, 0.0, &traj.x, traj.mode));
    for _ in 0..total_periods * spec.samples_per_period {
        for _ in 0..per_sample {
            rk.advance_step(&mut sys, &mut traj);
        }
        match &traj.stop {
            Some(Stop::NonFinite {
                tau,
                state,
                expression,
            }) => return Err(not_finite(&sys, *tau, state, expression)),
            Some(Stop::Collision { .. }) => break,
            None => {}
        }
        let tau = rk.tau(traj.steps);
        samples.push(sample(&mut sys, tau, &traj.x, traj.mode));
    }
    Ok(StateHistory {
        states: sys.model().states().to_vec(),
        samples,
        steady_state: steady,
        steady_from,
    })
}
