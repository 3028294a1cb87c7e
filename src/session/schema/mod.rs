//! The session file: `schema = 1`, an optional device, the model, and named analyses.
//!
//! ```toml
//! schema = 1
//! description = "Fig 4: frequency response at ADR 0.6"
//! [model]
//! adr = 0.6
//! [[analysis]]
//! name = "response"
//! kind = "frequency_response"
//! [analysis.settings]
//! omega = { min = 0.2, max = 6.0, points = 117 }
//! ```

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::locate::{Table, locate};
use super::model_section::ModelSection;
use super::written::{
    DEA_ONLY_KINDS, ModelPoint, WrittenModel, take_written_parts, writes_equations,
};
use crate::analysis::SteadyStateSpec;
use crate::analysis::continuation::branch_from_state::BranchFromState;
use crate::analysis::continuation::hunt::HuntSpec;
use crate::analysis::continuation::map::MapSpec;
use crate::analysis::global::basin::BasinSpec;
use crate::analysis::global::family::FamilySpec;
use crate::analysis::global::frequency_response::FrequencyResponseSpec;
use crate::analysis::grid::Axis;
use crate::analysis::orbit::chirp_sweep::ChirpSpec;
use crate::analysis::orbit::force_curve::ForceCurveSpec;
use crate::analysis::orbit::scalogram::ScalogramSpec;
use crate::analysis::orbit::time_history::TimeHistorySpec;
use crate::analysis::resolution::{Integrators, ResolutionSetting};
use crate::model::equations::chirped::ChirpedSystem;
use crate::model::error::check_in;
use crate::model::{Device, ParamError, ParamSpec, Params, limits};

mod edit;

/// The one schema version this build reads and writes.
pub const SCHEMA: u32 = 1;

/// Longest analysis name: its files (`NAME.attractors.csv` and temporaries beside them) must
/// stay within a file system's 255-byte names.
pub const MAX_NAME: usize = 64;

/// Longest session file name (without `.toml`): its results folder is `NAME.results`.
pub const MAX_STEM: usize = 200;

/// What can go wrong with a session file.
#[derive(Debug, thiserror::Error)]
pub enum SessionError {
    #[error("{path}: {error}")]
    Io {
        path: PathBuf,
        error: std::io::Error,
    },
    /// Malformed TOML or a key/value the schema does not allow; the message has line and column.
    #[error("{path}: {message}")]
    Syntax { path: PathBuf, message: String },
    /// A value out of range, with where it is: the table (`[model]`, `analysis 'b'
    /// settings`), the line and the value as written.
    #[error("{path}: {}{location}: {}", line_prefix(*.line), as_written(error, written.as_deref()))]
    Value {
        path: PathBuf,
        location: String,
        line: Option<usize>,
        /// The value's text in the file, when it is written there.
        written: Option<String>,
        error: Box<crate::model::ParamError>,
    },
}

fn line_prefix(line: Option<usize>) -> String {
    line.map_or(String::new(), |l| format!("line {l}: "))
}

/// `field = VALUE AS WRITTEN is out of range: allowed ...`.
fn as_written(error: &crate::model::ParamError, written: Option<&str>) -> String {
    match written {
        Some(text) => format!(
            "{} = {text} is out of range: allowed {}",
            error.field, error.allowed
        ),
        None => error.to_string(),
    }
}

/// The file as written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SessionFile {
    pub schema: u32,
    #[serde(default)]
    pub description: Option<String>,
    /// The device for physical units (default: the paper's silicone device).
    #[serde(default)]
    pub device: Option<Device>,
    #[serde(default)]
    pub model: ModelSection,
    #[serde(default)]
    pub analysis: Vec<RawAnalysis>,
}

/// One `[[analysis]]` table as written: its settings are read once its kind is known.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawAnalysis {
    pub name: String,
    pub kind: String,
    /// Model values for this analysis only.
    #[serde(default)]
    pub model: ModelSection,
    #[serde(default)]
    pub settings: Option<toml::Table>,
}

/// One named analysis: its model overrides and settings.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AnalysisEntry {
    pub name: String,
    pub model: ModelSection,
    /// Its overrides of a written model's parameters (empty for the built-in model).
    pub values: BTreeMap<String, f64>,
    pub settings: Settings,
}

