//! A branch continued from an initial state: the state is integrated to its steady response,
//! which seeds the continuation (what `isola continue` and a session's `continuation` do).

use serde::{Deserialize, Serialize};

use crate::analysis::AnalysisError;
use crate::analysis::continuation::branch::{ContinuationSpec, ContinuedBranch, continue_branch};
use crate::analysis::orbit::steady_state::{SteadyStateSpec, steady_state};
use crate::analysis::progress::Progress;
use crate::model::Params;

/// Where the seed comes from and how its branch is continued.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BranchFromState {
    /// Initial displacement Δλ = λ_I − λ_p at τ = 0.
    pub dx0: f64,
    /// Initial velocity at τ = 0.
    pub v0: f64,
    pub steady: SteadyStateSpec,
    pub continuation: ContinuationSpec,
}

/// Integrates (`dx0`, `v0`) to its steady state in `params` and continues the branch of the
/// periodic response it reaches; an error if it reaches none (collision, non-periodic).
pub fn branch_from_state(
    params: &Params,
    spec: &BranchFromState,
    progress: &Progress,
) -> Result<ContinuedBranch, AnalysisError> {
    spec.steady.validate()?;
    spec.continuation.validate(params)?;
    let seed = steady_state(params, params.lambda_p() + spec.dx0, spec.v0, &spec.steady);
    let k = seed.period.ok_or_else(|| AnalysisError::NoPeriodicSeed {
        dx0: spec.dx0,
        v0: spec.v0,
        class: seed.class.as_str().into(),
    })?;
    Ok(continue_branch(
        params,
        k,
        seed.poincare[0],
        &spec.continuation,
        progress,
    )?)
}
