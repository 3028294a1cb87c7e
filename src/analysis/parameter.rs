//! The parameters an analysis can vary: a family's model parameter, and ω_e or a model
//! parameter for a continuation, a map or a response against a parameter. The built-in
//! model's have names of their own; a written model's are named as the model names them.

use serde::{Deserialize, Serialize};

use crate::model::error::ParamError;
use crate::model::{DriveSpec, ParamSpec, Params};

/// The built-in model's parameters an analysis can vary, as the errors list them.
pub const BUILT_IN_PARAMETERS: &str = "omega, adr, e_a, c_tilde, lambda_p, j";

/// Longest name of a written model's parameter that an analysis can vary.
pub const MAX_NAME: usize = 46;

/// The name of a written model's parameter, held inline (so that it is `Copy`).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Name {
    len: u8,
    bytes: [u8; MAX_NAME],
}

impl Name {
    /// `s` if it is a name a model can give (letters, digits and `_`, not starting with a
    /// digit, at most [`MAX_NAME`] bytes).
    pub fn new(s: &str) -> Option<Name> {
        let ok = !s.is_empty()
            && s.len() <= MAX_NAME
            && s.chars().all(|c| c.is_alphanumeric() || c == '_')
            && !s.starts_with(|c: char| c.is_ascii_digit());
        ok.then(|| {
            let mut bytes = [0; MAX_NAME];
            bytes[..s.len()].copy_from_slice(s.as_bytes());
            Name {
                len: s.len() as u8,
                bytes,
            }
        })
    }

    pub fn as_str(&self) -> &str {
        std::str::from_utf8(&self.bytes[..self.len as usize]).expect("built from a str")
    }
}

impl std::fmt::Debug for Name {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:?}", self.as_str())
    }
}

/// The parameters a family can vary: the built-in model's, or a written model's by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum FamilyParameter {
    Adr,
    EA,
    CTilde,
    LambdaP,
    J,
    /// A written model's parameter.
    Named(Name),
}

impl FamilyParameter {
    pub fn name(&self) -> &str {
        match self {
            FamilyParameter::Adr => "adr",
            FamilyParameter::EA => "e_a",
            FamilyParameter::CTilde => "c_tilde",
            FamilyParameter::LambdaP => "lambda_p",
            FamilyParameter::J => "j",
            FamilyParameter::Named(n) => n.as_str(),
        }
    }

    /// Parses a name as users write it: the built-in model's names, else any name a
    /// written model may give a parameter.
    pub fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "adr" => FamilyParameter::Adr,
            "e_a" => FamilyParameter::EA,
            "c_tilde" => FamilyParameter::CTilde,
            "lambda_p" => FamilyParameter::LambdaP,
            "j" => FamilyParameter::J,
            _ => FamilyParameter::Named(Name::new(s)?),
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
            FamilyParameter::Named(n) => return Err(not_built_in(n.as_str())),
        }
        spec.build()
    }

    /// An error unless the built-in model has this parameter.
    pub fn check_built_in(&self) -> Result<(), ParamError> {
        match self {
            FamilyParameter::Named(n) => Err(not_built_in(n.as_str())),
            _ => Ok(()),
        }
    }
}

/// The error for a parameter the built-in model does not have.
fn not_built_in(name: &str) -> ParamError {
    ParamError {
        field: format!("parameter `{name}`"),
        value: ParamError::NOT_NUMERIC,
        allowed: match BUILT_IN_PARAMETERS.strip_prefix("omega, ") {
            // each member of a family is a response over ω already
            Some(others) if name == "omega" => {
                format!("one of the built-in model's but omega, which each member spans: {others}")
            }
            _ => format!("one of the built-in model's: {BUILT_IN_PARAMETERS}"),
        },
    }
}

impl TryFrom<String> for FamilyParameter {
    type Error = String;
    fn try_from(s: String) -> Result<Self, String> {
        Self::parse(&s).ok_or_else(|| unknown(&s))
    }
}

impl From<FamilyParameter> for String {
    fn from(p: FamilyParameter) -> String {
        p.name().to_string()
    }
}

/// The error for a text that cannot name a parameter.
fn unknown(s: &str) -> String {
    format!(
        "unknown parameter '{s}': allowed {BUILT_IN_PARAMETERS}, or a written model's \
         parameter (a name of at most {MAX_NAME} letters, digits and _)"
    )
}

/// The parameter a branch is continued in: ω_e or one of the model's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum ContinuationParameter {
    Omega,
    Model(FamilyParameter),
}

impl ContinuationParameter {
    pub fn name(&self) -> &str {
        match self {
            ContinuationParameter::Omega => "omega",
            ContinuationParameter::Model(p) => p.name(),
        }
    }

    /// Parses a name as users write it (`omega`, `adr`, `e_a`, `c_tilde`, `lambda_p`, `j`,
    /// or a written model's parameter).
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "omega" => Some(ContinuationParameter::Omega),
            _ => FamilyParameter::parse(s).map(ContinuationParameter::Model),
        }
    }

    /// An error unless the built-in model has this parameter.
    pub fn check_built_in(&self) -> Result<(), ParamError> {
        match self {
            ContinuationParameter::Omega => Ok(()),
            ContinuationParameter::Model(m) => m.check_built_in(),
        }
    }

    /// Its value in `p` (NaN for a parameter the built-in model does not have).
    pub fn value(&self, p: &Params) -> f64 {
        match self {
            ContinuationParameter::Omega => p.omega(),
            ContinuationParameter::Model(m) => match m {
                FamilyParameter::Adr => p.drive_i().adr().unwrap_or(0.0),
                FamilyParameter::EA => p.drive_i().e_a(),
                FamilyParameter::CTilde => p.c_tilde(),
                FamilyParameter::LambdaP => p.lambda_p(),
                FamilyParameter::J => p.j(),
                FamilyParameter::Named(_) => f64::NAN,
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
        Self::parse(&s).ok_or_else(|| unknown(&s))
    }
}

impl From<ContinuationParameter> for String {
    fn from(p: ContinuationParameter) -> String {
        p.name().to_string()
    }
}
