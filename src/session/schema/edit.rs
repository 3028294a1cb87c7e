//! Editing a session in place: model keys and settings set in its TOML document, with its
//! comments and layout kept and the result validated again; and saving it.

use std::path::Path;

use crate::analysis::orbit::chirp_sweep::ChirpSpec;
use crate::analysis::orbit::scalogram::ScalogramSpec;

use super::{Session, SessionError, Settings};

impl Session {
    /// Sets model key `key` for analysis `index` (comments and layout kept, then re-validated):
    /// in the analysis' own `model` table if it overrides that key, in `[model]` otherwise (or
    /// always, for `None`). The other form of the same quantity (`omega` and `frequency_hz`,
    /// ...) is removed from that table.
    pub fn set_model_key(
        &mut self,
        index: Option<usize>,
        key: &str,
        value: f64,
    ) -> Result<(), SessionError> {
        let overridden = index.is_some_and(|i| {
            self.document
                .get("analysis")
                .and_then(|a| a.as_array_of_tables())
                .and_then(|a| a.get(i))
                .and_then(|t| t.get("model"))
                .and_then(|m| m.as_table_like())
                .is_some_and(|m| same_quantity(key).iter().any(|k| m.contains_key(k)))
        });
        let mut document = self.document.clone();
        if self.written.is_some() && !overridden {
            set_written_parameter(&mut document, key, value).map_err(|message| {
                SessionError::Syntax {
                    path: self.path.clone(),
                    message,
                }
            })?;
            return self.replace_document(document);
        }
        let table: &mut dyn toml_edit::TableLike = match index {
            Some(i) if overridden => document["analysis"]
                .as_array_of_tables_mut()
                .and_then(|a| a.get_mut(i))
                .and_then(|t| t.get_mut("model"))
                .and_then(|m| m.as_table_like_mut())
                .expect("checked above"),
            _ => {
                if !document.contains_key("model") {
                    document["model"] = toml_edit::table();
                }
                document["model"]
                    .as_table_like_mut()
                    .ok_or_else(|| SessionError::Syntax {
                        path: self.path.clone(),
                        message: "[model] is not a table".into(),
                    })?
            }
        };
        put_model_key(table, key, value);
        self.replace_document(document)
    }

    /// The `[[analysis]]` table number `index` of `document`.
    fn analysis_table_mut<'d>(
        &self,
        document: &'d mut toml_edit::DocumentMut,
        index: usize,
    ) -> Result<&'d mut toml_edit::Table, SessionError> {
        document["analysis"]
            .as_array_of_tables_mut()
            .and_then(|a| a.get_mut(index))
            .ok_or_else(|| SessionError::Syntax {
                path: self.path.clone(),
                message: format!("no analysis number {index}"),
            })
    }

    /// Sets model key `key` for analysis `index` only: in its own `model` table (made if it
    /// has none), so the session's model and the other analyses keep theirs.
    pub fn override_model_key(
        &mut self,
        index: usize,
        key: &str,
        value: f64,
    ) -> Result<(), SessionError> {
        let mut document = self.document.clone();
        let table = self.analysis_table_mut(&mut document, index)?;
        if !table.contains_key("model") {
            table.insert(
                "model",
                toml_edit::Item::Value(toml_edit::Value::InlineTable(Default::default())),
            );
        }
        let model = table["model"]
            .as_table_like_mut()
            .ok_or_else(|| SessionError::Syntax {
                path: self.path.clone(),
                message: format!("analysis {index}: model is not a table"),
            })?;
        put_model_key(model, key, value);
        self.replace_document(document)
    }

    /// The settings of analysis `index` as a TOML table, every default filled in.
    pub fn settings_table(&self, index: usize) -> toml::Table {
        self.analyses
            .get(index)
            .and_then(|e| e.settings.to_toml().ok())
            .unwrap_or_default()
    }

    /// The settings of analysis `index` with the optional tables it does not have filled in
    /// at their defaults (a chirp sweep's `scalogram`): what can be set in it.
    pub fn settings_offered(&self, index: usize) -> toml::Table {
        let mut table = self.settings_table(index);
        if let Some(Settings::ChirpSweep(ChirpSpec {
            scalogram: None, ..
        })) = self.analyses.get(index).map(|e| &e.settings)
            && let Ok(default) = toml::Table::try_from(ScalogramSpec::default())
        {
            table.insert("scalogram".into(), toml::Value::Table(default));
        }
        table
    }

    /// Sets the setting at `path` (e.g. `["omega", "points"]`) of analysis `index`; a table on
    /// the way that the file leaves to its defaults, or leaves out (an optional `scalogram`),
    /// is written out in full first.
    pub fn set_setting(
        &mut self,
        index: usize,
        path: &[&str],
        value: toml::Value,
    ) -> Result<(), SessionError> {
        let full = self.settings_offered(index);
        let mut document = self.document.clone();
        let analysis = self.analysis_table_mut(&mut document, index)?;
        if !analysis.contains_key("settings") {
            analysis.insert("settings", toml_edit::table());
        }
        let mut table: &mut dyn toml_edit::TableLike = analysis["settings"]
            .as_table_like_mut()
            .ok_or_else(|| SessionError::Syntax {
                path: self.path.clone(),
                message: "settings is not a table".into(),
            })?;
        let mut defaults = Some(&full);
        let (leaf, parents) = path.split_last().ok_or_else(|| SessionError::Syntax {
            path: self.path.clone(),
            message: "empty setting path".into(),
        })?;
        for key in parents {
            let default = defaults.and_then(|d| d.get(*key));
            defaults = default.and_then(|d| d.as_table());
            if !table.contains_key(key) {
                let filled = default
                    .cloned()
                    .unwrap_or(toml::Value::Table(Default::default()));
                table.insert(key, toml_edit::Item::Value(to_edit_value(&filled)));
            }
            table = table
                .get_mut(key)
                .and_then(|i| i.as_table_like_mut())
                .ok_or_else(|| SessionError::Syntax {
                    path: self.path.clone(),
                    message: format!("setting '{key}' is not a table"),
                })?;
        }
        table.insert(leaf, toml_edit::Item::Value(to_edit_value(&value)));
        self.replace_document(document)
    }

    /// The session's text as it will be saved.
    pub fn to_text(&self) -> String {
        self.document.to_string()
    }

    /// Saves atomically to `path` (and makes it this session's path).
    pub fn save_as(&mut self, path: &Path) -> Result<(), SessionError> {
        crate::session::atomic::write_atomic(path, self.to_text().as_bytes()).map_err(|error| {
            SessionError::Io {
                path: path.to_path_buf(),
                error,
            }
        })?;
        self.path = path.to_path_buf();
        Ok(())
    }
}

