//! Forcing in time: the periodic drive of a parameter set, or a chirp whose frequency moves
//! linearly (Fig 3 sweeps).

use super::params::Params;

/// (φ_I², φ_II²) as functions of time τ.
pub trait Forcing {
    fn phi_sq(&self, tau: f64) -> (f64, f64);
}

impl Forcing for Params {
    fn phi_sq(&self, tau: f64) -> (f64, f64) {
        self.phi_sq_at(tau)
    }
}

/// A frequency moving linearly from `omega_start` to `omega_end` over `span`, then held. Its
/// phase is ∫ω dτ = ω₀τ + (ω₁ − ω₀)τ²/(2·span): writing cos(ω(τ)·τ) instead would double the
/// instantaneous frequency (MODEL.md §4b).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sweep {
    pub omega_start: f64,
    pub omega_end: f64,
    pub span: f64,
}

impl Sweep {
    /// Instantaneous frequency at τ.
    pub fn omega_at(&self, tau: f64) -> f64 {
        let s = (tau / self.span).clamp(0.0, 1.0);
        self.omega_start + (self.omega_end - self.omega_start) * s
    }

    /// Phase θ(τ) = ∫₀^τ ω dτ'.
    pub fn phase_at(&self, tau: f64) -> f64 {
        let rate = (self.omega_end - self.omega_start) / self.span;
        if tau <= self.span {
            self.omega_start * tau + 0.5 * rate * tau * tau
        } else {
            self.phase_at(self.span) + self.omega_end * (tau - self.span)
        }
    }
}

/// The drive of `params` with ω_e swept (Fig 3).
#[derive(Debug, Clone, Copy)]
pub struct Chirp {
    pub params: Params,
    pub sweep: Sweep,
}

impl Forcing for Chirp {
    fn phi_sq(&self, tau: f64) -> (f64, f64) {
        let theta = self.sweep.phase_at(tau);
        let p = &self.params;
        let phi_sq_ii = if p.drive_ii().is_off() {
            0.0
        } else {
            p.drive_ii().phi_sq(theta + p.phase_ii())
        };
        (p.drive_i().phi_sq(theta), phi_sq_ii)
    }
}
