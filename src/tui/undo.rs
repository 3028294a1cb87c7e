//! Undo and redo of session edits (parameters, settings, analyses added, copied, renamed or
//! deleted): the session's text before each edit, so any edit comes back exactly, comments
//! and layout included.

/// The session as it was at one point.
#[derive(Debug, Clone, PartialEq)]
pub struct Version {
    pub text: String,
    /// The analysis selected then.
    pub selected: usize,
    /// The edit that came after it (`ADR = 1.0`, `added b2`), to say what is undone.
    pub what: String,
}

/// Versions to go back and forth to.
#[derive(Debug, Default)]
pub struct Versions {
    undo: Vec<Version>,
    redo: Vec<Version>,
}

/// Edits remembered at most (a session's text is a few kB).
const DEPTH: usize = 200;

impl Versions {
    /// Remembers the session before an edit; a new edit drops what could be redone.
    pub fn remember(&mut self, before: Version) {
        self.undo.push(before);
        if self.undo.len() > DEPTH {
            self.undo.remove(0);
        }
        self.redo.clear();
    }

    /// The version to go back to from `now` (which can then be redone), if any.
    pub fn undo(&mut self, now: Version) -> Option<Version> {
        step(&mut self.undo, &mut self.redo, now)
    }

    /// The version undone last, going forward from `now`.
    pub fn redo(&mut self, now: Version) -> Option<Version> {
        step(&mut self.redo, &mut self.undo, now)
    }

    /// Forgets everything (another session was opened).
    pub fn clear(&mut self) {
        self.undo.clear();
        self.redo.clear();
    }
}

/// The last version of `from`, with `now` put on `to` (under the same edit's name) to come
/// back to.
fn step(from: &mut Vec<Version>, to: &mut Vec<Version>, now: Version) -> Option<Version> {
    let there = from.pop()?;
    to.push(Version {
        what: there.what.clone(),
        ..now
    });
    Some(there)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(text: &str, what: &str) -> Version {
        Version {
            text: text.into(),
            selected: 0,
            what: what.into(),
        }
    }

    #[test]
    fn undo_and_redo_walk_the_edits_and_a_new_edit_drops_the_redo() {
        let mut versions = Versions::default();
        // a → b (edit 1) → c (edit 2)
        versions.remember(v("a", "edit 1"));
        versions.remember(v("b", "edit 2"));
        let back = versions.undo(v("c", "")).unwrap();
        assert_eq!((back.text.as_str(), back.what.as_str()), ("b", "edit 2"));
        let back = versions.undo(v("b", "")).unwrap();
        assert_eq!(back.text, "a");
        assert!(versions.undo(v("a", "")).is_none());
        let forward = versions.redo(v("a", "")).unwrap();
        assert_eq!(
            (forward.text.as_str(), forward.what.as_str()),
            ("b", "edit 1")
        );
        // a new edit from b: c can no longer be redone
        versions.remember(v("b", "edit 3"));
        assert!(versions.redo(v("d", "")).is_none());
        assert_eq!(versions.undo(v("d", "")).unwrap().text, "b");
    }
}
