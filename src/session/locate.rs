//! Where a value is written in a session file: the line of a key and its text as the user
//! wrote it, for error messages that point at the file.

/// A table of the file: `[model]`, `[device]`, or the model or settings of `[[analysis]]` N.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Table {
    Model,
    Device,
    AnalysisModel(usize),
    AnalysisSettings(usize),
    /// The `[[analysis]]` table itself.
    Analysis(usize),
}

/// Where a field is written: its line (1-based) and its value's text, if it is written at all.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Written {
    pub line: Option<usize>,
    /// The value as written (`1e-9`, `nan`, `{ min = 1, max = 0, points = 3 }`).
    pub text: Option<String>,
}

fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

/// Finds `field` (a dotted path such as `steady.resolution.max_step`) in `table` of `text`.
/// If the field itself is not written, the line of its nearest written parent (or of the
/// table) is given, without a text.
pub fn locate(text: &str, table: Table, field: &str) -> Written {
    let Ok(doc) = toml_edit::Document::parse(text.to_string()) else {
        return Written::default();
    };
    let root = doc.as_item();
    let analysis = |i: usize| {
        root.get("analysis")
            .and_then(|a| a.as_array_of_tables())
            .and_then(|a| a.get(i))
    };
    let (start, span): (
        Option<&dyn toml_edit::TableLike>,
        Option<std::ops::Range<usize>>,
    ) = match table {
        Table::Model => (
            root.get("model").and_then(|m| m.as_table_like()),
            root.get("model").and_then(|m| m.span()),
        ),
        Table::Device => (
            root.get("device").and_then(|m| m.as_table_like()),
            root.get("device").and_then(|m| m.span()),
        ),
        Table::AnalysisModel(i) | Table::AnalysisSettings(i) | Table::Analysis(i) => {
            let key = match table {
                Table::AnalysisModel(_) => Some("model"),
                Table::AnalysisSettings(_) => Some("settings"),
                _ => None,
            };
            match (analysis(i), key) {
                (Some(a), Some(k)) => match a.get(k) {
                    Some(item) => (item.as_table_like(), item.span().or(a.span())),
                    None => (None, a.span()),
                },
                (Some(a), None) => (Some(a as &dyn toml_edit::TableLike), a.span()),
                (None, _) => (None, None),
            }
        }
    };
    let mut best = Written {
        line: span.map(|s| line_of(text, s.start)),
        text: None,
    };
    let Some(mut table) = start else {
        return best;
    };
    let parts: Vec<&str> = field.split('.').collect();
    for (depth, part) in parts.iter().enumerate() {
        let Some((key, item)) = table.get_key_value(part) else {
            return best;
        };
        if let Some(s) = key.span() {
            best.line = Some(line_of(text, s.start));
        }
        if depth + 1 == parts.len() {
            best.text = item
                .span()
                .and_then(|s| text.get(s))
                .map(|t| t.trim().to_string())
                .or_else(|| item.as_value().map(|v| v.to_string().trim().to_string()));
            return best;
        }
        match item.as_table_like() {
            Some(t) => table = t,
            None => return best,
        }
    }
    best
}

/// A serde message in a user's words: `invalid value: integer `-3`, expected usize` becomes
/// `-3 is not allowed: a whole number >= 0 is expected`.
pub fn plain(message: &str) -> String {
    // the deserializer's own note of where (`in `dx.points``) is said elsewhere
    let message = message.lines().next().unwrap_or(message).trim();
    let quoted = |m: &str| m.split('`').nth(1).map(str::to_string);
    let expected = message.rsplit("expected ").next().unwrap_or("").trim();
    let what = match expected {
        "usize" | "u32" | "u64" | "u16" | "u8" => Some("a whole number >= 0"),
        "i32" | "i64" | "isize" => Some("a whole number"),
        "f64" | "f32" => Some("a number"),
        "a boolean" => Some("true or false"),
        "a string" => Some("text in quotes"),
        _ => None,
    };
    let found = quoted(message).or_else(|| {
        // `invalid type: string "x", expected f64`
        message
            .split_once("string ")
            .map(|(_, rest)| rest.split(", expected").next().unwrap_or(rest).to_string())
    });
    // a number or a list where a table of settings goes
    if let Some(name) = expected.strip_prefix("struct ") {
        let fields = match name.split_whitespace().next().unwrap_or("") {
            "Tolerance" => "{ rtol = …, atol = … }",
            "Axis" => "{ min = …, max = …, points = … }",
            _ => "of its settings",
        };
        let given = [
            ("floating point", "a number"),
            ("integer", "a number"),
            ("string", "text"),
            ("sequence", "a list"),
            ("length", "a list"),
            ("boolean", "true or false"),
        ]
        .into_iter()
        .find(|(serde_word, _)| message.contains(serde_word));
        if message.starts_with("invalid") {
            return match given {
                Some((_, given)) => format!("a table {fields} is expected, not {given}"),
                None => format!("a table {fields} is expected"),
            };
        }
    }
    match (what, found) {
        (Some(what), Some(found)) if message.starts_with("invalid") => {
            format!("{found} is not allowed: {what} is expected")
        }
        (Some(what), None) if message.starts_with("invalid") => {
            format!("{what} is expected ({message})")
        }
        _ => message.to_string(),
    }
}
