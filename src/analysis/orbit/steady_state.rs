//! Integrate to a periodic steady state and classify it (MODEL.md §4, §4b).
//!
//! Two-stage period test: a period is accepted only once some k ≤ `max_period` has its last
//! k stroboscopic points repeat to `tol_converged`, far below the matching tolerance; the
//! period is then the smallest k whose points repeat to `tol_match`. A slowly spiralling
//! transient (Floquet multiplier near −1 or e^{±2πi/3}) thus cannot pass for a 1:2 or 1:3
//! response, and a converged period-1 orbit is not reported as period 2.

use serde::{Deserialize, Serialize};

use crate::analysis::orbit::period_detector::PeriodDetector;
use crate::analysis::orbit::period_map::{OrbitRecord, PeriodMap, Rk4PeriodMap};
use crate::analysis::orbit::ratio::Ratio;
use crate::model::Params;
use crate::model::error::{ParamError, check};
use crate::solver::{Collision, Resolution};

/// How a steady state is sought.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SteadyStateSpec {
    /// Longest response period k, in forcing periods, still called periodic.
    pub max_period: usize,
    /// Forcing periods integrated before giving up as non-periodic.
    pub max_forcing_periods: usize,
    /// Stage 1: the stroboscopic points must repeat to this (max-norm on [λ_I, v]).
    pub tol_converged: f64,
    /// Stage 2: the period is the smallest k that repeats to this.
    pub tol_match: f64,
    /// Fixed-step resolution of the fast integrator.
    pub resolution: Resolution,
}

impl Default for SteadyStateSpec {
    fn default() -> Self {
        SteadyStateSpec {
            max_period: 8,
            max_forcing_periods: 6000,
            tol_converged: 1e-9,
            tol_match: 1e-5,
            resolution: Resolution::default(),
        }
    }
}

impl SteadyStateSpec {
    /// A period detector with these settings, on points of `N` numbers.
    pub fn period_detector<const N: usize>(&self) -> PeriodDetector<N> {
        PeriodDetector::new(self.max_period, self.tol_converged, self.tol_match)
    }

    /// Checks every field.
    pub fn validate(&self) -> Result<(), ParamError> {
        check(
            "max_period",
            self.max_period as f64,
            |k| (1.0..=64.0).contains(&k),
            "[1, 64]",
        )?;
        check(
            "max_forcing_periods",
            self.max_forcing_periods as f64,
            |n| n >= 2.0 * self.max_period as f64 && n <= 1e7,
            format!("[{}, 10000000]", 2 * self.max_period),
        )?;
        check(
            "tol_converged",
            self.tol_converged,
            |t| t > 0.0 && t < self.tol_match,
            format!("(0, tol_match = {})", self.tol_match),
        )?;
        check(
            "tol_match",
            self.tol_match,
            |t| t > 0.0 && t < 1.0,
            "(0, 1)",
        )?;
        self.resolution
            .validate()
            .map_err(|e| e.within("resolution"))
    }
}

/// What a trajectory settles to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Class {
    Periodic,
    NonPeriodic,
    Collision,
}

impl Class {
    pub fn as_str(&self) -> &'static str {
        match self {
            Class::Periodic => "periodic",
            Class::NonPeriodic => "non-periodic",
            Class::Collision => "collision",
        }
    }
}

/// A classified steady state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SteadyState {
    pub class: Class,
    /// Response period k in forcing periods (periodic only).
    pub period: Option<usize>,
    /// ω_r : ω_e (periodic only).
    pub ratio: Option<Ratio>,
    /// max − min of λ_I over one response period (over the last `max_period` forcing periods
    /// for a non-periodic response; none after a collision).
    pub amplitude: Option<f64>,
    /// The k stroboscopic points [λ_I, v] at τ = nT, in time order (for a written model,
    /// its two grid states).
    pub poincare: Vec<[f64; 2]>,
    /// A written model's whole states at those points, when it has more than its two grid
    /// states (empty otherwise).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub states: Vec<Vec<f64>>,
    /// Forcing periods integrated before the steady state was accepted.
    pub transient_periods: usize,
    pub lambda_min: Option<f64>,
    pub lambda_max: Option<f64>,
    pub lambda_mean: Option<f64>,
    /// Where the mass left the model, for a collision.
    pub collision: Option<Collision>,
}

