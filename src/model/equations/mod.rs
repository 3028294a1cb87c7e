//! Models written in a session: state variables, parameters, named intermediates, functions
//! and the derivative of each state, as expressions compiled at load into [`tape`]s. The
//! arguments of `max`, `min`, `abs` and `if` are switching functions the engine splits steps
//! at; the Jacobian is the expressions' symbolic derivative.
//!
//! ```toml
//! [model]
//! states = ["lambda_I", "v"]
//! frequency = "omega"
//! amplitude = "lambda_I"
//! collision = ["lambda_I <= 0", "lambda_II <= 0"]
//! [model.parameters]
//! omega = { value = 1.8, min = 0.01, max = 50 }
//! [model.let]
//! lambda_II = "2*lambda_p - lambda_I"
//! [model.functions]
//! "g(lam)" = "(lam - lam^-3) / (1 - (lam^2 + lam^-2 - 2)/J)"
//! [model.derivatives]
//! lambda_I = "v"
//! v = "f_II - f_I"
//! ```

#[cfg(target_arch = "x86_64")]
mod avx2;
pub mod build;
pub mod chirped;
pub mod definition;
pub mod graph;
#[cfg(target_arch = "x86_64")]
mod lane_code;
pub mod lanes;
#[cfg(target_arch = "x86_64")]
mod native;
#[cfg(target_arch = "x86_64")]
pub mod native_step;
pub mod parse;
pub mod system;
pub mod tape;
pub mod time_table;

pub use build::EquationModel;
pub use definition::{ModelDefinition, ParameterDefinition};
pub use system::EquationSystem;

/// The version of written models' numerics, part of their results' fingerprints beside
/// [`crate::analysis::NUMERICS_VERSION`]: bump it with any change that alters a number a
/// written model computes and not the built-in model's, so that only written models'
/// stored results become stale.
/// 2: a periodic forcing read from a table of one period, negative powers through one
/// reciprocal: numbers moved by rounding (≤ 2e-13 in Fig 4's response).
/// 3: a time history recorded within its tolerance (each period at N and 2N steps), and
/// ended, with a `collision` column, where a collision ends the orbit.
/// 4: a collision located within the step that met it (its τ and state), not at the step's
/// end.
/// 5: a continuous switch estimated by secant and inverse quadratic steps on the step's
/// interpolant, not bracketed on it: the sub-step lands past it by a little less (≤ 3e-13 in
/// Fig 4's response).
pub const NUMERICS_VERSION: u32 = 5;

/// Why a written model cannot be used: where (the TOML key, and line and column when known)
/// and what.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{place}: {message}")]
pub struct EquationError {
    /// `model.let.g_I, line 14, column 9`.
    pub place: String,
    pub message: String,
}
