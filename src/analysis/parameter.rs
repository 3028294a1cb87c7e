//! The parameters an analysis can vary: a family's model parameter, and ω_e or a model
//! parameter for a continuation, a map or a response against a parameter.

use serde::{Deserialize, Serialize};

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

/// The parameter a branch is continued in: ω_e or one of the model's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum ContinuationParameter {
    Omega,
    Model(FamilyParameter),
}

impl ContinuationParameter {
    pub fn name(&self) -> &'static str {
        match self {
            ContinuationParameter::Omega => "omega",
            ContinuationParameter::Model(p) => p.name(),
        }
    }

    /// Parses a name as users write it (`omega`, `adr`, `e_a`, `c_tilde`, `lambda_p`, `j`).
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "omega" | "w" => Some(ContinuationParameter::Omega),
            _ => FamilyParameter::parse(s).map(ContinuationParameter::Model),
        }
    }

    /// Its value in `p`.
    pub fn value(&self, p: &Params) -> f64 {
        match self {
            ContinuationParameter::Omega => p.omega(),
            ContinuationParameter::Model(m) => match m {
                FamilyParameter::Adr => p.drive_i().adr().unwrap_or(0.0),
                FamilyParameter::EA => p.drive_i().e_a(),
                FamilyParameter::CTilde => p.c_tilde(),
                FamilyParameter::LambdaP => p.lambda_p(),
                FamilyParameter::J => p.j(),
            },
        }
    }

    /// `base` with this parameter set to `value`.
    pub fn apply(&self, base: &Params, value: f64) -> Result<Params, ParamError> {
        match self {
            ContinuationParameter::Omega => base.with_omega(value),
            ContinuationParameter::Model(m) => m.apply(base, value),
        }
    }
}

impl TryFrom<String> for ContinuationParameter {
    type Error = String;
    fn try_from(s: String) -> Result<Self, String> {
        Self::parse(&s).ok_or_else(|| {
            format!("unknown parameter '{s}': allowed omega, adr, e_a, c_tilde, lambda_p, j")
        })
    }
}

impl From<ContinuationParameter> for String {
    fn from(p: ContinuationParameter) -> String {
        p.name().to_string()
    }
}
