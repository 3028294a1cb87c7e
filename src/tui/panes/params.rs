//! The parameter pane: the model of the selected analysis (non-dimensional, physical units
//! beside) and its settings, edited in place; an invalid value is refused with the reason.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph, Widget, Wrap};

use crate::tui::line_edit::LineEdit;
use crate::tui::theme::Theme;
use isola::session::{Session, SessionError};

/// What a row edits.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    /// A model key, and the key and unit of its physical form, if it has one.
    Model {
        key: String,
        physical: Option<(&'static str, &'static str)>,
    },
    /// A quantity the model derives from others (E_b, E_c): shown, not edited; the text says
    /// what to edit instead.
    Derived(&'static str),
    /// A setting of the analysis, by path.
    Setting {
        path: Vec<String>,
        value: toml::Value,
    },
}

/// One editable row.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub label: String,
    pub value: String,
    /// The value in full (every digit that reads back exactly): what an edit starts from.
    pub exact: String,
    /// The value in physical units, if it has them.
    pub physical: String,
    /// Set by this analysis only (not the session's model).
    pub overridden: bool,
    pub target: Target,
}

/// The rows for analysis `index`.
pub fn rows(session: &Session, index: usize) -> Vec<Row> {
    let mut out = Vec::new();
    let Some(entry) = session.analyses.get(index) else {
        return out;
    };
    let device = session.device();
    if let Some(written) = &session.written {
        let values = written.values(&entry.values);
        for (p, value) in written.model.parameters().iter().zip(values) {
            out.push(Row {
                label: p.name.clone(),
                value: format_number(value),
                exact: value.to_string(),
                physical: p
                    .unit
                    .clone()
                    .or_else(|| p.about.clone())
                    .unwrap_or_default(),
                overridden: entry.values.contains_key(&p.name),
                target: Target::Model {
                    key: p.name.clone(),
                    physical: None,
                },
            });
        }
        settings_rows(session, index, &mut out);
        return out;
    }
    let Ok(p) = session.params(Some(entry)) else {
        return out;
    };
    let m = &entry.model;
    let model =
        |label: &str, key: &str, physical, value: f64, phys: String, overridden: bool| Row {
            label: label.into(),
            value: format_number(value),
            exact: value.to_string(),
            physical: phys,
            overridden,
            target: Target::Model {
                key: key.to_string(),
                physical,
            },
        };
    out.push(model(
        "λ_p",
        "lambda_p",
        None,
        p.lambda_p(),
        String::new(),
        m.lambda_p.is_some(),
    ));
    out.push(model("J", "j", None, p.j(), String::new(), m.j.is_some()));
    out.push(model(
        "c̃",
        "c_tilde",
        Some(("damping_n_s_per_m", "N·s/m")),
        p.c_tilde(),
        format!("{:.3} N·s/m", device.damping(p.c_tilde())),
        m.c_tilde.is_some() || m.damping_n_s_per_m.is_some(),
    ));
    out.push(model(
        "ω_e",
        "omega",
        Some(("frequency_hz", "Hz")),
        p.omega(),
        format!("{:.2} Hz", device.hz(p.omega())),
        m.omega.is_some() || m.frequency_hz.is_some(),
    ));
    let d = p.drive_i();
    match d.adr() {
        Some(adr) => {
            out.push(model(
                "E_a",
                "e_a",
                None,
                d.e_a(),
                format!("{:.1} MV/m peak", device.mv_per_m(d.phi_peak())),
                m.e_a.is_some(),
            ));
            out.push(model(
                "ADR",
                "adr",
                None,
                adr,
                format!(
                    "{:.2}+{:.2} kV",
                    device.kv(d.phi_dc()),
                    device.kv(d.phi_ac())
                ),
                m.adr.is_some(),
            ));
            let derived = |label: &str, value: f64, what: &str| Row {
                label: label.into(),
                value: format_number(value),
                exact: value.to_string(),
                physical: what.into(),
                overridden: false,
                target: Target::Derived("derived from E_a and ADR: edit those"),
            };
            out.push(derived("E_b", d.e_b(), "φ² at ω_e"));
            out.push(derived("E_c", d.e_c(), "φ² at 2ω_e"));
        }
        None => {
            out.push(model(
                "φ_DC",
                "phi_dc",
                Some(("dc_kv", "kV")),
                d.phi_dc(),
                format!("{:.2} kV", device.kv(d.phi_dc())),
                m.phi_dc.is_some() || m.dc_kv.is_some(),
            ));
            out.push(model(
                "φ_AC",
                "phi_ac",
                Some(("ac_kv", "kV")),
                d.phi_ac(),
                format!("{:.2} kV", device.kv(d.phi_ac())),
                m.phi_ac.is_some() || m.ac_kv.is_some(),
            ));
        }
    }
    // at rest under the mean drive, and the small oscillations about it (`isola model`)
    if let Some(rest) = isola::model::statics::equilibrium(&p) {
        let derived = |label: &str, value: f64, what: String| Row {
            label: label.into(),
            value: format_number(value),
            exact: value.to_string(),
            physical: what,
            overridden: false,
            target: Target::Derived("derived from the model at rest: edit λ_p, J or the drive"),
        };
        out.push(derived(
            "λ_I*",
            rest.lambda_i,
            format!("at rest, Δλ {:+.4}", rest.lambda_i - p.lambda_p()),
        ));
        if let Some(omega_0) = rest.omega_0 {
            out.push(derived(
                "ω₀",
                omega_0,
                format!(
                    "{:.2} Hz; 2ω₀ {:.2} Hz",
                    device.hz(omega_0),
                    device.hz(2.0 * omega_0)
                ),
            ));
        }
    }
    settings_rows(session, index, &mut out);
    out
}

