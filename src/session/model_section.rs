//! The `[model]` table of a session: non-dimensional values, or physical ones converted with
//! the session's device.

use serde::{Deserialize, Serialize};

use crate::model::error::{ParamError, check};
use crate::model::limits;
use crate::model::{Device, DriveSpec, ParamSpec};

/// Model parameters as a session writes them. Every key is optional (the paper's baseline
/// fills the gaps); a quantity may be given non-dimensionally or physically, not both.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelSection {
    pub lambda_p: Option<f64>,
    pub j: Option<f64>,
    pub c_tilde: Option<f64>,
    /// Physical damping coefficient c, N·s/m (instead of c_tilde).
    pub damping_n_s_per_m: Option<f64>,
    pub omega: Option<f64>,
    /// Forcing frequency in Hz (instead of omega).
    pub frequency_hz: Option<f64>,
    pub e_a: Option<f64>,
    pub adr: Option<f64>,
    pub phi_dc: Option<f64>,
    pub phi_ac: Option<f64>,
    /// DC and AC voltages in kV (instead of phi_dc, phi_ac).
    pub dc_kv: Option<f64>,
    pub ac_kv: Option<f64>,
    pub phi_dc_ii: Option<f64>,
    pub phi_ac_ii: Option<f64>,
    pub phase_ii: Option<f64>,
}

/// A key's range, [lo, hi], and how the error words it.
type Allowed = (f64, f64, String);

impl ModelSection {
    /// These values over `base` (a session's model under an analysis' overrides). A quantity
    /// with two forms (`omega` or `frequency_hz`, ...) is taken whole from whichever sets it,
    /// so an analysis' `omega` overrides the session's `frequency_hz`.
    pub fn over(&self, base: &ModelSection) -> ModelSection {
        macro_rules! pick {
            ($($f:ident),*) => { ModelSection { $($f: self.$f.or(base.$f)),* } };
        }
        let mut merged = pick!(
            lambda_p,
            j,
            c_tilde,
            damping_n_s_per_m,
            omega,
            frequency_hz,
            e_a,
            adr,
            phi_dc,
            phi_ac,
            dc_kv,
            ac_kv,
            phi_dc_ii,
            phi_ac_ii,
            phase_ii
        );
        macro_rules! whole {
            ($a:ident, $b:ident) => {
                if self.$a.is_some() || self.$b.is_some() {
                    merged.$a = self.$a;
                    merged.$b = self.$b;
                }
            };
        }
        whole!(omega, frequency_hz);
        whole!(c_tilde, damping_n_s_per_m);
        whole!(phi_dc, dc_kv);
        whole!(phi_ac, ac_kv);
        merged
    }

    /// Checks every key that is set against its own range, in its own units (a physical value
    /// against the non-dimensional range converted with `device`), so that an error names the
    /// key as written.
    pub fn check_keys(&self, device: &Device) -> Result<(), ParamError> {
        // a physical range converted from a non-dimensional one, a hair inside so that the
        // value converted back is inside the non-dimensional range too
        let inside = |(lo, hi): (f64, f64)| (lo + 1e-9 * (hi - lo), hi - 1e-9 * (hi - lo));
        let physical = |(lo, hi): (f64, f64), to: &dyn Fn(f64) -> f64, unit: &str, of: &str| {
            let (a, b) = (to(lo), to(hi));
            let (lo_p, hi_p) = if lo == 0.0 {
                (0.0, inside((a, b)).1)
            } else {
                inside((a, b))
            };
            (
                lo_p,
                hi_p,
                format!("[{lo_p:.6}, {hi_p:.6}] {unit} ({of} {lo} to {hi} for this device)"),
            )
        };
        let range = |(lo, hi): (f64, f64)| (lo, hi, format!("[{lo}, {hi}]"));
        let keys: [(&str, Option<f64>, Allowed); 15] = [
            (
                "lambda_p",
                self.lambda_p,
                (0.0, f64::MAX, "> 0, between the Gent poles".into()),
            ),
            ("j", self.j, range(limits::J)),
            ("c_tilde", self.c_tilde, range(limits::C_TILDE)),
            (
                "damping_n_s_per_m",
                self.damping_n_s_per_m,
                physical(limits::C_TILDE, &|c| device.damping(c), "N·s/m", "c̃"),
            ),
            ("omega", self.omega, range(limits::OMEGA)),
            (
                "frequency_hz",
                self.frequency_hz,
                physical(limits::OMEGA, &|w| device.hz(w), "Hz", "ω_e"),
            ),
            ("e_a", self.e_a, range(limits::E_A)),
            ("adr", self.adr, range(limits::ADR)),
            ("phi_dc", self.phi_dc, range(limits::PHI_DC)),
            ("phi_ac", self.phi_ac, range(limits::PHI_AC)),
            (
                "dc_kv",
                self.dc_kv,
                physical(limits::PHI_DC, &|p| device.kv(p), "kV", "φ_DC"),
            ),
            (
                "ac_kv",
                self.ac_kv,
                physical(limits::PHI_AC, &|p| device.kv(p), "kV", "φ_AC"),
            ),
            ("phi_dc_ii", self.phi_dc_ii, range(limits::PHI_DC)),
            ("phi_ac_ii", self.phi_ac_ii, range(limits::PHI_AC)),
            ("phase_ii", self.phase_ii, range(limits::PHASE)),
        ];
        for (key, value, (lo, hi, allowed)) in keys {
            if let Some(v) = value {
                check(
                    key,
                    v,
                    |v| v >= lo && v <= hi && (key != "lambda_p" || v > 0.0),
                    allowed,
                )?;
            }
        }
        for (a, b) in [
            ("omega", "frequency_hz"),
            ("c_tilde", "damping_n_s_per_m"),
            ("phi_dc", "dc_kv"),
            ("phi_ac", "ac_kv"),
        ] {
            if let (Some(_), Some(v)) = (self.get(a), self.get(b)) {
                return Err(ParamError {
                    field: b.into(),
                    value: v,
                    allowed: format!("one form only: {a} or {b}, not both"),
                });
            }
        }
        Ok(())
    }