/// The analysis kinds and their settings (every setting has a default but a family's
/// parameter and values).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Settings {
    ForceCurve(ForceCurveSpec),
    TimeHistory(TimeHistorySpec),
    ChirpSweep(ChirpSpec),
    SteppedSweep(SteppedSweepSpec),
    FrequencyResponse(FrequencyResponseSpec),
    Basin(BasinSpec),
    Family(FamilySpec),
    Continuation(BranchFromState),
    Hunt(HuntSpec),
    Map(MapSpec),
}

/// The kinds a session may name.
pub const KINDS: [&str; 10] = [
    "force_curve",
    "time_history",
    "chirp_sweep",
    "stepped_sweep",
    "frequency_response",
    "basin",
    "family",
    "continuation",
    "hunt",
    "map",
];

impl Settings {
    /// The scalogram a chirp sweep's response is drawn and written with: its own
    /// (`scalogram = {...}`) where it has one, else the defaults.
    pub fn scalogram_spec(&self) -> ScalogramSpec {
        match self {
            Settings::ChirpSweep(ChirpSpec {
                scalogram: Some(spec),
                ..
            }) => spec.clone(),
            _ => ScalogramSpec::default(),
        }
    }

    /// Reads the settings table of an analysis of `kind`; an error gives the path of the key
    /// that failed (`dx.points`), if any, and a message in plain words.
    pub fn read(kind: &str, table: Option<toml::Table>) -> Result<Settings, SettingsError> {
        fn get<T: serde::de::DeserializeOwned>(t: toml::Table) -> Result<T, SettingsError> {
            serde_path_to_error::deserialize(toml::Value::Table(t)).map_err(|e| {
                let path = e.path().to_string();
                SettingsError {
                    path: (path != ".").then_some(path),
                    message: super::locate::plain(&e.into_inner().to_string()),
                }
            })
        }
        fn or_default<T: serde::de::DeserializeOwned + Default>(
            t: Option<toml::Table>,
        ) -> Result<T, SettingsError> {
            t.map_or_else(|| Ok(T::default()), get)
        }
        let needed = |what: &str| SettingsError {
            path: None,
            message: format!("a {what} needs settings: parameter and values"),
        };
        let mut table = table;
        let resolution = table
            .as_mut()
            .and_then(|t| t.remove("resolution"))
            .map(|value| {
                ResolutionSetting::from_toml(&value).map_err(|message| SettingsError {
                    path: Some("resolution".into()),
                    message,
                })
            })
            .transpose()?;
        let written = table.clone();
        let mut settings = match kind {
            "force_curve" => Settings::ForceCurve(or_default(table)?),
            "time_history" => Settings::TimeHistory(or_default(table)?),
            "chirp_sweep" => Settings::ChirpSweep(or_default(table)?),
            "stepped_sweep" => Settings::SteppedSweep(or_default(table)?),
            "frequency_response" => Settings::FrequencyResponse(or_default(table)?),
            "basin" => Settings::Basin(or_default(table)?),
            "continuation" => Settings::Continuation(or_default(table)?),
            "hunt" => Settings::Hunt(or_default(table)?),
            "map" => Settings::Map(get(table.ok_or_else(|| needed("map"))?)?),
            "family" => Settings::Family(get(table.ok_or_else(|| needed("family"))?)?),
            other => {
                return Err(SettingsError {
                    path: None,
                    message: format!("unknown kind '{other}': one of {}", KINDS.join(", ")),
                });
            }
        };
        if let Some(setting) = resolution {
            settings.set_resolution(setting, written.as_ref())?;
        }
        Ok(settings)
    }

    /// Sets what `resolution = SETTING` sets (see [`ResolutionSetting`]); refused where the
    /// settings `written` also write that integrator under its own key
    /// (`steady.resolution`, `tolerance`...), so the two can never disagree.
    fn set_resolution(
        &mut self,
        setting: ResolutionSetting,
        written: Option<&toml::Table>,
    ) -> Result<(), SettingsError> {
        let error = |message: String| SettingsError {
            path: Some("resolution".into()),
            message,
        };
        let key = self.integrator_key(setting);
        if let Some(key) = key.filter(|k| written.is_some_and(|t| has_path(t, k))) {
            return Err(error(format!(
                "{setting} and settings.{key} both set the {}: write one of them",
                match setting {
                    ResolutionSetting::StepsPerPeriod(_) => "RK4 steps",
                    ResolutionSetting::Reference { .. } => "Dormand–Prince tolerance",
                }
            )));
        }
        self.with_integrators(|s| s.set_resolution(setting))
            .unwrap_or_else(|| {
                Err(format!(
                    "{setting} is out of range: force curves are static, nothing is integrated"
                ))
            })
            .map_err(error)
    }

