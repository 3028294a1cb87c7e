//! Cubic Hermite interpolation over one step, from the values and slopes at both ends.
//! Used to locate switches inside an RK4 step and to refine extrema between steps.

use super::lane::Real;

/// Value at fraction `s` ∈ [0, 1] of a step of length `h`.
#[inline(always)]
pub fn value<T: Real>(y0: T, d0: T, y1: T, d1: T, h: T, s: T) -> T {
    let c = T::splat;
    let s2 = s * s;
    let s3 = s2 * s;
    (c(2.0) * s3 - c(3.0) * s2 + c(1.0)) * y0
        + (s3 - c(2.0) * s2 + s) * h * d0
        + (c(-2.0) * s3 + c(3.0) * s2) * y1
        + (s3 - s2) * h * d1
}

/// Slope dy/ds at fraction `s` ∈ [0, 1] of a step of length `h` (dy/dτ = slope / h).
#[inline(always)]
pub fn slope<T: Real>(y0: T, d0: T, y1: T, d1: T, h: T, s: T) -> T {
    let c = T::splat;
    let s2 = s * s;
    (c(6.0) * s2 - c(6.0) * s) * (y0 - y1)
        + (c(3.0) * s2 - c(4.0) * s + c(1.0)) * h * d0
        + (c(3.0) * s2 - c(2.0) * s) * h * d1
}

/// A root of the cubic in (0, 1], given y0 ≥ 0 > y1: Newton's method kept inside the shrinking
/// sign-change bracket (bisection where a Newton step leaves it), from the secant estimate,
/// stopped when successive estimates agree to `tolerance`. In a batch, each lane stops at
/// its own estimate as it would alone; lanes outside `active` are left alone (their result
/// is meaningless).
#[inline(always)]
pub fn crossing<T: Real>(y0: T, d0: T, y1: T, d1: T, h: T, tolerance: f64, active: T::Mask) -> T {
    let (mut lo, mut hi) = (T::splat(0.0), T::splat(1.0));
    let mut s = y0 / (y0 - y1);
    let mut root = s;
    let mut active = active;
    for _ in 0..60 {
        if !T::any(active) {
            return root;
        }
        let y = value(y0, d0, y1, d1, h, s);
        let negative = y.lt(T::splat(0.0));
        hi = T::select(negative, s, hi);
        lo = T::select(negative, lo, s);
        let newton = s - y / slope(y0, d0, y1, d1, h, s);
        let inside = newton.gt(lo) & newton.lt(hi);
        let next = T::select(inside, newton, T::splat(0.5) * (lo + hi));
        let done = (next - s).abs().lt(T::splat(tolerance));
        root = T::select(active & done, next, root);
        active = active & !done;
        s = T::select(active, next, s);
    }
    T::select(active, s, root)
}

/// The first fraction of a step in (0, 1] where `holds` (false at 0, true at 1) becomes
/// true: bisection to round-off (at most 60 halvings), for a condition with no value to
/// interpolate (a collision met on the step's interpolant).
pub fn first_where(mut holds: impl FnMut(f64) -> bool) -> f64 {
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    // 2⁻⁶⁰ of the step: below its time's round-off
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if holds(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
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