/// The keys a quantity may be written under (its non-dimensional and physical forms).
fn same_quantity(key: &str) -> &'static [&'static str] {
    const FORMS: [&[&str]; 4] = [
        &["omega", "frequency_hz"],
        &["c_tilde", "damping_n_s_per_m"],
        &["phi_dc", "dc_kv"],
        &["phi_ac", "ac_kv"],
    ];
    const OTHERS: [&str; 7] = [
        "lambda_p",
        "j",
        "e_a",
        "adr",
        "phi_dc_ii",
        "phi_ac_ii",
        "phase_ii",
    ];
    FORMS
        .iter()
        .find(|f| f.contains(&key))
        .copied()
        .or_else(|| {
            OTHERS
                .iter()
                .position(|k| *k == key)
                .map(|i| &OTHERS[i..=i])
        })
        .unwrap_or(&[])
}

/// A TOML value in `toml_edit`'s form (tables become inline tables).
fn to_edit_value(value: &toml::Value) -> toml_edit::Value {
    match value {
        toml::Value::String(s) => s.as_str().into(),
        toml::Value::Integer(i) => (*i).into(),
        toml::Value::Float(f) => (*f).into(),
        toml::Value::Boolean(b) => (*b).into(),
        toml::Value::Datetime(d) => d.to_string().into(),
        toml::Value::Array(a) => a
            .iter()
            .map(to_edit_value)
            .collect::<toml_edit::Array>()
            .into(),
        toml::Value::Table(t) => t
            .iter()
            .map(|(k, v)| (k.clone(), to_edit_value(v)))
            .collect::<toml_edit::InlineTable>()
            .into(),
    }
}

/// `key = value` in a model table, the other form of the same quantity (`omega` and
/// `frequency_hz`, ...) removed.
/// Sets written parameter `name`'s value in `[model.parameters]`: the number itself, or the
/// `value` of its table (its range, unit and comment kept).
fn set_written_parameter(
    document: &mut toml_edit::DocumentMut,
    name: &str,
    value: f64,
) -> Result<(), String> {
    let parameters = document
        .get_mut("model")
        .and_then(|m| m.get_mut("parameters"))
        .and_then(|p| p.as_table_like_mut())
        .ok_or("[model.parameters] is not a table")?;
    let entry = parameters
        .get_mut(name)
        .ok_or_else(|| format!("`{name}` is not a parameter of the model"))?;
    match entry.as_table_like_mut() {
        Some(table) => {
            table.insert("value", toml_edit::value(value));
        }
        None => *entry = toml_edit::value(value),
    }
    Ok(())
}

fn put_model_key(table: &mut dyn toml_edit::TableLike, key: &str, value: f64) {
    for other in same_quantity(key) {
        if *other != key {
            table.remove(other);
        }
    }
    table.insert(key, toml_edit::value(value));
}
