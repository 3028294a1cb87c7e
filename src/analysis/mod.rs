//! Analyses built on the solvers. Each is a plain function of its spec.

pub mod force_curve;
pub mod period_map;
pub mod ratio;
pub mod steady_state;

pub use period_map::{DopriPeriodMap, OrbitRecord, PeriodMap, Rk4PeriodMap};
pub use ratio::Ratio;
pub use steady_state::{Class, SteadyState, SteadyStateSpec, steady_state, steady_state_with};
