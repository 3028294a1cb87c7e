//! Every integration test in one binary, and the library's unit tests (`unit/`, at their
//! modules' paths): one link, the library compiled once for `cargo test`, and its generic
//! analyses compiled once for all of them. `cargo test --test it MODULE::` runs one file's
//! tests (`unit::solver::rk4::` the integrator's unit tests).

mod common;
mod corpus;

mod bifurcation_curves;
mod cli;
mod continuation;
mod figures;
mod global_analyses;
mod hostile_sessions;
mod hunt;
mod map;
mod paper_claims;
mod reference;
mod reproduce;
mod resolution;
mod sessions;
mod signals;
mod store;
mod sweep_findings;
mod tui_pty;
mod unit;
