//! Unit tests of `analysis::orbit::attractor` (`src/analysis/orbit/attractor.rs`).

use isola::analysis::Ratio;
use isola::analysis::orbit::attractor::*;
use isola::analysis::orbit::steady_state::{Class, SteadyState};

fn periodic(points: Vec<[f64; 2]>) -> SteadyState {
    SteadyState {
        class: Class::Periodic,
        period: Some(points.len()),
        ratio: Some(Ratio::new(1, points.len() as u32)),
        amplitude: Some(0.4),
        poincare: points,
        states: Vec::new(),
        transient_periods: 10,
        lambda_min: Some(0.8),
        lambda_max: Some(1.2),
        lambda_mean: Some(1.0),
        collision: None,
    }
}

#[test]
fn phase_order_does_not_matter() {
    let a = periodic(vec![[0.9, 0.1], [1.1, -0.2]]);
    let b = periodic(vec![[1.1 + 1e-7, -0.2], [0.9, 0.1 - 1e-7]]);
    assert!(same_attractor(&a, &b, 1e-5));
    let c = periodic(vec![[1.1, -0.2], [0.9, 0.2]]);
    assert!(!same_attractor(&a, &c, 1e-5));
    let d = periodic(vec![[0.9, 0.1]]);
    assert!(!same_attractor(&a, &d, 1e-5));
    let mut t = AttractorTable::default();
    assert_eq!(t.classify(&a, 1e-5), 0);
    assert_eq!(t.classify(&c, 1e-5), 1);
    assert_eq!(t.classify(&b, 1e-5), 0);
    assert_eq!(t.attractors[0].count, 2);
    assert_eq!(t.total(), 3);
}
