//! What the model's parameters imply before anything moves: the drive's Fourier coefficients,
//! the static equilibrium under the mean drive, and the linear natural frequency about it.

use serde::Serialize;

use super::Params;
use super::forces::{gent_poles, gent_slope, membrane_force, net_force, tension};
use crate::solver::illinois::illinois;

/// The static equilibrium λ_I* under the mean drive and the small oscillations about it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Equilibrium {
    /// λ_I* where f_II = f_I with φ² at its mean (E_a on each membrane), v = 0.
    pub lambda_i: f64,
    /// Linear natural frequency ω₀, ω₀² = d(f_I − f_II)/dλ_I at λ_I*; none where that slope
    /// is not defined (a membrane exactly at loss of tension, where the force has a kink) or
    /// not positive (both membranes slack: the mass rests anywhere near, no restoring force).
    pub omega_0: Option<f64>,
}

/// The derived quantities of a parameter set (non-dimensional).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Derived {
    /// φ_I² = E_a + E_b cos(ω_e τ) + E_c cos(2ω_e τ) (MODEL.md §2).
    pub e_a: f64,
    pub e_b: f64,
    pub e_c: f64,
    /// φ_AC/φ_DC; none for a pure AC drive.
    pub adr: Option<f64>,
    pub phi_dc: f64,
    pub phi_ac: f64,
    /// None when the mean drive pulls the mass onto a frame (no equilibrium inside the model).
    pub equilibrium: Option<Equilibrium>,
}

/// Points the search for the equilibrium tries between λ_p and the end of the model's domain
/// before it gives up (the first sign change of the net force is then bracketed and narrowed).
const SEARCH_POINTS: usize = 4096;

/// The derived quantities of `p`.
pub fn derived(p: &Params) -> Derived {
    let d = p.drive_i();
    Derived {
        e_a: d.e_a(),
        e_b: d.e_b(),
        e_c: d.e_c(),
        adr: d.adr(),
        phi_dc: d.phi_dc(),
        phi_ac: d.phi_ac(),
        equilibrium: equilibrium(p),
    }
}

/// The static equilibrium nearest λ_p under the mean drive (φ_I² = E_a, φ_II² = E_a of
/// membrane II's drive), reached by moving from λ_p the way the net force pushes; `None` if the
/// mass reaches a frame or a Gent limit first.
pub fn equilibrium(p: &Params) -> Option<Equilibrium> {
    let mean_phi_sq = (p.drive_i().e_a(), p.drive_ii().e_a());
    let net = |x: f64| net_force(p, x, 0.0, mean_phi_sq.0, mean_phi_sq.1);
    let x0 = p.lambda_p();
    let push = net(x0);
    let lambda_i = if push == 0.0 {
        x0
    } else {
        // the model's domain: λ_I and λ_II = 2λ_p − λ_I both above 0 and below the upper pole
        let upper = gent_poles(p.j()).1;
        let end = if push > 0.0 {
            (2.0 * x0).min(upper)
        } else {
            (2.0 * x0 - upper).max(0.0)
        };
        // distances from λ_p along the push, and the force there: positive while it still
        // pushes the same way, negative (a zero counted as negative) once it stops, also at
        // the edge of a stretch where both membranes are slack and nothing pushes
        let (sign, step) = (push.signum(), (end - x0).abs() / SEARCH_POINTS as f64);
        let ahead = |s: f64| match sign * net(x0 + sign * s) {
            a if a > 0.0 => a,
            a => a.min(-f64::MIN_POSITIVE),
        };
        let k = (1..SEARCH_POINTS).find(|&k| ahead(k as f64 * step) < 0.0)?;
        let (near, far) = ((k - 1) as f64 * step, k as f64 * step);
        let distance = illinois(x0, (near, far), (ahead(near), ahead(far)), ahead);
        x0 + sign * distance
    };
    Some(Equilibrium {
        lambda_i,
        omega_0: stiffness(p, lambda_i, mean_phi_sq).map(f64::sqrt),
    })
}

/// A tension this close to 0 at the equilibrium is its kink: λ_I* is located to a few ulps,
/// so a membrane that goes slack there has a tension of ~1e-15; one clear of it, ~1e-2.
const AT_LOSS: f64 = 1e-9;

/// d(f_I − f_II)/dλ_I at λ_I = `x`, v = 0 under (φ_I², φ_II²): each taut membrane adds its
/// slope g′(λ) − φ² (λ_II = 2λ_p − λ_I moves the other way, so its force's slope adds too);
/// a slack one adds nothing. None at a membrane's kink (tension exactly 0) or if not positive.
fn stiffness(p: &Params, x: f64, (phi_sq_i, phi_sq_ii): (f64, f64)) -> Option<f64> {
    let (c, j) = (p.c_tilde(), p.j());
    let mut slope = 0.0;
    for (lambda, phi_sq) in [(x, phi_sq_i), (2.0 * p.lambda_p() - x, phi_sq_ii)] {
        if membrane_force(lambda, phi_sq, 0.0, c, j) > 0.0 {
            slope += gent_slope(lambda, j) - phi_sq;
        }
        if lambda > gent_poles(j).0 && tension(lambda, phi_sq, 0.0, c, j).abs() <= AT_LOSS {
            return None;
        }
    }
    (slope > 0.0).then_some(slope)
}
