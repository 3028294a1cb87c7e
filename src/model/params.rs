//! Model parameters: what the user writes ([`ParamSpec`]) and the validated set the solvers
//! take ([`Params`]).

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use super::drive::{Drive, DriveSpec};
use super::error::{ParamError, check, check_in};
use super::forces::gent_poles;
use super::limits;

/// The model parameters as a user writes them (CLI flags, session files). Omitted fields take
/// the paper's baseline: λ_p = 1.02, J = 16, c̃ = 0.04, E_a = 0.2², ADR = 0.6, ω_e = 3.7.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ParamSpec {
    /// Pre-stretch λ_p of both membranes.
    pub lambda_p: f64,
    /// Gent limiting-stretch constant J.
    pub j: f64,
    /// Non-dimensional damping c̃.
    pub c_tilde: f64,
    /// Non-dimensional forcing frequency ω_e.
    pub omega: f64,
    /// Drive on membrane I.
    pub drive: DriveSpec,
    /// Optional drive on membrane II, at the same ω_e.
    pub drive_ii: Option<DriveSpec>,
    /// Phase lead of membrane II's AC voltage, radians.
    pub phase_ii: f64,
}

impl Default for ParamSpec {
    fn default() -> Self {
        ParamSpec {
            lambda_p: 1.02,
            j: 16.0,
            c_tilde: 0.04,
            omega: 3.7,
            drive: DriveSpec::EaAdr {
                e_a: 0.04,
                adr: 0.6,
            },
            drive_ii: None,
            phase_ii: 0.0,
        }
    }
}

impl ParamSpec {
    /// Validates every field; the error names the first bad one.
    pub fn build(&self) -> Result<Params, ParamError> {
        let in_range = |field, value, (lo, hi): (f64, f64)| check_in(field, value, lo, hi);
        let j = in_range("j", self.j, limits::J)?;
        let (lo, hi) = gent_poles(j);
        let lambda_p = check(
            "lambda_p",
            self.lambda_p,
            |l| l > lo && l < hi,
            format!("({lo:.5}, {hi:.5}), between the Gent poles for J = {j}"),
        )?;
        let c_tilde = in_range("c_tilde", self.c_tilde, limits::C_TILDE)?;
        let omega = in_range("omega", self.omega, limits::OMEGA)?;
        let drive_i = Drive::from_spec(self.drive)?;
        let drive_ii = self
            .drive_ii
            .map(|d| Drive::from_spec(d).map_err(|e| e.suffixed("_ii")))
            .transpose()?;
        let phase_ii = in_range("phase_ii", self.phase_ii, limits::PHASE)?;
        Ok(Params {
            lambda_p,
            j,
            c_tilde,
            omega,
            drive_i,
            drive_ii: drive_ii.unwrap_or(Drive::OFF),
            phase_ii,
        })
    }
}

/// A validated parameter set: every value finite and in range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Params {
    lambda_p: f64,
    j: f64,
    c_tilde: f64,
    omega: f64,
    drive_i: Drive,
    drive_ii: Drive,
    phase_ii: f64,
}

impl Default for Params {
    fn default() -> Self {
        Self::baseline()
    }
}

impl Params {
    /// The paper's baseline at ADR 0.6, ω_e = 3.7.
    pub fn baseline() -> Self {
        ParamSpec::default().build().expect("the baseline is valid")
    }

    /// The paper's baseline (E_a = 0.2², λ_p 1.02, c̃ 0.04, J 16) at another ADR and ω_e.
    pub fn paper(adr: f64, omega: f64) -> Result<Self, ParamError> {
        ParamSpec {
            omega,
            drive: DriveSpec::EaAdr { e_a: 0.04, adr },
            ..ParamSpec::default()
        }
        .build()
    }

    /// The spec that rebuilds these parameters.
    pub fn to_spec(&self) -> ParamSpec {
        ParamSpec {
            lambda_p: self.lambda_p,
            j: self.j,
            c_tilde: self.c_tilde,
            omega: self.omega,
            drive: self.drive_i.to_spec(),
            drive_ii: (!self.drive_ii.is_off()).then(|| self.drive_ii.to_spec()),
            phase_ii: self.phase_ii,
        }
    }

    /// The same parameters at another forcing frequency.
    pub fn with_omega(&self, omega: f64) -> Result<Self, ParamError> {
        ParamSpec {
            omega,
            ..self.to_spec()
        }
        .build()
    }

    pub fn lambda_p(&self) -> f64 {
        self.lambda_p
    }
    pub fn j(&self) -> f64 {
        self.j
    }
    pub fn c_tilde(&self) -> f64 {
        self.c_tilde
    }
    pub fn omega(&self) -> f64 {
        self.omega
    }
    pub fn drive_i(&self) -> &Drive {
        &self.drive_i
    }
    pub fn drive_ii(&self) -> &Drive {
        &self.drive_ii
    }
    pub fn phase_ii(&self) -> f64 {
        self.phase_ii
    }

    /// Forcing period T = 2π/ω_e.
    pub fn period(&self) -> f64 {
        2.0 * PI / self.omega
    }

    /// (φ_I², φ_II²) at time τ.
    pub fn phi_sq_at(&self, tau: f64) -> (f64, f64) {
        let theta = self.omega * tau;
        let phi_sq_ii = if self.drive_ii.is_off() {
            0.0
        } else {
            self.drive_ii.phi_sq(theta + self.phase_ii)
        };
        (self.drive_i.phi_sq(theta), phi_sq_ii)
    }
}
