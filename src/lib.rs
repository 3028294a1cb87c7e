//! isola: the nonlinear dynamics of forced, piecewise-smooth oscillators, starting with
//! antagonistic pure-shear dielectric elastomer actuators. Data flows one way:
//! model → solver → analysis → jobs → session → figure (and `logging`, set up by the front
//! ends).

pub mod analysis;
pub mod figure;
pub mod jobs;
pub mod logging;
pub mod model;
pub mod reproduce;
pub mod session;
pub mod solver;

/// This build: package version and the commit it was built from (`-modified` if the tree
/// had changes), recorded with every result.
pub const BUILD: &str = concat!(env!("CARGO_PKG_VERSION"), "+", env!("ISOLA_COMMIT"));