    /// The key (in these settings) of the integrator `setting` sets, if they have one.
    fn integrator_key(&self, setting: ResolutionSetting) -> Option<&'static str> {
        let mut settings = self.clone();
        settings
            .with_integrators(|s| match setting {
                ResolutionSetting::StepsPerPeriod(_) => s.rk4().map(|(k, _)| k),
                ResolutionSetting::Reference { .. } => s.dopri().map(|(k, _)| k),
            })
            .flatten()
    }

    /// These settings at twice the resolution (see [`Integrators::double_resolution`]); the
    /// same for force curves, which integrate nothing.
    pub fn at_twice_the_resolution(&self) -> Result<Settings, ParamError> {
        let mut settings = self.clone();
        settings
            .with_integrators(|s| s.double_resolution())
            .transpose()?;
        Ok(settings)
    }

    /// The resolution these settings integrate at, in words (empty for force curves).
    pub fn resolution_in_words(&self) -> String {
        let mut settings = self.clone();
        settings
            .with_integrators(|s| s.describe_resolution())
            .unwrap_or_default()
    }

    /// Runs `f` on the spec of these settings as its [`Integrators`]; `None` for force
    /// curves, which integrate nothing.
    fn with_integrators<R>(&mut self, f: impl FnOnce(&mut dyn Integrators) -> R) -> Option<R> {
        Some(match self {
            Settings::ForceCurve(_) => return None,
            Settings::TimeHistory(s) => f(s),
            Settings::ChirpSweep(s) => f(s),
            Settings::SteppedSweep(s) => f(s),
            Settings::FrequencyResponse(s) => f(s),
            Settings::Basin(s) => f(s),
            Settings::Family(s) => f(s),
            Settings::Continuation(s) => f(s),
            Settings::Hunt(s) => f(s),
            Settings::Map(s) => f(s),
        })
    }

    /// The settings as a TOML table, defaults included.
    pub fn to_toml(&self) -> Result<toml::Table, toml::ser::Error> {
        match self {
            Settings::ForceCurve(s) => toml::Table::try_from(s),
            Settings::TimeHistory(s) => toml::Table::try_from(s),
            Settings::ChirpSweep(s) => toml::Table::try_from(s),
            Settings::SteppedSweep(s) => toml::Table::try_from(s),
            Settings::FrequencyResponse(s) => toml::Table::try_from(s),
            Settings::Basin(s) => toml::Table::try_from(s),
            Settings::Family(s) => toml::Table::try_from(s),
            Settings::Continuation(s) => toml::Table::try_from(s),
            Settings::Hunt(s) => toml::Table::try_from(s),
            Settings::Map(s) => toml::Table::try_from(s),
        }
    }

    pub fn kind(&self) -> &'static str {
        match self {
            Settings::ForceCurve(_) => "force_curve",
            Settings::TimeHistory(_) => "time_history",
            Settings::ChirpSweep(_) => "chirp_sweep",
            Settings::SteppedSweep(_) => "stepped_sweep",
            Settings::FrequencyResponse(_) => "frequency_response",
            Settings::Basin(_) => "basin",
            Settings::Family(_) => "family",
            Settings::Continuation(_) => "continuation",
            Settings::Hunt(_) => "hunt",
            Settings::Map(_) => "map",
        }
    }

    /// The version of numerics that only an analysis with these settings uses, for its
    /// fingerprint beside [`crate::analysis::NUMERICS_VERSION`]: a chirp sweep's scalogram
    /// ([`crate::analysis::orbit::scalogram::NUMERICS_VERSION`]), the continuation's for the
    /// kinds that continue branches ([`crate::analysis::continuation::NUMERICS_VERSION`]), so
    /// that a change there makes only such results stale.
    pub fn own_numerics(&self) -> Option<serde_json::Value> {
        match self {
            Settings::ChirpSweep(spec) if spec.scalogram.is_some() => Some(serde_json::json!({
                "scalogram": crate::analysis::orbit::scalogram::NUMERICS_VERSION
            })),
            Settings::Continuation(_) | Settings::Hunt(_) | Settings::Map(_) => {
                Some(serde_json::json!({
                    "continuation": crate::analysis::continuation::NUMERICS_VERSION
                }))
            }
            _ => None,
        }
    }

    /// What of the model an analysis with these settings uses. Its fingerprint leaves out the
    /// rest, so an edit of something it does not use leaves its result current.
    pub fn model_use(&self) -> ModelUse {
        // a family or map parameter's name is the model key it replaces: the model's own
        // value is never read (E_a and ADR read back exactly as given, so a member's drive
        // does not depend on the other's last bits)
        match self {
            // the force curves take λ_p, φ and J from their own settings
            Settings::ForceCurve(_) => ModelUse::Nothing,
            // each sweeps its own ω grid: the model's ω_e is never read
            Settings::FrequencyResponse(_) | Settings::SteppedSweep(_) | Settings::Hunt(_) => {
                ModelUse::AllBut(vec!["omega".into()])
            }
            Settings::Family(spec) => {
                ModelUse::AllBut(vec!["omega".into(), spec.parameter.name().into()])
            }
            Settings::Map(spec) => {
                ModelUse::AllBut(vec![spec.x.name().into(), spec.parameter.name().into()])
            }
            // a chirp's integrator is set up from the model's period; a basin and a time
            // history run at the model's ω_e, and a continuation starts there
            Settings::ChirpSweep(_)
            | Settings::TimeHistory(_)
            | Settings::Basin(_)
            | Settings::Continuation(_) => ModelUse::All,
        }
    }
}