impl SteadyState {
    /// The paper's name for the response: "2:1 super-harmonic" or "1:1 harmonic" for a
    /// period-1 orbit (by its strongest line), "1:k subharmonic" for a period-k orbit, or the
    /// class. The paper names subharmonics by their period even where another line of the
    /// response is stronger (its 1:3 response at ADR 1.0, ω_e 3.6 is strongest at 2ω_e/3).
    pub fn response_type(&self) -> String {
        match (self.period, self.ratio) {
            (Some(1), Some(r)) if r.response > 1 => format!("{r} super-harmonic"),
            (Some(1), Some(r)) => format!("{r} harmonic"),
            (Some(k), _) => format!("1:{k} subharmonic"),
            _ => self.class.as_str().to_string(),
        }
    }

    /// The label users read: the ratio, or the class when there is none.
    pub fn label(&self) -> String {
        match self.ratio {
            Some(r) => r.to_string(),
            None => self.class.as_str().to_string(),
        }
    }
}

/// The steady state reached from λ_I = `x0`, dλ_I/dτ = `v0` at τ = 0, with the fast
/// integrator. Note `x0` is the stretch λ_I itself, not the offset Δλ.
pub fn steady_state(params: &Params, x0: f64, v0: f64, spec: &SteadyStateSpec) -> SteadyState {
    let mut map = Rk4PeriodMap::new(params, &spec.resolution, x0, v0);
    steady_state_with(&mut map, spec)
}

/// The steady state reached by any stroboscopic map (fast or reference integrator).
pub fn steady_state_with(map: &mut impl PeriodMap, spec: &SteadyStateSpec) -> SteadyState {
    let mut detector = spec.period_detector();
    while detector.periods() < spec.max_forcing_periods {
        let point = match map.advance() {
            Ok(p) => p,
            Err(c) => return collided(c, detector.periods() + 1),
        };
        if let Some(k) = detector.push(point) {
            return record(map, k, detector.periods(), Class::Periodic);
        }
    }
    record(
        map,
        spec.max_period,
        spec.max_forcing_periods,
        Class::NonPeriodic,
    )
}

/// Follows the response for `k` more periods, recording it, and builds the result.
fn record(map: &mut impl PeriodMap, k: usize, n: usize, class: Class) -> SteadyState {
    let mut rec = OrbitRecord::new(map.samples_per_period());
    let mut poincare = Vec::with_capacity(k);
    for _ in 0..k {
        match map.advance_recording(&mut rec) {
            Ok(p) => poincare.push(p),
            Err(c) => return collided(c, n),
        }
    }
    from_record(&rec, poincare, k, n, class)
}

/// The result for a response followed over `k` forcing periods into `rec`, after `n`
/// transient periods.
pub(crate) fn from_record(
    rec: &OrbitRecord,
    poincare: Vec<[f64; 2]>,
    k: usize,
    n: usize,
    class: Class,
) -> SteadyState {
    let periodic = class == Class::Periodic;
    SteadyState {
        class,
        period: periodic.then_some(k),
        ratio: periodic.then(|| Ratio::of_samples(&rec.samples, k)),
        amplitude: Some(rec.amplitude()),
        poincare,
        states: Vec::new(),
        transient_periods: n,
        lambda_min: Some(rec.lambda_min),
        lambda_max: Some(rec.lambda_max),
        lambda_mean: Some(rec.lambda_mean()),
        collision: None,
    }
}

pub(crate) fn collided(c: Collision, n: usize) -> SteadyState {
    SteadyState {
        class: Class::Collision,
        period: None,
        ratio: None,
        amplitude: None,
        poincare: Vec::new(),
        states: Vec::new(),
        transient_periods: n,
        lambda_min: None,
        lambda_max: None,
        lambda_mean: None,
        collision: Some(c),
    }
}
