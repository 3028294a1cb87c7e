//! Unit tests of `session::store::finite` (`src/session/store/finite.rs`).

use isola::session::store::finite::*;
use serde::Serialize;

#[derive(Serialize)]
struct Steady {
    amplitude: Option<f64>,
    poincare: Vec<[f64; 2]>,
}

#[test]
fn finds_the_first_non_finite_number_and_its_path() {
    let ok = vec![Steady {
        amplitude: Some(0.4),
        poincare: vec![[1.0, 2.0]],
    }];
    assert_eq!(first_non_finite(&ok), None);
    let bad = vec![
        Steady {
            amplitude: None,
            poincare: vec![],
        },
        Steady {
            amplitude: Some(0.1),
            poincare: vec![[1.0, 2.0], [3.0, f64::NEG_INFINITY]],
        },
    ];
    let found = first_non_finite(&bad).unwrap();
    assert_eq!(found.path, "[1].poincare[1][1]");
    assert_eq!(found.value, f64::NEG_INFINITY);
    let nan = Steady {
        amplitude: Some(f64::NAN),
        poincare: vec![],
    };
    let found = first_non_finite(&nan).unwrap();
    assert_eq!(found.path, "amplitude");
    assert!(found.value.is_nan());
    assert_eq!(found.to_string(), "amplitude is NaN");
}
