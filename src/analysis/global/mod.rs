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

/// Chunks a grid is cut into at least, where its fewest units a chunk allow.
const MIN_CHUNKS: usize = 24;

/// Units (cells, ω_e) per chunk of the results store for `count` of them: the largest power
/// of two from `fewest` to `most` that leaves at least 24 chunks. A small grid is still spread
/// over cores and nodes; a large one pays the store's work for each chunk (a claim, a file, a
/// checksum) on fewer of them. A unit's outcome is computed on its own either way.
fn units_per_chunk(count: usize, fewest: usize, most: usize) -> usize {
    let wanted = (count / MIN_CHUNKS).max(1);
    (1 << wanted.ilog2()).clamp(fewest, most)
}
