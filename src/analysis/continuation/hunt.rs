//! The isola hunter: every subharmonic or hidden branch a frequency response from many
//! initial states found is continued both ways in ω_e, and told apart as an isola (it closes on itself
//! between two folds) or attached (it ends on a period doubling of the main branch).

use serde::{Deserialize, Serialize};

use crate::analysis::AnalysisError;
use crate::analysis::continuation::branch::{
    BifurcationKind, BranchEnd, ContinuationError, ContinuationSpec, ContinuedBranch,
    continue_branch,
};
use crate::analysis::continuation::model::Continuable;
use crate::analysis::global::frequency_response::{
    Branch, FrequencyResponse, FrequencyResponseSpec, frequency_response,
};
use crate::analysis::parameter::ContinuationParameter;
use crate::analysis::progress::Progress;
use crate::model::error::ParamError;
use crate::model::system::StateVec;

/// Brute-force responses lie on a continued branch when their stroboscopic points match the
/// branch's converged orbit at the same ω_e within this distance (max-norm on [λ_I, v]): the
/// fixed-step integration and the 1e-9 period test leave about 1e-6.
const ON_BRANCH_TOL: f64 = 1e-4;

/// A hunt: the frequency response that finds the seeds, and how their branches are continued.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HuntSpec {
    pub response: FrequencyResponseSpec,
    /// Continuation in ω_e (its `parameter` must be `omega`); branches stop at its `min` and
    /// `max` (by default 0.2 and 6, the paper's range).
    pub continuation: ContinuationSpec,
}

impl HuntSpec {
    /// Checks the response and the continuation, which must run in ω_e.
    pub fn validate<M: Continuable>(&self, base: &M) -> Result<(), ParamError> {
        self.response.validate().map_err(|e| e.within("response"))?;
        if self.continuation.parameter != ContinuationParameter::Omega {
            return Err(ParamError {
                field: "continuation.parameter".into(),
                value: ParamError::NOT_NUMERIC,
                allowed: "omega (a hunt continues in the forcing frequency)".into(),
            });
        }
        self.continuation
            .validate(base)
            .map_err(|e| e.within("continuation"))
    }
}

/// What a continued subharmonic branch turned out to be.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// Closes on itself: an isola.
    Isola,
    /// Both ends on period doublings of a response of a divisor period.
    Attached,
    /// One end on a period doubling, the other somewhere else (range, collision, ...).
    HalfAttached,
    /// Neither closed nor attached within the range.
    Open,
}

impl Verdict {
    pub fn as_str(&self) -> &'static str {
        match self {
            Verdict::Isola => "isola",
            Verdict::Attached => "attached",
            Verdict::HalfAttached => "half-attached",
            Verdict::Open => "open",
        }
    }

    /// The verdict from how the branch's two ends stopped.
    pub fn of(branch: &ContinuedBranch) -> Self {
        if branch.closed() {
            return Verdict::Isola;
        }
        let parent = |e: &BranchEnd| matches!(e, BranchEnd::Parent { .. });
        match branch.ends.iter().filter(|e| parent(e)).count() {
            2 => Verdict::Attached,
            1 => Verdict::HalfAttached,
            _ => Verdict::Open,
        }
    }
}

/// One continued subharmonic branch and the brute-force branches it passes through.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HuntedBranch {
    /// Ids of the frequency response's branches that lie on it (the first was the seed).
    pub seeds: Vec<usize>,
    /// e.g. "1:2 subharmonic".
    pub response_type: String,
    pub verdict: Verdict,
    /// ω_e range of the whole branch, located folds included.
    pub omega_min: f64,
    pub omega_max: f64,
    pub peak_amplitude: f64,
    pub peak_omega: f64,
    /// Every brute-force response on it is hidden from both stepped sweeps.
    pub hidden: bool,
    /// ω_e ranges of its stable and unstable arcs.
    pub stable_arcs: Vec<[f64; 2]>,
    pub unstable_arcs: Vec<[f64; 2]>,
    pub branch: ContinuedBranch,
}

impl HuntedBranch {
    fn new(seed: &Branch, hidden: bool, branch: ContinuedBranch) -> Self {
        let (omega_min, omega_max) = branch.parameter_range();
        let peak = branch
            .points
            .iter()
            .max_by(|a, b| a.amplitude.total_cmp(&b.amplitude))
            .expect("a continued branch has its seed point");
        let mut arcs: Vec<([f64; 2], bool)> = branch
            .arc_ends()
            .into_iter()
            .map(|a| {
                let (p, q) = (a.parameter_start, a.parameter_end);
                ([p.min(q), p.max(q)], a.stable)
            })
            .collect();
        arcs.sort_by(|a, b| a.0[0].total_cmp(&b.0[0]));
        let arcs = |stable: bool| -> Vec<[f64; 2]> {
            arcs.iter().filter(|a| a.1 == stable).map(|a| a.0).collect()
        };
        HuntedBranch {
            seeds: vec![seed.id],
            response_type: seed.response_type.clone(),
            verdict: Verdict::of(&branch),
            omega_min,
            omega_max,
            peak_amplitude: peak.amplitude,
            peak_omega: peak.omega,
            hidden,
            stable_arcs: arcs(true),
            unstable_arcs: arcs(false),
            branch,
        }
    }

