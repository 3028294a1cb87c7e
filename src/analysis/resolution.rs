//! The resolution a user sets on an analysis (`resolution` in a session's settings,
//! `--resolution` on the command line), and the same analysis at twice the resolution.
//!
//! One spelling for every kind: `128` is RK4 with 128 steps per forcing period (the default
//! is 64); `rtol=1e-12` is the Dormand–Prince reference with that relative tolerance (and an
//! absolute one a hundredth of it, as every default has). Each analysis takes the form of the
//! integrator it uses; one that has both takes either, each setting its own integrator.

use std::fmt;

use crate::analysis::continuation::branch_from_state::BranchFromState;
use crate::analysis::continuation::hunt::HuntSpec;
use crate::analysis::continuation::map::MapSpec;
use crate::analysis::global::basin::BasinSpec;
use crate::analysis::global::family::FamilySpec;
use crate::analysis::global::frequency_response::FrequencyResponseSpec;
use crate::analysis::orbit::chirp_sweep::ChirpSpec;
use crate::analysis::orbit::time_history::TimeHistorySpec;
use crate::solver::{Resolution, Tolerance};

/// The allowed RK4 steps per forcing period, [lo, hi].
pub const STEPS_PER_PERIOD: (u32, u32) = (8, 100_000);

/// The allowed Dormand–Prince relative tolerances, (lo, hi) open: the absolute tolerance,
/// a hundredth of it, must stay above 1e-16.
pub const RTOL: (f64, f64) = (1e-14, 1.0);

/// How finely an analysis integrates, as the user writes it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ResolutionSetting {
    /// RK4 with at least N steps per forcing period, each at most 3.2/N.
    StepsPerPeriod(u32),
    /// The adaptive Dormand–Prince reference with relative tolerance `rtol` and absolute
    /// tolerance `rtol`/100.
    Reference { rtol: f64 },
}

/// The allowed values in words, for errors.
pub fn allowed() -> String {
    format!(
        "a whole number of RK4 steps per forcing period in [{}, {}], or rtol=X for the \
         Dormand–Prince reference with X in ({:e}, {})",
        STEPS_PER_PERIOD.0, STEPS_PER_PERIOD.1, RTOL.0, RTOL.1
    )
}

impl ResolutionSetting {
    /// Reads `128` or `rtol=1e-12`; an error gives the value and the allowed range.
    pub fn parse(text: &str) -> Result<Self, String> {
        let text = text.trim();
        let out_of_range = || format!("{text} is out of range: allowed {}", allowed());
        if let Some(rtol) = text.strip_prefix("rtol=") {
            let rtol: f64 = rtol.trim().parse().map_err(|_| out_of_range())?;
            return match rtol.is_finite() && rtol > RTOL.0 && rtol < RTOL.1 {
                true => Ok(ResolutionSetting::Reference { rtol }),
                false => Err(out_of_range()),
            };
        }
        let steps: u32 = text.parse().map_err(|_| out_of_range())?;
        match (STEPS_PER_PERIOD.0..=STEPS_PER_PERIOD.1).contains(&steps) {
            true => Ok(ResolutionSetting::StepsPerPeriod(steps)),
            false => Err(out_of_range()),
        }
    }

    /// Reads the setting as a session writes it: `resolution = 128` or
    /// `resolution = "rtol=1e-12"` (or `"128"`).
    pub fn from_toml(value: &toml::Value) -> Result<Self, String> {
        match value {
            toml::Value::Integer(n) => Self::parse(&n.to_string()),
            toml::Value::String(s) => Self::parse(s),
            other => Err(format!(
                "{other} is out of range: allowed {}",
                allowed().replace("rtol=X", "\"rtol=X\"")
            )),
        }
    }

    /// The Dormand–Prince tolerance of `rtol`.
    pub fn tolerance(rtol: f64) -> Tolerance {
        Tolerance {
            rtol,
            atol: rtol * 1e-2,
        }
    }
}

impl fmt::Display for ResolutionSetting {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ResolutionSetting::StepsPerPeriod(n) => write!(f, "{n}"),
            ResolutionSetting::Reference { rtol } => write!(f, "rtol={rtol:e}"),
        }
    }
}

/// The integrators an analysis' settings hold, each with its key as a session writes it
/// (inside the analysis' settings): what `resolution` sets, and what twice the resolution
/// refines.
pub trait Integrators {
    /// The analysis' name in messages (`a basin`).
    fn what(&self) -> &'static str;
    /// The RK4 resolution, if the analysis integrates with RK4.
    fn rk4(&mut self) -> Option<(&'static str, &mut Resolution)> {
        None
    }
    /// The Dormand–Prince tolerance, if the analysis integrates with it.
    fn dopri(&mut self) -> Option<(&'static str, &mut Tolerance)> {
        None
    }

