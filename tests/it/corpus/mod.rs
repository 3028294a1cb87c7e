//! The generator of hostile sessions: from one cheap session per analysis kind, with every
//! setting written out, one field at a time is given a hostile value (NaN, ±inf, 1e400, -0,
//! 5e-324, ±1e308, huge and negative integers, text, a boolean, an array, a table), every
//! range gets min > max, every quantity with two forms gets both, and every model and device
//! key is set out of range. Each case says which field it touched, as the user wrote it.

use isola::session::Session;

/// One generated session.
#[derive(Debug, Clone)]
pub struct Case {
    /// What was done, for messages: `basin: settings.dx.points = -1`.
    pub label: String,
    /// The key the user wrote, as an error must name it (`dx.points`, `frequency_hz`).
    pub field: String,
    pub text: String,
}

/// Hostile values, as written in TOML.
pub const VALUES: [&str; 16] = [
    "nan",
    "inf",
    "-inf",
    "1e400",
    "-0.0",
    "5e-324",
    "1e308",
    "-1e308",
    "9223372036854775807",
    "-9223372036854775808",
    "-1",
    "0",
    "\"text\"",
    "true",
    "[1, 2]",
    "{ a = 1 }",
];

/// The cheap session of each kind (a few seconds at most in all).
pub const BASES: [(&str, &str); 10] = [
    ("force_curve", "points = 41\n"),
    ("time_history", "dx0 = 0.3\n"),
    (
        "chirp_sweep",
        "span = 200.0\nomega_end = 4.0\nscalogram = { columns = 20 }\n",
    ),
    (
        "stepped_sweep",
        "omega = { min = 3.5, max = 3.9, points = 3 }\n",
    ),
    (
        "frequency_response",
        "omega = { min = 3.5, max = 3.9, points = 3 }\ndx = { min = -0.6, max = 0.6, points = 3 }\nv = { min = -0.8, max = 0.8, points = 3 }\n",
    ),
    (
        "basin",
        "dx = { min = -0.8, max = 0.8, points = 3 }\nv = { min = -1.0, max = 1.0, points = 3 }\n",
    ),
    (
        "family",
        "parameter = \"adr\"\nvalues = [0.5, 0.6]\n[analysis.settings.response]\nomega = { min = 3.6, max = 3.8, points = 2 }\ndx = { min = -0.6, max = 0.6, points = 2 }\nv = { min = -0.8, max = 0.8, points = 2 }\n",
    ),
    (
        "continuation",
        "dx0 = 0.3\n[analysis.settings.continuation]\nparameter = \"omega\"\nmin = 3.6\nmax = 3.8\nmax_points = 20\n",
    ),
    (
        "hunt",
        "[analysis.settings.response]\nomega = { min = 3.6, max = 3.8, points = 3 }\ndx = { min = -0.6, max = 0.6, points = 3 }\nv = { min = -0.8, max = 0.8, points = 3 }\n[analysis.settings.continuation]\nmin = 3.5\nmax = 3.9\nmax_points = 6\n",
    ),
    (
        "map",
        "parameter = \"adr\"\nvalues = { min = 0.5, max = 0.6, points = 2 }\ncurves = false\n[analysis.settings.response]\nomega = { min = 3.6, max = 3.8, points = 2 }\ndx = { min = -0.6, max = 0.6, points = 2 }\nv = { min = -0.8, max = 0.8, points = 2 }\n",
    ),
];

/// The settings that keep a time history of a hostile model short.
const SHORT: &str = "[analysis.settings]\nsteady = { max_forcing_periods = 300 }\n";

const PLACEHOLDER: &str = "@@hostile@@";

/// The base session of `kind` with every setting written out (defaults included).
fn expanded(kind: &str, settings: &str) -> toml::Table {
    let text = format!(
        "schema = 1\n[[analysis]]\nname = \"a\"\nkind = \"{kind}\"\n[analysis.settings]\n{settings}"
    );
    let session = Session::parse(std::path::Path::new("base.toml"), &text)
        .unwrap_or_else(|e| panic!("base session of {kind}: {e}"));
    let mut analysis = toml::Table::new();
    analysis.insert("name".into(), "a".into());
    analysis.insert("kind".into(), kind.into());
    analysis.insert("settings".into(), session.settings_table(0).into());
    let mut root = toml::Table::new();
    root.insert("schema".into(), 1.into());
    root.insert(
        "analysis".into(),
        toml::Value::Array(vec![toml::Value::Table(analysis)]),
    );
    root
}

/// Every leaf of `table` (arrays are leaves, and so is their first element), as dotted paths.
fn leaves(table: &toml::Table, prefix: &str, out: &mut Vec<Vec<String>>) {
    for (key, value) in table {
        let path: Vec<String> = prefix
            .split('.')
            .filter(|p| !p.is_empty())
            .map(str::to_string)
            .chain([key.clone()])
            .collect();
        match value {
            toml::Value::Table(t) => leaves(t, &path.join("."), out),
            toml::Value::Array(a) => {
                out.push(path.clone());
                if !a.is_empty() {
                    let mut first = path;
                    first.push("0".into());
                    out.push(first);
                }
            }
            _ => out.push(path),
        }
    }
}

