//! Fig 4/5 insets: the time history and phase path of one orbit, its transient and its steady
//! part told apart, from the accurate integrator's dense output.

use serde::{Deserialize, Serialize};

use super::AnalysisError;
use super::steady_state::{SteadyState, SteadyStateSpec, steady_state};
use crate::model::Params;
use crate::model::error::check;
use crate::solver::{Dopri5, Tolerance};

/// One orbit to record.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TimeHistorySpec {
    /// Initial state (Δλ, v) at τ = 0.
    pub dx0: f64,
    pub v0: f64,
    /// Samples per forcing period.
    pub samples_per_period: usize,
    /// Response periods recorded after the transient.
    pub steady_periods: usize,
    /// Longest transient recorded (forcing periods); the rest is skipped, not drawn.
    pub max_transient_periods: usize,
    pub steady: SteadyStateSpec,
    pub tolerance: Tolerance,
}

impl Default for TimeHistorySpec {
    fn default() -> Self {
        TimeHistorySpec {
            dx0: 0.0,
            v0: 0.0,
            samples_per_period: 64,
            steady_periods: 2,
            max_transient_periods: 2000,
            steady: SteadyStateSpec::default(),
            tolerance: Tolerance::default(),
        }
    }
}

/// One sample of the orbit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Sample {
    pub tau: f64,
    pub lambda: f64,
    pub v: f64,
    /// φ_I at this time.
    pub phi_i: f64,
    /// On the steady response (after the transient).
    pub steady: bool,
}

/// The recorded orbit and its classification.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TimeHistory {
    pub samples: Vec<Sample>,
    pub steady_state: SteadyState,
    /// τ where the steady part begins.
    pub steady_from: f64,
}

impl TimeHistorySpec {
    /// Checks every setting; the error names the first bad one.
    pub fn validate(&self) -> Result<(), crate::model::ParamError> {
        check(
            "samples_per_period",
            self.samples_per_period as f64,
            |n| (4.0..=10_000.0).contains(&n),
            "[4, 10000]",
        )?;
        check(
            "steady_periods",
            self.steady_periods as f64,
            |n| (1.0..=1000.0).contains(&n),
            "[1, 1000]",
        )?;
        self.steady.validate().map_err(|e| e.within("steady"))?;
        self.tolerance
            .validate()
            .map_err(|e| e.within("tolerance"))?;
        Ok(())
    }
}

/// Records the orbit from the spec's initial state: the transient (at most
/// `max_transient_periods`) and `steady_periods` response periods after it.
pub fn time_history(params: &Params, spec: &TimeHistorySpec) -> Result<TimeHistory, AnalysisError> {
    spec.validate()?;
    let x0 = params.lambda_p() + spec.dx0;
    let steady = steady_state(params, x0, spec.v0, &spec.steady);
    let period = params.period();
    let k = steady.period.unwrap_or(1);
    let transient = steady.transient_periods.min(spec.max_transient_periods);
    let total_periods = transient + spec.steady_periods * k;
    let steady_from = transient as f64 * period;
    let dopri = Dopri5::new(params, spec.tolerance);
    let mut state = dopri.state(0.0, x0, spec.v0);
    let dt = period / spec.samples_per_period as f64;
    let n = total_periods * spec.samples_per_period;
    let mut samples = Vec::with_capacity(n + 1);
    let phi_i = |tau: f64| params.drive_i().phi(params.omega() * tau);
    let sample = |tau: f64, y: [f64; 2]| Sample {
        tau,
        lambda: y[0],
        v: y[1],
        phi_i: phi_i(tau),
        steady: tau >= steady_from - 1e-9,
    };
    samples.push(sample(0.0, [x0, spec.v0]));
    let _ = dopri.integrate(&mut state, total_periods as f64 * period, |d| {
        while samples.len() <= n {
            let t = samples.len() as f64 * dt;
            if t > d.t1 + 1e-12 {
                break;
            }
            samples.push(sample(t, d.at(t.min(d.t1))));
        }
    });
    Ok(TimeHistory {
        samples,
        steady_state: steady,
        steady_from,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The steady part repeats with the response period, and it spans the reported amplitude.
    #[test]
    fn steady_part_repeats_and_spans_the_amplitude() {
        let p = Params::baseline();
        let spec = TimeHistorySpec {
            dx0: 0.3,
            ..TimeHistorySpec::default()
        };
        let h = time_history(&p, &spec).unwrap();
        assert_eq!(h.steady_state.period, Some(2));
        let steady: Vec<&Sample> = h.samples.iter().filter(|s| s.steady).collect();
        let per = 2 * spec.samples_per_period;
        assert!(steady.len() > per);
        for i in 0..steady.len() - per {
            assert!((steady[i].lambda - steady[i + per].lambda).abs() < 1e-6);
        }
        let (lo, hi) = steady
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
                (lo.min(s.lambda), hi.max(s.lambda))
            });
        // samples miss the exact extremes by at most O(dt²)
        assert!((hi - lo - h.steady_state.amplitude.unwrap()).abs() < 2e-3);
        assert!(h.samples.iter().any(|s| !s.steady));
    }
}
