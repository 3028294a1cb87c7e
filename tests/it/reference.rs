//! The adaptive reference integrator checked against exact results, and the fast RK4 checked
//! against the reference.

use isola::analysis::{DopriPeriodMap, SteadyStateSpec, steady_state, steady_state_with};
use isola::model::forces::{gent, gent_energy};
use isola::model::{DriveSpec, ParamSpec, Params};
use isola::solver::{Dopri5, Resolution, Tolerance};

const TIGHT: Tolerance = Tolerance {
    rtol: 1e-12,
    atol: 1e-14,
};

fn unforced_undamped(lambda_p: f64) -> Params {
    ParamSpec {
        lambda_p,
        c_tilde: 0.0,
        omega: 1.0,
        drive: DriveSpec::Phi {
            phi_dc: 0.0,
            phi_ac: 0.0,
        },
        ..ParamSpec::default()
    }
    .build()
    .unwrap()
}

/// With no voltage a membrane is taut exactly when λ > 1, so the potential is
/// W(max(λ_I, 1)) + W(max(λ_II, 1)): continuous with its slope, and conserved with v²/2.
fn energy(p: &Params, x: f64, v: f64) -> f64 {
    let w = |l: f64| gent_energy(l.max(1.0), p.j());
    0.5 * v * v + w(x) + w(2.0 * p.lambda_p() - x)
}

/// Energy is conserved to 1e-9 (relative) over 200 time units, both on a smooth orbit and on
/// one that goes slack twice per cycle, where the switching events are crossed ~100 times.
#[test]
fn unforced_undamped_motion_conserves_energy() {
    for (lambda_p, x0, v0) in [(1.2, 1.25, 0.0), (1.02, 1.02, 0.9)] {
        let p = unforced_undamped(lambda_p);
        let dopri = Dopri5::new(&p, TIGHT);
        let mut s = dopri.state(0.0, x0, v0);
        let e0 = energy(&p, x0, v0);
        let mut worst: f64 = 0.0;
        let mut switches = 0;
        let mut mode = s.mode;
        for k in 1..=200 {
            dopri.integrate(&mut s, k as f64, |_| {}).unwrap();
            worst = worst.max((energy(&p, s.x, s.v) - e0).abs() / e0);
            if s.mode != mode {
                switches += 1;
                mode = s.mode;
            }
        }
        assert!(
            worst < 1e-9,
            "λ_p {lambda_p}: relative energy drift {worst:e}"
        );
        if lambda_p == 1.02 {
            assert!(
                switches > 20,
                "the slack orbit must cross its switches ({switches})"
            );
        }
    }
}

/// A tiny oscillation about λ_p has the linear period 2π/√(2 g'(λ_p)); the measured period
/// (from zero crossings on the dense output) matches to 1e-7 relative at amplitude 1e-4
/// (nonlinear correction ~ amplitude² ≈ 1e-8).
#[test]
fn small_oscillation_has_the_linear_period() {
    let p = unforced_undamped(1.2);
    let dg = (gent(1.2 + 1e-6, 16.0) - gent(1.2 - 1e-6, 16.0)) / 2e-6;
    let expected = 2.0 * std::f64::consts::PI / (2.0 * dg).sqrt();
    let dopri = Dopri5::new(&p, TIGHT);
    let mut s = dopri.state(0.0, 1.2 + 1e-4, 0.0);
    let mut crossings = Vec::new();
    dopri
        .integrate(&mut s, 20.0 * expected, |d| {
            let (a, b) = (d.at(d.t0)[1], d.at(d.t1)[1]);
            if a > 0.0 && b <= 0.0 {
                // refine the velocity's downward zero on the dense output
                let t = isola::solver::dopri::root_of(|t| d.at(t)[1], d.t0, d.t1, a);
                crossings.push(t);
            }
        })
        .unwrap();
    assert!(crossings.len() >= 19);
    let measured = (crossings.last().unwrap() - crossings[0]) / (crossings.len() - 1) as f64;
    assert!(
        ((measured - expected) / expected).abs() < 1e-7,
        "{measured} vs {expected}"
    );
}

/// Slack orbits (membranes losing tension every cycle): the fast RK4 at its default resolution
/// matches the reference at rtol 1e-12 to 5e-6 in amplitude and stroboscopic points, and
/// refining the step 2× cuts the error by at least 10× (fourth order, not the second order an
/// unsplit kink leaves).
#[test]
fn rk4_converges_to_the_reference_at_fourth_order() {
    for (adr, omega, dx, v0) in [
        (0.6, 3.7, 0.3, 0.0),
        (0.6, 1.8, 0.4, 0.0),
        (1.0, 3.6, -0.1, 0.5),
    ] {
        let p = Params::paper(adr, omega).unwrap();
        let x0 = p.lambda_p() + dx;
        let spec = SteadyStateSpec::default();
        let reference = steady_state_with(&mut DopriPeriodMap::new(&p, TIGHT, x0, v0), &spec);
        let fast = steady_state(&p, x0, v0, &spec);
        assert_eq!(fast.period, reference.period);
        assert_eq!(fast.ratio, reference.ratio);
        let amp_ref = reference.amplitude.unwrap();
        let err = |s: &isola::analysis::SteadyState| (s.amplitude.unwrap() - amp_ref).abs();
        assert!(
            err(&fast) < 5e-6,
            "ω {omega}: amplitude error {:e}",
            err(&fast)
        );
        let strobe_err = fast
            .poincare
            .iter()
            .map(|q| {
                reference
                    .poincare
                    .iter()
                    .map(|r| (q[0] - r[0]).abs().max((q[1] - r[1]).abs()))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max);
        assert!(
            strobe_err < 5e-6,
            "ω {omega}: Poincaré error {strobe_err:e}"
        );
        let at = |n: u32| {
            let spec = SteadyStateSpec {
                resolution: Resolution {
                    min_steps_per_period: n,
                    max_step: 10.0,
                },
                ..SteadyStateSpec::default()
            };
            err(&steady_state(&p, x0, v0, &spec))
        };
        let (coarse, fine) = (at(48), at(96));
        assert!(coarse / fine > 10.0, "ω {omega}: {coarse:e} → {fine:e}");
    }
}

/// The reference agrees with itself at two tolerances (1e-10 vs 1e-12) to 1e-8 in amplitude.
#[test]
fn reference_is_self_consistent() {
    let p = Params::paper(0.6, 3.7).unwrap();
    let spec = SteadyStateSpec::default();
    let x0 = p.lambda_p() + 0.3;
    let a = steady_state_with(&mut DopriPeriodMap::new(&p, TIGHT, x0, 0.0), &spec);
    let loose = Tolerance {
        rtol: 1e-10,
        atol: 1e-12,
    };
    let b = steady_state_with(&mut DopriPeriodMap::new(&p, loose, x0, 0.0), &spec);
    assert!((a.amplitude.unwrap() - b.amplitude.unwrap()).abs() < 1e-8);
}
