//! The built-in DEA as an [`Oscillator`]: the lanes of [`crate::analysis::global::batch`].

use std::sync::atomic::AtomicBool;

use super::Oscillator;
use crate::analysis::AnalysisError;
use crate::analysis::global::batch::{KnownAttractors, steady_states};
use crate::analysis::orbit::steady_state::{SteadyState, SteadyStateSpec, steady_state};
use crate::analysis::parameter::ContinuationParameter;
use crate::model::system::StateVec;
use crate::model::{ParamError, Params};

impl Oscillator for Params {
    type State = [f64; 2];
    type Parameter = ContinuationParameter;

    fn frequency(&self) -> ContinuationParameter {
        ContinuationParameter::Omega
    }

    fn with(&self, parameter: ContinuationParameter, value: f64) -> Result<Params, ParamError> {
        parameter.apply(self, value)
    }

    fn resolve(
        &self,
        parameter: ContinuationParameter,
    ) -> Result<ContinuationParameter, ParamError> {
        parameter.check_built_in().map(|()| parameter)
    }

    fn value_of(&self, parameter: ContinuationParameter) -> f64 {
        parameter.value(self)
    }

    fn state_vec(&self, state: &[f64; 2]) -> StateVec {
        StateVec::from(*state)
    }

    fn grid_start(&self, [dx, v]: [f64; 2]) -> [f64; 2] {
        [self.lambda_p() + dx, v]
    }

    fn poincare_states(&self, s: &SteadyState) -> Vec<[f64; 2]> {
        s.poincare.clone()
    }

    fn steady_state(
        &self,
        [x0, v0]: [f64; 2],
        spec: &SteadyStateSpec,
    ) -> Result<SteadyState, AnalysisError> {
        Ok(steady_state(self, x0, v0, spec))
    }

    fn steady_states(
        &self,
        starts: &[[f64; 2]],
        spec: &SteadyStateSpec,
        known: Option<&mut KnownAttractors>,
        cancel: &AtomicBool,
        on_done: &mut dyn FnMut(usize),
    ) -> Result<Vec<SteadyState>, AnalysisError> {
        steady_states(self, starts, spec, known, cancel, on_done).ok_or(AnalysisError::Cancelled)
    }

    fn known_attractors(&self, spec: &SteadyStateSpec, capture: f64) -> Option<KnownAttractors> {
        Some(KnownAttractors::new(self, &spec.resolution, capture))
    }
}
