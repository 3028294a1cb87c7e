//! Analyses added, duplicated, renamed and deleted in a session, the rest of the file (its
//! comments and layout) kept. Every edit is validated as a loaded file is; on an error the
//! session is left as it was. Results stay on disk under the names they were computed for.

use super::schema::{KINDS, Session, SessionError};
use super::written::WrittenModel;

/// The settings a new analysis of `kind` is written with: those it cannot do without (the
/// rest take their defaults, shown in the workbench's parameter pane).
fn required_settings(kind: &str, written: Option<&WrittenModel>) -> toml_edit::Table {
    let mut table = toml_edit::Table::new();
    let round = |x: f64| (x * 1e6).round() / 1e6;
    // a written model's chirp from half its frequency to twice it, within its range (the
    // built-in's default, from 0, is not a frequency a written model is swept from)
    if let (Some(w), "chirp_sweep") = (written, kind) {
        let omega = &w.model.parameters()[w.model.frequency()];
        let v = omega.default;
        table.insert(
            "omega_start",
            toml_edit::value(round((0.5 * v).max(omega.min))),
        );
        table.insert(
            "omega_end",
            toml_edit::value(round((2.0 * v).min(omega.max))),
        );
        return table;
    }
    // the built-in model's ADR, or a written model's first parameter but its frequency,
    // around its value within its range
    let (parameter, [lo, value, hi]) = match written {
        None => ("adr".to_string(), [0.2, 0.6, 1.0]),
        Some(w) => {
            let model = &w.model;
            let Some(p) = (model.parameters().iter().enumerate())
                .find(|&(i, _)| i != model.frequency())
                .map(|(_, p)| p)
            else {
                return table; // a model of its frequency alone: nothing to vary
            };
            let v = p.default;
            let d = if v == 0.0 { 1.0 } else { 0.5 * v.abs() };
            (
                p.name.clone(),
                [round((v - d).max(p.min)), v, round((v + d).min(p.max))],
            )
        }
    };
    match kind {
        "family" => {
            table.insert("parameter", toml_edit::value(parameter));
            let mut values = vec![lo, value, hi];
            values.dedup();
            let values: toml_edit::Array = values.into_iter().collect();
            table.insert("values", toml_edit::value(values));
        }
        "map" => {
            table.insert("parameter", toml_edit::value(parameter));
            let mut axis = toml_edit::InlineTable::new();
            // the built-in's ADR over the paper's range
            let (lo, hi) = if written.is_none() {
                (0.1, 1.2)
            } else {
                (lo, hi)
            };
            axis.insert("min", lo.into());
            axis.insert("max", hi.into());
            axis.insert("points", (if lo < hi { 12 } else { 1 }).into());
            table.insert("values", toml_edit::value(axis));
        }
        _ => {}
    }
    table
}

impl Session {
    /// A session error that is not about the file's text.
    fn edit_error(&self, message: String) -> SessionError {
        SessionError::Syntax {
            path: self.path.clone(),
            message,
        }
    }

    /// Appends an analysis of `kind` called `name` (settings at their defaults, the model the
    /// session's); returns its index.
    pub fn add_analysis(&mut self, kind: &str, name: &str) -> Result<usize, SessionError> {
        if !KINDS.contains(&kind) {
            return Err(self.edit_error(format!(
                "unknown kind '{kind}': one of {}",
                KINDS.join(", ")
            )));
        }
        let mut table = toml_edit::Table::new();
        table.insert("name", toml_edit::value(name));
        table.insert("kind", toml_edit::value(kind));
        let mut settings = required_settings(kind, self.written.as_ref());
        if !settings.is_empty() {
            settings.decor_mut().set_prefix("");
            table.insert("settings", toml_edit::Item::Table(settings));
        }
        let mut tables = self.analysis_tables();
        tables.push(table);
        self.with_analysis_tables(tables)?;
        Ok(self.analyses.len() - 1)
    }

    /// Inserts a copy of analysis `index` (its model overrides and settings) called `name`
    /// right after it; returns the copy's index.
    pub fn duplicate_analysis(&mut self, index: usize, name: &str) -> Result<usize, SessionError> {
        let mut tables = self.analysis_tables();
        let mut copy = tables
            .get(index)
            .cloned()
            .ok_or_else(|| self.edit_error(format!("no analysis number {index}")))?;
        copy.insert("name", toml_edit::value(name));
        // the original's leading comment stays with the original
        copy.decor_mut().clear();
        tables.insert(index + 1, copy);
        self.with_analysis_tables(tables)?;
        Ok(index + 1)
    }

    /// Renames analysis `index`.
    pub fn rename_analysis(&mut self, index: usize, name: &str) -> Result<(), SessionError> {
        let mut tables = self.analysis_tables();
        let table = tables
            .get_mut(index)
            .ok_or_else(|| self.edit_error(format!("no analysis number {index}")))?;
        table.insert("name", toml_edit::value(name));
        self.with_analysis_tables(tables)
    }

    /// Removes analysis `index` from the session (not its results from the disk).
    pub fn delete_analysis(&mut self, index: usize) -> Result<(), SessionError> {
        let mut tables = self.analysis_tables();
        if index >= tables.len() {
            return Err(self.edit_error(format!("no analysis number {index}")));
        }
        tables.remove(index);
        self.with_analysis_tables(tables)
    }

    /// The `[[analysis]]` tables as they are written.
    fn analysis_tables(&self) -> Vec<toml_edit::Table> {
        self.document
            .get("analysis")
            .and_then(|a| a.as_array_of_tables())
            .map(|a| a.iter().cloned().collect())
            .unwrap_or_default()
    }

    /// The session with these `[[analysis]]` tables, validated.
    fn with_analysis_tables(&mut self, tables: Vec<toml_edit::Table>) -> Result<(), SessionError> {
        let mut document = self.document.clone();
        // tables are written in the order of their positions: the analyses (and the tables
        // inside them) after everything else, in their new order
        let mut next = max_position(document.as_table()) + 1;
        let mut array = toml_edit::ArrayOfTables::new();
        for mut table in tables {
            number_tables(&mut table, &mut next);
            array.push(table);
        }
        if array.is_empty() {
            document.remove("analysis");
        } else {
            document.insert("analysis", toml_edit::Item::ArrayOfTables(array));
        }
        self.replace_document(document)
    }
}

/// The largest position of a table in `table` or under it, other than the analyses'.
fn max_position(table: &toml_edit::Table) -> isize {
    table
        .iter()
        .filter(|(key, _)| *key != "analysis")
        .filter_map(|(_, item)| item.as_table())
        .map(|t| t.position().unwrap_or(0).max(max_position(t)))
        .max()
        .unwrap_or(0)
}

/// Gives `table` and the tables under it positions from `next` on, in document order.
fn number_tables(table: &mut toml_edit::Table, next: &mut isize) {
    table.set_position(Some(*next));
    *next += 1;
    for (_, item) in table.iter_mut() {
        if let Some(inner) = item.as_table_mut() {
            number_tables(inner, next);
        }
    }
}
