//! The hunt across a parameter family: at each value of one model parameter, the subharmonic
//! branches of the frequency response continued in ω_e and told apart (isola, attached); the
//! values between which the picture changes bracket where an isola is born or merges.

use serde::{Deserialize, Serialize};

use crate::analysis::AnalysisError;
use crate::analysis::continuation::hunt::{HuntSpec, HuntedBranch, Verdict, hunt};
use crate::analysis::continuation::model::Continuable;
use crate::analysis::parameter::{ContinuationParameter, FamilyParameter};
use crate::analysis::progress::Progress;
use crate::model::error::ParamError;

/// A hunt per value of `parameter`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HuntFamilySpec {
    pub parameter: FamilyParameter,
    pub values: Vec<f64>,
    #[serde(default)]
    pub hunt: HuntSpec,
}

impl HuntFamilySpec {
    /// Checks the values (1 to 1000, increasing, each a valid model with `base`) and the hunt.
    pub fn validate<M: Continuable>(&self, base: &M) -> Result<(), ParamError> {
        let increasing = self.values.windows(2).all(|w| w[1] > w[0]);
        if self.values.is_empty() || self.values.len() > 1000 || !increasing {
            return Err(ParamError {
                field: "values".into(),
                value: self.values.len() as f64,
                allowed: "1 to 1000 increasing values".into(),
            });
        }
        let parameter = base.resolve(ContinuationParameter::Model(self.parameter))?;
        for &v in &self.values {
            let p = base
                .with(parameter, v)
                .map_err(|e| e.as_value_of("values"))?;
            self.hunt.validate(&p)?;
        }
        Ok(())
    }
}

/// The hunted branches at one value of the family.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HuntMember {
    pub value: f64,
    pub branches: Vec<HuntedBranch>,
}

impl HuntMember {
    /// The verdict of the period-`k` branch with the largest peak, if there is one.
    pub fn verdict(&self, k: usize) -> Option<Verdict> {
        self.branches
            .iter()
            .filter(|b| b.branch.period == k)
            .max_by(|a, b| a.peak_amplitude.total_cmp(&b.peak_amplitude))
            .map(|b| b.verdict)
    }
}

/// Between two adjacent values the period-k picture changes: `before` → `after` (`None`: no
/// such branch).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Transition {
    pub period: usize,
    pub from: f64,
    pub to: f64,
    pub before: Option<Verdict>,
    pub after: Option<Verdict>,
}

impl Transition {
    /// What happens, in one word: `birth`, `vanishing`, `merging`, `detaching`, or `change`
    /// for any other pair of verdicts.
    pub fn event(&self) -> &'static str {
        match (self.before, self.after) {
            (None, Some(Verdict::Isola)) => "birth",
            (Some(Verdict::Isola), None) => "vanishing",
            (Some(Verdict::Isola), Some(Verdict::Attached | Verdict::HalfAttached)) => "merging",
            (Some(Verdict::Attached | Verdict::HalfAttached), Some(Verdict::Isola)) => "detaching",
            _ => "change",
        }
    }

    /// `1:2 isola born between adr 0.2 and 0.3`, `... merges ...`.
    pub fn describe(&self, parameter: &str) -> String {
        let what = match (self.before, self.after) {
            (None, Some(Verdict::Isola)) => "an isola is born".to_string(),
            (Some(Verdict::Isola), None) => "the isola vanishes".to_string(),
            (Some(Verdict::Isola), Some(Verdict::Attached | Verdict::HalfAttached)) => {
                "the isola merges with the main branch".to_string()
            }
            (Some(Verdict::Attached | Verdict::HalfAttached), Some(Verdict::Isola)) => {
                "the branch detaches into an isola".to_string()
            }
            (a, b) => format!(
                "{} → {}",
                a.map_or("none", |v| v.as_str()),
                b.map_or("none", |v| v.as_str())
            ),
        };
        format!(
            "1:{}: {what} between {parameter} {} and {}",
            self.period, self.from, self.to
        )
    }
}

/// Runs the hunt at each value in turn (each on the whole pool).
pub fn hunt_family<M: Continuable>(
    params: &M,
    spec: &HuntFamilySpec,
    progress: &Progress,
    mut on_member: impl FnMut(&HuntMember),
) -> Result<Vec<HuntMember>, AnalysisError> {
    spec.validate(params)?;
    let parameter = params.resolve(ContinuationParameter::Model(spec.parameter))?;
    spec.values
        .iter()
        .map(|&value| {
            let p = params.with(parameter, value)?;
            let found = hunt(&p, &spec.hunt, progress)?;
            let member = HuntMember {
                value,
                branches: found.branches,
            };
            on_member(&member);
            Ok(member)
        })
        .collect()
}

/// Where the verdict of each subharmonic period changes between adjacent members.
pub fn transitions(members: &[HuntMember]) -> Vec<Transition> {
    let mut periods: Vec<usize> = members
        .iter()
        .flat_map(|m| m.branches.iter().map(|b| b.branch.period))
        .collect();
    periods.sort_unstable();
    periods.dedup();
    let mut out = Vec::new();
    for k in periods {
        for w in members.windows(2) {
            let (before, after) = (w[0].verdict(k), w[1].verdict(k));
            if before != after {
                out.push(Transition {
                    period: k,
                    from: w[0].value,
                    to: w[1].value,
                    before,
                    after,
                });
            }
        }
    }
    out
}