/// Whether `table` writes the dotted `path` (`steady.resolution`).
fn has_path(table: &toml::Table, path: &str) -> bool {
    let mut at = Some(table);
    let mut keys = path.split('.').peekable();
    while let (Some(t), Some(key)) = (at, keys.next()) {
        match t.get(key) {
            Some(_) if keys.peek().is_none() => return true,
            Some(v) => at = v.as_table(),
            None => return false,
        }
    }
    false
}

/// What of the model an analysis uses (see [`Settings::model_use`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ModelUse {
    All,
    /// Everything but these model keys (`omega`, which it sweeps; the parameter a family or
    /// map sets itself). A key of the drive (`adr`, `e_a`) is left out only where the model
    /// gives the drive in those terms: given as voltages, they are what is read.
    AllBut(Vec<String>),
    Nothing,
}

/// Settings that could not be read: the key's path inside the settings, if one failed.
#[derive(Debug, Clone, PartialEq)]
pub struct SettingsError {
    pub path: Option<String>,
    pub message: String,
}

/// A stepped sweep in a session: its ω grid in order (reverse min and max to step down).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SteppedSweepSpec {
    pub omega: Axis,
    pub dx0: f64,
    pub v0: f64,
    pub steady: SteadyStateSpec,
    /// The factor by which the amplitude must change between two steps to be a jump (see
    /// [`crate::analysis::global::stepped_sweep::StepJump`]).
    pub jump_ratio: f64,
}

impl Integrators for SteppedSweepSpec {
    fn what(&self) -> &'static str {
        "a stepped sweep"
    }
    fn rk4(&mut self) -> Option<(&'static str, &mut crate::solver::Resolution)> {
        Some(("steady.resolution", &mut self.steady.resolution))
    }
}

impl Default for SteppedSweepSpec {
    fn default() -> Self {
        SteppedSweepSpec {
            omega: Axis::new(0.2, 6.0, 117),
            dx0: 0.0,
            v0: 0.0,
            steady: SteadyStateSpec::default(),
            jump_ratio: crate::analysis::orbit::chirp_sweep::DEFAULT_JUMP_RATIO,
        }
    }
}

/// A loaded session: the parsed file, its analyses, its text (for saving with the user's
/// comments), and where it lives.
#[derive(Debug, Clone)]
pub struct Session {
    pub path: PathBuf,
    pub file: SessionFile,
    /// The model the session writes as equations, if it does (then `file.model` is unused).
    pub written: Option<WrittenModel>,
    pub analyses: Vec<AnalysisEntry>,
    pub(super) document: toml_edit::DocumentMut,
}

