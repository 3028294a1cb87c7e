//! Analyses built on the solvers. Each is a plain function of its spec, in three groups that
//! depend on each other one way only (continuation → global → orbit):
//!
//! - [`orbit`]: one orbit: the stroboscopic map, the period test and classification, time
//!   histories, sweeps of one trajectory, shooting and Floquet multipliers;
//! - [`global`]: brute force over many initial states: batches in lanes, capture regions,
//!   frequency responses, basins, families, and the [`Oscillator`] trait they are generic
//!   over (the built-in model or one written in the session);
//! - [`continuation`]: branches of periodic orbits, their bifurcations, the isola hunter,
//!   fold curves and two-parameter maps.
//!
//! [`parameter`] names what an analysis can vary; [`grid`] the axes; [`cost`] the worst-case
//! cost of any of them; [`resolution`] the resolution a user sets on any of them.

pub mod continuation;
pub mod cost;
pub mod global;
pub mod grid;
pub mod orbit;
pub mod parameter;
pub mod progress;
pub mod resolution;
pub mod windows;

pub use global::oscillator::Oscillator;
pub use orbit::period_map::{DopriPeriodMap, OrbitRecord, PeriodMap, Rk4PeriodMap};
pub use orbit::ratio::Ratio;
pub use orbit::steady_state::{
    Class, SteadyState, SteadyStateSpec, steady_state, steady_state_with,
};
pub use progress::Progress;

/// The version of isola's numerics, part of every result's fingerprint: bump it with any
/// change that alters a number any analysis writes (a new step rule, tolerance, seed or
/// classification), so that chunks and results of builds with other numerics are never
/// mixed with this build's. Changes that keep every result byte-identical keep it.
/// 2: a drive given as (E_a, ADR) keeps them exactly, so drives rebuilt from it (family
/// members, sweep frequencies, continuation starts) moved by up to an ulp.
/// 3: the early stop learns a response as soon as a trajectory has nearly settled on it,
/// from the cycle Newton's method finds ahead of it, so responses' values move by about 1e-8
/// and a subharmonic's Poincaré points may start at another of its points.
/// 4: a grid of more than 64 starts (a basin's chunk, a frequency response's ω_e) runs in 64
/// lanes instead of 16, so another trajectory may reach a response first: a response's
/// values move by up to about 4e-9 and the start it names may be another.
/// 5: a capture region grows to the ring half-way (in ratio) between the rung of its ladder
/// that passed and the one that failed, so trajectories are captured sooner: a subharmonic
/// response may name another of its points as its start (every other value the same).
/// A written model's own numerics have their version too
/// ([`crate::model::equations::NUMERICS_VERSION`]).
pub const NUMERICS_VERSION: u32 = 5;

/// Why an analysis produced no result.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AnalysisError {
    #[error(transparent)]
    Param(#[from] crate::model::ParamError),
    #[error(transparent)]
    Shooting(#[from] orbit::shooting::ShootingError),
    // the start as the settings name it, for the built-in model and a written one alike
    #[error(
        "the trajectory from dx0 = {dx0}, v0 = {v0} settles to a {class} response: nothing to \
         continue"
    )]
    NoPeriodicSeed { dx0: f64, v0: f64, class: String },
    #[error("cancelled")]
    Cancelled,
    #[error(
        "the recorded orbit cannot meet its tolerance (rtol = {rtol:e}, atol = {atol:e}): at \
         {steps} RK4 steps per {per}, the most allowed, the error estimated over the sample \
         interval from τ = {tau} is still {excess:.3} times its share of it (round-off, \
         an orbit too sensitive to follow that closely, or a model whose slope is unbounded \
         where the orbit passes, as sqrt(x) at x = 0); allowed rtol in (1e-14, 1), and a \
         larger one will do"
    )]
    ToleranceNotMet {
        rtol: f64,
        atol: f64,
        steps: usize,
        /// What `steps` are counted per: `forcing period` or `sample interval`.
        per: &'static str,
        tau: f64,
        /// The error estimate over the tolerance.
        excess: f64,
    },
    #[error("the model gives a value that is not finite at τ = {tau}, from {state}: {expression}")]
    NotFinite {
        tau: f64,
        /// The state as `name = value, ...`.
        state: String,
        /// The first named value that is not finite (`model.let.g_I = NaN`), if known.
        expression: String,
    },
}

impl AnalysisError {
    /// The error of a model that gave a value that is not finite: where, from which state (by
    /// the states' names), in which expression.
    pub fn not_finite(
        sys: &impl crate::model::system::System,
        tau: f64,
        state: &crate::model::system::Vector,
        expression: &Option<String>,
    ) -> AnalysisError {
        let state = sys
            .state_names()
            .iter()
            .zip(state)
            .map(|(name, &v)| match v.abs() {
                // a state running away reads as 1.2e150, not as 150 digits
                a if a >= 1e9 => format!("{name} = {v:e}"),
                _ => format!("{name} = {v}"),
            })
            .collect::<Vec<_>>()
            .join(", ");
        AnalysisError::NotFinite {
            tau,
            state,
            expression: expression.clone().unwrap_or_else(|| {
                // every named value is finite there: a stage of the next step is not
                "every expression is finite there, but not at a stage of the step from it: the \
                 state left an expression's domain within one step (sqrt or ln of a negative, a \
                 division by zero) or ran away; a finer resolution, or a collision condition \
                 ending the trajectory where the model stops holding, can help"
                    .into()
            }),
        }
    }
}
