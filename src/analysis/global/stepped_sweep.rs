//! Fig 3 (stepped form): ω_e stepped up or down, each step starting from the previous step's
//! final state, settled to steady state and classified.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::analysis::AnalysisError;
use crate::analysis::global::oscillator::Oscillator;
use crate::analysis::orbit::chirp_sweep::{Direction, JUMP_FLOOR};
use crate::analysis::orbit::steady_state::{SteadyState, SteadyStateSpec};

/// One step of a stepped sweep.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SweepStep {
    pub omega: f64,
    pub steady: SteadyState,
    /// The step began from rest because the previous one ended on a frame.
    pub restarted: bool,
}

/// A jump between two neighbouring steps: the response type changes, or the amplitude
/// changes by the factor `jump_ratio` (or more) and by at least
/// [`JUMP_FLOOR`] of the sweep's largest
/// amplitude. Each step is settled, so a jump is one step wide.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct StepJump {
    /// The step after the jump (numbered from 0 in the sweep's order).
    pub step: usize,
    /// ω_e (or the swept value) of the step before, and of the step after.
    pub omega_before: f64,
    pub omega_after: f64,
    pub type_before: String,
    pub type_after: String,
    /// `None` where the response has none (non-periodic, collision).
    pub amplitude_before: Option<f64>,
    pub amplitude_after: Option<f64>,
    /// Up or down where both steps have an amplitude.
    pub direction: Option<Direction>,
}

/// The largest amplitude of one response type over a sweep.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TypePeak {
    pub response_type: String,
    /// Steps that settled on this type.
    pub steps: usize,
    pub peak_amplitude: f64,
    pub peak_omega: f64,
}

/// What a stepped sweep found: its jumps and each response type's peak.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SweepFindings {
    /// In the order of the sweep.
    pub jumps: Vec<StepJump>,
    /// In the order each type is first met; types without an amplitude are left out.
    pub peaks: Vec<TypePeak>,
}

impl SweepFindings {
    /// The jumps and peaks of `steps`, with jumps of amplitude by `jump_ratio` or more.
    pub fn of(steps: &[SweepStep], jump_ratio: f64) -> SweepFindings {
        let largest = steps
            .iter()
            .filter_map(|s| s.steady.amplitude)
            .fold(0.0, f64::max);
        let jumps = steps
            .windows(2)
            .enumerate()
            .filter_map(|(i, pair)| {
                let (a, b) = (&pair[0].steady, &pair[1].steady);
                let (type_before, type_after) = (a.response_type(), b.response_type());
                let direction = a.amplitude.zip(b.amplitude).map(|(x, y)| {
                    if y >= x {
                        Direction::Up
                    } else {
                        Direction::Down
                    }
                });
                let jumped = a.amplitude.zip(b.amplitude).is_some_and(|(x, y)| {
                    let (low, high) = (x.min(y), x.max(y));
                    high >= jump_ratio * low && high - low >= JUMP_FLOOR * largest
                });
                (jumped || type_before != type_after).then(|| StepJump {
                    step: i + 1,
                    omega_before: pair[0].omega,
                    omega_after: pair[1].omega,
                    type_before,
                    type_after,
                    amplitude_before: a.amplitude,
                    amplitude_after: b.amplitude,
                    direction,
                })
            })
            .collect();
        let mut peaks: Vec<TypePeak> = Vec::new();
        for s in steps {
            let Some(amplitude) = s.steady.amplitude else {
                continue;
            };
            let response_type = s.steady.response_type();
            match peaks.iter_mut().find(|p| p.response_type == response_type) {
                Some(p) => {
                    p.steps += 1;
                    if amplitude > p.peak_amplitude {
                        p.peak_amplitude = amplitude;
                        p.peak_omega = s.omega;
                    }
                }
                None => peaks.push(TypePeak {
                    response_type,
                    steps: 1,
                    peak_amplitude: amplitude,
                    peak_omega: s.omega,
                }),
            }
        }
        SweepFindings { jumps, peaks }
    }
}

/// Steps through `omegas` in the order given, starting at `start` = [λ_I, v]. After a
/// collision the next step starts again from rest at λ_p, as after a reset of the rig.
pub fn stepped_sweep<O: Oscillator>(
    params: &O,
    omegas: &[f64],
    start: O::State,
    spec: &SteadyStateSpec,
    cancel: &AtomicBool,
    on_step: impl FnMut(&SweepStep),
) -> Result<Vec<SweepStep>, AnalysisError> {
    let steps = omegas
        .iter()
        .map(|&w| Ok((w, params.with(params.frequency(), w)?)))
        .collect::<Result<Vec<_>, crate::model::ParamError>>()?;
    stepped_sweep_over(&steps, start, spec, None, cancel, on_step)
}

/// The same through any sequence of (value, model): a quasi-static sweep of whichever
/// parameter the values are of (the step's `omega` field then holds the value). With
/// `capture`, a step stops early once its trajectory is captured by the verified regions (at
/// most `capture` across) of the response found ahead of it
/// ([`crate::analysis::global::batch`]); its result is then that response's, ending at the
/// Poincaré point the trajectory is at.
pub fn stepped_sweep_over<O: Oscillator>(
    steps: &[(f64, O)],
    start: O::State,
    spec: &SteadyStateSpec,
    capture: Option<f64>,
    cancel: &AtomicBool,
    mut on_step: impl FnMut(&SweepStep),
) -> Result<Vec<SweepStep>, AnalysisError> {
    spec.validate()?;
    let mut state = start;
    let mut restarted = false;
    let mut out = Vec::with_capacity(steps.len());
    for (value, p) in steps {
        if cancel.load(Ordering::Relaxed) {
            return Err(AnalysisError::Cancelled);
        }
        let steady = match capture.and_then(|c| p.known_attractors(spec, c)) {
            Some(mut known) => {
                let starts = std::slice::from_ref(&state);
                let mut ends =
                    p.steady_states(starts, spec, Some(&mut known), cancel, &mut |_| {})?;
                ends.pop().expect("one steady state per start")
            }
            None => p.steady_state(state, spec)?,
        };
        let step = SweepStep {
            omega: *value,
            steady,
            restarted,
        };
        // the last stroboscopic point is the state at a period boundary: phase 0 again
        restarted = step.steady.poincare.is_empty();
        state = p
            .poincare_states(&step.steady)
            .last()
            .copied()
            .unwrap_or_else(|| p.rest());
        on_step(&step);
        out.push(step);
    }
    Ok(out)
}
