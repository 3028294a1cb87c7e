//! The ranges of initial states shared by the commands that sample many of them.

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
