//! One orbit: the stroboscopic map, the two-stage period test and the classification of a
//! steady state, time histories, chirp sweeps and their scalograms, force curves, shooting
//! for a periodic orbit and its Floquet multipliers.

pub mod attractor;
pub mod chirp_sweep;
pub mod floquet;
pub mod force_curve;
pub mod period_detector;
pub mod period_map;
pub mod ratio;
pub mod scalogram;
pub mod shooting;
pub mod steady_state;
pub mod time_history;
pub mod variational;
