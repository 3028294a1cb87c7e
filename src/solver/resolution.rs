//! How finely the fixed-step integrator cuts a forcing period.

use std::fmt;

use serde::de::{self, Deserializer, MapAccess, Unexpected, Visitor};
use serde::{Deserialize, Serialize};

use crate::model::error::{ParamError, check};

/// Steps per forcing period: at least `min_steps_per_period`, and more when needed to keep
/// the step below `max_step` (low ω_e has long periods). Read from a table of the two, or
/// from a whole number N: [`Resolution::steps`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Resolution {
    pub min_steps_per_period: u32,
    pub max_step: f64,
}

/// The longest RK4 step times the steps per period: the default's 64 steps of at most 0.05,
/// so that N steps per period are also steps of at most 3.2/N at long periods (ω_e < 1.96).
const STEP_TIMES_STEPS: f64 = 0.05 * 64.0;

impl Default for Resolution {
    fn default() -> Self {
        Resolution {
            min_steps_per_period: 64,
            max_step: 0.05,
        }
    }
}

impl Resolution {
    /// At least `n` steps per forcing period, each at most 3.2/n (`n` = 64 is the default).
    pub fn steps(n: u32) -> Resolution {
        Resolution {
            min_steps_per_period: n,
            max_step: STEP_TIMES_STEPS / n as f64,
        }
    }

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

/// The table form as written (any field left out at its default).
#[derive(Deserialize)]
#[serde(default, deny_unknown_fields)]
struct Fields {
    min_steps_per_period: u32,
    max_step: f64,
}

impl Default for Fields {
    fn default() -> Self {
        let r = Resolution::default();
        Fields {
            min_steps_per_period: r.min_steps_per_period,
            max_step: r.max_step,
        }
    }
}

impl<'de> Deserialize<'de> for Resolution {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Either;
        impl<'de> Visitor<'de> for Either {
            type Value = Resolution;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(
                    "a whole number of RK4 steps per forcing period in [8, 100000], or a table \
                     { min_steps_per_period, max_step }",
                )
            }
            fn visit_u64<E: de::Error>(self, n: u64) -> Result<Resolution, E> {
                match u32::try_from(n) {
                    Ok(n) if n > 0 => Ok(Resolution::steps(n)),
                    _ => Err(E::invalid_value(Unexpected::Unsigned(n), &self)),
                }
            }
            fn visit_i64<E: de::Error>(self, n: i64) -> Result<Resolution, E> {
                match u64::try_from(n) {
                    Ok(n) => self.visit_u64(n),
                    Err(_) => Err(E::invalid_value(Unexpected::Signed(n), &self)),
                }
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Resolution, A::Error> {
                let f = Fields::deserialize(de::value::MapAccessDeserializer::new(map))?;
                Ok(Resolution {
                    min_steps_per_period: f.min_steps_per_period,
                    max_step: f.max_step,
                })
            }
        }
        d.deserialize_any(Either)
    }
}