/// The rows of analysis `index`'s settings, then those of the optional tables it leaves out
/// (a chirp sweep's `scalogram`) at their defaults, marked as not written: setting one
/// writes its table.
fn settings_rows(session: &Session, index: usize, out: &mut Vec<Row>) {
    let set = session.settings_table(index);
    flatten(&set, &mut Vec::new(), out);
    for (key, value) in session.settings_offered(index) {
        if let (false, toml::Value::Table(t)) = (set.contains_key(&key), value) {
            let first = out.len();
            flatten(&t, &mut vec![key], out);
            for row in &mut out[first..] {
                row.physical = "off: set to write it".into();
            }
        }
    }
}

/// The settings of `table` as rows: each table's own values first, then its tables, so that
/// every table's rows are together under one heading.
fn flatten(table: &toml::Table, prefix: &mut Vec<String>, out: &mut Vec<Row>) {
    let (tables, values): (Vec<_>, Vec<_>) = table.iter().partition(|(_, v)| v.is_table());
    for (k, v) in values.into_iter().chain(tables) {
        prefix.push(k.clone());
        match v {
            toml::Value::Table(t) => flatten(t, prefix, out),
            value => out.push(Row {
                label: prefix.join("."),
                value: format_value(value),
                exact: match value {
                    toml::Value::Float(f) => f.to_string(),
                    other => format_value(other),
                },
                physical: String::new(),
                overridden: false,
                target: Target::Setting {
                    path: prefix.clone(),
                    value: value.clone(),
                },
            }),
        }
        prefix.pop();
    }
}

