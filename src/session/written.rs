//! A session whose `[model]` writes its own equations: the definition read with where each
//! expression is (for errors with line and column), compiled once, and the analyses'
//! `model = { NAME = value }` overrides of its parameters.

use std::collections::BTreeMap;

use crate::model::equations::{EquationModel, EquationSystem, ModelDefinition};
use crate::model::{ParamError, Params};

/// A written model as a session holds it.
#[derive(Debug, Clone)]
pub struct WrittenModel {
    pub definition: ModelDefinition,
    pub model: EquationModel,
}

/// The model of one analysis: the built-in DEA, or the session's written model at its values.
#[derive(Debug, Clone)]
pub enum ModelPoint {
    BuiltIn(Params),
    Written(EquationSystem),
}

/// The kinds only the built-in DEA runs (its force curves); a written model runs every other
/// kind.
pub const DEA_ONLY_KINDS: [&str; 1] = ["force_curve"];

/// Whether `text`'s `[model]` writes equations (has `states`).
pub fn writes_equations(table: &toml::Table) -> bool {
    table
        .get("model")
        .and_then(|m| m.as_table())
        .is_some_and(|m| m.contains_key("states"))
}

/// `table` without its `[model]` and without each analysis' `model`, which are returned:
/// the overrides as name → value, in analysis order. A value that is not a number is an
/// error naming the analysis and the key.
pub fn take_written_parts(table: &mut toml::Table) -> Result<Vec<BTreeMap<String, f64>>, String> {
    table.remove("model");
    let mut overrides = Vec::new();
    let Some(toml::Value::Array(analyses)) = table.get_mut("analysis") else {
        return Ok(overrides);
    };
    for analysis in analyses {
        let name = analysis
            .get("name")
            .and_then(|n| n.as_str())
            .unwrap_or("?")
            .to_string();
        let mut values = BTreeMap::new();
        if let Some(t) = analysis.as_table_mut()
            && let Some(model) = t.remove("model")
        {
            let toml::Value::Table(model) = model else {
                return Err(format!(
                    "analysis '{name}': model must be a table of values"
                ));
            };
            for (key, value) in model {
                let number = match value {
                    toml::Value::Float(v) => v,
                    toml::Value::Integer(i) => i as f64,
                    other => {
                        return Err(format!(
                            "analysis '{name}' model: {key} = {other} is not a number"
                        ));
                    }
                };
                values.insert(key, number);
            }
        }
        overrides.push(values);
    }
    Ok(overrides)
}

impl WrittenModel {
    /// Reads and compiles the `[model]` of session text `text`.
    pub fn read(text: &str) -> Result<WrittenModel, String> {
        let definition = ModelDefinition::from_text(text).map_err(|e| format!("[model]: {e}"))?;
        let model = EquationModel::new(&definition, text).map_err(|e| e.to_string())?;
        Ok(WrittenModel { definition, model })
    }

    /// The parameter values under `overrides` (names checked at load), the defaults for the
    /// rest.
    pub fn values(&self, overrides: &BTreeMap<String, f64>) -> Vec<f64> {
        let mut values = self.model.defaults();
        for (name, &v) in overrides {
            if let Some(i) = self.model.parameter(name) {
                values[i] = v;
            }
        }
        values
    }

    /// The model at `overrides`, checked.
    pub fn system(&self, overrides: &BTreeMap<String, f64>) -> Result<EquationSystem, ParamError> {
        self.model.system(&self.values(overrides))
    }

    /// What of the model a fingerprint holds: the definition and the parameter values,
    /// without those the analysis does not read (`omega` stands for the frequency parameter).
    pub fn fingerprint_model(
        &self,
        overrides: &BTreeMap<String, f64>,
        used: &crate::session::schema::ModelUse,
    ) -> serde_json::Value {
        use crate::session::schema::ModelUse;
        let frequency = self.model.frequency_name();
        let all: BTreeMap<&str, f64> = self
            .model
            .parameters()
            .iter()
            .zip(self.values(overrides))
            .map(|(p, v)| (p.name.as_str(), v))
            .collect();
        let mut values = all.clone();
        match used {
            ModelUse::All => {}
            ModelUse::AllBut(keys) => {
                for key in keys {
                    values.remove(if key == "omega" {
                        frequency
                    } else {
                        key.as_str()
                    });
                }
            }
            ModelUse::Nothing => values.clear(),
        }
        // the values as written of the parameters left out go too: the analysis sets them
        let mut equations = serde_json::json!(self.definition);
        for name in all.keys().filter(|name| !values.contains_key(*name)) {
            if let Some(p) = equations["parameters"].get_mut(*name) {
                match p.as_object_mut() {
                    Some(full) => drop(full.remove("value")),
                    None => *p = serde_json::Value::Null,
                }
            }
        }
        serde_json::json!({
            "equations": equations,
            "values": values,
            "numerics": crate::model::equations::NUMERICS_VERSION,
        })
    }

    /// An error for an override that names no parameter, if any.
    pub fn unknown_override(&self, overrides: &BTreeMap<String, f64>) -> Option<String> {
        let names: Vec<&str> = self
            .model
            .parameters()
            .iter()
            .map(|p| p.name.as_str())
            .collect();
        overrides
            .keys()
            .find(|k| !names.contains(&k.as_str()))
            .map(|k| {
                format!(
                    "`{k}` is not a parameter of the model (its parameters: {})",
                    names.join(", ")
                )
            })
    }
}
