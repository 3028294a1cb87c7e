//! Integrators on the state `[λ_I, dλ_I/dτ]`.
//!
//! - [`rk4`]: fixed-step RK4 whose step divides the forcing period, several trajectories in
//!   SIMD lanes, the drive read from a per-period table, and steps split where a membrane
//!   goes slack or taut. The workhorse of every global analysis.
//! - [`dopri`]: adaptive Dormand–Prince 5(4) with dense output and located switching and
//!   collision events: time histories and the accuracy reference.

pub mod dopri;
pub(crate) mod dopri_tableau;
pub mod drive_table;
pub mod field;
pub mod general;
pub mod general_lanes;
pub mod hermite;
pub mod illinois;
pub mod isa;
pub mod lane;
pub mod resolution;
pub mod rk4;
pub mod sampled;

pub use dopri::{DenseStep, Dopri5, State, Tolerance};
pub use field::{Field, Mode};
pub use resolution::Resolution;
pub use rk4::{Lanes, Rk4, StepEnds};

/// Where a trajectory ends when it leaves the model (MODEL.md §1).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Collision {
    /// Non-dimensional time of the collision: located within the step that met it (RK4, on
    /// the step's interpolant), or exactly (`dopri`).
    pub tau: f64,
    /// λ_I there (at the frame or the locking stretch, just past it).
    pub lambda_i: f64,
}
