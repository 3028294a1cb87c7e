//! Analyses built on the solvers. Each is a plain function of its spec.

pub mod attractor;
pub mod basin;
pub mod batch;
pub mod bifurcation_curve;
pub mod branch_from_state;
pub mod capture;
mod capture_cover;
pub mod chirp_sweep;
pub mod continuation;
pub mod cost;
pub mod family;
pub mod floquet;
pub mod force_curve;
pub mod frequency_response;
pub mod grid;
pub mod hunt;
pub mod hunt_family;
pub mod isola_limits;
pub mod map;
pub mod oscillator;
pub mod period_detector;
pub mod period_map;
pub mod progress;
pub mod ratio;
pub mod scalogram;
pub mod shooting;
pub mod steady_state;
pub mod stepped_sweep;
pub mod time_history;

pub use oscillator::Oscillator;
pub use period_map::{DopriPeriodMap, OrbitRecord, PeriodMap, Rk4PeriodMap};
pub use progress::Progress;
pub use ratio::Ratio;
pub use steady_state::{Class, SteadyState, SteadyStateSpec, steady_state, steady_state_with};

/// The version of isola's numerics, part of every result's fingerprint: bump it with any
/// change that alters a number any analysis writes (a new step rule, tolerance, seed or
/// classification), so that chunks and results of builds with other numerics are never
/// mixed with this build's. Changes that keep every result byte-identical keep it.
/// 2: a drive given as (E_a, ADR) keeps them exactly, so drives rebuilt from it (family
/// members, sweep frequencies, continuation starts) moved by up to an ulp.
pub const NUMERICS_VERSION: u32 = 2;

/// Why an analysis produced no result.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AnalysisError {
    #[error(transparent)]
    Param(#[from] crate::model::ParamError),
    #[error(transparent)]
    Shooting(#[from] shooting::ShootingError),
    #[error(
        "the trajectory from Δλ {dx0}, v {v0} settles to a {class} response: nothing to continue"
    )]
    NoPeriodicSeed { dx0: f64, v0: f64, class: String },
    #[error("cancelled")]
    Cancelled,
    #[error(
        "the model gives a value that is not finite at τ = {tau}, from the state {state:?}: {expression}"
    )]
    NotFinite {
        tau: f64,
        state: Vec<f64>,
        expression: String,
    },
}
