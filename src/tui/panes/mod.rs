//! The panes around the plot: analyses, parameters, jobs, status bar, and overlays.

pub mod analyses;
pub mod jobs;
pub mod overlay;
pub mod params;
pub mod status;

/// `text` in at most `room` characters: cut with `…` if longer.
pub fn ellipsis(text: &str, room: usize) -> String {
    if text.chars().count() > room {
        let cut: String = text.chars().take(room.saturating_sub(1)).collect();
        format!("{cut}…")
    } else {
        text.to_string()
    }
}
