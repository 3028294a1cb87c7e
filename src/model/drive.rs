//! The AC+DC voltage on one membrane, φ(τ) = φ_DC + φ_AC·cos(ω_e τ), and its square
//! φ² = E_a + E_b cos(ω_e τ) + E_c cos(2 ω_e τ) (MODEL.md §2).

use serde::{Deserialize, Serialize};

use super::error::{ParamError, check_in};
use super::limits;

/// How a user gives a drive: the paper's (E_a, ADR) or the voltages (φ_DC, φ_AC).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(untagged, deny_unknown_fields)]
pub enum DriveSpec {
    /// Mean-square voltage E_a and AC-to-DC ratio ADR = φ_AC/φ_DC.
    EaAdr { e_a: f64, adr: f64 },
    /// DC and AC amplitudes of the non-dimensional voltage.
    Phi { phi_dc: f64, phi_ac: f64 },
}

/// A validated drive, stored as its voltages (φ_DC ≥ 0, φ_AC ≥ 0), and as given if it was
/// given as (E_a, ADR): those read back exactly, so a drive rebuilt from them (a family
/// member, a frequency of a sweep) has the very voltages of the original.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drive {
    phi_dc: f64,
    phi_ac: f64,
    given: Option<(f64, f64)>,
}

impl Drive {
    /// No voltage at all.
    pub const OFF: Drive = Drive {
        phi_dc: 0.0,
        phi_ac: 0.0,
        given: None,
    };

    /// From E_a = φ_DC² + φ_AC²/2 and ADR = φ_AC/φ_DC.
    pub fn from_ea_adr(e_a: f64, adr: f64) -> Result<Self, ParamError> {
        let e_a = check_in("e_a", e_a, limits::E_A.0, limits::E_A.1)?;
        let adr = check_in("adr", adr, limits::ADR.0, limits::ADR.1)?;
        let phi_dc = (e_a / (1.0 + 0.5 * adr * adr)).sqrt();
        Ok(Drive {
            phi_dc,
            phi_ac: adr * phi_dc,
            given: Some((e_a, adr)),
        })
    }

    /// From the DC and AC amplitudes of φ.
    pub fn from_phi(phi_dc: f64, phi_ac: f64) -> Result<Self, ParamError> {
        Ok(Drive {
            phi_dc: check_in("phi_dc", phi_dc, limits::PHI_DC.0, limits::PHI_DC.1)?,
            phi_ac: check_in("phi_ac", phi_ac, limits::PHI_AC.0, limits::PHI_AC.1)?,
            given: None,
        })
    }

    /// Validates a user's spec.
    pub fn from_spec(spec: DriveSpec) -> Result<Self, ParamError> {
        match spec {
            DriveSpec::EaAdr { e_a, adr } => Self::from_ea_adr(e_a, adr),
            DriveSpec::Phi { phi_dc, phi_ac } => Self::from_phi(phi_dc, phi_ac),
        }
    }

    pub fn phi_dc(&self) -> f64 {
        self.phi_dc
    }

    pub fn phi_ac(&self) -> f64 {
        self.phi_ac
    }

    /// E_a = φ_DC² + φ_AC²/2, the mean of φ² (as given, if it was).
    pub fn e_a(&self) -> f64 {
        match self.given {
            Some((e_a, _)) => e_a,
            None => self.phi_dc * self.phi_dc + 0.5 * self.phi_ac * self.phi_ac,
        }
    }

    /// E_b = 2 φ_DC φ_AC, the amplitude of φ² at ω_e.
    pub fn e_b(&self) -> f64 {
        2.0 * self.phi_dc * self.phi_ac
    }

    /// E_c = φ_AC²/2, the amplitude of φ² at 2 ω_e.
    pub fn e_c(&self) -> f64 {
        0.5 * self.phi_ac * self.phi_ac
    }

    /// ADR = φ_AC/φ_DC (as given, if it was); `None` for a pure AC drive.
    pub fn adr(&self) -> Option<f64> {
        match self.given {
            Some((_, adr)) => Some(adr),
            None => (self.phi_dc > 0.0).then(|| self.phi_ac / self.phi_dc),
        }
    }

    /// Peak voltage φ_DC + φ_AC.
    pub fn phi_peak(&self) -> f64 {
        self.phi_dc + self.phi_ac
    }

    /// φ at forcing phase θ = ω_e τ (plus any phase shift of this membrane).
    pub fn phi(&self, theta: f64) -> f64 {
        self.phi_dc + self.phi_ac * theta.cos()
    }

    /// φ² at forcing phase θ.
    pub fn phi_sq(&self, theta: f64) -> f64 {
        let phi = self.phi(theta);
        phi * phi
    }

    /// True when no voltage is applied.
    pub fn is_off(&self) -> bool {
        self.phi_dc == 0.0 && self.phi_ac == 0.0
    }

    /// The spec that rebuilds this drive in the paper's variables when possible.
    pub fn to_spec(&self) -> DriveSpec {
        match self.adr() {
            Some(adr) => DriveSpec::EaAdr {
                e_a: self.e_a(),
                adr,
            },
            None => DriveSpec::Phi {
                phi_dc: self.phi_dc,
                phi_ac: self.phi_ac,
            },
        }
    }
}
