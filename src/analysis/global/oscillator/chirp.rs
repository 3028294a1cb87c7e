//! The chirp sweep of a written model (Fig 3 on any model periodic in time): its frequency
//! parameter swept and its time read as the sweep's phase ([`ChirpedSystem`]), its output
//! sampled every `dt`.
//!
//! Each sample interval is integrated by the general engine's RK4 (kinks located and split)
//! with step doubling ([`Sampler`]): its error within the spec's `tolerance`, as the
//! built-in's adaptive steps hold theirs, the fine run at least [`LEAST_STEPS_PER_PERIOD`]
//! steps per period of the sweep's highest frequency.

use std::sync::atomic::{AtomicBool, Ordering};

use super::Oscillator;
use crate::analysis::AnalysisError;
use crate::analysis::orbit::chirp_sweep::{ChirpSpec, ChirpSweep};
use crate::model::equations::EquationSystem;
use crate::model::equations::chirped::ChirpedSystem;
use crate::model::system::System;
use crate::solver::general::{GeneralRk4, Stop};
use crate::solver::sampled::Sampler;

/// Least RK4 steps of the fine run per period of the sweep's highest frequency.
pub const LEAST_STEPS_PER_PERIOD: usize = 64;
/// Most RK4 steps per sample interval a sweep takes to meet its tolerance.
pub const MAX_STEPS_PER_SAMPLE: usize = 1 << 20;

/// Sweeps `sys` as `spec` says, from the grid offset (`dx0`, `v0`); the output is recorded
/// where the built-in records λ_I.
pub fn written_chirp_sweep(
    sys: &EquationSystem,
    spec: &ChirpSpec,
    cancel: &AtomicBool,
    mut on_progress: impl FnMut(f64),
) -> Result<ChirpSweep, AnalysisError> {
    spec.validate_settings()?;
    let mut chirped = ChirpedSystem::new(sys, spec.sweep(), spec.dt)?;
    let dim = chirped.dim();
    let mut x = sys.grid_start([spec.dx0, spec.v0]);
    let omega_max = spec.omega_start.max(spec.omega_end);
    let per_period = spec.dt * omega_max / std::f64::consts::TAU;
    // the coarse run's steps per sample: half the fine run's least
    let least = ((LEAST_STEPS_PER_PERIOD as f64 * per_period / 2.0).ceil() as usize).max(1);
    let first = GeneralRk4::with_steps(&chirped, 2 * least).start(&mut chirped, &x[..dim]);
    let mut lambda = Vec::with_capacity(spec.samples());
    lambda.push(chirped.output(0.0, &first.x, first.mode).0);
    let mut collision_tau = stopped_at(&chirped, first.stop)?;
    let mut sampler = Sampler::new(
        chirped.clone(),
        1,
        least,
        MAX_STEPS_PER_SAMPLE,
        spec.tolerance,
    );
    let intervals = if collision_tau.is_some() {
        0
    } else {
        spec.samples() - 1
    };
    for j in 0..intervals as u64 {
        // every sample: one may take up to 2²¹ steps where the model's slope has no bound
        if cancel.load(Ordering::Relaxed) {
            return Err(AnalysisError::Cancelled);
        }
        if j % 256 == 0 {
            on_progress(j as f64 / intervals as f64);
        }
        let fine = sampler
            .interval(j, &x)
            .map_err(|not| AnalysisError::ToleranceNotMet {
                rtol: spec.tolerance.rtol,
                atol: spec.tolerance.atol,
                steps: not.steps,
                per: "sample interval",
                tau: j as f64 * spec.dt,
                excess: not.excess,
            })?;
        if let Some((tau, state, mode)) = &fine.end {
            lambda.push(chirped.output(*tau, state, *mode).0);
            x = *state;
        }
        collision_tau = stopped_at(&chirped, fine.stop)?;
        if collision_tau.is_some() {
            break;
        }
    }
    on_progress(1.0);
    Ok(spec.recorded(lambda, collision_tau))
}

/// Where `stop` ended the sweep: τ of a collision (none where it did not stop), or the error
/// of a value that is not finite.
fn stopped_at(sys: &impl System, stop: Option<Stop>) -> Result<Option<f64>, AnalysisError> {
    match stop {
        Some(Stop::Collision { tau, .. }) => Ok(Some(tau)),
        Some(Stop::NonFinite {
            tau,
            state,
            expression,
        }) => Err(AnalysisError::not_finite(sys, tau, &state, &expression)),
        None => Ok(None),
    }
}
