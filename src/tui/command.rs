//! The command line on `:`: what a key does, and more, as words (`run stale`, `add basin b2`,
//! `set omega 50 Hz`), with Tab completing command, kind and analysis names.

use std::path::PathBuf;

use isola::session::schema::KINDS;

/// Which analyses `run` runs.
#[derive(Debug, Clone, PartialEq)]
pub enum Which {
    Selected,
    All,
    /// Every analysis without a current result (stale, partial or never run).
    Stale,
    Named(String),
}

/// A command as typed.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    Run(Which),
    Add {
        kind: String,
        name: String,
    },
    Duplicate {
        name: String,
    },
    Rename {
        name: String,
    },
    Delete {
        name: Option<String>,
    },
    Set {
        field: String,
        value: String,
    },
    /// A model value for the selected analysis only.
    Override {
        field: String,
        value: String,
    },
    Select {
        name: String,
    },
    Save(Option<PathBuf>),
    Open(PathBuf),
    /// Load the session file again, as it is on disk (edited outside).
    Reload,
    /// `export FILE [--table T] [--where COLUMN OP VALUE]...`
    Export {
        path: PathBuf,
        table: Option<String>,
        filters: Vec<isola::session::select::Filter>,
    },
    /// Moves the plot cursor to the point nearest these coordinates (ω_e; Δλ v; ω_e and a
    /// map's parameter; τ); `hz`: the first is a frequency in Hz.
    Goto {
        at: Vec<f64>,
        hz: bool,
    },
    Theme(String),
    /// Writes the view shown as a figure: SVG or PNG by the file's extension.
    Figure(PathBuf),
    /// Draws analysis NAME's result muted under the selected one's (`None`: stop).
    Compare(Option<String>),
    /// What a key does, by its name in the config (`zoom`, `cancel`, `undo`...).
    Key(super::keymap::Action),
    Help,
    Quit,
}

/// Every command: its words, its arguments and what it does (for the help overlay).
pub const COMMANDS: [(&str, &str, &str); 18] = [
    (
        "run",
        "[all|stale|NAME]",
        "run the selected analysis, or these",
    ),
    ("add", "KIND NAME", "add an analysis of a kind"),
    ("dup", "NAME", "copy the selected analysis as NAME"),
    ("rename", "NAME", "rename the selected analysis"),
    ("delete", "[NAME]", "delete an analysis (asks)"),
    ("set", "FIELD VALUE", "set a parameter: set omega 50 Hz"),
    (
        "override",
        "FIELD VALUE",
        "set a model value for this analysis only",
    ),
    ("select", "NAME", "select an analysis"),
    ("save", "[FILE]", "save the session (as FILE)"),
    ("open", "FILE", "open a session"),
    (
        "reload",
        "",
        "load the session file as on disk (asks over edits)",
    ),
    (
        "export",
        "FILE [--table T] [--where C OP V]",
        "export the orbit shown or the result's rows",
    ),
    (
        "figure",
        "FILE",
        "write the view as a figure: FILE.svg, FILE.png or FILE.pdf",
    ),
    ("goto", "X [Y]", "move the cursor: 3.7 · 52 Hz · DX V"),
    ("theme", "NAME", "switch theme: dark, light, mono or a file"),
    (
        "compare",
        "[NAME]",
        "draw NAME's responses muted under these (none: stop)",
    ),
    ("help", "", "the keys and commands"),
    ("quit", "", "quit (asks if jobs run or edits are unsaved)"),
];

/// What each kind of analysis computes, for the kind picker (`a`).
pub const KIND_ABOUT: [(&str, &str); 10] = [
    ("force_curve", "the membranes' net force over Δλ (Fig 2)"),
    (
        "time_history",
        "one orbit, its transient and steady part (Fig 4/5)",
    ),
    (
        "chirp_sweep",
        "a slow sweep of ω_e up or down: jumps, envelope (Fig 3)",
    ),
    (
        "stepped_sweep",
        "ω_e stepped from the last state: what sweeps reach",
    ),
    (
        "frequency_response",
        "all responses per ω_e from many starts (Fig 4/5)",
    ),
    (
        "basin",
        "which start goes to which response, at one ω_e (Fig 6)",
    ),
    (
        "family",
        "frequency responses over a parameter's values (Fig 7–12)",
    ),
    (
        "continuation",
        "orbits followed in a parameter, with their stability",
    ),
    (
        "hunt",
        "a response, its subharmonic branches continued: isolas",
    ),
    (
        "map",
        "stable responses over ω_e and a parameter, with folds",
    ),
];

