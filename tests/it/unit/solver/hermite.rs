//! Unit tests of `solver::hermite` (`src/solver/hermite.rs`).

use isola::solver::hermite::*;
use isola::solver::lane::{Batch, Bits};

#[test]
fn reproduces_a_cubic_exactly() {
    let y = |t: f64| 1.0 + 2.0 * t - 3.0 * t * t + 0.5 * t * t * t;
    let dy = |t: f64| 2.0 - 6.0 * t + 1.5 * t * t;
    let (t0, h) = (0.3, 0.7);
    for i in 0..=10 {
        let s = i as f64 / 10.0;
        let got = value(y(t0), dy(t0), y(t0 + h), dy(t0 + h), h, s);
        assert!((got - y(t0 + s * h)).abs() < 1e-14);
    }
}

#[test]
fn slope_is_the_derivative_and_crossing_the_root() {
    let y = |t: f64| 0.4 - 1.3 * t + 0.2 * t * t + 0.3 * t * t * t;
    let dy = |t: f64| -1.3 + 0.4 * t + 0.9 * t * t;
    let (t0, h) = (0.1, 0.8);
    let ends = (y(t0), dy(t0), y(t0 + h), dy(t0 + h));
    for i in 0..=10 {
        let s = i as f64 / 10.0;
        let got = slope(ends.0, ends.1, ends.2, ends.3, h, s) / h;
        assert!((got - dy(t0 + s * h)).abs() < 1e-13, "{s}");
    }
    assert!(ends.0 > 0.0 && ends.2 < 0.0);
    let s = crossing(ends.0, ends.1, ends.2, ends.3, h, 1e-12, true);
    assert!(y(t0 + s * h).abs() < 1e-12, "{s}");
    assert!((0.0..=1.0).contains(&s));
}

/// Side by side in a batch, each lane's root is bit for bit the one it finds alone, however
/// many Newton steps the others take; a lane left out is not searched.
#[test]
fn a_batch_finds_each_lanes_root_as_alone() {
    // cubics crossing zero early, late, steeply and at a near-double root
    let cubics: [[f64; 4]; 4] = [
        [0.4, -1.3, -0.5, -0.2],
        [1e-3, 0.5, -2e-4, -0.8],
        [2.0, -40.0, -3.0, -35.0],
        [0.3, -0.9, -1e-6, 0.9],
    ];
    let h = 0.05;
    let lanes = |j: usize| Batch(cubics.map(|c| c[j]));
    let (y0, d0, y1, d1) = (lanes(0), lanes(1), lanes(2), lanes(3));
    let active = Bits([true, true, false, true]);
    let roots = crossing(y0, d0, y1, d1, Batch([h; 4]), 1e-4, active);
    for (j, c) in cubics.iter().enumerate() {
        let alone = crossing(c[0], c[1], c[2], c[3], h, 1e-4, true);
        assert!((0.0..=1.0).contains(&alone), "lane {j}: {alone}");
        if active.0[j] {
            assert_eq!(roots.0[j].to_bits(), alone.to_bits(), "lane {j}");
        } else {
            // its first estimate, the secant's, never refined
            assert_eq!(roots.0[j], c[0] / (c[0] - c[2]), "lane {j}");
        }
    }
}

#[test]
fn finds_the_peak_of_a_sine() {
    // interpolation error bound h⁴/384·max|y''''| = h⁴/384
    for h in [0.2, 0.05] {
        let t0 = std::f64::consts::FRAC_PI_2 - 0.35 * h;
        let (s, peak) =
            interior_extremum(t0.sin(), t0.cos(), (t0 + h).sin(), (t0 + h).cos(), h).unwrap();
        assert!((peak - 1.0).abs() < h.powi(4) / 384.0, "{peak}");
        assert!((t0 + s * h - std::f64::consts::FRAC_PI_2).abs() < h * h);
    }
    assert!(interior_extremum(0.0, 1.0, 0.1, 1.0, 0.1).is_none());
}
