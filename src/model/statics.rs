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

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::model::forces::membrane_forces;
    use crate::model::{DriveSpec, ParamSpec};
    use crate::solver::{Dopri5, Tolerance};

    fn model(lambda_p: f64, e_a: f64) -> Params {
        ParamSpec {
            lambda_p,
            drive: DriveSpec::EaAdr { e_a, adr: 0.6 },
            ..ParamSpec::default()
        }
        .build()
        .unwrap()
    }

    /// At λ_I* the two membranes pull equally under the mean drive, both taut; more voltage
    /// on membrane I softens it and moves the mass further towards membrane II.
    #[test]
    fn the_equilibrium_balances_the_membranes() {
        let mut last = 0.0;
        for e_a in [0.0, 0.01, 0.04, 0.09] {
            let p = model(1.02, e_a);
            let eq = equilibrium(&p).unwrap();
            let (f_i, f_ii) = membrane_forces(&p, eq.lambda_i, 0.0, e_a, 0.0);
            assert!(f_i > 0.0 && f_ii > 0.0, "E_a {e_a}");
            assert!(
                (f_ii - f_i).abs() <= 1e-12 * f_i,
                "E_a {e_a}: {f_i} against {f_ii}"
            );
            assert!(eq.lambda_i >= last, "E_a {e_a}");
            last = eq.lambda_i;
        }
        assert_eq!(equilibrium(&model(1.02, 0.0)).unwrap().lambda_i, 1.02);
    }

    /// Without a linear restoring force there is no ω₀: at λ_p = 1 undriven both membranes
    /// rest exactly at loss of tension (a kink), and membrane II still does when E_a = 1
    /// slackens membrane I; below λ_p = 1 both are slack (no force near the rest point);
    /// a mean drive that slackens membrane I leaves the mass where membrane II goes slack.
    #[test]
    fn no_natural_frequency_without_a_linear_restoring_force() {
        for (lambda_p, e_a) in [(1.0, 0.0), (0.9, 0.0), (1.0, 1.0)] {
            let eq = equilibrium(&model(lambda_p, e_a)).unwrap();
            assert_eq!(eq.lambda_i, lambda_p, "λ_p {lambda_p}, E_a {e_a}");
            assert_eq!(eq.omega_0, None, "λ_p {lambda_p}, E_a {e_a}");
        }
        // E_a 0.2 slackens membrane I at λ_p 1.02: membrane II pushes the mass until it goes
        // slack itself at λ_II = 1, the edge of a stretch where neither pulls
        let eq = equilibrium(&model(1.02, 0.2)).unwrap();
        assert!((eq.lambda_i - 1.04).abs() < 1e-12, "{eq:?}");
        assert_eq!(eq.omega_0, None);
        assert!(equilibrium(&model(1.02, 0.04)).unwrap().omega_0.is_some());
    }

    /// ω₀ is the frequency of small free vibrations about λ_I*: no AC voltage, no damping,
    /// released 1e-4 from it, the period counted between upward crossings of λ_I* over
    /// 200 periods with the reference integrator.
    #[test]
    fn omega_0_is_the_frequency_of_small_free_vibrations() {
        let e_a: f64 = 0.04;
        let free = ParamSpec {
            c_tilde: 0.0,
            drive: DriveSpec::Phi {
                phi_dc: e_a.sqrt(),
                phi_ac: 0.0,
            },
            ..ParamSpec::default()
        }
        .build()
        .unwrap();
        let eq = equilibrium(&free).unwrap();
        let omega_0 = eq.omega_0.unwrap();
        let dopri = Dopri5::new(
            &free,
            Tolerance {
                rtol: 1e-12,
                atol: 1e-14,
            },
        );
        let mut state = dopri.state(0.0, eq.lambda_i + 1e-4, 0.0);
        let periods = 200.0;
        let mut crossings = Vec::new();
        dopri
            .integrate(&mut state, periods * 2.0 * PI / omega_0, |d| {
                let below = |t: f64| d.at(t)[0] - eq.lambda_i;
                if below(d.t0) < 0.0 && below(d.t1) >= 0.0 {
                    let t = illinois(
                        d.t0,
                        (0.0, d.t1 - d.t0),
                        (-below(d.t0), -below(d.t1)),
                        |s| -below(d.t0 + s),
                    );
                    crossings.push(d.t0 + t);
                }
            })
            .unwrap();
        assert!(crossings.len() >= 199, "{}", crossings.len());
        let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
        let omega = 2.0 * PI / period;
        // measured 1e-8: what is left is the amplitude's own (nonlinear) frequency shift
        assert!(
            (omega / omega_0 - 1.0).abs() < 1e-6,
            "{omega} against {omega_0}"
        );
    }

    /// The paper's baseline (λ_p 1.02, E_a 0.04, J 16, ADR 0.6), the figures the README
    /// gives: E_b, E_c as MODEL.md §2 checks them; λ_I* as a bisection of the force balance
    /// written out independently (in Python) gives it, 1.0254357280757076; ω₀ as the same
    /// with a central-difference g′ gives it, 2.7398979598 (the difference's own error ~1e-10).
    #[test]
    fn baseline_figures() {
        let d = derived(&Params::baseline());
        assert!(
            (d.e_b - 0.041).abs() < 5e-4 && (d.e_c - 0.006).abs() < 5e-4,
            "{d:?}"
        );
        let eq = d.equilibrium.unwrap();
        assert!((eq.lambda_i - 1.0254357280757076).abs() < 1e-13, "{eq:?}");
        assert!((eq.omega_0.unwrap() - 2.7398979598).abs() < 1e-9, "{eq:?}");
    }
}