/// Parses a command line.
pub fn parse(line: &str) -> Result<Command, String> {
    // split as a shell would: `--where "omega >= 3.5"`, `'my results.csv'`
    let words = shlex::split(line).ok_or_else(|| {
        format!("{line}: a quote is not closed (\" and ' quote a word with spaces)")
    })?;
    let words: Vec<&str> = words.iter().map(String::as_str).collect();
    let Some((&verb, args)) = words.split_first() else {
        return Err("no command: : then e.g. run, add basin b2, set adr 1.0, help".into());
    };
    let usage = |verb: &str| {
        let (_, args, _) = COMMANDS
            .iter()
            .find(|(v, _, _)| *v == verb)
            .unwrap_or(&("", "", ""));
        format!("usage: {verb} {args}")
    };
    let one = |verb: &str| match args {
        [name] => Ok(name.to_string()),
        _ => Err(usage(verb)),
    };
    let path = |verb: &str| one(verb).map(PathBuf::from);
    Ok(match verb {
        "run" | "r" => Command::Run(match args {
            [] => Which::Selected,
            ["all"] => Which::All,
            ["stale"] => Which::Stale,
            [name] => Which::Named(name.to_string()),
            _ => return Err(usage("run")),
        }),
        "add" => match args {
            [kind, name] => Command::Add {
                kind: kind.to_string(),
                name: name.to_string(),
            },
            _ => return Err(format!("{} (kinds: {})", usage("add"), KINDS.join(", "))),
        },
        "dup" | "duplicate" => Command::Duplicate { name: one("dup")? },
        "rename" => Command::Rename {
            name: one("rename")?,
        },
        "delete" | "del" => match args {
            [] => Command::Delete { name: None },
            [name] => Command::Delete {
                name: Some(name.to_string()),
            },
            _ => return Err(usage("delete")),
        },
        "set" | "override" => {
            // FIELD, then the value: the rest, units and all (`50 Hz`)
            let [field, value @ ..] = args else {
                return Err(usage(verb));
            };
            if value.is_empty() {
                return Err(usage(verb));
            }
            let (field, value) = (field.to_string(), value.join(" "));
            if verb == "set" {
                Command::Set { field, value }
            } else {
                Command::Override { field, value }
            }
        }
        "select" | "sel" => Command::Select {
            name: one("select")?,
        },
        "save" | "w" => match args {
            [] => Command::Save(None),
            [file] => Command::Save(Some(PathBuf::from(file))),
            _ => return Err(usage("save")),
        },
        "open" | "e!" => Command::Open(path("open")?),
        "reload" | "e" => match args {
            [] => Command::Reload,
            _ => return Err(usage("reload")),
        },
        "export" => export(args).map_err(|e| format!("{e}; {}", usage("export")))?,
        "figure" => Command::Figure(path("figure")?),
        "help" | "?" => Command::Help,
        "quit" | "q" => Command::Quit,
        "goto" | "g" => goto(args).ok_or_else(|| usage("goto"))?,
        "theme" => Command::Theme(one("theme")?),
        "compare" => match args {
            [] => Command::Compare(None),
            [name] => Command::Compare(Some(name.to_string())),
            _ => return Err(usage("compare")),
        },
        other if args.is_empty() && super::keymap::Action::parse(other).is_some() => {
            Command::Key(super::keymap::Action::parse(other).expect("checked"))
        }
        other => {
            let verbs: Vec<&str> = COMMANDS.iter().map(|(v, _, _)| *v).collect();
            return Err(format!(
                "'{other}': not a command ({}, or a key's name: see help)",
                verbs.join(", ")
            ));
        }
    })
}

/// `X [Y]` as numbers, or `X Hz`.
fn goto(args: &[&str]) -> Option<Command> {
    let number = |s: &str| s.parse::<f64>().ok().filter(|x| x.is_finite());
    let hz = matches!(args, [_, "Hz" | "hz"]);
    Some(Command::Goto {
        at: match args {
            [x, "Hz" | "hz"] | [x] => vec![number(x)?],
            [x, y] => vec![number(x)?, number(y)?],
            _ => return None,
        },
        hz,
    })
}

/// `FILE [--table T] [--where COLUMN OP VALUE]...`: a condition may be written with spaces
/// (`--where omega >= 3.5`), up to the next `--`.
fn export(args: &[&str]) -> Result<Command, String> {
    let Some((path, mut rest)) = args.split_first() else {
        return Err("no file".into());
    };
    let (mut table, mut filters) = (None, Vec::new());
    while let Some((&flag, after)) = rest.split_first() {
        let end = after
            .iter()
            .position(|w| w.starts_with("--"))
            .unwrap_or(after.len());
        let value = after[..end].join(" ");
        match flag {
            "--table" if end == 1 => table = Some(value),
            "--where" if end > 0 => filters
                .push(isola::session::select::parse_filter(&value).map_err(|e| e.to_string())?),
            other => return Err(format!("'{other}' after the file")),
        }
        rest = &after[end..];
    }
    Ok(Command::Export {
        path: PathBuf::from(path),
        table,
        filters,
    })
}

