//! One line being typed: a parameter's value, a path, a command, a filter. Its keys are a
//! shell's (through `tui-input`): ← →, Home and End (Ctrl-A, Ctrl-E), Ctrl-← and Ctrl-→ by
//! word, Backspace and Delete, Ctrl-U (the whole line), Ctrl-W (the word before), Ctrl-K (to
//! the end). A value given to be replaced (a parameter's) starts selected: the first character
//! typed replaces it, a deletion clears it, a move keeps it and moves into it.

use crossterm::event::{Event, KeyEvent};
use ratatui::style::Style;
use ratatui::text::Span;
use tui_input::backend::crossterm::{EventHandler, to_input_request};
use tui_input::{Input, InputRequest};

/// The text typed so far, with its cursor.
#[derive(Debug, Clone, Default)]
pub struct LineEdit {
    input: Input,
    /// The whole text is selected: typing replaces it.
    selected: bool,
}

impl PartialEq for LineEdit {
    fn eq(&self, other: &Self) -> bool {
        (self.value(), self.input.cursor(), self.selected)
            == (other.value(), other.input.cursor(), other.selected)
    }
}

impl LineEdit {
    /// `text` with the cursor at its end.
    pub fn new(text: impl Into<String>) -> Self {
        LineEdit {
            input: Input::new(text.into()),
            selected: false,
        }
    }

    /// `text` selected, to be replaced by what is typed (or edited after a move).
    pub fn replacing(text: impl Into<String>) -> Self {
        LineEdit {
            selected: true,
            ..LineEdit::new(text)
        }
    }

    /// `before` then `after`, the cursor between them.
    pub fn around(before: &str, after: &str) -> Self {
        LineEdit {
            input: Input::new(format!("{before}{after}")).with_cursor(before.chars().count()),
            selected: false,
        }
    }

    /// The text before the cursor and after it (all of it before, while it is selected).
    pub fn split(&self) -> (&str, &str) {
        let value = self.input.value();
        if self.selected {
            return (value, "");
        }
        let at = value
            .char_indices()
            .nth(self.input.cursor())
            .map_or(value.len(), |(i, _)| i);
        value.split_at(at)
    }

    /// Where the word at the cursor ends (a byte offset): the cursor itself if no word goes
    /// on after it; the whole text while it is selected.
    pub fn word_end(&self) -> usize {
        let (before, after) = self.split();
        before.len() + after.find(char::is_whitespace).unwrap_or(after.len())
    }

    /// The text.
    pub fn value(&self) -> &str {
        self.input.value()
    }

    /// Whether the whole text is selected (the next character typed replaces it).
    pub fn is_selected(&self) -> bool {
        self.selected
    }

    /// Applies `key`; false if it is not an editing key (Enter, Esc, Tab, ↑ ↓...), which the
    /// caller handles.
    pub fn key(&mut self, key: KeyEvent) -> bool {
        let event = Event::Key(key);
        let Some(request) = to_input_request(&event) else {
            return false;
        };
        if std::mem::take(&mut self.selected) {
            match request {
                InputRequest::InsertChar(_) => self.input.reset(),
                InputRequest::DeletePrevChar
                | InputRequest::DeleteNextChar
                | InputRequest::DeletePrevWord
                | InputRequest::DeleteNextWord
                | InputRequest::DeleteLine
                | InputRequest::DeleteTillEnd
                | InputRequest::DeleteFromStart => {
                    self.input.reset();
                    return true;
                }
                _ => {}
            }
        }
        self.input.handle_event(&event);
        true
    }