impl Session {
    /// Reads and validates a session file.
    pub fn load(path: &Path) -> Result<Self, SessionError> {
        let text = std::fs::read_to_string(path).map_err(|error| SessionError::Io {
            path: path.to_path_buf(),
            error,
        })?;
        Self::parse(path, &text)
    }

    /// Parses and validates session text (`path` is for messages and results).
    pub fn parse(path: &Path, text: &str) -> Result<Self, SessionError> {
        let syntax = |message: String| SessionError::Syntax {
            path: path.to_path_buf(),
            message,
        };
        if text.trim().is_empty() {
            return Err(syntax(
                "the file is empty (if an editor is writing it, run again once it is saved)".into(),
            ));
        }
        let document: toml_edit::DocumentMut = text
            .parse()
            .map_err(|e: toml_edit::TomlError| syntax(e.to_string()))?;
        let mut table: toml::Table = toml::from_str(text).map_err(|e| syntax(e.to_string()))?;
        let (file, written, mut overrides) = if writes_equations(&table) {
            let overrides = take_written_parts(&mut table).map_err(syntax)?;
            let file = SessionFile::deserialize(toml::Value::Table(table))
                .map_err(|e| syntax(e.to_string()))?;
            (
                file,
                Some(WrittenModel::read(text).map_err(syntax)?),
                overrides,
            )
        } else {
            let file: SessionFile = toml::from_str(text).map_err(|e| syntax(e.to_string()))?;
            (file, None, Vec::new())
        };
        if file.schema != SCHEMA {
            return Err(syntax(format!(
                "schema = {}: this isola reads schema = {SCHEMA}",
                file.schema
            )));
        }
        let mut analyses = Vec::with_capacity(file.analysis.len());
        for (i, raw) in file.analysis.iter().enumerate() {
            let settings = Settings::read(&raw.kind, raw.settings.clone()).map_err(|e| {
                let (table, field) = match &e.path {
                    Some(p) => (Table::AnalysisSettings(i), p.as_str()),
                    None if e.message.starts_with("unknown kind") => (Table::Analysis(i), "kind"),
                    None => (Table::Analysis(i), "settings"),
                };
                let at = locate(text, table, field);
                let key = e.path.as_ref().map_or(String::new(), |p| match &at.text {
                    Some(t) => format!("settings.{p} = {t}: "),
                    None => format!("settings.{p}: "),
                });
                syntax(format!(
                    "{}analysis '{}' ({}): {key}{}",
                    line_prefix(at.line),
                    raw.name,
                    raw.kind,
                    e.message
                ))
            })?;
            let values = overrides.get_mut(i).map(std::mem::take).unwrap_or_default();
            if let Some(w) = &written {
                if DEA_ONLY_KINDS.contains(&raw.kind.as_str()) {
                    let runs: Vec<&str> = KINDS
                        .into_iter()
                        .filter(|kind| !DEA_ONLY_KINDS.contains(kind))
                        .collect();
                    return Err(syntax(format!(
                        "analysis '{}' ({}): a written model runs {} (force curves are the \
                         built-in DEA's own)",
                        raw.name,
                        raw.kind,
                        runs.join(", ")
                    )));
                }
                if raw.kind == "chirp_sweep" && !w.model.periodic_in_time() {
                    return Err(syntax(format!(
                        "analysis '{}' (chirp_sweep): a chirp sweep reads {omega}*t as the \
                         sweep's phase, so the model's time t may enter only as k*{omega}*t (k \
                         a whole number, plus a fixed phase) inside sin, cos or tan; this model \
                         uses t otherwise",
                        raw.name,
                        omega = w.model.frequency_name()
                    )));
                }
                if let Some(e) = w.unknown_override(&values) {
                    return Err(syntax(format!("analysis '{}' model: {e}", raw.name)));
                }
            }
            analyses.push(AnalysisEntry {
                name: raw.name.clone(),
                model: raw.model.clone(),
                values,
                settings,
            });
        }
        let stem = path.file_stem().map_or(0, |s| s.len());
        if stem > MAX_STEM {
            return Err(syntax(format!(
                "the file name is {stem} bytes long: at most {MAX_STEM} (without .toml), so that \
                 its results folder can be named"
            )));
        }
        let session = Session {
            path: path.to_path_buf(),
            file,
            written,
            analyses,
            document,
        };
        session.validate()?;
        Ok(session)
    }

