//! Unit tests of `analysis::orbit::floquet` (`src/analysis/orbit/floquet.rs`).

use isola::analysis::orbit::floquet::*;
use nalgebra::Matrix2;

#[test]
fn multipliers_of_known_matrices() {
    let m = Matrix2::new(0.5, 0.0, 0.0, -2.0);
    let mu = Multipliers::of(&m);
    assert_eq!(mu.0[0].re, -2.0);
    assert!((mu.0[1].re - 0.5).abs() < 1e-15);
    assert!(!mu.stable());
    let (c, s) = (0.9 * 1.0f64.cos(), 0.9 * 1.0f64.sin());
    let rot = Matrix2::new(c, -s, s, c);
    let mu = Multipliers::of(&rot);
    assert!(mu.complex() && mu.stable());
    assert!((mu.spectral_radius() - 0.9).abs() < 1e-14);
    let t = TestFunctions::of(&rot);
    assert!(t.torus.unwrap() < 0.0);
    let t = TestFunctions::of(&Matrix2::new(1.0, 0.3, 0.0, 0.4));
    assert!(t.fold.abs() < 1e-15 && t.flip > 0.0 && t.torus.is_none());
}