    /// The text as shown: the cursor (`▏`) where it is, the text in `style`, or in `selected`
    /// while it is selected.
    pub fn spans(&self, style: Style, selected: Style) -> Vec<Span<'static>> {
        self.spans_within(usize::MAX, style, selected)
    }

    /// [`Self::spans`] in at most `width` cells: a text too long is shown around the cursor,
    /// `…` where it is cut.
    pub fn spans_within(&self, width: usize, style: Style, selected: Style) -> Vec<Span<'static>> {
        let chars: Vec<char> = self.input.value().chars().collect();
        // cells for the text besides the cursor's
        let room = width.max(3) - 1;
        let cut = |part: &[char], keep_end: bool| -> String {
            if part.len() <= room {
                return part.iter().collect();
            }
            let keep = room - 1;
            if keep_end {
                std::iter::once('…')
                    .chain(part[part.len() - keep..].iter().copied())
                    .collect()
            } else {
                part[..keep]
                    .iter()
                    .copied()
                    .chain(std::iter::once('…'))
                    .collect()
            }
        };
        if self.selected {
            return vec![
                Span::styled(cut(&chars, true), selected),
                Span::styled("▏", style),
            ];
        }
        let at = self.input.cursor().min(chars.len());
        let before = cut(&chars[..at], true);
        let left = room.saturating_sub(before.chars().count());
        let after: String = if chars.len() - at <= left {
            chars[at..].iter().collect()
        } else if left == 0 {
            String::new()
        } else {
            chars[at..at + left - 1]
                .iter()
                .copied()
                .chain(std::iter::once('…'))
                .collect()
        };
        vec![Span::styled(format!("{before}▏{after}"), style)]
    }

    /// The cells the text takes as shown, its cursor included.
    pub fn width(&self) -> usize {
        self.input.value().chars().count() + 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crossterm::event::{KeyCode, KeyModifiers};

    fn press(edit: &mut LineEdit, code: KeyCode, modifiers: KeyModifiers) {
        assert!(edit.key(KeyEvent::new(code, modifiers)), "{code:?} edits");
    }

    fn typed(edit: &mut LineEdit, text: &str) {
        for c in text.chars() {
            press(edit, KeyCode::Char(c), KeyModifiers::NONE);
        }
    }

    fn shown(edit: &LineEdit) -> String {
        edit.spans(Style::default(), Style::default())
            .iter()
            .map(|s| s.content.to_string())
            .collect()
    }

    #[test]
    fn a_value_to_replace_is_replaced_by_what_is_typed() {
        let mut edit = LineEdit::replacing("0.02");
        typed(&mut edit, "0.05");
        assert_eq!(edit.value(), "0.05");
        // a deletion clears it
        let mut edit = LineEdit::replacing("0.02");
        press(&mut edit, KeyCode::Backspace, KeyModifiers::NONE);
        assert_eq!(edit.value(), "");
        // a move keeps it, and edits from there
        let mut edit = LineEdit::replacing("0.02");
        press(&mut edit, KeyCode::Home, KeyModifiers::NONE);
        typed(&mut edit, "1");
        assert_eq!(edit.value(), "10.02");
        press(&mut edit, KeyCode::End, KeyModifiers::NONE);
        press(&mut edit, KeyCode::Left, KeyModifiers::NONE);
        press(&mut edit, KeyCode::Backspace, KeyModifiers::NONE);
        assert_eq!(edit.value(), "10.2");
        assert_eq!(shown(&edit), "10.▏2");
    }

    #[test]
    fn a_text_longer_than_its_box_is_shown_around_the_cursor() {
        let shown_in = |edit: &LineEdit, width: usize| -> String {
            edit.spans_within(width, Style::default(), Style::default())
                .iter()
                .map(|s| s.content.to_string())
                .collect()
        };
        let mut edit = LineEdit::new("0.123456789012345");
        assert_eq!(shown_in(&edit, 10), "…89012345▏");
        press(&mut edit, KeyCode::Home, KeyModifiers::NONE);
        assert_eq!(shown_in(&edit, 10), "▏0.123456…");
        for _ in 0..4 {
            press(&mut edit, KeyCode::Right, KeyModifiers::NONE);
        }
        assert_eq!(shown_in(&edit, 10), "0.12▏3456…");
        // it fits: whole
        assert_eq!(shown_in(&edit, 40), "0.12▏3456789012345");
        for w in 3..20 {
            assert!(shown_in(&edit, w).chars().count() <= w, "{w}");
        }
    }

    #[test]
    fn control_keys_edit_and_never_type_their_letter() {
        let mut edit = LineEdit::new("export my results.csv");
        press(&mut edit, KeyCode::Char('w'), KeyModifiers::CONTROL);
        assert_eq!(edit.value(), "export my ");
        press(&mut edit, KeyCode::Char('a'), KeyModifiers::CONTROL);
        press(&mut edit, KeyCode::Char('k'), KeyModifiers::CONTROL);
        assert_eq!(edit.value(), "");
        let mut edit = LineEdit::new("50 Hz");
        press(&mut edit, KeyCode::Char('u'), KeyModifiers::CONTROL);
        assert_eq!(edit.value(), "");
        // a character of another script, and the cursor in the middle of it
        let mut edit = LineEdit::new("ω_e");
        press(&mut edit, KeyCode::Left, KeyModifiers::NONE);
        press(&mut edit, KeyCode::Left, KeyModifiers::NONE);
        assert_eq!(shown(&edit), "ω▏_e");
        // Enter and Esc are the caller's
        assert!(!edit.key(KeyEvent::new(KeyCode::Enter, KeyModifiers::NONE)));
        assert!(!edit.key(KeyEvent::new(KeyCode::Esc, KeyModifiers::NONE)));
    }
}