    /// Checks the model, every analysis' parameters, and that names are unique.
    fn validate(&self) -> Result<(), SessionError> {
        let text = self.document.to_string();
        // the error located in the first of `tables` that has its field written
        let value_error = |location: String, tables: &[Table], error: ParamError| {
            let found = tables
                .iter()
                .map(|&t| locate(&text, t, &error.field))
                .find(|w| w.text.is_some());
            let at = found.unwrap_or_else(|| locate(&text, tables[0], &error.field));
            SessionError::Value {
                path: self.path.clone(),
                location,
                line: at.line,
                written: at.text,
                error: Box::new(error),
            }
        };
        self.device()
            .validate()
            .map_err(|e| value_error("[device]".into(), &[Table::Device], e))?;
        self.point(None)
            .map_err(|e| value_error("[model]".into(), &[Table::Model], e))?;
        for (i, entry) in self.analyses.iter().enumerate() {
            if self.analyses[..i].iter().any(|a| a.name == entry.name) {
                return Err(SessionError::Syntax {
                    path: self.path.clone(),
                    message: format!("analysis name '{}' is used twice", entry.name),
                });
            }
            let valid_name = !entry.name.is_empty()
                && entry
                    .name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
            if !valid_name || entry.name.len() > MAX_NAME {
                let at = locate(&text, Table::Analysis(i), "name");
                return Err(SessionError::Syntax {
                    path: self.path.clone(),
                    message: format!(
                        "{}analysis name '{}': use 1 to {MAX_NAME} letters, digits, _ and -",
                        line_prefix(at.line),
                        entry.name
                    ),
                });
            }
            if let Some(w) = &self.written
                && let [state] = w.model.states()
                && matches!(
                    entry.settings,
                    Settings::Basin(_)
                        | Settings::FrequencyResponse(_)
                        | Settings::Family(_)
                        | Settings::Hunt(_)
                        | Settings::Map(_)
                )
            {
                // a scalar flow keeps its starts in order: its stroboscopic map is monotone,
                // and settles on responses of one forcing period
                let at = locate(&text, Table::Analysis(i), "kind");
                return Err(SessionError::Syntax {
                    path: self.path.clone(),
                    message: format!(
                        "{}analysis '{}' ({}): a grid of starts spans two states, and this model \
                         has one (`{state}`), whose every response lasts one forcing period; \
                         run a time_history, stepped_sweep or continuation, or write the model \
                         with a second state",
                        line_prefix(at.line),
                        entry.name,
                        entry.settings.kind()
                    ),
                });
            }
            let point = self.point(Some(entry)).map_err(|e| {
                value_error(
                    format!("analysis '{}' model", entry.name),
                    &[Table::AnalysisModel(i), Table::Model],
                    e,
                )
            })?;
            let in_settings = |e| {
                value_error(
                    format!("analysis '{}' settings", entry.name),
                    &[Table::AnalysisSettings(i)],
                    e,
                )
            };
            check_settings(&entry.settings, &point).map_err(in_settings)?;
            // settings the cost model refuses (a step too fine for the forcing period)
            if let Err(super::budget::BudgetError::Setting(e)) = super::budget::cost_of(self, entry)
            {
                return Err(in_settings(e));
            }
        }
        Ok(())
    }

    /// The indices of the two states a grid spans: λ_I and v for the built-in model.
    pub fn grid(&self) -> [usize; 2] {
        self.written.as_ref().map_or([0, 1], |w| w.model.grid())
    }

    pub fn device(&self) -> Device {
        self.file.device.unwrap_or_default()
    }

    /// The built-in model for `entry` (its overrides over the session's model), or the
    /// session's own. An error for a session that writes its own model: see [`Self::point`].
    pub fn params(
        &self,
        entry: Option<&AnalysisEntry>,
    ) -> Result<Params, crate::model::ParamError> {
        if self.written.is_some() {
            return Err(ParamError {
                field: "model".into(),
                value: ParamError::NOT_NUMERIC,
                allowed: "the built-in model (this session writes its own)".into(),
            });
        }
        self.param_spec(entry)?.build()
    }

