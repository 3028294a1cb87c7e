//! The panes around the plot: analyses, parameters, jobs, status bar, and overlays.

pub mod analyses;
pub mod jobs;
pub mod overlay;
pub mod params;
pub mod status;

use ratatui::text::Span;

/// `text` in at most `room` characters: cut with `…` if longer.
pub fn ellipsis(text: &str, room: usize) -> String {
    if text.chars().count() > room {
        let cut: String = text.chars().take(room.saturating_sub(1)).collect();
        format!("{cut}…")
    } else {
        text.to_string()
    }
}

/// `text` in lines of at most `width` cells, broken between words (inside a word longer
/// than a line).
pub fn wrap(text: &str, width: usize) -> Vec<String> {
    let width = width.max(1);
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in text.split(' ') {
        let sep = usize::from(!line.is_empty());
        if Span::raw(line.as_str()).width() + sep + Span::raw(word).width() <= width {
            if sep == 1 {
                line.push(' ');
            }
            line.push_str(word);
            continue;
        }
        if !line.is_empty() {
            lines.push(std::mem::take(&mut line));
        }
        let mut rest = word;
        while Span::raw(rest).width() > width {
            let cut = rest
                .char_indices()
                .nth(width)
                .map_or(rest.len(), |(i, _)| i);
            lines.push(rest[..cut].to_string());
            rest = &rest[cut..];
        }
        line.push_str(rest);
    }
    if !line.is_empty() || lines.is_empty() {
        lines.push(line);
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::wrap;

    #[test]
    fn a_long_message_is_wrapped_between_words() {
        assert_eq!(
            wrap("not saved: /a/very/long/path: No space left on device", 20),
            [
                "not saved:",
                "/a/very/long/path:",
                "No space left on",
                "device"
            ]
        );
        // a word longer than a line is broken inside it
        assert_eq!(wrap("abcdefgh", 3), ["abc", "def", "gh"]);
        assert_eq!(wrap("", 10), [""]);
    }
}
