//! Unit tests of `analysis::orbit::force_curve` (`src/analysis/orbit/force_curve.rs`).

use isola::analysis::orbit::force_curve::*;
use isola::model::forces::gent;

/// Fig 2A: with λ_p = 1 the force is −2g(1+Δλ)... only one membrane pulls for any Δλ ≠ 0;
/// with λ_p > 1 both pull near the origin (slope −2g'(λ_p)) and the slope halves where one
/// goes slack at λ = 1, i.e. |Δλ| = λ_p − 1.
#[test]
fn fig2a_shapes() {
    let curves = force_curves(&ForceCurveSpec::default()).unwrap();
    assert_eq!(curves.len(), 3);
    let at = |c: &ForceCurve, dx: f64| {
        c.points
            .iter()
            .min_by(|a, b| (a[0] - dx).abs().total_cmp(&(b[0] - dx).abs()))
            .unwrap()[1]
    };
    // restoring, odd-symmetric with no voltage
    for c in &curves {
        for dx in [0.1, 0.3, 0.6] {
            assert!(at(c, dx) < 0.0 && at(c, -dx) > 0.0);
            assert!((at(c, dx) + at(c, -dx)).abs() < 1e-12);
        }
    }
    // λ_p = 1.02, Δλ = 0.4: membrane II (λ = 0.64) is slack, the force is −g(1.42)
    let c = &curves[1];
    assert!((at(c, 0.4) + gent(1.42, 16.0)).abs() < 1e-12);
    // with voltage the curve is no longer symmetric (Fig 2B)
    let spec = ForceCurveSpec {
        lambda_p: vec![1.02],
        phi_i: vec![0.0, 0.2, 0.3],
        ..ForceCurveSpec::default()
    };
    let c = force_curves(&spec).unwrap();
    assert!((at(&c[2], 0.1) + at(&c[2], -0.1)).abs() > 1e-3);
    // the voltage on membrane I weakens it: the force at Δλ = 0 points to +Δλ
    assert!(at(&c[1], 0.0) > 0.0 && at(&c[2], 0.0) > at(&c[1], 0.0));
}

#[test]
fn bad_spec_names_the_field() {
    let spec = ForceCurveSpec {
        points: 1,
        ..ForceCurveSpec::default()
    };
    assert_eq!(force_curves(&spec).unwrap_err().field, "points");
    let spec = ForceCurveSpec {
        lambda_p: vec![-1.0],
        ..ForceCurveSpec::default()
    };
    assert_eq!(force_curves(&spec).unwrap_err().field, "lambda_p");
}
