//! Brute force over many initial states: trajectories in SIMD lanes with verified early
//! stops, stepped sweeps, frequency responses, basins and families, generic over the
//! [`oscillator::Oscillator`] a model is.

pub mod basin;
pub mod batch;
pub mod capture;
mod capture_cover;
pub mod cycle;
pub mod ellipse;
pub mod family;
pub mod flow;
pub mod frequency_response;
pub mod oscillator;
pub mod stepped_sweep;
