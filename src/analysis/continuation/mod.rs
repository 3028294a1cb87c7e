//! Branches of periodic orbits continued by pseudo-arclength in ω_e or a model parameter,
//! their folds, period doublings and Neimark–Sacker points, the isola hunter, fold and
//! period-doubling curves in two parameters, where isolas are born and merge, and
//! two-parameter maps, on any [`model::Continuable`] model.

pub mod bifurcation_curve;
pub mod branch;
pub mod branch_from_state;
pub mod hunt;
pub mod hunt_family;
pub mod isola_limits;
pub mod map;
pub mod model;
