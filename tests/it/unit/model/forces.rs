//! Unit tests of `model::forces` (`src/model/forces.rs`).

use isola::model::forces::*;
use isola::model::params::Params;

#[test]
fn poles_for_j16_are_sqrt5_pm_2() {
    let (lo, hi) = gent_poles(16.0);
    assert!((lo - (5f64.sqrt() - 2.0)).abs() < 1e-15);
    assert!((hi - (5f64.sqrt() + 2.0)).abs() < 1e-14);
    // the Gent denominator vanishes there
    for l in [lo, hi] {
        assert!((1.0 - (l * l + 1.0 / (l * l) - 2.0) / 16.0).abs() < 1e-13);
    }
}

#[test]
fn gent_is_the_derivative_of_its_energy() {
    for &l in &[0.4, 0.8, 1.0, 1.02, 1.3, 2.0, 3.5] {
        let h = 1e-6;
        let fd = (gent_energy(l + h, 16.0) - gent_energy(l - h, 16.0)) / (2.0 * h);
        assert!((fd - gent(l, 16.0)).abs() < 1e-7 * (1.0 + gent(l, 16.0).abs()));
    }
    // near λ = 1 the Gent law is linear with slope 4 (neo-Hookean limit)
    assert!((gent(1.0 + 1e-7, 16.0) / 1e-7 - 4.0).abs() < 1e-5);
}

/// The analytic slope against central differences, and 4 at λ = 1 (neo-Hookean limit).
#[test]
fn gent_slope_is_the_derivative_of_gent() {
    assert_eq!(gent_slope(1.0, 16.0), 4.0);
    for &l in &[0.4, 0.8, 1.02, 1.3, 2.0, 3.5] {
        let h = 1e-6;
        let fd = (gent(l + h, 16.0) - gent(l - h, 16.0)) / (2.0 * h);
        assert!((fd / gent_slope(l, 16.0) - 1.0).abs() < 1e-7, "{l}");
    }
}

/// Below the lower pole the Gent formula turns positive; the membrane is slack instead.
#[test]
fn slack_below_the_gent_pole_carries_no_force() {
    let lo = gent_poles(16.0).0;
    for &l in &[0.05, 0.1, 0.2, lo - 1e-9] {
        assert!(
            gent(l, 16.0) > 0.0,
            "the formula's artefact is there at {l}"
        );
        assert_eq!(membrane_force(l, 0.04, 0.0, 0.04, 16.0), 0.0);
        assert_eq!(membrane_force(l, 0.0, -5.0, 0.04, 16.0), 0.0);
    }
    // just above the pole the tension is hugely negative: the force stays continuous
    assert_eq!(membrane_force(lo + 1e-9, 0.0, 0.0, 0.04, 16.0), 0.0);
}

#[test]
fn loss_of_tension_clips_compression_and_viscous_push() {
    // λ < 1 with no voltage: compression, so no force
    assert_eq!(membrane_force(0.99, 0.0, 0.0, 0.04, 16.0), 0.0);
    // taut membrane: full tension including damping
    let p = tension(1.1, 0.04, 0.5, 0.04, 16.0);
    assert!(p > 0.0);
    assert_eq!(membrane_force(1.1, 0.04, 0.5, 0.04, 16.0), p);
    // the voltage slackens a membrane that is stretched a little (Fig 2B)
    assert!(tension(1.005, 0.09, 0.0, 0.0, 16.0) < 0.0);
}

#[test]
fn frames_and_gent_limit_are_outside_the_model() {
    let p = Params::baseline();
    assert!(!outside_model(&p, 1.02));
    assert!(!outside_model(&p, 0.3));
    assert!(outside_model(&p, 0.0));
    assert!(outside_model(&p, -0.1));
    assert!(outside_model(&p, 2.04));
    assert!(!outside_model(&p, 2.03));
}