/// A number as short as it reads exactly.
pub fn format_number(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    if x.abs() < 1e-3 || x.abs() >= 1e6 {
        return format!("{x:.4e}");
    }
    // six significant digits, trailing zeros dropped (0.04000000000000001 reads 0.04)
    let decimals = (5 - x.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

fn format_value(v: &toml::Value) -> String {
    match v {
        toml::Value::Float(f) => format_number(*f),
        toml::Value::String(s) => s.clone(),
        toml::Value::Array(a) => a.iter().map(format_value).collect::<Vec<_>>().join(", "),
        other => other.to_string(),
    }
}

/// What the user typed for `target`, as the value to set; the error names the field.
pub fn parse_edit(row: &Row, text: &str) -> Result<Edit, String> {
    let text = text.trim();
    match &row.target {
        Target::Model { key, physical } => {
            let (number, key) = match physical {
                Some((phys_key, unit)) if text.ends_with(unit) => {
                    (text.trim_end_matches(unit).trim(), phys_key.to_string())
                }
                _ => (text, key.clone()),
            };
            let value: f64 = number.parse().map_err(|_| {
                // a number with a unit this value does not take (`50 Hz` on a written model)
                let unit = text
                    .split_once(char::is_whitespace)
                    .filter(|(n, _)| n.parse::<f64>().is_ok())
                    .map(|(_, u)| u.trim());
                match (unit, physical) {
                    (Some(u), Some((_, unit))) => format!(
                        "{}: '{text}': {u} is not its unit: give a number, or one in {unit}",
                        row.label
                    ),
                    (Some(u), None) => format!(
                        "{}: '{text}': it takes a plain number, with no unit ({u} is none \
                         this model knows)",
                        row.label
                    ),
                    (None, _) => format!("{}: '{text}' is not a number", row.label),
                }
            })?;
            Ok(Edit::Model { key, value })
        }
        Target::Derived(why) => Err(format!("{}: {why}", row.label)),
        Target::Setting { path, value } => {
            let parsed = parse_like(value, text)
                .ok_or_else(|| format!("{}: '{text}' is not {}", row.label, describe(value)))?;
            Ok(Edit::Setting {
                path: path.clone(),
                value: parsed,
            })
        }
    }
}

/// An edit ready to apply to the session.
#[derive(Debug, Clone, PartialEq)]
pub enum Edit {
    Model {
        key: String,
        value: f64,
    },
    Setting {
        path: Vec<String>,
        value: toml::Value,
    },
}

fn describe(v: &toml::Value) -> &'static str {
    match v {
        toml::Value::Integer(_) => "a whole number",
        toml::Value::Float(_) => "a number",
        toml::Value::Boolean(_) => "true or false",
        toml::Value::Array(_) => "a list of numbers (a, b, c)",
        _ => "a value",
    }
}

/// `text` read as a value of the same type as `like`.
fn parse_like(like: &toml::Value, text: &str) -> Option<toml::Value> {
    Some(match like {
        toml::Value::Integer(_) => toml::Value::Integer(text.parse().ok()?),
        toml::Value::Float(_) => toml::Value::Float(text.parse().ok()?),
        toml::Value::Boolean(_) => toml::Value::Boolean(text.parse().ok()?),
        toml::Value::String(_) => toml::Value::String(text.to_string()),
        toml::Value::Array(items) => {
            let item = items.first().cloned().unwrap_or(toml::Value::Float(0.0));
            let inner = text.trim_start_matches('[').trim_end_matches(']');
            toml::Value::Array(
                inner
                    .split(',')
                    .filter(|s| !s.trim().is_empty())
                    .map(|s| parse_like(&item, s.trim()))
                    .collect::<Option<_>>()?,
            )
        }
        _ => return None,
    })
}

/// A session error as one line for the pane (without the file path).
pub fn error_line(e: &SessionError) -> String {
    match e {
        SessionError::Value {
            location, error, ..
        } => format!("{location}: {error}"),
        SessionError::Syntax { message, .. } => message.clone(),
        SessionError::Io { error, .. } => error.to_string(),
    }
}

/// The pane's state as drawn.
pub struct ParamsPane<'a> {
    pub rows: &'a [&'a Row],
    pub selected: usize,
    /// The text being typed, if editing.
    pub editing: Option<&'a LineEdit>,
    pub error: Option<&'a str>,
    pub focused: bool,
    /// The filter the rows are listed by, if it hides some.
    pub filter: Option<&'a str>,
    pub theme: &'a Theme,
}

impl Widget for ParamsPane<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let t = self.theme;
        let inner = Block::default().borders(Borders::ALL).inner(area);
        let (list_h, error_rows) = self.heights(inner);
        let (lines, selected_line, _) = self.lines(inner.width as usize);
        let skip = (selected_line + 1).saturating_sub(list_h);
        let (above, below) = (skip, lines.len().saturating_sub(skip + list_h));
        // what is out of sight is counted on the borders
        let mut block = Block::default()
            .borders(Borders::ALL)
            .border_style(t.border(self.focused))
            .title(match self.filter {
                Some(f) => format!(" Parameters /{f} "),
                None => " Parameters ".to_string(),
            });
        if above > 0 {
            block =
                block.title(Line::styled(format!(" ↑ {above} more "), t.muted()).right_aligned());
        }
        if below > 0 {
            block = block
                .title_bottom(Line::styled(format!(" ↓ {below} more "), t.muted()).right_aligned());
        }
        block.render(area, buf);
        let visible: Vec<Line> = lines.into_iter().skip(skip).take(list_h).collect();
        Paragraph::new(visible)
            .render(Rect::new(inner.x, inner.y, inner.width, list_h as u16), buf);
        if let Some(e) = self.error {
            Paragraph::new(Line::styled(e.to_string(), t.error()))
                .wrap(Wrap { trim: true })
                .render(
                    Rect::new(inner.x, inner.y + list_h as u16, inner.width, error_rows),
                    buf,
                );
        }
    }
}

