//! Unit tests of `analysis::global::batch` (`src/analysis/global/batch.rs`).

use isola::analysis::global::batch::*;
use isola::analysis::orbit::steady_state::SteadyStateSpec;
use isola::analysis::steady_state;
use isola::model::Params;
use std::sync::atomic::AtomicBool;

fn grid(n: usize, lambda_p: f64) -> Vec<[f64; 2]> {
    (0..n * n)
        .map(|i| {
            let (a, b) = (i / n, i % n);
            [
                lambda_p - 0.8 + 1.6 * a as f64 / (n - 1) as f64,
                -1.0 + 2.0 * b as f64 / (n - 1) as f64,
            ]
        })
        .collect()
}

/// Without early stop the batch gives exactly the single-trajectory results, bit for bit:
/// 81 states, so 64 lanes that narrow to 32 and 16 as they finish.
#[test]
fn batch_equals_one_by_one() {
    let p = Params::baseline();
    let spec = SteadyStateSpec::default();
    let ics = grid(9, p.lambda_p());
    let never = AtomicBool::new(false);
    let batch = steady_states(&p, &ics, &spec, None, &never, &mut |_| {}).unwrap();
    for (ic, b) in ics.iter().zip(&batch) {
        let one = steady_state(&p, ic[0], ic[1], &spec);
        assert_eq!(&one, b, "from {ic:?}");
    }
}

/// With early stop every trajectory gets the same class, period and amplitude (to 1e-7:
/// the attractor's own, converged to 1e-9 from another start) as the plain method, in
/// fewer periods.
#[test]
fn early_stop_keeps_classes_and_amplitudes() {
    let p = Params::baseline();
    let spec = SteadyStateSpec::default();
    let ics = grid(8, p.lambda_p());
    let never = AtomicBool::new(false);
    let plain = steady_states(&p, &ics, &spec, None, &never, &mut |_| {}).unwrap();
    let mut known = KnownAttractors::new(&p, &spec.resolution, 0.1);
    for s in &plain {
        known.learn(s, 1e-6);
    }
    assert!(known.responses().len() >= 2);
    let fast = steady_states(&p, &ics, &spec, Some(&mut known), &never, &mut |_| {}).unwrap();
    let (mut periods_plain, mut periods_fast) = (0, 0);
    for (a, b) in plain.iter().zip(&fast) {
        assert_eq!(a.class, b.class);
        assert_eq!(a.period, b.period);
        if let (Some(x), Some(y)) = (a.amplitude, b.amplitude) {
            assert!((x - y).abs() < 1e-7, "{x} vs {y}");
        }
        periods_plain += a.transient_periods;
        periods_fast += b.transient_periods;
    }
    assert!(
        periods_fast * 10 < periods_plain * 7,
        "{periods_fast} vs {periods_plain}"
    );
}

#[test]
fn cancel_stops_at_once() {
    let p = Params::baseline();
    let cancel = AtomicBool::new(true);
    let ics = grid(4, p.lambda_p());
    assert!(
        steady_states(
            &p,
            &ics,
            &SteadyStateSpec::default(),
            None,
            &cancel,
            &mut |_| {}
        )
        .is_none()
    );
}
