//! Unit tests of `solver::field` (`src/solver/field.rs`).

use isola::model::Params;
use isola::model::forces::{net_force, outside_model};
use isola::model::{DriveSpec, ParamSpec};
use isola::solver::field::*;

/// The one-division form equals the readable force law of `model::forces`.
#[test]
fn fast_form_equals_the_force_law() {
    let p = ParamSpec {
        drive_ii: Some(DriveSpec::Phi {
            phi_dc: 0.1,
            phi_ac: 0.05,
        }),
        ..ParamSpec::default()
    }
    .build()
    .unwrap();
    let f = Field::new(&p);
    let mut n = 0;
    for i in 0..=200 {
        let x = 0.01 + 2.02 * i as f64 / 200.0;
        for &v in &[-2.0, -0.3, 0.0, 0.1, 1.5] {
            for &(a, b) in &[(0.0, 0.0), (0.04, 0.0), (0.09, 0.03)] {
                let fast = f.accel(x, v, a, b).0;
                let slow = net_force(&p, x, v, a, b);
                assert!(
                    (fast - slow).abs() <= 1e-12 * (1.0 + slow.abs()),
                    "x {x} v {v}: {fast} vs {slow}"
                );
                assert_eq!(f.inside(x), !outside_model(&p, x));
                n += 1;
            }
        }
    }
    assert!(n > 3000);
}

/// In its own mode the smooth extension is the true field.
#[test]
fn smooth_extension_agrees_in_its_own_mode() {
    let p = Params::baseline();
    let f = Field::new(&p);
    for i in 0..100 {
        let x = 0.5 + i as f64 * 0.01;
        let (a, mode) = f.accel(x, 0.2, 0.04, 0.0);
        let b = f.accel_in_mode(x, 0.2, 0.04, 0.0, mode);
        assert!((a - b).abs() < 1e-12 * (1.0 + a.abs()));
    }
}

/// The division-free switching function has the sign of the tension, and is the same
/// multiple of it for both membranes as `scaled_tensions` uses.
#[test]
fn scaled_tension_has_the_sign_of_the_tension() {
    let p = Params::baseline();
    let f = Field::new(&p);
    for i in 0..=400 {
        let x = 0.01 + 2.0 * i as f64 / 400.0;
        for &v in &[-1.0, -0.01, 0.0, 0.02, 0.7] {
            for m in [Membrane::I, Membrane::Ii] {
                let p = f.tension_of(m, x, v, 0.05, 0.01);
                let scaled = f.scaled_tension_of(m, x, v, 0.05, 0.01);
                assert_eq!(p > 0.0, scaled > 0.0, "x {x} v {v} {m:?}: {p} vs {scaled}");
                assert_eq!(p == -1.0, scaled == -1.0, "x {x} v {v} {m:?}");
            }
            let t = f.scaled_tensions(x, v, 0.05, 0.01);
            if t.den_i > 0.0 {
                assert_eq!(
                    t.big_p_i,
                    f.scaled_tension_of(Membrane::I, x, v, 0.05, 0.01)
                );
            }
            if t.den_ii > 0.0 {
                assert_eq!(
                    t.big_p_ii,
                    f.scaled_tension_of(Membrane::Ii, x, v, 0.05, 0.01)
                );
            }
        }
    }
}

/// The rate of the switching function is its derivative along a trajectory.
#[test]
fn scaled_tension_rate_is_its_derivative() {
    let p = Params::baseline();
    let f = Field::new(&p);
    // a made-up trajectory and drive, smooth in τ
    let x = |t: f64| 1.02 + 0.3 * (1.7 * t).sin();
    let v = |t: f64| 0.51 * (1.7 * t).cos();
    let a = |t: f64| -0.867 * (1.7 * t).sin();
    let phi = |t: f64| (0.04 + 0.01 * (3.0 * t).cos(), 0.02 * (1.0 + t * t));
    let phi_rate = |t: f64| (-0.03 * (3.0 * t).sin(), 0.04 * t);
    let e = 1e-6;
    for i in 0..40 {
        let t = 0.1 * i as f64;
        for m in [Membrane::I, Membrane::Ii] {
            let g = |t: f64| f.scaled_tension_of(m, x(t), v(t), phi(t).0, phi(t).1);
            let numeric = (g(t + e) - g(t - e)) / (2.0 * e);
            let rate = f.scaled_tension_rate(m, [x(t), v(t), a(t)], phi(t), phi_rate(t));
            assert!(
                (rate - numeric).abs() < 1e-6 * (1.0 + numeric.abs()),
                "{m:?} at {t}: {rate} vs {numeric}"
            );
        }
    }
}

/// In every mode, the one-division smooth extension equals the difference of the two
/// switching functions it pulls with, below the lower Gent pole too (p = −1 there).
#[test]
fn smooth_extension_is_the_pull_of_the_taut_membranes() {
    let p = Params::baseline();
    let f = Field::new(&p);
    let mut below_pole = 0;
    for i in 0..=200 {
        let x = 0.01 + 2.0 * i as f64 / 200.0;
        for &v in &[-1.0, 0.0, 0.7] {
            let (p_i, p_ii) = f.tensions(x, v, 0.05, 0.01);
            below_pole += usize::from(p_i == -1.0 || p_ii == -1.0);
            for code in [0.0, 1.0, 2.0, 3.0] {
                let mode = Mode::from_code(code);
                let expected =
                    if mode.taut_ii { p_ii } else { 0.0 } - if mode.taut_i { p_i } else { 0.0 };
                let a = f.accel_in_mode(x, v, 0.05, 0.01, mode);
                assert!(
                    (a - expected).abs() <= 1e-12 * (1.0 + expected.abs()),
                    "x {x} v {v} {mode:?}: {a} vs {expected}"
                );
            }
        }
    }
    assert!(below_pole > 0, "the range reaches below a lower pole");
}
