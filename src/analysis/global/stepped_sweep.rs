//! Fig 3 (stepped form): ω_e stepped up or down, each step starting from the previous step's
//! final state, settled to steady state and classified.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::analysis::AnalysisError;
use crate::analysis::global::oscillator::Oscillator;
use crate::analysis::orbit::steady_state::{SteadyState, SteadyStateSpec};

/// One step of a stepped sweep.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SweepStep {
    pub omega: f64,
    pub steady: SteadyState,
    /// The step began from rest because the previous one ended on a frame.
    pub restarted: bool,
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
    stepped_sweep_over(&steps, start, spec, cancel, on_step)
}

/// The same through any sequence of (value, model): a quasi-static sweep of whichever
/// parameter the values are of (the step's `omega` field then holds the value).
pub fn stepped_sweep_over<O: Oscillator>(
    steps: &[(f64, O)],
    start: O::State,
    spec: &SteadyStateSpec,
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
        let steady = p.steady_state(state, spec)?;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Params;

    /// Fig 3A's primary resonance at ADR 0.6 (softening, from the loss of tension): sweeping
    /// up stays low until ω_e ≈ 2.25; sweeping down jumps onto the high branch there and rides
    /// it down to ω_e ≈ 1.85, where the forward sweep is still low: hysteresis.
    #[test]
    fn primary_resonance_shows_hysteresis() {
        let p = Params::baseline();
        let spec = SteadyStateSpec::default();
        let up: Vec<f64> = (0..=14).map(|i| 1.7 + 0.05 * i as f64).collect();
        let down: Vec<f64> = up.iter().rev().copied().collect();
        let never = AtomicBool::new(false);
        let rest = [p.lambda_p(), 0.0];
        let fw = stepped_sweep(&p, &up, rest, &spec, &never, |_| {}).unwrap();
        let bw = stepped_sweep(&p, &down, rest, &spec, &never, |_| {}).unwrap();
        let amp = |s: &SweepStep| s.steady.amplitude.unwrap_or(0.0);
        let high_fw = fw.iter().filter(|s| amp(s) > 0.2).count();
        let high_bw = bw.iter().filter(|s| amp(s) > 0.2).count();
        assert!(
            high_bw >= high_fw + 5,
            "backward {high_bw} vs forward {high_fw} high steps"
        );
        // at ω_e = 1.9 the backward sweep is on the high branch (≈ 0.4), the forward on the low
        let at =
            |steps: &[SweepStep]| amp(steps.iter().find(|s| (s.omega - 1.9).abs() < 1e-9).unwrap());
        assert!(at(&bw) > 0.3 && at(&fw) < 0.05, "{} {}", at(&bw), at(&fw));
    }
}
