//! Evenly spaced axes for grids of initial states and parameter ranges.

use serde::{Deserialize, Serialize};

use crate::model::error::{ParamError, check, check_in};

/// `points` values from `min` to `max` inclusive.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axis {
    pub min: f64,
    pub max: f64,
    pub points: usize,
}

impl Axis {
    pub fn new(min: f64, max: f64, points: usize) -> Self {
        Axis { min, max, points }
    }

    /// Checks the range and that 1 ≤ points ≤ `max_points`; names the axis' field in the
    /// error (`dx.max`).
    pub fn validate(&self, name: &str, max_points: usize) -> Result<(), ParamError> {
        check(
            &format!("{name}.min"),
            self.min,
            |_| true,
            "a finite number",
        )?;
        check(
            &format!("{name}.max"),
            self.max,
            |m| m >= self.min,
            format!(">= min = {}", self.min),
        )?;
        let points = format!("{name}.points");
        check(
            &points,
            self.points as f64,
            |n| n >= 1.0 && n <= max_points as f64,
            format!("[1, {max_points}]"),
        )?;
        if self.points == 1 && self.max != self.min {
            return Err(ParamError {
                field: points,
                value: self.points as f64,
                allowed: "at least 2 points for a range with max > min".into(),
            });
        }
        Ok(())
    }

    /// Checks that both ends lie in [`lo`, `hi`] (`dx.min`, `dx.max` named).
    pub fn check_within(&self, name: &str, (lo, hi): (f64, f64)) -> Result<(), ParamError> {
        check_in(&format!("{name}.min"), self.min, lo, hi)?;
        check_in(&format!("{name}.max"), self.max, lo, hi)?;
        Ok(())
    }

    /// The i-th value.
    pub fn at(&self, i: usize) -> f64 {
        if self.points <= 1 {
            self.min
        } else {
            self.min + (self.max - self.min) * i as f64 / (self.points - 1) as f64
        }
    }

    pub fn values(&self) -> Vec<f64> {
        (0..self.points).map(|i| self.at(i)).collect()
    }

    /// The step between values (0 for a single point).
    pub fn step(&self) -> f64 {
        if self.points <= 1 {
            0.0
        } else {
            (self.max - self.min) / (self.points - 1) as f64
        }
    }
}

/// The initial states [λ_I, v] of a grid over (Δλ, v) about `lambda_p`, Δλ-major: cell
/// `i_dx · v.points + i_v`.
pub fn starts(lambda_p: f64, dx: &Axis, v: &Axis) -> Vec<[f64; 2]> {
    (0..dx.points * v.points)
        .map(|c| [lambda_p + dx.at(c / v.points), v.at(c % v.points)])
        .collect()
}