    /// The value of key `key`, if set.
    pub fn get(&self, key: &str) -> Option<f64> {
        match key {
            "lambda_p" => self.lambda_p,
            "j" => self.j,
            "c_tilde" => self.c_tilde,
            "damping_n_s_per_m" => self.damping_n_s_per_m,
            "omega" => self.omega,
            "frequency_hz" => self.frequency_hz,
            "e_a" => self.e_a,
            "adr" => self.adr,
            "phi_dc" => self.phi_dc,
            "phi_ac" => self.phi_ac,
            "dc_kv" => self.dc_kv,
            "ac_kv" => self.ac_kv,
            "phi_dc_ii" => self.phi_dc_ii,
            "phi_ac_ii" => self.phi_ac_ii,
            "phase_ii" => self.phase_ii,
            _ => None,
        }
    }

    /// The non-dimensional parameters, converting physical values with `device`; every key
    /// is checked in its own units first ([`ModelSection::check_keys`]).
    pub fn to_spec(&self, device: &Device) -> Result<ParamSpec, ParamError> {
        self.check_keys(device)?;
        let base = ParamSpec::default();
        // one form of each quantity at most (checked above): the one given
        let c_tilde = self
            .c_tilde
            .or(self.damping_n_s_per_m.map(|c| device.c_tilde(c)));
        let omega = self
            .omega
            .or(self.frequency_hz.map(|f| device.omega_from_hz(f)));
        let phi_dc = self.phi_dc.or(self.dc_kv.map(|v| device.phi_from_kv(v)));
        let phi_ac = self.phi_ac.or(self.ac_kv.map(|v| device.phi_from_kv(v)));
        let drive = match (phi_dc, phi_ac, self.e_a, self.adr) {
            (Some(_), _, Some(e), _) | (_, Some(_), Some(e), _) => {
                return Err(ParamError {
                    field: "e_a".into(),
                    value: e,
                    allowed: "either e_a/adr or phi_dc/phi_ac (or dc_kv/ac_kv), not both".into(),
                });
            }
            (Some(_), _, _, Some(a)) | (_, Some(_), _, Some(a)) => {
                return Err(ParamError {
                    field: "adr".into(),
                    value: a,
                    allowed: "either e_a/adr or phi_dc/phi_ac (or dc_kv/ac_kv), not both".into(),
                });
            }
            (None, None, e_a, adr) => DriveSpec::EaAdr {
                e_a: e_a.unwrap_or(0.04),
                adr: adr.unwrap_or(0.6),
            },
            (dc, ac, _, _) => DriveSpec::Phi {
                phi_dc: dc.unwrap_or(0.0),
                phi_ac: ac.unwrap_or(0.0),
            },
        };
        let drive_ii = match (self.phi_dc_ii, self.phi_ac_ii) {
            (None, None) => None,
            (dc, ac) => Some(DriveSpec::Phi {
                phi_dc: dc.unwrap_or(0.0),
                phi_ac: ac.unwrap_or(0.0),
            }),
        };
        Ok(ParamSpec {
            lambda_p: self.lambda_p.unwrap_or(base.lambda_p),
            j: self.j.unwrap_or(base.j),
            c_tilde: c_tilde.unwrap_or(base.c_tilde),
            omega: omega.unwrap_or(base.omega),
            drive,
            drive_ii,
            phase_ii: self.phase_ii.unwrap_or(0.0),
        })
    }
}
