//! Actions and the keys bound to them; any binding can be changed in the config file's
//! `[keys]` table, e.g. `run = ["r", "f5"]`.

use std::collections::BTreeMap;

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

/// What a key asks the app to do.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Action {
    Quit,
    Help,
    FocusNext,
    FocusPrev,
    Up,
    Down,
    Left,
    Right,
    /// Larger cursor moves on plots.
    FastUp,
    FastDown,
    FastLeft,
    FastRight,
    Edit,
    Back,
    Run,
    CancelJob,
    Save,
    SaveAs,
    Open,
    Export,
    Zoom,
    Scalogram,
    /// The command line (`:`).
    Command,
    Undo,
    Redo,
    /// Holds the plot as it is while results keep coming in.
    Freeze,
    /// Shows only the analyses and parameters whose names contain a text.
    Filter,
    /// Adds an analysis: a kind to pick, then its name.
    Add,
    /// Writes the view shown as a figure (SVG) beside the session.
    Figure,
}

impl Action {
    /// Every action with its config name and a few words for the help overlay.
    pub const ALL: [(Action, &'static str, &'static str); 29] = [
        (Action::Quit, "quit", "quit (asks: jobs, edits)"),
        (Action::Help, "help", "this help"),
        (Action::FocusNext, "focus_next", "next pane"),
        (Action::FocusPrev, "focus_prev", "previous pane"),
        (Action::Up, "up", "move up"),
        (Action::Down, "down", "move down"),
        (Action::Left, "left", "move left"),
        (Action::Right, "right", "move right"),
        (Action::FastUp, "fast_up", "cursor up ×10"),
        (Action::FastDown, "fast_down", "cursor down ×10"),
        (Action::FastLeft, "fast_left", "cursor left ×10"),
        (Action::FastRight, "fast_right", "cursor right ×10"),
        (Action::Edit, "edit", "edit value / pick point"),
        (Action::Back, "back", "cancel edit, close"),
        (Action::Run, "run", "run selected analysis"),
        (Action::CancelJob, "cancel", "cancel job"),
        (Action::Save, "save", "save session"),
        (Action::SaveAs, "save_as", "save session as…"),
        (Action::Open, "open", "open a session"),
        (Action::Export, "export", "export result to CSV"),
        (Action::Zoom, "zoom", "plot full screen"),
        (Action::Scalogram, "scalogram", "sweep: envelope/scalogram"),
        (Action::Command, "command", "command line (below)"),
        (Action::Undo, "undo", "undo the last edit"),
        (Action::Redo, "redo", "redo what was undone"),
        (Action::Freeze, "freeze", "hold the plot / resume"),
        (Action::Filter, "filter", "filter the lists"),
        (Action::Add, "new", "add an analysis (pick a kind)"),
        (Action::Figure, "figure", "write the view as SVG"),
    ];

    /// The action of config (and command) name `name`.
    pub fn parse(name: &str) -> Option<Action> {
        Action::ALL
            .iter()
            .find(|(_, n, _)| *n == name)
            .map(|(a, _, _)| *a)
    }
}

/// A key as written in the config: `r`, `S`, `?`, `ctrl-s`, `shift-tab`, `enter`, `f5`...
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Key {
    code: KeyCode,
    ctrl: bool,
}

impl Key {
    pub fn parse(s: &str) -> Result<Key, String> {
        let (ctrl, rest) = match s.strip_prefix("ctrl-") {
            Some(rest) => (true, rest),
            None => (false, s),
        };
        let code = match rest {
            "tab" => KeyCode::Tab,
            "shift-tab" | "backtab" => KeyCode::BackTab,
            "enter" => KeyCode::Enter,
            "esc" => KeyCode::Esc,
            "up" => KeyCode::Up,
            "down" => KeyCode::Down,
            "left" => KeyCode::Left,
            "right" => KeyCode::Right,
            "pageup" => KeyCode::PageUp,
            "pagedown" => KeyCode::PageDown,
            "space" => KeyCode::Char(' '),
            f if f.starts_with('f') && f.len() > 1 => KeyCode::F(
                f[1..]
                    .parse()
                    .map_err(|_| format!("'{s}': not a key (f1 to f12)"))?,
            ),
            c if c.chars().count() == 1 => KeyCode::Char(c.chars().next().unwrap_or(' ')),
            _ => {
                return Err(format!(
                    "'{s}': not a key (a character, ctrl-x, tab, shift-tab, enter, esc, \
                     up/down/left/right, pageup/pagedown, space, f1…f12)"
                ));
            }
        };
        Ok(Key { code, ctrl })
    }

