//! The command line on `:`: what a key does, and more, as words (`run stale`, `add basin b2`,
//! `set omega 50 Hz`), with Tab completing command, kind and analysis names and paths.

use std::path::{Path, PathBuf};

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
    let path = |verb: &str| one(verb).map(|p| home_path(&p));
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
            [file] => Command::Save(Some(home_path(file))),
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
        path: home_path(path),
        table,
        filters,
    })
}

/// `path` as typed, a leading `~` (alone or before `/`) standing for the home folder, as in a
/// shell.
pub fn home_path(path: &str) -> PathBuf {
    let home = std::env::var_os("HOME").filter(|h| !h.is_empty());
    match (path.strip_prefix('~'), home) {
        (Some(rest), Some(home)) if rest.is_empty() || rest.starts_with('/') => {
            PathBuf::from(home).join(rest.trim_start_matches('/'))
        }
        _ => PathBuf::from(path),
    }
}

/// What Tab makes of the text before the cursor.
#[derive(Debug, Default, PartialEq)]
pub struct Completion {
    /// That text completed, where Tab adds to it.
    pub line: Option<String>,
    /// What fits the word being completed, as shown, where more than one thing does.
    pub choices: Vec<String>,
}

/// Lists a folder: each entry's name and whether it is a folder (empty if it cannot be read).
pub type ListDir<'a> = &'a dyn Fn(&Path) -> Vec<(String, bool)>;

/// Completes the last word of `line`: command names first, then kinds after `add`, analysis
/// names after `run`, `delete`, `select` and `compare`, themes after `theme`, and paths after
/// `open`, `save`, `export` and `figure` (through `list`, relative to the working folder).
/// One fitting choice is completed (with a space after it, unless it is a folder); several
/// are completed as far as they agree and listed.
pub fn complete(line: &str, analyses: &[String], list: ListDir) -> Completion {
    let ends_in_space = line.ends_with(' ');
    let mut words: Vec<&str> = line.split_whitespace().collect();
    if ends_in_space || words.is_empty() {
        words.push("");
    }
    let Some((&last, head)) = words.split_last() else {
        return Completion::default();
    };
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
            "open" | "save" | "export" | "figure" => path_choices(last, list),
            _ => Vec::new(),
        },
        _ => Vec::new(),
    };
    let head: String = head.iter().map(|w| format!("{w} ")).collect();
    finish(&head, last, choices, true)
}

/// Completes `text` as a path (the save-as, export and open boxes), through `list`; no space
/// after a file, the box holds one path.
pub fn complete_path(text: &str, list: ListDir) -> Completion {
    finish("", text, path_choices(text, list), false)
}

/// The entries of `word`'s folder whose names start as its last part does, as the whole word
/// (`sessions/fig04.toml`, a folder with `/` after it); hidden ones only if asked with `.`.
fn path_choices(word: &str, list: ListDir) -> Vec<String> {
    // the folder listed, as typed before the name (kept in each choice), and the name's start
    let (dir, prefix, start) = match word.rsplit_once('/') {
        None => (Path::new("."), String::new(), word),
        Some(("", start)) => (Path::new("/"), "/".to_string(), start),
        Some((folder, start)) => (Path::new(folder), format!("{folder}/"), start),
    };
    let mut choices: Vec<String> = list(dir)
        .into_iter()
        .filter(|(name, _)| {
            name.starts_with(start) && (start.starts_with('.') || !name.starts_with('.'))
        })
        .map(|(name, is_dir)| format!("{prefix}{name}{}", if is_dir { "/" } else { "" }))
        .collect();
    choices.sort();
    choices
}