    /// The model of `entry` (or the session's own), built-in or written.
    pub fn point(&self, entry: Option<&AnalysisEntry>) -> Result<ModelPoint, ParamError> {
        match &self.written {
            Some(w) => {
                let none = BTreeMap::new();
                w.system(entry.map_or(&none, |e| &e.values))
                    .map(ModelPoint::Written)
            }
            None => self.params(entry).map(ModelPoint::BuiltIn),
        }
    }

    fn param_spec(
        &self,
        entry: Option<&AnalysisEntry>,
    ) -> Result<ParamSpec, crate::model::ParamError> {
        let model = match entry {
            Some(e) => e.model.over(&self.file.model),
            None => self.file.model.clone(),
        };
        model.to_spec(&self.device())
    }

    /// The analysis called `name`.
    pub fn analysis(&self, name: &str) -> Option<&AnalysisEntry> {
        self.analysis_index(name).map(|i| &self.analyses[i])
    }

    /// The index of the analysis called `name`.
    pub fn analysis_index(&self, name: &str) -> Option<usize> {
        self.analyses.iter().position(|a| a.name == name)
    }

    /// A stable fingerprint of what `entry` computes: its kind and settings, the model (what of
    /// it the analysis uses: [`Settings::model_use`]), the device (physical columns) and the
    /// numerics version of this build. A result or chunk with another fingerprint is stale and
    /// never mixed in.
    pub fn fingerprint(&self, entry: &AnalysisEntry) -> String {
        self.fingerprint_with(entry, crate::analysis::NUMERICS_VERSION)
    }

    /// The fingerprint `entry` has under numerics version `numerics`: the first 16 bytes of
    /// the SHA-256 of [`Self::fingerprint_input`] as compact JSON, in hex.
    pub fn fingerprint_with(&self, entry: &AnalysisEntry, numerics: u32) -> String {
        use sha2::Digest;
        let what = self.fingerprint_input(entry, numerics);
        let digest = sha2::Sha256::digest(what.to_string().as_bytes());
        super::store::chunk::hex(&digest[..16])
    }

    /// What `entry` computes from, under numerics version `numerics`: the model's values it
    /// uses, the device, its settings (with its kind), the numerics version and, for the kinds
    /// that have one, their own ([`Settings::own_numerics`]).
    pub fn fingerprint_input(&self, entry: &AnalysisEntry, numerics: u32) -> serde_json::Value {
        let used = entry.settings.model_use();
        let model = match &self.written {
            Some(w) => w.fingerprint_model(&entry.values, &used),
            None => self.built_in_fingerprint_model(entry, &used),
        };
        let mut input = serde_json::json!({
            "numerics": numerics,
            "device": self.device(),
            "model": model,
            "settings": &entry.settings,
        });
        if let Some(own) = entry.settings.own_numerics() {
            input["own_numerics"] = own;
        }
        input
    }

    /// What of the built-in model `entry` uses, for its fingerprint: its parameters without
    /// the keys `used` leaves out (in the drive too).
    fn built_in_fingerprint_model(
        &self,
        entry: &AnalysisEntry,
        used: &ModelUse,
    ) -> serde_json::Value {
        let mut model = serde_json::to_value(self.param_spec(Some(entry)).ok())
            .unwrap_or(serde_json::Value::Null);
        match used {
            ModelUse::All => {}
            ModelUse::AllBut(keys) => {
                if let Some(object) = model.as_object_mut() {
                    for key in keys {
                        object.remove(key.as_str());
                        if let Some(drive) = object.get_mut("drive").and_then(|d| d.as_object_mut())
                        {
                            drive.remove(key.as_str());
                        }
                    }
                }
            }
            ModelUse::Nothing => model = serde_json::Value::Null,
        }
        model
    }

    /// Re-reads and validates an edited document; on error the session is left as it was.
    pub(super) fn replace_document(
        &mut self,
        document: toml_edit::DocumentMut,
    ) -> Result<(), SessionError> {
        let reparsed = Session::parse(&self.path, &document.to_string())?;
        *self = reparsed;
        Ok(())
    }