/// The line with its last word completed, if exactly one completion fits (or their common
/// start, if longer than what is typed): command names first, then kinds after `add`,
/// analysis names after `run`, `delete` and `select`.
pub fn complete(line: &str, analyses: &[String]) -> Option<String> {
    let ends_in_space = line.ends_with(' ');
    let mut words: Vec<&str> = line.split_whitespace().collect();
    if ends_in_space || words.is_empty() {
        words.push("");
    }
    let last = *words.last()?;
    let choices: Vec<String> = match words.len() {
        1 => COMMANDS.iter().map(|(v, _, _)| v.to_string()).collect(),
        2 => match words[0] {
            "add" => KINDS.iter().map(|k| k.to_string()).collect(),
            "run" => ["all", "stale"]
                .iter()
                .map(|s| s.to_string())
                .chain(analyses.iter().cloned())
                .collect(),
            "delete" | "select" | "compare" => analyses.to_vec(),
            "theme" => ["dark", "light", "mono"].map(String::from).to_vec(),
            _ => return None,
        },
        _ => return None,
    };
    let fitting: Vec<&String> = choices.iter().filter(|c| c.starts_with(last)).collect();
    let common = fitting.split_first().map(|(first, rest)| {
        rest.iter().fold(first.as_str(), |common, c| {
            let n = common
                .char_indices()
                .zip(c.chars())
                .take_while(|((_, a), b)| a == b)
                .last()
                .map_or(0, |((i, a), _)| i + a.len_utf8());
            &common[..n]
        })
    })?;
    if common.len() <= last.len() && fitting.len() > 1 {
        return None;
    }
    let head = &words[..words.len() - 1];
    let mut out: String = head.iter().map(|w| format!("{w} ")).collect();
    out.push_str(common);
    if fitting.len() == 1 {
        out.push(' ');
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands_parse_with_their_arguments() {
        assert_eq!(parse("run").unwrap(), Command::Run(Which::Selected));
        assert_eq!(parse(" run  stale ").unwrap(), Command::Run(Which::Stale));
        assert_eq!(
            parse("run b2").unwrap(),
            Command::Run(Which::Named("b2".into()))
        );
        assert_eq!(
            parse("add basin b2").unwrap(),
            Command::Add {
                kind: "basin".into(),
                name: "b2".into()
            }
        );
        assert_eq!(
            parse("set omega 50 Hz").unwrap(),
            Command::Set {
                field: "omega".into(),
                value: "50 Hz".into()
            }
        );
        assert_eq!(parse("delete").unwrap(), Command::Delete { name: None });
        assert_eq!(parse("save").unwrap(), Command::Save(None));
        assert!(
            parse("add basin")
                .unwrap_err()
                .contains("usage: add KIND NAME")
        );
        assert!(
            parse("set adr")
                .unwrap_err()
                .contains("usage: set FIELD VALUE")
        );
        assert!(parse("fly").unwrap_err().contains("not a command"));
        assert!(parse("").is_err());
    }

    /// Quotes group words as a shell's do: a condition written as the README's command
    /// lines write it, a path with spaces (both failed: `'3.5"' is not a finite number`,
    /// `usage: figure FILE`); a quote left open is named.
    #[test]
    fn quoted_words_are_one_argument() {
        let Command::Export {
            path,
            table,
            filters,
        } = parse(r#"export "my results.csv" --where "omega>=3.5" --table points"#).unwrap()
        else {
            panic!("not an export");
        };
        assert_eq!(path, PathBuf::from("my results.csv"));
        assert_eq!(table.as_deref(), Some("points"));
        assert_eq!(filters.len(), 1);
        assert_eq!(
            parse("figure 'fig 4.svg'").unwrap(),
            Command::Figure(PathBuf::from("fig 4.svg"))
        );
        assert_eq!(
            parse(r#"save "a b.toml""#).unwrap(),
            Command::Save(Some(PathBuf::from("a b.toml")))
        );
        assert!(
            parse(r#"export x.csv --where "omega >= 3"#)
                .unwrap_err()
                .contains("a quote is not closed")
        );
    }

    #[test]
    fn tab_completes_commands_kinds_and_names() {
        let names = vec![
            "basin".to_string(),
            "basin_b".to_string(),
            "orbit".to_string(),
        ];
        assert_eq!(complete("ru", &names).as_deref(), Some("run "));
        assert_eq!(complete("add ba", &names).as_deref(), Some("add basin "));
        assert_eq!(
            complete("add fr", &names).as_deref(),
            Some("add frequency_response ")
        );
        // two names share "basin": completed to it, no space
        assert_eq!(
            complete("delete b", &names).as_deref(),
            Some("delete basin")
        );
        assert_eq!(complete("run o", &names).as_deref(), Some("run orbit "));
        assert_eq!(complete("run st", &names).as_deref(), Some("run stale "));
        // nothing more to add, or nothing fits
        assert_eq!(complete("s", &names), None);
        assert_eq!(complete("zz", &names), None);
        assert_eq!(complete("set omega 3", &names), None);
    }
}