    /// Sets the integrator `setting` names; an error (the allowed values for this analysis)
    /// where it has no such integrator.
    fn set_resolution(&mut self, setting: ResolutionSetting) -> Result<(), String> {
        let what = self.what();
        match setting {
            ResolutionSetting::StepsPerPeriod(n) => match self.rk4() {
                Some((_, r)) => *r = Resolution::steps(n),
                None => {
                    return Err(format!(
                        "{setting} is out of range: {what} integrates with Dormand–Prince only: \
                         allowed rtol=X with X in ({:e}, {})",
                        RTOL.0, RTOL.1
                    ));
                }
            },
            ResolutionSetting::Reference { rtol } => match self.dopri() {
                Some((_, t)) => *t = ResolutionSetting::tolerance(rtol),
                None => {
                    return Err(format!(
                        "{setting} is out of range: {what} integrates with RK4 only: allowed a \
                         whole number of steps per forcing period in [{}, {}]",
                        STEPS_PER_PERIOD.0, STEPS_PER_PERIOD.1
                    ));
                }
            },
        }
        Ok(())
    }

    /// Every integrator at twice the resolution: RK4 steps halved (twice the steps per
    /// period, half the longest step), Dormand–Prince tolerances divided by 32 (its steps
    /// scale as the tolerance to the 1/5). An error if that leaves the allowed range.
    fn double_resolution(&mut self) -> Result<(), crate::model::ParamError> {
        if let Some((key, r)) = self.rk4() {
            r.min_steps_per_period = r.min_steps_per_period.saturating_mul(2);
            r.max_step /= 2.0;
            r.validate().map_err(|e| e.within(key))?;
        }
        if let Some((key, t)) = self.dopri() {
            t.rtol /= 32.0;
            t.atol /= 32.0;
            t.validate().map_err(|e| e.within(key))?;
        }
        Ok(())
    }

    /// The resolution in words (`128 steps per period, rtol 3.1e-12`).
    fn describe_resolution(&mut self) -> String {
        let mut parts = Vec::new();
        if let Some((_, r)) = self.rk4() {
            parts.push(format!(
                "RK4 {} steps per period (h ≤ {})",
                r.min_steps_per_period, r.max_step
            ));
        }
        if let Some((_, t)) = self.dopri() {
            parts.push(format!("Dormand–Prince rtol {:e}", t.rtol));
        }
        parts.join(", ")
    }
}

impl Integrators for TimeHistorySpec {
    fn what(&self) -> &'static str {
        "a time history"
    }
    fn rk4(&mut self) -> Option<(&'static str, &mut Resolution)> {
        Some(("steady.resolution", &mut self.steady.resolution))
    }
    fn dopri(&mut self) -> Option<(&'static str, &mut Tolerance)> {
        Some(("tolerance", &mut self.tolerance))
    }
}

impl Integrators for ChirpSpec {
    fn what(&self) -> &'static str {
        "a chirp sweep"
    }
    fn dopri(&mut self) -> Option<(&'static str, &mut Tolerance)> {
        Some(("tolerance", &mut self.tolerance))
    }
}

impl Integrators for FrequencyResponseSpec {
    fn what(&self) -> &'static str {
        "a frequency response"
    }
    fn rk4(&mut self) -> Option<(&'static str, &mut Resolution)> {
        Some(("steady.resolution", &mut self.steady.resolution))
    }
}

impl Integrators for BasinSpec {
    fn what(&self) -> &'static str {
        "a basin"
    }
    fn rk4(&mut self) -> Option<(&'static str, &mut Resolution)> {
        Some(("steady.resolution", &mut self.steady.resolution))
    }
}

impl Integrators for FamilySpec {
    fn what(&self) -> &'static str {
        "a family"
    }
    fn rk4(&mut self) -> Option<(&'static str, &mut Resolution)> {
        Some((
            "response.steady.resolution",
            &mut self.response.steady.resolution,
        ))
    }
}

impl Integrators for BranchFromState {
    fn what(&self) -> &'static str {
        "a continuation"
    }
    fn rk4(&mut self) -> Option<(&'static str, &mut Resolution)> {
        Some(("steady.resolution", &mut self.steady.resolution))
    }
    fn dopri(&mut self) -> Option<(&'static str, &mut Tolerance)> {
        Some((
            "continuation.shooting.tol",
            &mut self.continuation.shooting.tol,
        ))
    }
}

impl Integrators for HuntSpec {
    fn what(&self) -> &'static str {
        "a hunt"
    }
    fn rk4(&mut self) -> Option<(&'static str, &mut Resolution)> {
        Some((
            "response.steady.resolution",
            &mut self.response.steady.resolution,
        ))
    }
    fn dopri(&mut self) -> Option<(&'static str, &mut Tolerance)> {
        Some((
            "continuation.shooting.tol",
            &mut self.continuation.shooting.tol,
        ))
    }
}

impl Integrators for MapSpec {
    fn what(&self) -> &'static str {
        "a map"
    }
    fn rk4(&mut self) -> Option<(&'static str, &mut Resolution)> {
        Some((
            "response.steady.resolution",
            &mut self.response.steady.resolution,
        ))
    }
}
