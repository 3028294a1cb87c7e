//! Illinois false position: the root of a function that is positive at one end of a bracket
//! and negative at the other, to round-off of the time it is a step from.

/// The point of (`lo`, `hi`] where `g` first turns negative, given `g_lo` ≥ 0 > `g_hi` at the
/// ends, narrowed until the bracket is a few ulps of `t + hi` wide (`t`: the time the
/// bracket's sub-steps start from); returns the negative side. Each end kept twice has its
/// value halved (the Illinois correction).
pub fn illinois(
    t: f64,
    (mut lo, mut hi): (f64, f64),
    (mut g_lo, mut g_hi): (f64, f64),
    mut g: impl FnMut(f64) -> f64,
) -> f64 {
    let mut side = 0;
    for _ in 0..100 {
        if hi - lo <= 4.0 * f64::EPSILON * (t.abs() + hi) {
            break;
        }
        let mut s = if g_lo - g_hi > 0.0 {
            lo + (hi - lo) * g_lo / (g_lo - g_hi)
        } else {
            0.5 * (lo + hi)
        };
        if !(s > lo && s < hi) {
            s = 0.5 * (lo + hi);
        }
        let gs = g(s);
        if gs < 0.0 {
            (hi, g_hi) = (s, gs);
            if side == -1 {
                g_lo *= 0.5;
            }
            side = -1;
        } else {
            (lo, g_lo) = (s, gs);
            if side == 1 {
                g_hi *= 0.5;
            }
            side = 1;
        }
    }
    hi
}
