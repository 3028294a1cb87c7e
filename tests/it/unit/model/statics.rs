//! Unit tests of `model::statics` (`src/model/statics.rs`).

use isola::model::Params;
use isola::model::forces::membrane_forces;
use isola::model::statics::*;
use isola::model::{DriveSpec, ParamSpec};
use isola::solver::illinois::illinois;
use isola::solver::{Dopri5, Tolerance};
use std::f64::consts::PI;

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
