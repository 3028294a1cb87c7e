//! Fig 4/5 insets: the time history and phase path of one orbit, its transient and its steady
//! part told apart, from the accurate integrator's dense output.

use serde::{Deserialize, Serialize};

use crate::analysis::AnalysisError;
use crate::analysis::orbit::steady_state::{SteadyState, SteadyStateSpec, steady_state};
use crate::model::Params;
use crate::model::error::{check, check_in};
use crate::model::forces::membrane_forces;
use crate::solver::{Dopri5, Tolerance};

/// One orbit to record.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TimeHistorySpec {
    /// Initial state (Δλ, v) at τ = 0.
    pub dx0: f64,
    pub v0: f64,
    /// Samples per forcing period, in [`SAMPLES_PER_PERIOD`].
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

/// The allowed samples per forcing period, [lo, hi].
pub const SAMPLES_PER_PERIOD: (usize, usize) = (4, 4096);

/// One sample of the orbit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Sample {
    pub tau: f64,
    pub lambda: f64,
    pub v: f64,
    /// φ_I at this time.
    pub phi_i: f64,
    /// The forces f_I, f_II the membranes carry (MODEL.md §1): 0 where a membrane is slack.
    pub tension_i: f64,
    pub tension_ii: f64,
    /// On the steady response (after the transient).
    pub steady: bool,
}

impl Sample {
    /// Whether membrane I, membrane II is slack (carries no force).
    pub fn slack(&self) -> (bool, bool) {
        (self.tension_i == 0.0, self.tension_ii == 0.0)
    }
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
        let (lo, hi) = SAMPLES_PER_PERIOD;
        check_in(
            "samples_per_period",
            self.samples_per_period as f64,
            lo as f64,
            hi as f64,
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
    let sample = |tau: f64, [lambda, v]: [f64; 2]| {
        let (phi_sq_i, phi_sq_ii) = params.phi_sq_at(tau);
        let (tension_i, tension_ii) = membrane_forces(params, lambda, v, phi_sq_i, phi_sq_ii);
        Sample {
            tau,
            lambda,
            v,
            phi_i: phi_i(tau),
            tension_i,
            tension_ii,
            steady: tau >= steady_from - 1e-9,
        }
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
    /// The forcing's frequency (ω_e, or a written model's).
    pub omega: f64,
    /// The response period in forcing periods (1 for 1:1, 2 for 1:2...), if the samples
    /// repeat within the recorded steady part.
    pub period_forcing_periods: Option<usize>,
    /// max − min of the amplitude's quantity (λ_I, or a written model's output): the
    /// amplitude isola reports everywhere.
    pub amplitude: f64,
    /// The built-in model's: the share of the steady part during which membrane I, membrane
    /// II carries no force (tension ≤ 0: slack). None for a written model.
    pub slack: Option<[f64; 2]>,
}

/// The summary of the steady part of samples (τ, λ_I, v, steady) taken every `dt` = `τ[1] − τ[0]`
/// of an orbit of `p`; `None` without a steady part of at least a forcing period.
pub fn steady_summary(
    p: &Params,
    tau: &[f64],
    lambda: &[f64],
    v: &[f64],
    steady: &[bool],
) -> Option<SteadySummary> {
    let n = tau.len().min(lambda.len()).min(v.len()).min(steady.len());
    let mut summary = periodic_summary(p.omega(), &tau[..n], &lambda[..n], &steady[..n])?;
    let idx: Vec<usize> = (0..n).filter(|&k| steady[k]).collect();
    let (mut slack_i, mut slack_ii) = (0usize, 0usize);
    for &k in &idx {
        let (phi_sq_i, phi_sq_ii) = p.phi_sq_at(tau[k]);
        let (f_i, f_ii) = membrane_forces(p, lambda[k], v[k], phi_sq_i, phi_sq_ii);
        slack_i += usize::from(f_i <= 0.0);
        slack_ii += usize::from(f_ii <= 0.0);
    }
    let steady_samples = idx.len() as f64;
    summary.slack = Some([slack_i, slack_ii].map(|s| s as f64 / steady_samples));
    Some(summary)
}

/// The summary of the steady part of samples (τ, x, steady), taken every `dt` = `τ[1] − τ[0]`,
/// of an orbit forced at frequency `omega`, `x` the quantity whose max − min is the amplitude;
/// no slack. `None` without a steady part of at least a forcing period.
pub fn periodic_summary(
    omega: f64,
    tau: &[f64],
    x: &[f64],
    steady: &[bool],
) -> Option<SteadySummary> {
    let idx: Vec<usize> = (0..tau.len().min(x.len()).min(steady.len()))
        .filter(|&k| steady[k])
        .collect();
    let dt = tau.get(1)? - tau.first()?;
    let per = (std::f64::consts::TAU / omega / dt).round() as usize;
    if dt <= 0.0 || per == 0 || idx.len() <= per {
        return None;
    }
    let (lo, hi) = idx
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &k| {
            (lo.min(x[k]), hi.max(x[k]))
        });
    let amplitude = hi - lo;
    // the smallest whole number of forcing periods after which the samples repeat
    let tolerance = 1e-3 * amplitude.max(1e-3);
    let period_forcing_periods = (1..=idx.len() / per).find(|&k| {
        let shift = k * per;
        shift < idx.len()
            && (0..idx.len() - shift).all(|i| (x[idx[i + shift]] - x[idx[i]]).abs() < tolerance)
    });
    Some(SteadySummary {
        omega,
        period_forcing_periods,
        amplitude,
        slack: None,
    })
}