    fn of(event: &KeyEvent) -> Key {
        Key {
            code: event.code,
            ctrl: event.modifiers.contains(KeyModifiers::CONTROL),
        }
    }

    /// How the help overlay and status bar show it.
    pub fn label(&self) -> String {
        let base = match self.code {
            KeyCode::Tab => "Tab".into(),
            KeyCode::BackTab => "S-Tab".into(),
            KeyCode::Enter => "Enter".into(),
            KeyCode::Esc => "Esc".into(),
            KeyCode::Up => "↑".into(),
            KeyCode::Down => "↓".into(),
            KeyCode::Left => "←".into(),
            KeyCode::Right => "→".into(),
            KeyCode::PageUp => "PgUp".into(),
            KeyCode::PageDown => "PgDn".into(),
            KeyCode::F(n) => format!("F{n}"),
            KeyCode::Char(' ') => "Space".into(),
            KeyCode::Char(c) => c.to_string(),
            _ => "?".into(),
        };
        if self.ctrl { format!("C-{base}") } else { base }
    }
}

/// Keys for actions.
#[derive(Debug, Clone)]
pub struct Keymap {
    bindings: BTreeMap<Action, Vec<Key>>,
}

impl Default for Keymap {
    fn default() -> Self {
        let defaults: [(Action, &[&str]); 29] = [
            (Action::Quit, &["q"]),
            (Action::Help, &["?"]),
            (Action::FocusNext, &["tab"]),
            (Action::FocusPrev, &["shift-tab"]),
            (Action::Up, &["up", "k"]),
            (Action::Down, &["down", "j"]),
            (Action::Left, &["left", "h"]),
            (Action::Right, &["right", "l"]),
            (Action::FastUp, &["K", "pageup"]),
            (Action::FastDown, &["J", "pagedown"]),
            (Action::FastLeft, &["H"]),
            (Action::FastRight, &["L"]),
            (Action::Edit, &["enter"]),
            (Action::Back, &["esc"]),
            (Action::Run, &["r"]),
            (Action::CancelJob, &["c"]),
            (Action::Save, &["s"]),
            (Action::SaveAs, &["S"]),
            (Action::Open, &["o"]),
            (Action::Export, &["e"]),
            (Action::Zoom, &["z"]),
            (Action::Scalogram, &["w"]),
            (Action::Command, &[":"]),
            (Action::Undo, &["u"]),
            (Action::Redo, &["ctrl-r"]),
            (Action::Freeze, &["f"]),
            (Action::Filter, &["/"]),
            (Action::Add, &["a"]),
            (Action::Figure, &["p"]),
        ];
        Keymap {
            bindings: defaults
                .iter()
                .map(|(a, keys)| (*a, keys.iter().filter_map(|k| Key::parse(k).ok()).collect()))
                .collect(),
        }
    }
}

impl Keymap {
    /// The defaults with the config's `[keys]` table over them.
    pub fn with_overrides(overrides: &BTreeMap<String, Vec<String>>) -> Result<Keymap, String> {
        let mut map = Keymap::default();
        for (name, keys) in overrides {
            let action = Action::parse(name).ok_or_else(|| {
                let names: Vec<&str> = Action::ALL.iter().map(|(_, n, _)| *n).collect();
                format!("[keys] {name}: not an action (one of {})", names.join(", "))
            })?;
            let keys = keys
                .iter()
                .map(|k| Key::parse(k).map_err(|e| format!("[keys] {name}: {e}")))
                .collect::<Result<Vec<_>, _>>()?;
            if keys.is_empty() {
                return Err(format!(
                    "[keys] {name}: no key (the action would be unreachable)"
                ));
            }
            map.bindings.insert(action, keys);
        }
        map.check_conflicts(overrides)?;
        Ok(map)
    }