impl ParamsPane<'_> {
    /// The row (of `rows`) on each line of the pane drawn in `area`, top down; `None` on a
    /// heading.
    pub fn shown(&self, area: Rect) -> Vec<Option<usize>> {
        let inner = Block::default().borders(Borders::ALL).inner(area);
        let (list_h, _) = self.heights(inner);
        let (_, selected_line, row_of_line) = self.lines(inner.width as usize);
        let skip = (selected_line + 1).saturating_sub(list_h);
        row_of_line.into_iter().skip(skip).take(list_h).collect()
    }

    /// The rows of the list and of the error under it (wrapped, at most 4) inside `inner`.
    fn heights(&self, inner: Rect) -> (usize, u16) {
        let error_rows = self.error.map_or(0, |e| {
            (e.chars().count() as u16)
                .div_ceil(inner.width.max(1))
                .min(4)
        });
        (inner.height.saturating_sub(error_rows) as usize, error_rows)
    }

    /// Every line of the pane at `width` cells, the line of the selected row, and the row on
    /// each line. The model's
    /// rows come first, then the settings; nested settings (`steady.max_period`) under a
    /// heading of their table (`steady`), by their own name. Labels are aligned within each
    /// group and cut at the front only when a label and its value cannot both fit.
    fn lines(&self, width: usize) -> (Vec<Line<'static>>, usize, Vec<Option<usize>>) {
        let t = self.theme;
        let cells = |s: &str| Span::raw(s).width();
        // (group heading, label as shown) of each row
        let shown: Vec<(String, String)> = self
            .rows
            .iter()
            .map(|row| match &row.target {
                Target::Model { .. } | Target::Derived(_) => {
                    ("model".to_string(), row.label.clone())
                }
                Target::Setting { path, .. } if path.len() > 1 => (
                    path[..path.len() - 1].join("."),
                    format!("  {}", path[path.len() - 1]),
                ),
                Target::Setting { .. } => ("settings".to_string(), row.label.clone()),
            })
            .collect();
        let group_width = |group: &str| {
            shown
                .iter()
                .filter(|(g, _)| g == group)
                .map(|(_, l)| cells(l))
                .max()
                .unwrap_or(4)
        };
        let mut lines: Vec<Line> = Vec::new();
        let mut row_of_line: Vec<Option<usize>> = Vec::new();
        let mut selected_line = 0;
        let mut last_group: Option<&str> = None;
        let mut settings_said = false;
        for (i, (row, (group, label))) in self.rows.iter().zip(&shown).enumerate() {
            if last_group != Some(group.as_str()) {
                let setting = matches!(row.target, Target::Setting { .. });
                if setting && !settings_said {
                    lines.push(Line::styled("settings", t.muted()));
                    row_of_line.push(None);
                    settings_said = true;
                }
                if group != "settings" {
                    lines.push(Line::styled(group.clone(), t.muted()));
                    row_of_line.push(None);
                }
                last_group = Some(group.as_str());
            }
            if i == self.selected {
                selected_line = lines.len();
            }
            let editing = self.editing.filter(|_| i == self.selected);
            let mut whole = None;
            let value_w = match editing {
                // a long text scrolls in its box rather than squeeze the names
                Some(text) => text.width().min(width / 2),
                None => cells(&row.value) + usize::from(row.overridden),
            };
            let label_w = group_width(group).min(width.saturating_sub(value_w + 1).max(4));
            // padded by the cells it takes, not its chars (c̃ is two chars in one cell)
            let label = truncate(label, label_w);
            let pad = label_w.saturating_sub(cells(&label));
            let mut spans = vec![Span::raw(format!("{label}{} ", " ".repeat(pad)))];
            match editing {
                Some(text) => spans.extend(text.spans_within(
                    width.saturating_sub(label_w + 1),
                    t.cursor(),
                    t.selection(),
                )),
                None => {
                    spans.push(Span::raw(row.value.clone()));
                    if row.overridden {
                        spans.push(Span::styled("*", t.warn()));
                    }
                    // the physical form only where it fits whole: never "37.4 MV/m p"; a
                    // written model's words about a parameter cut short where they do not
                    let room = width.saturating_sub(label_w + 1 + value_w + 2);
                    let words = matches!(row.target, Target::Model { physical: None, .. });
                    let shown = if cells(&row.physical) <= room {
                        Some(row.physical.clone())
                    } else if words && room >= 6 {
                        let cut: String = row.physical.chars().take(room - 1).collect();
                        Some(format!("{cut}…"))
                    } else {
                        None
                    };
                    if shown.as_ref() != Some(&row.physical) && i == self.selected {
                        whole = Some(row.physical.clone());
                    }
                    if let Some(text) = shown.filter(|s| !s.is_empty()) {
                        spans.push(Span::styled(format!("  {text}"), t.muted()));
                    }
                }
            }
            let mut line = Line::from(spans);
            if i == self.selected && self.focused {
                line = line.style(t.selected());
            }
            lines.push(line);
            row_of_line.push(Some(i));
            // the selected row's words, where cut or left out, whole on the lines under it
            for part in whole
                .take()
                .map_or_else(Vec::new, |w| super::wrap(&w, width.saturating_sub(2)))
            {
                lines.push(Line::styled(format!("  {part}"), t.muted()));
                row_of_line.push(Some(i));
            }
        }
        (lines, selected_line, row_of_line)
    }
}

fn truncate(s: &str, n: usize) -> String {
    if s.chars().count() <= n {
        s.to_string()
    } else {
        let keep: String = s
            .chars()
            .rev()
            .take(n.saturating_sub(1))
            .collect::<Vec<_>>()
            .into_iter()
            .rev()
            .collect();
        format!("…{keep}")
    }
}
