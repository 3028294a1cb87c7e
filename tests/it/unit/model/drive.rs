//! Unit tests of `model::drive` (`src/model/drive.rs`).

use isola::model::drive::*;

/// MODEL.md §2 check values: E_a = 0.2², ADR 0.6 → E_b ≈ 0.041, E_c ≈ 0.006;
/// ADR 1.0 → E_b ≈ 0.053, E_c ≈ 0.013 (to the 3 decimals the page gives).
#[test]
fn e_b_and_e_c_match_model_md() {
    let d = Drive::from_ea_adr(0.04, 0.6).unwrap();
    assert!((d.e_b() - 0.041).abs() < 5e-4, "{}", d.e_b());
    assert!((d.e_c() - 0.006).abs() < 5e-4, "{}", d.e_c());
    assert!((d.e_a() - 0.04).abs() < 1e-15);
    let d = Drive::from_ea_adr(0.04, 1.0).unwrap();
    assert!((d.e_b() - 0.053).abs() < 5e-4, "{}", d.e_b());
    assert!((d.e_c() - 0.013).abs() < 5e-4, "{}", d.e_c());
    assert!((d.adr().unwrap() - 1.0).abs() < 1e-14);
}

/// φ² = E_a + E_b cos θ + E_c cos 2θ for any θ.
#[test]
fn phi_squared_expands_into_three_harmonics() {
    let d = Drive::from_phi(0.17, 0.09).unwrap();
    for i in 0..50 {
        let th = 0.37 * i as f64;
        let expanded = d.e_a() + d.e_b() * th.cos() + d.e_c() * (2.0 * th).cos();
        assert!((d.phi_sq(th) - expanded).abs() < 1e-15);
    }
}

/// A drive given as (E_a, ADR) reads them back exactly, so one rebuilt from its spec (a
/// family member, a frequency of a sweep) has the very same voltages, to the bit.
#[test]
fn a_drive_rebuilt_from_its_spec_is_the_same_to_the_bit() {
    for (e_a, adr) in [(0.04, 0.6), (0.03, 1.0), (0.0523, 0.37), (0.04, 0.0)] {
        let d = Drive::from_ea_adr(e_a, adr).unwrap();
        assert_eq!((d.e_a(), d.adr()), (e_a, Some(adr)));
        let again = Drive::from_spec(d.to_spec()).unwrap();
        assert_eq!(
            (again.phi_dc().to_bits(), again.phi_ac().to_bits()),
            (d.phi_dc().to_bits(), d.phi_ac().to_bits())
        );
    }
}

#[test]
fn bad_drive_names_the_field() {
    let e = Drive::from_ea_adr(-0.1, 0.6).unwrap_err();
    assert_eq!(e.field, "e_a");
    let e = Drive::from_ea_adr(0.04, f64::NAN).unwrap_err();
    assert_eq!(e.field, "adr");
    assert!(e.to_string().contains("[0, 1000]"), "{e}");
    assert_eq!(Drive::from_phi(0.1, -1.0).unwrap_err().field, "phi_ac");
}