    /// One action per key: a key bound twice (by the config, or by the config and a default
    /// it did not change) is an error naming both actions.
    fn check_conflicts(&self, overrides: &BTreeMap<String, Vec<String>>) -> Result<(), String> {
        let name_of = |action: Action| {
            Action::ALL
                .iter()
                .find(|(a, _, _)| *a == action)
                .map_or("?", |(_, n, _)| *n)
        };
        let mut seen: BTreeMap<(String, bool), Action> = BTreeMap::new();
        for (&action, keys) in &self.bindings {
            for key in keys {
                let id = (format!("{:?}", key.code), key.ctrl);
                if let Some(&other) = seen.get(&id) {
                    let (a, b) = (name_of(other), name_of(action));
                    let changed = |n: &str| overrides.contains_key(n);
                    let fix = match (changed(a), changed(b)) {
                        (true, true) => format!("give {a} or {b} another key"),
                        (true, false) => format!("{b} has it by default: give {b} another key too"),
                        _ => format!("{a} has it by default: give {a} another key too"),
                    };
                    return Err(format!(
                        "[keys]: {} is the key of both {a} and {b}; {fix}",
                        key.label()
                    ));
                }
                seen.insert(id, action);
            }
        }
        Ok(())
    }

    /// The action of a key press, if any (Ctrl-C is not here: it always quits).
    pub fn action(&self, event: &KeyEvent) -> Option<Action> {
        let key = Key::of(event);
        // a shifted letter arrives as its upper case with SHIFT; bindings name the character
        self.bindings
            .iter()
            .find(|(_, keys)| keys.contains(&key))
            .map(|(a, _)| *a)
    }

    /// The first key of an action, as shown.
    pub fn label(&self, action: Action) -> String {
        self.bindings
            .get(&action)
            .and_then(|k| k.first())
            .map_or_else(|| "—".into(), Key::label)
    }

    /// Every key of an action, as shown.
    pub fn labels(&self, action: Action) -> String {
        self.bindings.get(&action).map_or_else(String::new, |keys| {
            keys.iter().map(Key::label).collect::<Vec<_>>().join("/")
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn press(code: KeyCode) -> KeyEvent {
        KeyEvent::new(code, KeyModifiers::NONE)
    }

    #[test]
    fn defaults_and_overrides() {
        let map = Keymap::default();
        assert!(
            map.check_conflicts(&BTreeMap::new()).is_ok(),
            "the defaults clash"
        );
        assert_eq!(map.action(&press(KeyCode::Char('r'))), Some(Action::Run));
        assert_eq!(map.action(&press(KeyCode::Char('j'))), Some(Action::Down));
        let overrides = BTreeMap::from([("run".to_string(), vec!["f5".to_string()])]);
        let map = Keymap::with_overrides(&overrides).unwrap();
        assert_eq!(map.action(&press(KeyCode::F(5))), Some(Action::Run));
        assert_eq!(map.action(&press(KeyCode::Char('r'))), None);
        let bad = BTreeMap::from([("fly".to_string(), vec!["x".to_string()])]);
        assert!(
            Keymap::with_overrides(&bad)
                .unwrap_err()
                .contains("not an action")
        );
        // a key taken from another action (here save's s) is refused, naming both
        let clash = BTreeMap::from([("run".to_string(), vec!["s".to_string()])]);
        let error = Keymap::with_overrides(&clash).unwrap_err();
        assert!(
            error.contains("s is the key of both")
                && error.contains("run")
                && error.contains("save"),
            "{error}"
        );
        // unless that action moves too
        let moved = BTreeMap::from([
            ("run".to_string(), vec!["s".to_string()]),
            ("save".to_string(), vec!["ctrl-s".to_string()]),
        ]);
        let map = Keymap::with_overrides(&moved).unwrap();
        assert_eq!(map.action(&press(KeyCode::Char('s'))), Some(Action::Run));
        let none = BTreeMap::from([("run".to_string(), vec![])]);
        assert!(
            Keymap::with_overrides(&none)
                .unwrap_err()
                .contains("no key")
        );
        let bad = BTreeMap::from([("run".to_string(), vec!["hyper-x".to_string()])]);
        assert!(
            Keymap::with_overrides(&bad)
                .unwrap_err()
                .contains("not a key")
        );
    }
}
