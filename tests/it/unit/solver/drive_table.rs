//! Unit tests of `solver::drive_table` (`src/solver/drive_table.rs`).

use isola::model::Params;
use isola::model::{DriveSpec, ParamSpec};
use isola::solver::drive_table::*;

/// Membrane II driven too, out of phase, so both halves of the drive are exercised.
fn both_membranes_driven() -> Params {
    ParamSpec {
        drive_ii: Some(DriveSpec::Phi {
            phi_dc: 0.1,
            phi_ac: 0.07,
        }),
        phase_ii: 1.3,
        ..ParamSpec::default()
    }
    .build()
    .unwrap()
}

#[test]
fn local_drive_matches_cos_over_a_step() {
    let p = both_membranes_driven();
    for &tau0 in &[0.0, 0.37, 12.9, 1234.5] {
        let local = LocalDrive::new(&p, tau0);
        let h = p.period() / 8.0;
        for i in 0..=20 {
            let d = h * i as f64 / 20.0;
            let (a, b) = local.phi_sq(d);
            let (ea, eb) = p.phi_sq_at(tau0 + d);
            assert!(
                (a - ea).abs() < 1e-13 && (b - eb).abs() < 1e-13,
                "{tau0} {d}"
            );
        }
    }
}

#[test]
fn rate_is_the_derivative_of_the_drive() {
    let p = both_membranes_driven();
    let local = LocalDrive::new(&p, 0.37);
    let (h, e) = (p.period() / 8.0, 1e-6);
    for i in 0..=10 {
        let d = h * i as f64 / 10.0;
        let (value, rate) = local.phi_sq_with_rate(d);
        assert_eq!(value, local.phi_sq(d));
        let (up, down) = (p.phi_sq_at(0.37 + d + e), p.phi_sq_at(0.37 + d - e));
        assert!((rate.0 - (up.0 - down.0) / (2.0 * e)).abs() < 1e-8, "{d}");
        assert!((rate.1 - (up.1 - down.1) / (2.0 * e)).abs() < 1e-8, "{d}");
    }
}

#[test]
fn small_sin_cos_is_accurate() {
    for i in -100..=100 {
        let x = std::f64::consts::FRAC_PI_4 * i as f64 / 100.0;
        let (s, c) = small_sin_cos(x);
        assert!(
            (s - x.sin()).abs() < 2e-16 && (c - x.cos()).abs() < 2e-16,
            "{x}"
        );
    }
}
