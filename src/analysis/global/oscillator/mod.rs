//! What the global analyses need of a model at one parameter point, whatever the model: the
//! built-in DEA ([`crate::model::Params`], integrated in SIMD lanes with verified early stops)
//! or a model written in the session ([`crate::model::equations::EquationSystem`], on the
//! general engine). Frequency responses, basins and sweeps are generic over it.

mod built_in;
pub mod chirp;
pub mod history;
pub mod written;

use std::sync::atomic::AtomicBool;

use crate::analysis::AnalysisError;
use crate::analysis::global::batch::KnownAttractors;
use crate::analysis::orbit::steady_state::{SteadyState, SteadyStateSpec};
use crate::analysis::parameter::ContinuationParameter;
use crate::model::ParamError;
use crate::model::system::StateVec;

/// A model at one parameter point, as the brute-force analyses use it.
pub trait Oscillator: Clone + Send + Sync + Sized {
    /// A whole state of the model.
    type State: Copy + Send + Sync + PartialEq + std::fmt::Debug;
    /// A parameter a response may be computed against (ω_e or a model parameter).
    type Parameter: Copy + Send + Sync;

    /// The forcing frequency, as a parameter.
    fn frequency(&self) -> Self::Parameter;
    /// The same model with `parameter` set to `value`, checked.
    fn with(&self, parameter: Self::Parameter, value: f64) -> Result<Self, ParamError>;
    /// `parameter`, named as users write it, as this model knows it; an error names what it
    /// has instead.
    fn resolve(&self, parameter: ContinuationParameter) -> Result<Self::Parameter, ParamError>;
    /// The value of `parameter` here.
    fn value_of(&self, parameter: Self::Parameter) -> f64;
    /// A whole state as a list of the model's state variables.
    fn state_vec(&self, state: &Self::State) -> StateVec;
    /// The state whose two grid states are the grid's origin plus `offset` (the built-in:
    /// λ_I = λ_p + Δλ, v), the others at their initial values.
    fn grid_start(&self, offset: [f64; 2]) -> Self::State;
    /// The whole states at a response's stroboscopic points, in time order.
    fn poincare_states(&self, s: &SteadyState) -> Vec<Self::State>;
    /// The steady state reached from `start` at τ = 0.
    fn steady_state(
        &self,
        start: Self::State,
        spec: &SteadyStateSpec,
    ) -> Result<SteadyState, AnalysisError>;
    /// The steady states reached from each of `starts`, in order; `on_done(i)` as each
    /// finishes. `known` (from [`Self::known_attractors`]) may stop trajectories early.
    fn steady_states(
        &self,
        starts: &[Self::State],
        spec: &SteadyStateSpec,
        known: Option<&mut KnownAttractors>,
        cancel: &AtomicBool,
        on_done: &mut dyn FnMut(usize),
    ) -> Result<Vec<SteadyState>, AnalysisError>;
    /// An empty table of known attractors with capture regions at most `capture` across, if
    /// this model can verify them (else trajectories run to full convergence).
    fn known_attractors(&self, spec: &SteadyStateSpec, capture: f64) -> Option<KnownAttractors>;

    /// The state at rest at the grid's origin: where sweeps start and restart.
    fn rest(&self) -> Self::State {
        self.grid_start([0.0, 0.0])
    }
}
