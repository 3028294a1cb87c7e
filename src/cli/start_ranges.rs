//! Initial states as the commands take them: one (`orbit`, `continue`) or ranges of them
//! (the commands that sample many).

use clap::Args;
use isola::analysis::grid::Axis;

use super::parse;

/// Where a grid of initial states (Δλ, v) at τ = 0 lies.
#[derive(Debug, Clone, Args)]
pub struct StartRanges {
    /// Range of initial Δλ = λ_I − λ_p.
    #[arg(long = "dx-range", default_value = "-0.8:0.8", value_parser = parse::interval, allow_hyphen_values = true)]
    dx_range: (f64, f64),
    /// Range of initial velocity dλ_I/dτ.
    #[arg(long = "v-range", default_value = "-1:1", value_parser = parse::interval, allow_hyphen_values = true)]
    v_range: (f64, f64),
}

impl StartRanges {
    /// The Δλ and v axes of an `n_dx` × `n_v` grid.
    pub fn axes(&self, (n_dx, n_v): (usize, usize)) -> (Axis, Axis) {
        (
            Axis::new(self.dx_range.0, self.dx_range.1, n_dx),
            Axis::new(self.v_range.0, self.v_range.1, n_v),
        )
    }
}

/// One initial state (Δλ, v) at τ = 0.
#[derive(Debug, Clone, Copy, Args)]
pub struct Start {
    /// Initial displacement Δλ = λ_I − λ_p at τ = 0.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = super::parse::finite)]
    pub x0: f64,
    /// Initial velocity dλ_I/dτ at τ = 0.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = super::parse::finite)]
    pub v0: f64,
}
