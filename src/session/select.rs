//! A selection of a stored result's rows written as CSV: `isola export --where`, and the
//! workbench's `:export FILE --where ...` (one branch, only the hidden responses...).

use std::path::Path;

use super::output::{Protected, check_target};
use super::schema::{AnalysisEntry, Session};
use super::store::{self, ResultPaths};

/// One `--where` condition: `COLUMN OP VALUE`.
#[derive(Debug, Clone, PartialEq)]
pub struct Filter {
    pub column: String,
    pub op: &'static str,
    pub value: String,
    /// The value as a number, if it is one.
    pub number: Option<f64>,
}

/// Why a selection was not written.
#[derive(Debug, thiserror::Error)]
pub enum SelectionError {
    /// No complete result of the session's current settings is stored.
    #[error("{0}: no current result")]
    NotCurrent(String),
    #[error(transparent)]
    Other(#[from] anyhow::Error),
}

/// `COLUMN OP VALUE`, OP one of `= == != < <= > >=`; an ordering needs a number.
pub fn parse_filter(s: &str) -> anyhow::Result<Filter> {
    let usage = "expected COLUMN OP VALUE with OP one of = != < <= > >= (e.g. \"omega>=3.5\")";
    let at = s
        .find(['<', '>', '=', '!'])
        .ok_or_else(|| anyhow::anyhow!("--where '{s}': no operator; {usage}"))?;
    let (column, rest) = (s[..at].trim(), &s[at..]);
    let op = ["<=", ">=", "!=", "==", "=", "<", ">"]
        .into_iter()
        .find(|op| rest.starts_with(op))
        .ok_or_else(|| anyhow::anyhow!("--where '{s}': '!' alone is no operator; {usage}"))?;
    let value = rest[op.len()..].trim();
    if column.is_empty() {
        anyhow::bail!("--where '{s}': no column before '{op}'; {usage}");
    }
    if value.is_empty() || value.starts_with(['<', '>', '=', '!']) {
        anyhow::bail!("--where '{s}': '{value}' is not a value; {usage}");
    }
    let number = value.parse::<f64>().ok().filter(|x| x.is_finite());
    if matches!(op, "<" | "<=" | ">" | ">=") && number.is_none() {
        anyhow::bail!(
            "--where '{s}': '{op}' compares numbers and '{value}' is not a finite number"
        );
    }
    Ok(Filter {
        column: column.to_string(),
        op: if op == "==" { "=" } else { op },
        value: value.to_string(),
        number,
    })
}

impl Filter {
    /// True if `cell` passes: numbers compare as numbers (an empty or text cell never passes
    /// an ordering), text compares exactly.
    pub fn keeps(&self, cell: &str) -> bool {
        use std::cmp::Ordering as O;
        let order = match (cell.parse::<f64>(), self.number) {
            (Ok(a), Some(b)) => a.partial_cmp(&b),
            (_, Some(_)) if matches!(self.op, "<" | "<=" | ">" | ">=") => None,
            _ => Some(cell.cmp(self.value.as_str())),
        };
        matches!(
            (self.op, order),
            ("=", Some(O::Equal))
                | ("!=", Some(O::Less | O::Greater))
                | ("<", Some(O::Less))
                | ("<=", Some(O::Less | O::Equal))
                | (">", Some(O::Greater))
                | (">=", Some(O::Greater | O::Equal))
        )
    }
}

/// Writes the rows of `entry`'s stored result (its companion `table`, such as `attractors`
/// or `branches`, or the main file) that pass every filter to `to`, atomically, read under
/// the store's lock from a verified result of the session's current settings; returns the
/// rows written. `to` may not be the session file, its results or a special file.
pub fn export_selection(
    session: &Session,
    entry: &AnalysisEntry,
    table: Option<&str>,
    filters: &[Filter],
    to: &Path,
) -> Result<usize, SelectionError> {
    let paths = ResultPaths::new(session, &entry.name);
    let protected = Protected::session(&session.path, &session.results_dir());
    let target = check_target(to, &protected).map_err(anyhow::Error::from)?;
    let fingerprint = session.fingerprint(entry);
    let source = match table {
        Some(table) => paths.csv.with_extension(format!("{table}.csv")),
        None => paths.csv.clone(),
    };
    let not_current = |why: &str| SelectionError::NotCurrent(format!("{} ({why})", entry.name));
    store::with_verified(&paths, |m| -> Result<usize, SelectionError> {
        if m.fingerprint != fingerprint {
            return Err(not_current(
                "the stored one was computed for other settings, device or numerics",
            ));
        }
        let name = source.file_name().unwrap_or_default().to_string_lossy();
        if !m.files.iter().any(|f| f.name == name) {
            // the tables it has: NAME.TABLE.csv beside the main NAME.csv
            let main = paths.csv.file_name().unwrap_or_default().to_string_lossy();
            let stem = main.trim_end_matches(".csv");
            let tables: Vec<&str> = m
                .files
                .iter()
                .filter_map(|f| f.name.strip_prefix(stem)?.strip_prefix('.'))
                .filter_map(|t| t.strip_suffix(".csv"))
                .collect();
            return Err(anyhow::anyhow!(
                "{}: a {} has no {} table; its tables: {} (and the main one, without --table)",
                entry.name,
                entry.settings.kind(),
                table.unwrap_or("main"),
                if tables.is_empty() {
                    "none".to_string()
                } else {
                    tables.join(", ")
                }
            )
            .into());
        }
        let open = |e: csv::Error| anyhow::anyhow!("{}: {e}", source.display());
        let mut reader = csv::Reader::from_path(&source).map_err(open)?;
        let headers = reader.headers().map_err(open)?.clone();
        let columns: Vec<usize> = filters
            .iter()
            .map(|f| {
                headers.iter().position(|h| h == f.column).ok_or_else(|| {
                    anyhow::anyhow!(
                        "--where: no column '{}'; columns: {}",
                        f.column,
                        headers.iter().collect::<Vec<_>>().join(", ")
                    )
                })
            })
            .collect::<anyhow::Result<_>>()?;
        let mut kept = 0;
        let mut bytes = Vec::new();
        {
            let mut w = csv::Writer::from_writer(&mut bytes);
            w.write_record(&headers).map_err(anyhow::Error::from)?;
            for row in reader.records() {
                let row = row.map_err(open)?;
                if filters.iter().zip(&columns).all(|(f, &c)| f.keeps(&row[c])) {
                    w.write_record(&row).map_err(anyhow::Error::from)?;
                    kept += 1;
                }
            }
            w.flush().map_err(anyhow::Error::from)?;
        }
        target.write(&bytes).map_err(anyhow::Error::from)?;
        Ok(kept)
    })
    .map_err(|why| not_current(&why.to_string()))?
}
