//! Fig 7–12: a frequency response for each value of one model parameter, summarised by the
//! branches that exist at each value.

use serde::{Deserialize, Serialize};

use super::AnalysisError;
use super::frequency_response::{
    Branch, FrequencyResponse, FrequencyResponseSpec, frequency_response,
};
use super::progress::Progress;
use crate::model::error::ParamError;
use crate::model::{DriveSpec, ParamSpec, Params};

/// The parameters a family can vary.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FamilyParameter {
    Adr,
    EA,
    CTilde,
    LambdaP,
    J,
}

impl FamilyParameter {
    pub fn name(&self) -> &'static str {
        match self {
            FamilyParameter::Adr => "adr",
            FamilyParameter::EA => "e_a",
            FamilyParameter::CTilde => "c_tilde",
            FamilyParameter::LambdaP => "lambda_p",
            FamilyParameter::J => "j",
        }
    }

    /// Parses a name as users write it.
    pub fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "adr" => FamilyParameter::Adr,
            "e_a" | "ea" => FamilyParameter::EA,
            "c_tilde" | "damping" => FamilyParameter::CTilde,
            "lambda_p" | "lambda-p" => FamilyParameter::LambdaP,
            "j" => FamilyParameter::J,
            _ => return None,
        })
    }

    /// `base` with this parameter set to `value` (the drive kept in (E_a, ADR) form).
    pub fn apply(&self, base: &Params, value: f64) -> Result<Params, ParamError> {
        let mut spec: ParamSpec = base.to_spec();
        let d = base.drive_i();
        let (e_a, adr) = (d.e_a(), d.adr().unwrap_or(0.0));
        match self {
            FamilyParameter::Adr => spec.drive = DriveSpec::EaAdr { e_a, adr: value },
            FamilyParameter::EA => spec.drive = DriveSpec::EaAdr { e_a: value, adr },
            FamilyParameter::CTilde => spec.c_tilde = value,
            FamilyParameter::LambdaP => spec.lambda_p = value,
            FamilyParameter::J => spec.j = value,
        }
        spec.build()
    }
}

/// A family: one parameter over a list of values.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FamilySpec {
    pub parameter: FamilyParameter,
    pub values: Vec<f64>,
    #[serde(default)]
    pub response: FrequencyResponseSpec,
}

/// One member of the family.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FamilyMember {
    pub value: f64,
    pub response: FrequencyResponse,
}

impl FamilyMember {
    /// The subharmonic branches (period ≥ 2) at this value.
    pub fn subharmonic_branches(&self) -> impl Iterator<Item = &Branch> {
        self.response.branches.iter().filter(|b| b.period >= 2)
    }
}

/// Runs the frequency response of each member in turn (each on the whole pool).
pub fn family(
    params: &Params,
    spec: &FamilySpec,
    progress: &Progress,
    mut on_member: impl FnMut(&FamilyMember),
) -> Result<Vec<FamilyMember>, AnalysisError> {
    if spec.values.is_empty() || spec.values.len() > 1000 {
        return Err(ParamError {
            field: "values",
            value: spec.values.len() as f64,
            allowed: "1 to 1000 values".into(),
        }
        .into());
    }
    let members: Vec<Params> = spec
        .values
        .iter()
        .map(|&v| spec.parameter.apply(params, v))
        .collect::<Result<_, _>>()?;
    let mut out = Vec::with_capacity(members.len());
    for (p, &value) in members.iter().zip(&spec.values) {
        // each member announces its own work on the shared progress as it starts
        let response = frequency_response(p, &spec.response, progress)?;
        let member = FamilyMember { value, response };
        on_member(&member);
        out.push(member);
    }
    Ok(out)
}
