//! Physical units (MODEL.md §3): the device that turns τ, ω_e, φ and c̃ into seconds, Hz, kV,
//! MV/m and N·s/m.

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use super::error::{ParamError, check_in};
use super::limits;

/// A pure-shear device: material and geometry, SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Device {
    /// Shear modulus μ, Pa.
    pub mu: f64,
    /// Gent constant J.
    pub j: f64,
    /// Undeformed length in the stretch direction L₁, m.
    pub l1: f64,
    /// Width L₂, m.
    pub l2: f64,
    /// Thickness L₃, m.
    pub l3: f64,
    /// Moving mass M, kg.
    pub mass: f64,
    /// Permittivity ε, F/m.
    pub epsilon: f64,
}

impl Default for Device {
    fn default() -> Self {
        Self::silicone()
    }
}

impl Device {
    /// The paper's ELASTOSIL device: μ = 400 kPa, J = 16, 20 × 200 × 0.1 mm, 50 g,
    /// ε = 2.48e−11 F/m.
    pub fn silicone() -> Self {
        Device {
            mu: 400e3,
            j: 16.0,
            l1: 20e-3,
            l2: 200e-3,
            l3: 0.1e-3,
            mass: 50e-3,
            epsilon: 2.48e-11,
        }
    }

    /// Checks every field against its range ([`super::limits`]).
    pub fn validate(&self) -> Result<(), ParamError> {
        for (field, value, (lo, hi)) in [
            ("mu", self.mu, limits::MU),
            ("j", self.j, limits::J),
            ("l1", self.l1, limits::LENGTH),
            ("l2", self.l2, limits::LENGTH),
            ("l3", self.l3, limits::LENGTH),
            ("mass", self.mass, limits::MASS),
            ("epsilon", self.epsilon, limits::EPSILON),
        ] {
            check_in(field, value, lo, hi)?;
        }
        Ok(())
    }

    /// Seconds per unit of τ: √(M L₁ / (μ L₂ L₃)).
    pub fn time_scale(&self) -> f64 {
        (self.mass * self.l1 / (self.mu * self.l2 * self.l3)).sqrt()
    }

    /// Seconds for a non-dimensional time τ.
    pub fn seconds(&self, tau: f64) -> f64 {
        tau * self.time_scale()
    }

    /// Non-dimensional time for `t` seconds.
    pub fn tau(&self, seconds: f64) -> f64 {
        seconds / self.time_scale()
    }

    /// Angular frequency Ω in rad/s for ω_e.
    pub fn rad_per_s(&self, omega: f64) -> f64 {
        omega / self.time_scale()
    }

    /// Frequency in Hz for ω_e.
    pub fn hz(&self, omega: f64) -> f64 {
        self.rad_per_s(omega) / (2.0 * PI)
    }

    /// ω_e for a frequency in Hz.
    pub fn omega_from_hz(&self, hz: f64) -> f64 {
        hz * 2.0 * PI * self.time_scale()
    }

    /// Volts per unit of φ: L₃ √(μ/ε).
    pub fn volt_scale(&self) -> f64 {
        self.l3 * (self.mu / self.epsilon).sqrt()
    }

    /// Voltage Φ in kV for φ.
    pub fn kv(&self, phi: f64) -> f64 {
        phi * self.volt_scale() * 1e-3
    }

    /// φ for a voltage in kV.
    pub fn phi_from_kv(&self, kv: f64) -> f64 {
        kv * 1e3 / self.volt_scale()
    }

    /// Nominal electric field Φ/L₃ in MV/m for φ.
    pub fn mv_per_m(&self, phi: f64) -> f64 {
        phi * (self.mu / self.epsilon).sqrt() * 1e-6
    }

    /// Physical damping coefficient c in N·s/m for c̃ = (c/2)√(L₁/(μ M L₂ L₃)).
    pub fn damping(&self, c_tilde: f64) -> f64 {
        2.0 * c_tilde * (self.mu * self.mass * self.l2 * self.l3 / self.l1).sqrt()
    }

    /// c̃ for a physical damping coefficient c in N·s/m.
    pub fn c_tilde(&self, damping: f64) -> f64 {
        0.5 * damping * (self.l1 / (self.mu * self.mass * self.l2 * self.l3)).sqrt()
    }
}