    /// The located folds and period doublings on it.
    pub fn folds(
        &self,
    ) -> impl Iterator<Item = &crate::analysis::continuation::branch::Bifurcation> {
        self.branch.of_kind(BifurcationKind::Fold)
    }

    /// One line: type, verdict, ω range, peak and located bifurcations.
    pub fn describe(&self) -> String {
        let bifs: Vec<String> = self
            .branch
            .bifurcations
            .iter()
            .map(|b| format!("{} ω {:.6}", b.kind.as_str(), b.omega))
            .collect();
        format!(
            "{} {}{}: ω {:.4}–{:.4}, peak {:.4} at ω {:.3}; {}",
            self.response_type,
            self.verdict.as_str(),
            if self.hidden { " (hidden)" } else { "" },
            self.omega_min,
            self.omega_max,
            self.peak_amplitude,
            self.peak_omega,
            if bifs.is_empty() {
                "no bifurcation in range".into()
            } else {
                bifs.join(", ")
            }
        )
    }
}

/// A brute-force branch whose continuation could not start (e.g. the seed is too close to
/// a fold for Newton).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HuntFailure {
    pub seed: usize,
    pub reason: String,
}

/// The hunt's result: the frequency response and its subharmonic and hidden branches continued.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Hunt {
    pub response: FrequencyResponse,
    pub branches: Vec<HuntedBranch>,
    pub failures: Vec<HuntFailure>,
}

impl Hunt {
    /// The isolas found.
    pub fn isolas(&self) -> impl Iterator<Item = &HuntedBranch> {
        self.branches.iter().filter(|b| b.verdict == Verdict::Isola)
    }
}

/// Runs the frequency response of `spec`, then continues each of its subharmonic and hidden branches.
pub fn hunt<M: Continuable>(
    params: &M,
    spec: &HuntSpec,
    progress: &Progress,
) -> Result<Hunt, AnalysisError> {
    spec.validate(params)?;
    let response = frequency_response(params, &spec.response, progress)?;
    hunt_in(params, response, &spec.continuation, progress)
}

/// Continues the subharmonic and hidden branches of a finished frequency response of `params`: each
/// seeded at its largest response, skipping brute-force branches that lie on a branch already
/// continued. A continuation counts each point it finds as one unit of work.
pub fn hunt_in<M: Continuable>(
    params: &M,
    response: FrequencyResponse,
    spec: &ContinuationSpec,
    progress: &Progress,
) -> Result<Hunt, AnalysisError> {
    let mut seeds: Vec<&Branch> = response
        .branches
        .iter()
        .filter(|b| b.may_be_an_isola())
        .collect();
    seeds.sort_by(|a, b| b.peak_amplitude.total_cmp(&a.peak_amplitude));
    let mut branches: Vec<HuntedBranch> = Vec::new();
    let mut failures = Vec::new();
    for seed in seeds {
        if let Some(h) = branches
            .iter_mut()
            .find(|h| lies_on(params, &response, seed, &h.branch, spec))
        {
            h.seeds.push(seed.id);
            h.hidden &= seed.hidden;
            continue;
        }
        let peak = response.peak(seed.id).expect("a branch has responses");
        let at = params.with(params.frequency(), peak.omega)?;
        let start = at.state_vec(&at.poincare_states(&peak.steady)[0]);
        match continue_branch(&at, seed.period, &start, spec, progress) {
            Ok(b) => branches.push(HuntedBranch::new(seed, seed.hidden, b)),
            Err(ContinuationError::Cancelled) => return Err(AnalysisError::Cancelled),
            Err(e) => failures.push(HuntFailure {
                seed: seed.id,
                reason: e.to_string(),
            }),
        }
    }
    Ok(Hunt {
        response,
        branches,
        failures,
    })
}

/// True when every response of brute-force branch `seed` lies on `continued` at its ω_e.
fn lies_on<M: Continuable>(
    model: &M,
    response: &FrequencyResponse,
    seed: &Branch,
    continued: &ContinuedBranch,
    spec: &ContinuationSpec,
) -> bool {
    continued.period == seed.period
        && response
            .responses
            .iter()
            .filter(|r| r.branch == Some(seed.id))
            .all(|r| {
                let states: Vec<StateVec> = model
                    .poincare_states(&r.steady)
                    .iter()
                    .map(|s| model.state_vec(s))
                    .collect();
                continued.passes_through(model, r.omega, &states, ON_BRANCH_TOL, &spec.shooting)
            })
}
