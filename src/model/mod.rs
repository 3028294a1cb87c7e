//! The DEA model of `MODEL.md`: validated parameters, the AC+DC drive, the force law with loss
//! of tension, and physical units. Pure functions, no I/O.

pub mod drive;
pub mod equations;
pub mod error;
pub mod forces;
pub mod forcing;
pub mod limits;
pub mod params;
pub mod statics;
pub mod system;
pub mod units;

pub use drive::{Drive, DriveSpec};
pub use error::ParamError;
pub use forcing::{Chirp, Forcing, Sweep};
pub use params::{ParamSpec, Params};
pub use units::Device;
