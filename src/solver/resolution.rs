//! How finely the fixed-step integrator cuts a forcing period.

use serde::{Deserialize, Serialize};

use crate::model::error::{ParamError, check};

/// Steps per forcing period: at least `min_steps_per_period`, and more when needed to keep
/// the step below `max_step` (low ω_e has long periods).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Resolution {
    pub min_steps_per_period: u32,
    pub max_step: f64,
}

impl Default for Resolution {
    fn default() -> Self {
        Resolution {
            min_steps_per_period: 64,
            max_step: 0.05,
        }
    }
}

impl Resolution {
    /// Checks the fields.
    pub fn validate(&self) -> Result<(), ParamError> {
        check(
            "min_steps_per_period",
            self.min_steps_per_period as f64,
            |n| (8.0..=1e5).contains(&n),
            "[8, 100000]",
        )?;
        check(
            "max_step",
            self.max_step,
            |h| (1e-5..=1.0).contains(&h),
            "[1e-5, 1]",
        )?;
        Ok(())
    }

    /// Steps for a forcing period `period`.
    pub fn steps_for(&self, period: f64) -> usize {
        let by_step = (period / self.max_step).ceil() as usize;
        by_step.max(self.min_steps_per_period as usize)
    }
}
