//! The paper checked claim by claim: each of its statements (quoted, with its figure or
//! section) beside what isola computes for it, with the precision of isola's number, how
//! that precision is known, and a verdict. Every number on isola's side comes from a
//! computation run here; only the paper's own words and numbers are written in.
//!
//! Two modes: [`Mode::Full`] uses the paper's resolutions (201 × 251 basins, frequency
//! responses over ω_e 0.2–6 by 0.05 from 15 × 15 starts); [`Mode::Quick`] coarser grids of
//! starts for the brute-force parts. The continuation-based locations (folds, births,
//! mergings, vanishings) are the same, to the same precision, in both.

mod branches;
mod responses;

use serde::Serialize;

use crate::analysis::continuation::branch::ContinuationError;
use crate::analysis::grid::Axis;
use crate::analysis::{AnalysisError, Progress};
use crate::model::ParamError;

/// How hard the brute-force parts look.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mode {
    /// Coarse grids of starts: about 20 s on two cores.
    Quick,
    /// The paper's resolutions.
    Full,
}

/// The grids of one [`Mode`].
#[derive(Debug, Clone, Copy, PartialEq)]
struct Grids {
    /// Basins: cells in Δλ and v over the paper's [−0.8, 0.8] × [−1, 1].
    basin: (usize, usize),
    /// Frequency responses: ω_e step, and starts per side of the grid of initial states.
    omega_step: f64,
    starts: usize,
    /// Bisections (in the parameter) before a located turning point takes over.
    bisection: f64,
    /// The bracket (in √E_a) of the smallest E_a with a collision.
    collision: f64,
}

impl Mode {
    fn grids(self) -> Grids {
        match self {
            Mode::Quick => Grids {
                basin: (41, 51),
                omega_step: 0.1,
                starts: 7,
                bisection: 1e-3,
                collision: 1e-2,
            },
            Mode::Full => Grids {
                basin: (201, 251),
                omega_step: 0.05,
                starts: 15,
                bisection: 1e-4,
                collision: 5e-4,
            },
        }
    }
}

impl Grids {
    /// ω_e from `min` to `max` by the mode's step.
    fn omega(&self, min: f64, max: f64) -> Axis {
        let points = ((max - min) / self.omega_step).round() as usize + 1;
        Axis::new(min, max, points)
    }
}

/// How isola's value compares with the paper's statement.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// Within the paper's own precision (its rounding, or its words).
    Agrees,
    /// Outside it: the difference is given.
    Differs,
    /// The statement holds only loosely (a typo, a range sampled too coarsely to say).
    Imprecise,
}

impl Verdict {
    pub fn as_str(&self) -> &'static str {
        match self {
            Verdict::Agrees => "agrees",
            Verdict::Differs => "differs",
            Verdict::Imprecise => "imprecise",
        }
    }
}

/// One of the paper's claims beside isola's computation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Claim {
    /// Short stable name, e.g. `isola-birth-adr`.
    pub id: &'static str,
    /// Where the paper says it: `Fig 7`, `§ Effects of damping`.
    pub figure: &'static str,
    /// The paper's words, quoted.
    pub paper: &'static str,
    /// The paper's number, where it gives one.
    pub paper_value: Option<f64>,
    /// What isola computes, in words with its numbers.
    pub isola: String,
    /// isola's headline number for the claim.
    pub value: f64,
    /// ± on `value`.
    pub precision: f64,
    /// How `precision` is known (continuation tolerance, grid step, bisection bracket...).
    pub precision_from: String,
    pub verdict: Verdict,
    /// `value` − `paper_value`, where both are numbers of the same quantity.
    pub difference: Option<f64>,
    /// One line: why the verdict.
    pub note: String,
}

/// Why a claim could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReproduceError {
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
    #[error(transparent)]
    Continuation(#[from] ContinuationError),
    #[error(transparent)]
    Param(#[from] ParamError),
    /// A computation did not find what the claim is about (an attractor, a branch, a fold).
    #[error("{claim}: {what}")]
    NotFound { claim: &'static str, what: String },
}

impl ReproduceError {
    fn not_found(claim: &'static str, what: impl Into<String>) -> Self {
        ReproduceError::NotFound {
            claim,
            what: what.into(),
        }
    }
}

/// Every claim, computed in `mode` on the current rayon pool; `on_claim` sees each as soon
/// as it is known (in the order of the returned list).
pub fn reproduce(
    mode: Mode,
    progress: &Progress,
    on_claim: impl FnMut(&Claim),
) -> Result<Vec<Claim>, ReproduceError> {
    let grids = mode.grids();
    let mut out = Claims {
        claims: Vec::new(),
        on_claim,
    };
    responses::drive_claims(&mut out)?;
    let seeds = responses::coexisting_claims(&grids, progress, &mut out)?;
    branches::branch_claims(&grids, &seeds, progress, &mut out)?;
    branches::collision_claim(&grids, &seeds, progress, &mut out)?;
    responses::subharmonic_elsewhere_claims(&grids, progress, &mut out)?;
    Ok(out.claims)
}

/// The claims computed so far, each shown to the caller as it is added.
struct Claims<F: FnMut(&Claim)> {
    claims: Vec<Claim>,
    on_claim: F,
}

/// Where a group of claims puts each one.
trait Sink {
    fn push(&mut self, claim: Claim);
}

impl<F: FnMut(&Claim)> Sink for Claims<F> {
    fn push(&mut self, claim: Claim) {
        (self.on_claim)(&claim);
        self.claims.push(claim);
    }
}

/// The verdict on a number the paper rounds: agrees if isola's value lies within the
/// paper's half-unit of its last digit (`paper_precision`) plus isola's own precision.
fn numeric_verdict(value: f64, precision: f64, paper: f64, paper_precision: f64) -> Verdict {
    if (value - paper).abs() <= paper_precision + precision {
        Verdict::Agrees
    } else {
        Verdict::Differs
    }
}

/// `Agrees` if `holds`, else `Differs`.
fn holds(holds: bool) -> Verdict {
    if holds {
        Verdict::Agrees
    } else {
        Verdict::Differs
    }
}
