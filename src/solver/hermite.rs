//! Cubic Hermite interpolation over one step, from the values and slopes at both ends.
//! Used to locate switches inside an RK4 step and to refine extrema between steps.

/// Value at fraction `s` ∈ [0, 1] of a step of length `h`.
#[inline]
pub fn value(y0: f64, d0: f64, y1: f64, d1: f64, h: f64, s: f64) -> f64 {
    let s2 = s * s;
    let s3 = s2 * s;
    (2.0 * s3 - 3.0 * s2 + 1.0) * y0
        + (s3 - 2.0 * s2 + s) * h * d0
        + (-2.0 * s3 + 3.0 * s2) * y1
        + (s3 - s2) * h * d1
}

/// Extremum of the cubic strictly inside the step, if its slope changes sign there:
/// returns (fraction s, value).
pub fn interior_extremum(y0: f64, d0: f64, y1: f64, d1: f64, h: f64) -> Option<(f64, f64)> {
    if d0 * d1 > 0.0 {
        return None;
    }
    // slope dy/ds / h = a s² + b s + c
    let a = 6.0 * (y0 - y1) / h + 3.0 * (d0 + d1);
    let b = 6.0 * (y1 - y0) / h - 4.0 * d0 - 2.0 * d1;
    let c = d0;
    let roots = quadratic_roots(a, b, c);
    roots
        .into_iter()
        .flatten()
        .filter(|s| (0.0..=1.0).contains(s))
        .map(|s| (s, value(y0, d0, y1, d1, h, s)))
        .next()
}

fn quadratic_roots(a: f64, b: f64, c: f64) -> [Option<f64>; 2] {
    if a.abs() < 1e-14 * (b.abs() + c.abs()) {
        return [(b != 0.0).then(|| -c / b), None];
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return [None, None];
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    let (r1, r2) = (q / a, if q != 0.0 { c / q } else { 0.0 });
    let (lo, hi) = if r1 < r2 { (r1, r2) } else { (r2, r1) };
    [Some(lo), Some(hi)]
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
