//! Fig 2: the static force f_II − f_I on the mass against the offset Δλ = λ_I − λ_p.

use serde::{Deserialize, Serialize};

use crate::model::error::{ParamError, check, check_in};
use crate::model::forces::{gent_poles, net_force};
use crate::model::limits;
use crate::model::{DriveSpec, ParamSpec};

/// Which curves to draw: one per pre-stretch and per static voltage on membrane I.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ForceCurveSpec {
    /// Pre-stretches λ_p, one curve each.
    pub lambda_p: Vec<f64>,
    /// Static voltages φ_I on membrane I, one curve each.
    pub phi_i: Vec<f64>,
    /// Gent constant J.
    pub j: f64,
    /// Range of Δλ.
    pub dx_min: f64,
    pub dx_max: f64,
    /// Points per curve.
    pub points: usize,
}

impl Default for ForceCurveSpec {
    /// Fig 2A: λ_p ∈ {1.0, 1.02, 1.05} with no voltage.
    fn default() -> Self {
        ForceCurveSpec {
            lambda_p: vec![1.0, 1.02, 1.05],
            phi_i: vec![0.0],
            j: 16.0,
            dx_min: -0.8,
            dx_max: 0.8,
            points: 401,
        }
    }
}

/// One curve: its parameters and the (Δλ, f_II − f_I) samples; Δλ outside the model (frames,
/// Gent limit) is left out.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ForceCurve {
    pub lambda_p: f64,
    pub phi_i: f64,
    pub points: Vec<[f64; 2]>,
}

impl ForceCurveSpec {
    /// Checks every setting; the error names the first bad one.
    pub fn validate(&self) -> Result<(), ParamError> {
        check(
            "points",
            self.points as f64,
            |n| (2.0..=1e6).contains(&n),
            "[2, 1000000]",
        )?;
        let j = check_in("j", self.j, limits::J.0, limits::J.1)?;
        for (field, list) in [("lambda_p", &self.lambda_p), ("phi_i", &self.phi_i)] {
            check(
                field,
                list.len() as f64,
                |n| (1.0..=100.0).contains(&n),
                "1 to 100 values",
            )?;
        }
        let (lo, hi) = gent_poles(j);
        for &l in &self.lambda_p {
            check(
                "lambda_p",
                l,
                |l| l > lo && l < hi,
                format!("({lo:.5}, {hi:.5}), between the Gent poles for J = {j}"),
            )?;
        }
        for &phi in &self.phi_i {
            check_in("phi_i", phi, limits::PHI_DC.0, limits::PHI_DC.1)?;
        }
        check_in("dx_min", self.dx_min, limits::DX.0, limits::DX.1)?;
        check_in("dx_max", self.dx_max, limits::DX.0, limits::DX.1)?;
        check(
            "dx_min",
            self.dx_min,
            |d| d < self.dx_max,
            format!("< dx_max = {}", self.dx_max),
        )?;
        Ok(())
    }
}

/// The static force curves of `spec` (no velocity, no damping force).
pub fn force_curves(spec: &ForceCurveSpec) -> Result<Vec<ForceCurve>, ParamError> {
    spec.validate()?;
    let mut curves = Vec::new();
    for &lambda_p in &spec.lambda_p {
        for &phi_i in &spec.phi_i {
            let params = ParamSpec {
                lambda_p,
                j: spec.j,
                drive: DriveSpec::Phi {
                    phi_dc: phi_i,
                    phi_ac: 0.0,
                },
                ..ParamSpec::default()
            }
            .build()?;
            let upper = gent_poles(spec.j).1;
            let phi_sq = phi_i * phi_i;
            let points = (0..spec.points)
                .map(|i| {
                    spec.dx_min + (spec.dx_max - spec.dx_min) * i as f64 / (spec.points - 1) as f64
                })
                .filter(|dx| {
                    let x = lambda_p + dx;
                    x > 0.0 && x < 2.0 * lambda_p && x < upper && 2.0 * lambda_p - x < upper
                })
                .map(|dx| [dx, net_force(&params, lambda_p + dx, 0.0, phi_sq, 0.0)])
                .collect();
            curves.push(ForceCurve {
                lambda_p,
                phi_i,
                points,
            });
        }
    }
    Ok(curves)
}
