//! Fig 4/5 insets: the time history and phase path of one orbit, its transient and its steady
//! part told apart, from the accurate integrator's dense output.

use serde::{Deserialize, Serialize};

use crate::analysis::AnalysisError;
use crate::analysis::orbit::steady_state::{SteadyState, SteadyStateSpec, steady_state};
use crate::model::Params;
use crate::model::error::check;
use crate::model::forces::membrane_force;
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

/// What the steady part of a recorded orbit shows, read off its samples.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SteadySummary {
    /// The forcing's ω_e.
    pub omega: f64,
    /// The response period in forcing periods (1 for 1:1, 2 for 1:2...), if the samples
    /// repeat within the recorded steady part.
    pub period_forcing_periods: Option<usize>,
    /// max − min of λ_I (the amplitude isola reports everywhere).
    pub amplitude: f64,
    /// The share of the steady part during which membrane I, membrane II carries no force
    /// (tension ≤ 0: slack).
    pub slack_i: f64,
    pub slack_ii: f64,
}

/// The summary of the steady part of samples (τ, λ_I, v, steady) taken every `dt` = τ[1] − τ[0]
/// of an orbit of `p`; `None` without a steady part of at least a forcing period.
pub fn steady_summary(
    p: &Params,
    tau: &[f64],
    lambda: &[f64],
    v: &[f64],
    steady: &[bool],
) -> Option<SteadySummary> {
    let idx: Vec<usize> = (0..tau.len().min(lambda.len()).min(v.len()).min(steady.len()))
        .filter(|&k| steady[k])
        .collect();
    let dt = tau.get(1)? - tau.first()?;
    let per = (p.period() / dt).round() as usize;
    if dt <= 0.0 || per == 0 || idx.len() <= per {
        return None;
    }
    let (lo, hi) = idx
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &k| {
            (lo.min(lambda[k]), hi.max(lambda[k]))
        });
    let amplitude = hi - lo;
    // the smallest whole number of forcing periods after which the samples repeat
    let tolerance = 1e-3 * amplitude.max(1e-3);
    let period_forcing_periods = (1..=idx.len() / per).find(|&k| {
        let shift = k * per;
        shift < idx.len()
            && (0..idx.len() - shift)
                .all(|i| (lambda[idx[i + shift]] - lambda[idx[i]]).abs() < tolerance)
    });
    let (c, j) = (p.c_tilde(), p.j());
    let (mut slack_i, mut slack_ii) = (0usize, 0usize);
    for &k in &idx {
        let (phi_sq_i, phi_sq_ii) = p.phi_sq_at(tau[k]);
        let lambda_ii = 2.0 * p.lambda_p() - lambda[k];
        slack_i += usize::from(membrane_force(lambda[k], phi_sq_i, v[k], c, j) <= 0.0);
        slack_ii += usize::from(membrane_force(lambda_ii, phi_sq_ii, -v[k], c, j) <= 0.0);
    }
    let n = idx.len() as f64;
    Some(SteadySummary {
        omega: p.omega(),
        period_forcing_periods,
        amplitude,
        slack_i: slack_i as f64 / n,
        slack_ii: slack_ii as f64 / n,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The summary read off the samples agrees with the steady-state analysis of the same
    /// orbit: its period, its amplitude (samples miss the extremes by O(dt²)). At λ_p = 1.02
    /// the peak voltage alone outweighs membrane I's tension at rest (φ_I² λ_p = 0.088 >
    /// g(λ_p) = 0.078), so even the small 1:1 orbit slackens it part of the time, and the 1:2
    /// isola orbit longer; membrane II is never driven and stays taut on the small orbit.
    #[test]
    fn the_summary_agrees_with_the_steady_state() {
        let p = Params::baseline();
        let mut slack = Vec::new();
        for (dx0, period) in [(0.3, 2), (0.0, 1)] {
            let spec = TimeHistorySpec {
                dx0,
                ..TimeHistorySpec::default()
            };
            let h = time_history(&p, &spec).unwrap();
            assert_eq!(h.steady_state.period, Some(period));
            let col = |f: fn(&Sample) -> f64| h.samples.iter().map(f).collect::<Vec<_>>();
            let steady: Vec<bool> = h.samples.iter().map(|s| s.steady).collect();
            let s = steady_summary(
                &p,
                &col(|s| s.tau),
                &col(|s| s.lambda),
                &col(|s| s.v),
                &steady,
            )
            .unwrap();
            assert_eq!(s.period_forcing_periods, Some(period));
            assert!((s.amplitude - h.steady_state.amplitude.unwrap()).abs() < 2e-3);
            assert!((0.0..1.0).contains(&s.slack_i) && (0.0..1.0).contains(&s.slack_ii));
            slack.push((s.slack_i, s.slack_ii));
        }
        let (isola, small) = (slack[0], slack[1]);
        assert!(isola.0 > small.0 && small.0 > 0.0, "{slack:?}");
        assert_eq!(small.1, 0.0);
    }

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
