//! The `[model]` table of a session that writes its own equations, as read from TOML.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use toml::Spanned;

/// A model written as equations. Keys follow the TOML (`model.let.g_I`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelDefinition {
    /// A short name for the model.
    #[serde(default)]
    pub name: Option<String>,
    /// The state variables, in order (at most [`crate::model::system::MAX_DIM`]).
    pub states: Vec<String>,
    /// The parameter that is the forcing frequency ω: the forcing period is 2π/ω.
    pub frequency: String,
    /// The output whose max − min over a response period is the amplitude.
    pub amplitude: Spanned<String>,
    /// The two states the basin and response grids span, as offsets from the `origin` (the
    /// others start at the origin). The first two states by default.
    #[serde(default)]
    pub grid: Option<Vec<String>>,
    /// Conditions that end a trajectory as a collision (`"lambda_I <= 0"`).
    #[serde(default)]
    pub collision: Vec<Spanned<String>>,
    /// The state the grids are laid out around, and from which the states off the grid
    /// start: an expression of the parameters per state (0 for states not named).
    #[serde(default)]
    pub origin: BTreeMap<String, Spanned<String>>,
    pub parameters: BTreeMap<String, ParameterDefinition>,
    /// Named intermediate expressions.
    #[serde(default, rename = "let")]
    pub lets: BTreeMap<String, Spanned<String>>,
    /// Functions of their arguments: `"g(lam)" = "..."`.
    #[serde(default)]
    pub functions: BTreeMap<String, Spanned<String>>,
    /// dx/dτ of each state.
    pub derivatives: BTreeMap<String, Spanned<String>>,
}

/// A parameter: a value, or a value with its allowed range, unit and meaning.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum ParameterDefinition {
    Value(f64),
    Full(ParameterTable),
}

/// A parameter's table form; its keys are checked (`mni = 0` is named, not ignored).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParameterTable {
    pub value: f64,
    #[serde(default)]
    pub min: Option<f64>,
    #[serde(default)]
    pub max: Option<f64>,
    #[serde(default)]
    pub unit: Option<String>,
    #[serde(default)]
    pub about: Option<String>,
}

impl<'de> Deserialize<'de> for ParameterDefinition {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        match toml::Value::deserialize(d)? {
            table @ toml::Value::Table(_) => ParameterTable::deserialize(table)
                .map(ParameterDefinition::Full)
                .map_err(|e| D::Error::custom(e.message().trim_end().trim_end_matches('.'))),
            v @ (toml::Value::Float(_) | toml::Value::Integer(_)) => f64::deserialize(v)
                .map(ParameterDefinition::Value)
                .map_err(D::Error::custom),
            other => Err(D::Error::custom(format!(
                "a parameter is a number or {{ value, min, max, unit, about }}, not a {}",
                other.type_str()
            ))),
        }
    }
}

impl ParameterDefinition {
    pub fn value(&self) -> f64 {
        match self {
            ParameterDefinition::Value(v) => *v,
            ParameterDefinition::Full(p) => p.value,
        }
    }

    /// The allowed range [min, max] (unbounded where not given).
    pub fn range(&self) -> (f64, f64) {
        match self {
            ParameterDefinition::Value(_) => (f64::NEG_INFINITY, f64::INFINITY),
            ParameterDefinition::Full(p) => (
                p.min.unwrap_or(f64::NEG_INFINITY),
                p.max.unwrap_or(f64::INFINITY),
            ),
        }
    }

    pub fn unit(&self) -> Option<&str> {
        match self {
            ParameterDefinition::Full(p) => p.unit.as_deref(),
            ParameterDefinition::Value(_) => None,
        }
    }

    pub fn about(&self) -> Option<&str> {
        match self {
            ParameterDefinition::Full(p) => p.about.as_deref(),
            ParameterDefinition::Value(_) => None,
        }
    }
}

/// A session's text read for its `[model]` alone, keeping where each expression is.
#[derive(Deserialize)]
struct Document {
    model: ModelDefinition,
}

impl ModelDefinition {
    /// The `[model]` table of a session's text that writes its equations, read with where
    /// each expression is.
    pub fn from_text(text: &str) -> Result<ModelDefinition, toml::de::Error> {
        toml::from_str::<Document>(text).map(|d| d.model)
    }
}

/// Where an expression's text starts in the document it was read from, if its characters
/// are the document's (a string without escapes); spans are byte offsets into `doc`.
pub fn expression_start(doc: &str, value: &Spanned<String>) -> Option<usize> {
    let raw = doc.get(value.span())?;
    for quote in ["\"\"\"", "'''", "\"", "'"] {
        if let Some(inner) = raw.strip_prefix(quote).and_then(|r| r.strip_suffix(quote)) {
            let skip = quote.len() + usize::from(quote.len() == 3 && inner.starts_with('\n'));
            let content = &raw[skip..raw.len() - quote.len()];
            return (content == value.get_ref().as_str()).then_some(value.span().start + skip);
        }
    }
    None
}

/// Line and column (from 1, in characters) of byte `offset` in `doc`.
pub fn line_column(doc: &str, offset: usize) -> (usize, usize) {
    let before = &doc[..offset.min(doc.len())];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    (line, before[line_start..].chars().count() + 1)
}
