//! Unit tests of `analysis::orbit::ratio` (`src/analysis/orbit/ratio.rs`).

use isola::analysis::orbit::ratio::*;
use std::f64::consts::PI;

fn wave(k: usize, n_per: usize, f: impl Fn(f64) -> f64) -> Vec<f64> {
    (0..k * n_per)
        .map(|j| f(2.0 * PI * j as f64 / n_per as f64))
        .collect()
}

#[test]
fn strongest_harmonic_names_the_ratio() {
    // θ = ω_e τ
    let r = Ratio::of_samples(&wave(1, 64, |t| (2.0 * t).cos() + 0.3 * t.cos()), 1);
    assert_eq!(r.to_string(), "2:1");
    let r = Ratio::of_samples(&wave(1, 64, |t| t.sin() + 0.3 * (2.0 * t).cos()), 1);
    assert_eq!(r.to_string(), "1:1");
    let r = Ratio::of_samples(&wave(2, 64, |t| (0.5 * t).cos() + 0.2 * t.cos()), 2);
    assert_eq!(r.to_string(), "1:2");
    let r = Ratio::of_samples(&wave(3, 64, |t| (t / 3.0).sin() + 0.4 * t.sin()), 3);
    assert_eq!(r.to_string(), "1:3");
    // a period-2 orbit whose strongest line is still ω_e is 1:1
    let r = Ratio::of_samples(&wave(2, 64, |t| t.cos() + 0.1 * (0.5 * t).cos()), 2);
    assert_eq!(r.to_string(), "1:1");
}
