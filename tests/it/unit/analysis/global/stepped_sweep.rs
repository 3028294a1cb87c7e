//! Unit tests of `analysis::global::stepped_sweep` (`src/analysis/global/stepped_sweep.rs`).

use isola::analysis::global::stepped_sweep::*;
use isola::analysis::orbit::steady_state::SteadyStateSpec;
use isola::model::Params;
use std::sync::atomic::AtomicBool;

/// Fig 3A's primary resonance at ADR 0.6 (softening, from the loss of tension): sweeping
/// up stays low until ω_e ≈ 2.25; sweeping down jumps onto the high branch there and rides
/// it down to ω_e ≈ 1.85, where the forward sweep is still low: hysteresis.
#[test]
fn primary_resonance_shows_hysteresis() {
    let p = Params::baseline();
    let spec = SteadyStateSpec::default();
    let up: Vec<f64> = (0..=14).map(|i| 1.7 + 0.05 * i as f64).collect();
    let down: Vec<f64> = up.iter().rev().copied().collect();
    let never = AtomicBool::new(false);
    let rest = [p.lambda_p(), 0.0];
    let fw = stepped_sweep(&p, &up, rest, &spec, &never, |_| {}).unwrap();
    let bw = stepped_sweep(&p, &down, rest, &spec, &never, |_| {}).unwrap();
    let amp = |s: &SweepStep| s.steady.amplitude.unwrap_or(0.0);
    let high_fw = fw.iter().filter(|s| amp(s) > 0.2).count();
    let high_bw = bw.iter().filter(|s| amp(s) > 0.2).count();
    assert!(
        high_bw >= high_fw + 5,
        "backward {high_bw} vs forward {high_fw} high steps"
    );
    // at ω_e = 1.9 the backward sweep is on the high branch (≈ 0.4), the forward on the low
    let at =
        |steps: &[SweepStep]| amp(steps.iter().find(|s| (s.omega - 1.9).abs() < 1e-9).unwrap());
    assert!(at(&bw) > 0.3 && at(&fw) < 0.05, "{} {}", at(&bw), at(&fw));
}
