//! Unit tests of `analysis::orbit::scalogram` (`src/analysis/orbit/scalogram.rs`).

use isola::analysis::grid::Axis;
use isola::analysis::orbit::scalogram::*;

/// A sinusoid of amplitude 0.3 at ω = 2 shows |W| ≈ 0.3 at ω = 2 and its ridge there.
#[test]
fn a_sinusoid_shows_its_frequency_and_amplitude() {
    let dt = 0.05;
    let signal: Vec<f64> = (0..20000)
        .map(|j| 1.0 + 0.3 * (2.0 * j as f64 * dt).cos())
        .collect();
    let spec = ScalogramSpec {
        frequencies: Axis::new(0.5, 4.0, 71),
        columns: 50,
    };
    let s = scalogram(&signal, dt, &spec).unwrap();
    // away from the edges
    for c in 10..40 {
        assert!((s.ridge[c] - 2.0).abs() < 0.051, "{}", s.ridge[c]);
        let f2 = s
            .frequencies
            .iter()
            .position(|&f| (f - 2.0).abs() < 1e-9)
            .unwrap();
        assert!(
            (s.magnitude[f2][c] - 0.3).abs() < 0.01,
            "{}",
            s.magnitude[f2][c]
        );
    }
}
