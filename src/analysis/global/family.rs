//! Fig 7–12: a frequency response for each value of one model parameter, summarised by the
//! branches that exist at each value.

use serde::{Deserialize, Serialize};

use crate::analysis::AnalysisError;
use crate::analysis::Oscillator;
use crate::analysis::global::frequency_response::{
    Branch, FrequencyResponse, FrequencyResponseSpec, Work, frequency_response_over,
};
use crate::analysis::parameter::ContinuationParameter;
use crate::analysis::parameter::FamilyParameter;
use crate::analysis::progress::Progress;
use crate::model::error::ParamError;

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
        self.response.branches.iter().filter(|b| b.is_subharmonic())
    }
}

impl FamilySpec {
    /// Checks the values (1 to 1000, each a valid model with `base`) and the response.
    pub fn validate<O: Oscillator>(&self, base: &O) -> Result<(), ParamError> {
        let parameter = base.resolve(ContinuationParameter::Model(self.parameter))?;
        if self.values.is_empty() || self.values.len() > 1000 {
            return Err(ParamError {
                field: "values".into(),
                value: self.values.len() as f64,
                allowed: "1 to 1000 values".into(),
            });
        }
        for &v in &self.values {
            base.with(parameter, v)
                .map_err(|e| e.as_value_of("values"))?;
        }
        self.response.validate().map_err(|e| e.within("response"))
    }
}

/// Member `i` of the family: the frequency response at the i-th value (on the whole pool);
/// its work, [`FrequencyResponseSpec::work`], is announced on `progress` by the caller.
pub fn family_member<O: Oscillator>(
    params: &O,
    spec: &FamilySpec,
    i: usize,
    progress: &Progress,
) -> Result<FamilyMember, AnalysisError> {
    let value = spec.values[i];
    let p = params.with(
        params.resolve(ContinuationParameter::Model(spec.parameter))?,
        value,
    )?;
    let response =
        frequency_response_over(&p, &spec.response, p.frequency(), progress, Work::Announced)?;
    Ok(FamilyMember { value, response })
}

/// Runs the frequency response of each member in turn (each on the whole pool), their work
/// announced together at the start.
pub fn family<O: Oscillator>(
    params: &O,
    spec: &FamilySpec,
    progress: &Progress,
    mut on_member: impl FnMut(&FamilyMember),
) -> Result<Vec<FamilyMember>, AnalysisError> {
    spec.validate(params)?;
    progress.grow_total(spec.values.len() * spec.response.work());
    (0..spec.values.len())
        .map(|i| {
            let member = family_member(params, spec, i, progress)?;
            on_member(&member);
            Ok(member)
        })
        .collect()
}
