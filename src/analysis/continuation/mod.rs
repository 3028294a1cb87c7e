//! Branches of periodic orbits continued by pseudo-arclength in ω_e or a model parameter,
//! their folds, period doublings and Neimark–Sacker points, the isola hunter, fold and
//! period-doubling curves in two parameters, where isolas are born and merge, and
//! two-parameter maps, on any [`model::Continuable`] model.

/// The version of the continuation's numerics, in the fingerprint of every kind that
/// continues branches (continuation, hunt, map) beside
/// [`crate::analysis::NUMERICS_VERSION`].
/// 1: a located special point is the corrected point of the smallest test met (a branch
/// point was reported 5.5e-6 off, from a point on the crossing branch); folds may move in
/// their last bits.
/// 2: a curve of bifurcations that makes no headway over 40 points ends there, stalled
/// (before, it crawled into a corner until its point limit).
/// 3: a curve of bifurcations corrects its points by a chord method (the Jacobian kept
/// while the steps at least halve), so its points and extrema move within the corrector's
/// tolerance (the map's turning points by up to 4e-8); a turning point's precision adds how
/// far its point may lie from the curve to the bracket's width.
pub const NUMERICS_VERSION: u32 = 3;

pub mod bifurcation_curve;
pub mod branch;
pub mod branch_from_state;
pub mod hunt;
pub mod hunt_family;
pub mod isola_limits;
pub mod map;
pub mod model;