/// `head` and `last` completed by `choices` (the whole words that fit or not), `space` after
/// a word completed whole.
fn finish(head: &str, last: &str, choices: Vec<String>, space: bool) -> Completion {
    let fitting: Vec<&String> = choices.iter().filter(|c| c.starts_with(last)).collect();
    let Some(common) = fitting.split_first().map(|(first, rest)| {
        rest.iter().fold(first.as_str(), |common, c| {
            let n = common
                .char_indices()
                .zip(c.chars())
                .take_while(|((_, a), b)| a == b)
                .last()
                .map_or(0, |((i, a), _)| i + a.len_utf8());
            &common[..n]
        })
    }) else {
        return Completion::default();
    };
    let mut done = Completion::default();
    if fitting.len() > 1 {
        // a path's choices shown by their names, without the folder typed
        let folder = last.rfind('/').map_or(0, |i| i + 1);
        done.choices = fitting
            .iter()
            .map(|c| c.get(folder..).unwrap_or(c).to_string())
            .collect();
    }
    if fitting.len() == 1 || common.len() > last.len() {
        let mut line = format!("{head}{common}");
        if space && fitting.len() == 1 && !common.ends_with('/') {
            line.push(' ');
        }
        done.line = Some(line);
    }
    done
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

    /// A folder of two sessions, a figure and a subfolder, as `list` shows it.
    fn listing(dir: &Path) -> Vec<(String, bool)> {
        match dir.to_str() {
            Some(".") => vec![
                ("fig04.toml".into(), false),
                ("fig06.toml".into(), false),
                ("figs".into(), true),
                (".hidden.toml".into(), false),
            ],
            Some("figs") => vec![("a.svg".into(), false)],
            _ => Vec::new(),
        }
    }

    #[test]
    fn tab_completes_commands_kinds_and_names() {
        let names = vec![
            "basin".to_string(),
            "basin_b".to_string(),
            "orbit".to_string(),
        ];
        let line = |text: &str| complete(text, &names, &listing).line;
        assert_eq!(line("ru").as_deref(), Some("run "));
        assert_eq!(line("add ba").as_deref(), Some("add basin "));
        assert_eq!(line("add fr").as_deref(), Some("add frequency_response "));
        // two names share "basin": completed to it, no space, and both listed
        let both = complete("delete b", &names, &listing);
        assert_eq!(both.line.as_deref(), Some("delete basin"));
        assert_eq!(both.choices, ["basin", "basin_b"]);
        assert_eq!(line("run o").as_deref(), Some("run orbit "));
        assert_eq!(line("run st").as_deref(), Some("run stale "));
        // nothing more to add: the choices are listed
        let s = complete("se", &names, &listing);
        assert_eq!(s.line, None);
        assert_eq!(s.choices, ["set", "select"]);
        assert_eq!(complete("s", &names, &listing).choices.len(), 3);
        // nothing fits
        assert_eq!(complete("zz", &names, &listing), Completion::default());
        assert_eq!(
            complete("set omega 3", &names, &listing),
            Completion::default()
        );
    }

    #[test]
    fn a_leading_tilde_is_the_home_folder() {
        let home = PathBuf::from(std::env::var_os("HOME").expect("HOME"));
        assert_eq!(home_path("~/runs/a.toml"), home.join("runs/a.toml"));
        assert_eq!(home_path("~"), home);
        assert_eq!(
            parse("open ~/a.toml").unwrap(),
            Command::Open(home.join("a.toml"))
        );
        // another user's home, or a tilde inside a name: as typed
        assert_eq!(home_path("~bob/a.toml"), PathBuf::from("~bob/a.toml"));
        assert_eq!(home_path("a~/b"), PathBuf::from("a~/b"));
    }

    #[test]
    fn tab_completes_paths_after_the_commands_that_take_one() {
        let names = Vec::new();
        let c = |text: &str| complete(text, &names, &listing);
        // as far as the files agree, then listed by name
        let fig = c("open f");
        assert_eq!(fig.line.as_deref(), Some("open fig"));
        assert_eq!(fig.choices, ["fig04.toml", "fig06.toml", "figs/"]);
        assert_eq!(c("open fig04").line.as_deref(), Some("open fig04.toml "));
        // a folder gets its slash and no space; its files are listed without it
        assert_eq!(c("figure figs").line.as_deref(), Some("figure figs/"));
        assert_eq!(
            c("figure figs/").line.as_deref(),
            Some("figure figs/a.svg ")
        );
        // hidden files only when asked for
        assert!(!c("open ").choices.iter().any(|f| f.starts_with('.')));
        assert_eq!(c("open .h").line.as_deref(), Some("open .hidden.toml "));
        // not after other commands
        assert_eq!(c("set f"), Completion::default());
        // a path box completes its whole text
        assert_eq!(
            complete_path("figs/", &listing).line.as_deref(),
            Some("figs/a.svg")
        );
    }
}
