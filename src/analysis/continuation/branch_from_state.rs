//! A branch continued from an initial state: the state is integrated to its steady response,
//! which seeds the continuation (what `isola continue` and a session's `continuation` do).

use serde::{Deserialize, Serialize};

use crate::analysis::AnalysisError;
use crate::analysis::continuation::branch::{ContinuationSpec, ContinuedBranch, continue_branch};
use crate::analysis::continuation::model::Continuable;
use crate::analysis::orbit::steady_state::SteadyStateSpec;
use crate::analysis::progress::Progress;

/// Where the seed comes from and how its branch is continued.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BranchFromState {
    /// Initial displacement Δλ = λ_I − λ_p at τ = 0 (a written model's first grid state's
    /// offset from its origin).
    pub dx0: f64,
    /// Initial velocity at τ = 0 (a written model's second grid state's offset).
    pub v0: f64,
    pub steady: SteadyStateSpec,
    pub continuation: ContinuationSpec,
}

/// Integrates (`dx0`, `v0`) to its steady state in `params` and continues the branch of the
/// periodic response it reaches; an error if it reaches none (collision, non-periodic).
pub fn branch_from_state<M: Continuable>(
    params: &M,
    spec: &BranchFromState,
    progress: &Progress,
) -> Result<ContinuedBranch, AnalysisError> {
    spec.steady.validate()?;
    spec.continuation.validate_from(params)?;
    let seed = params.steady_state(params.grid_start([spec.dx0, spec.v0]), &spec.steady)?;
    let k = seed.period.ok_or_else(|| AnalysisError::NoPeriodicSeed {
        dx0: spec.dx0,
        v0: spec.v0,
        class: seed.class.as_str().into(),
    })?;
    let start = params.state_vec(&params.poincare_states(&seed)[0]);
    Ok(continue_branch(
        params,
        k,
        &start,
        &spec.continuation,
        progress,
    )?)
}