    /// Where the results of this session live: `NAME.results/` beside the file.
    pub fn results_dir(&self) -> PathBuf {
        results_dir_of(&self.path)
    }
}

/// The results folder of the session file at `path`: `NAME.results` beside `NAME.toml`, and
/// for a file of another name its whole name's (`s.toml~.results`, `s.bak.results`), so that
/// an editor's backup or a copy never shares the session's results.
pub fn results_dir_of(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let stem = name.strip_suffix(".toml").unwrap_or(&name);
    path.with_file_name(format!("{stem}.results"))
}

/// An analysis' settings checked by the analysis' own rules, so a session fails at load time
/// rather than when it runs; ω values against the built-in's range or against the range of a
/// written model's frequency parameter.
fn check_settings(settings: &Settings, point: &ModelPoint) -> Result<(), ParamError> {
    use crate::analysis::Oscillator;
    let start = |dx0: f64, v0: f64| -> Result<(), ParamError> {
        check_in("dx0", dx0, limits::DX.0, limits::DX.1)?;
        check_in("v0", v0, limits::V.0, limits::V.1)?;
        Ok(())
    };
    let omegas = |axis: &Axis, field: &str| -> Result<(), ParamError> {
        match point {
            ModelPoint::BuiltIn(_) => axis.check_within(field, limits::OMEGA),
            ModelPoint::Written(sys) => [axis.min, axis.max].into_iter().try_for_each(|w| {
                sys.with(sys.frequency(), w)
                    .map(|_| ())
                    .map_err(|e| e.as_value_of(field))
            }),
        }
    };
    // a check over whichever model the point is
    macro_rules! on_model {
        (|$m:ident| $check:expr) => {
            match point {
                ModelPoint::BuiltIn($m) => $check,
                ModelPoint::Written($m) => $check,
            }
        };
    }
    match settings {
        Settings::ForceCurve(s) => s.validate(),
        Settings::TimeHistory(s) => {
            start(s.dx0, s.v0)?;
            s.validate()
        }
        Settings::ChirpSweep(s) => {
            start(s.dx0, s.v0)?;
            match point {
                ModelPoint::BuiltIn(_) => s.validate(),
                ModelPoint::Written(sys) => {
                    s.validate_settings()?;
                    ChirpedSystem::check(sys, &s.sweep())
                }
            }
        }
        Settings::SteppedSweep(s) => {
            start(s.dx0, s.v0)?;
            // checked as written (so the error names min or max as the file does), then in
            // increasing order, as a sweep down is written with min > max
            omegas(&s.omega, "omega")?;
            let mut range = s.omega;
            if range.min > range.max {
                std::mem::swap(&mut range.min, &mut range.max);
            }
            range.validate("omega", 100_000)?;
            s.steady.validate().map_err(|e| e.within("steady"))?;
            crate::analysis::orbit::chirp_sweep::check_jump_ratio(s.jump_ratio)
        }
        Settings::FrequencyResponse(s) => {
            s.validate()?;
            omegas(&s.omega, "omega")
        }
        Settings::Basin(s) => s.validate(),
        Settings::Family(s) => {
            on_model!(|m| s.validate(m))?;
            omegas(&s.response.omega, "response.omega")
        }
        Settings::Continuation(s) => {
            start(s.dx0, s.v0)?;
            s.steady.validate().map_err(|e| e.within("steady"))?;
            on_model!(|m| s.continuation.validate_from(m)).map_err(|e| e.within("continuation"))
        }
        Settings::Hunt(s) => {
            on_model!(|m| s.validate(m))?;
            omegas(&s.response.omega, "response.omega")
        }
        Settings::Map(s) => {
            on_model!(|m| s.validate(m))?;
            if s.x == crate::analysis::parameter::ContinuationParameter::Omega {
                omegas(&s.response.omega, "response.omega")?;
            }
            Ok(())
        }
    }
}

/// The leading comment of a session file's `text` (the `#` lines before anything else), as
/// one line of text: what the session is about.
pub fn description(text: &str) -> String {
    text.lines()
        .map(str::trim)
        .take_while(|l| l.starts_with('#') || l.is_empty())
        .filter_map(|l| l.strip_prefix('#'))
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}
