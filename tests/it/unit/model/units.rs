//! Unit tests of `model::units` (`src/model/units.rs`).

use isola::model::units::*;

/// MODEL.md §3: 1 unit of τ⁻¹ ≈ 89.44 rad/s, ω_e = 1.8 ≈ 25.6 Hz, 1 unit of φ ≈ 12.7 kV,
/// baseline peak φ (ADR 0.6, E_a 0.04) near 40 MV/m (to the digits the page gives).
#[test]
fn silicone_device_matches_model_md() {
    let d = Device::silicone();
    assert!(
        (d.rad_per_s(1.0) - 89.44).abs() < 0.005,
        "{}",
        d.rad_per_s(1.0)
    );
    assert!((d.hz(1.8) - 25.6).abs() < 0.05, "{}", d.hz(1.8));
    assert!((d.kv(1.0) - 12.7).abs() < 0.05, "{}", d.kv(1.0));
    let drive = isola::model::Drive::from_ea_adr(0.04, 0.6).unwrap();
    let field = d.mv_per_m(drive.phi_peak());
    assert!((35.0..42.0).contains(&field), "{field}");
}

#[test]
fn conversions_round_trip() {
    let d = Device::silicone();
    for &x in &[1e-3, 0.2, 1.8, 3.7, 6.0, 123.0] {
        assert!((d.omega_from_hz(d.hz(x)) - x).abs() < 1e-12 * x);
        assert!((d.phi_from_kv(d.kv(x)) - x).abs() < 1e-12 * x);
        assert!((d.c_tilde(d.damping(x)) - x).abs() < 1e-12 * x);
        assert!((d.tau(d.seconds(x)) - x).abs() < 1e-12 * x);
    }
}

#[test]
fn invalid_device_names_the_field() {
    let d = Device {
        l3: 0.0,
        ..Device::silicone()
    };
    assert_eq!(d.validate().unwrap_err().field, "l3");
    assert!(Device::silicone().validate().is_ok());
}
