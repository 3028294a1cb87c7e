//! Unit tests of `analysis::global::ellipse` (`src/analysis/global/ellipse.rs`).

use isola::analysis::global::ellipse::*;
use nalgebra::Matrix2;

/// Q solves Mᵀ Q M − Q = −I for a stable focus and a stable node; none for an unstable M.
#[test]
fn lyapunov_solves_the_equation() {
    for m in [
        Matrix2::new(0.6, -0.7, 0.7, 0.6),
        Matrix2::new(0.9, 0.3, 0.0, -0.5),
    ] {
        let q = lyapunov(&m).expect("stable");
        let r = m.transpose() * q * m - q;
        for i in 0..2 {
            for j in 0..2 {
                let expected = if i == j { -1.0 } else { 0.0 };
                assert!((r[(i, j)] - expected).abs() < 1e-12, "{m:?}: {r:?}");
            }
        }
    }
    assert!(lyapunov(&Matrix2::new(1.1, 0.0, 0.0, 0.5)).is_none());
}
