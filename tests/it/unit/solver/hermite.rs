//! Unit tests of `solver::hermite` (`src/solver/hermite.rs`).

use isola::solver::hermite::*;

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
    let s = crossing(ends.0, ends.1, ends.2, ends.3, h, 1e-12);
    assert!(y(t0 + s * h).abs() < 1e-12, "{s}");
    assert!((0.0..=1.0).contains(&s));
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
