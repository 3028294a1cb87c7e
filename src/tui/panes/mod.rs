//! The panes around the plot: analyses, parameters, jobs, status bar, and overlays.

pub mod analyses;
pub mod jobs;
pub mod overlay;
pub mod params;
pub mod status;
