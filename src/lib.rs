pub mod analysis;
pub mod jobs;
pub mod model;
pub mod session;
pub mod solver;