/// `root` with the value at `path` (under the analysis' settings) replaced by `value`.
fn with_setting(root: &toml::Table, path: &[String], value: toml::Value) -> toml::Table {
    let mut root = root.clone();
    let analysis = root["analysis"].as_array_mut().unwrap()[0]
        .as_table_mut()
        .unwrap();
    let mut here = analysis.get_mut("settings").unwrap();
    for part in &path[..path.len() - 1] {
        here = match here {
            toml::Value::Table(t) => t.get_mut(part).unwrap(),
            toml::Value::Array(a) => &mut a[part.parse::<usize>().unwrap()],
            _ => unreachable!("a leaf inside a leaf"),
        };
    }
    let last = &path[path.len() - 1];
    match here {
        toml::Value::Table(t) => {
            t.insert(last.clone(), value);
        }
        toml::Value::Array(a) => a[last.parse::<usize>().unwrap()] = value,
        _ => unreachable!(),
    }
    root
}

fn render(root: &toml::Table, raw: &str) -> String {
    toml::to_string(root)
        .unwrap()
        .replace(&format!("\"{PLACEHOLDER}\""), raw)
}

/// The device table with one field replaced.
fn device(field: &str, raw: &str) -> String {
    let fields = [
        ("mu", "400e3"),
        ("j", "16.0"),
        ("l1", "20e-3"),
        ("l2", "200e-3"),
        ("l3", "0.1e-3"),
        ("mass", "50e-3"),
        ("epsilon", "2.48e-11"),
    ];
    let mut text = String::from("[device]\n");
    for (k, v) in fields {
        text.push_str(&format!("{k} = {}\n", if k == field { raw } else { v }));
    }
    text
}

/// Every hostile case.
pub fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    let history = "schema = 1\n[[analysis]]\nname = \"a\"\nkind = \"time_history\"\n";
    // model keys, one at a time, in [model] and as an analysis' override
    let keys = [
        "lambda_p",
        "j",
        "c_tilde",
        "damping_n_s_per_m",
        "omega",
        "frequency_hz",
        "e_a",
        "adr",
        "phi_dc",
        "phi_ac",
        "dc_kv",
        "ac_kv",
        "phi_dc_ii",
        "phi_ac_ii",
        "phase_ii",
    ];
    for key in keys {
        for raw in VALUES {
            out.push(Case {
                label: format!("[model] {key} = {raw}"),
                field: key.into(),
                // a short history: an undamped model never settles, and would run 2000 periods
                text: format!(
                    "schema = 1\n[model]\n{key} = {raw}\n[[analysis]]\nname = \"a\"\nkind = \"time_history\"\n{SHORT}"
                ),
            });
        }
        out.push(Case {
            label: format!("analysis model {key} = 1e6"),
            field: key.into(),
            text: format!("{history}model = {{ {key} = 1e6 }}\n{SHORT}"),
        });
    }
    // both forms of one quantity
    for (a, b, va, vb) in [
        ("omega", "frequency_hz", "3.7", "50"),
        ("c_tilde", "damping_n_s_per_m", "0.04", "0.3"),
        ("phi_dc", "dc_kv", "0.1", "1.0"),
        ("phi_ac", "ac_kv", "0.1", "1.0"),
        ("e_a", "phi_dc", "0.04", "0.1"),
        ("adr", "phi_ac", "0.6", "0.1"),
    ] {
        out.push(Case {
            label: format!("[model] {a} and {b}"),
            field: b.into(),
            text: format!("schema = 1\n[model]\n{a} = {va}\n{b} = {vb}\n"),
        });
    }
    // device fields
    for field in ["mu", "j", "l1", "l2", "l3", "mass", "epsilon"] {
        for raw in ["nan", "inf", "-1", "0", "1e300", "5e-324", "\"text\""] {
            out.push(Case {
                label: format!("[device] {field} = {raw}"),
                field: field.into(),
                text: format!(
                    "schema = 1\n{}\n[[analysis]]\nname = \"a\"\nkind = \"time_history\"\n",
                    device(field, raw)
                ),
            });
        }
    }
    // every setting of every kind
    for (kind, settings) in BASES {
        let root = expanded(kind, settings);
        let mut paths = Vec::new();
        let analysis = root["analysis"].as_array().unwrap()[0].as_table().unwrap();
        leaves(analysis["settings"].as_table().unwrap(), "", &mut paths);
        for path in &paths {
            let field = path
                .iter()
                .filter(|p| p.parse::<usize>().is_err())
                .cloned()
                .collect::<Vec<_>>()
                .join(".");
            let hostile = with_setting(&root, path, PLACEHOLDER.into());
            for raw in VALUES {
                out.push(Case {
                    label: format!("{kind}: settings.{} = {raw}", path.join(".")),
                    field: field.clone(),
                    text: render(&hostile, raw),
                });
            }
        }
        // every range with min > max
        for path in paths
            .iter()
            .filter(|p| p.last().is_some_and(|l| l == "min"))
        {
            let parent = &path[..path.len() - 1];
            let get = |name: &str| {
                let mut here = analysis["settings"].clone();
                for part in parent {
                    here = here[part.as_str()].clone();
                }
                here[name].clone()
            };
            let (lo, hi) = (get("min"), get("max"));
            if lo == hi {
                continue;
            }
            let mut max_path = parent.to_vec();
            max_path.push("max".into());
            let swapped = with_setting(&with_setting(&root, path, hi), &max_path, lo);
            out.push(Case {
                label: format!("{kind}: settings.{} min > max", parent.join(".")),
                field: parent.join("."),
                text: render(&swapped, ""),
            });
        }
    }
    out
}
