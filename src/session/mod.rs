//! Sessions: the TOML file of what a user explores, the results beside it, CSV export and
//! atomic writes.

pub mod atomic;
pub mod export;
pub mod model_section;
pub mod results;
pub mod run;
pub mod schema;

pub use schema::{AnalysisEntry, Session, SessionError, SessionFile, Settings};
