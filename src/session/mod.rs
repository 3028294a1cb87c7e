//! Sessions: the TOML file of what a user explores, the results store beside it, CSV export,
//! atomic writes and checked output paths.

pub mod atomic;
pub mod budget;
pub mod convergence;
pub mod edit;
pub mod export;
pub mod locate;
pub mod model_section;
pub mod output;
pub mod preview;
pub mod results;
pub mod run;
pub mod schema;
pub mod select;
pub mod store;
pub mod written;

pub use schema::{AnalysisEntry, Session, SessionError, SessionFile, Settings};
