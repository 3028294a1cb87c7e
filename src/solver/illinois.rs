//! Illinois false position: the root of a function that is positive at one end of a bracket
//! and negative at the other, to round-off of the time it is a step from.

/// Most probes of one search.
const MAX_PROBES: usize = 100;

/// The point of (`lo`, `hi`] where `g` first turns negative, given `g_lo` ≥ 0 > `g_hi` at the
/// ends, narrowed until the bracket is a few ulps of `t + hi` wide (`t`: the time the
/// bracket's sub-steps start from); returns the negative side. Each end kept twice has its
/// value halved (the Illinois correction).
pub fn illinois(
    t: f64,
    ends: (f64, f64),
    values: (f64, f64),
    mut g: impl FnMut(f64) -> f64,
) -> f64 {
    let mut search = Illinois::new(t, ends, values);
    while let Some(s) = search.probe() {
        search.record(s, g(s));
    }
    search.root()
}

/// [`illinois`] as a search its caller drives, probe by probe: for hot loops compiled for
/// an instruction set, where a closure would be compiled on its own without it.
#[derive(Debug, Clone, Copy)]
pub struct Illinois {
    t: f64,
    lo: f64,
    hi: f64,
    g_lo: f64,
    g_hi: f64,
    /// Which end the last probe replaced: −1 the negative, 1 the other, 0 none yet.
    side: i8,
    probes: usize,
}

impl Illinois {
    /// The search on (`lo`, `hi`] with `g_lo` ≥ 0 > `g_hi`.
    #[inline(always)]
    pub fn new(t: f64, (lo, hi): (f64, f64), (g_lo, g_hi): (f64, f64)) -> Self {
        Illinois {
            t,
            lo,
            hi,
            g_lo,
            g_hi,
            side: 0,
            probes: 0,
        }
    }

    /// Where to evaluate g next; `None` once the bracket is a few ulps wide or after
    /// [`MAX_PROBES`] probes.
    #[inline(always)]
    pub fn probe(&self) -> Option<f64> {
        let (lo, hi) = (self.lo, self.hi);
        if self.probes == MAX_PROBES || hi - lo <= 4.0 * f64::EPSILON * (self.t.abs() + hi) {
            return None;
        }
        let mut s = if self.g_lo - self.g_hi > 0.0 {
            lo + (hi - lo) * self.g_lo / (self.g_lo - self.g_hi)
        } else {
            0.5 * (lo + hi)
        };
        if !(s > lo && s < hi) {
            s = 0.5 * (lo + hi);
        }
        Some(s)
    }

    /// g(`s`) = `gs` at the last probe `s`.
    #[inline(always)]
    pub fn record(&mut self, s: f64, gs: f64) {
        self.probes += 1;
        if gs < 0.0 {
            (self.hi, self.g_hi) = (s, gs);
            if self.side == -1 {
                self.g_lo *= 0.5;
            }
            self.side = -1;
        } else {
            (self.lo, self.g_lo) = (s, gs);
            if self.side == 1 {
                self.g_hi *= 0.5;
            }
            self.side = 1;
        }
    }

    /// The negative side of the bracket.
    #[inline(always)]
    pub fn root(&self) -> f64 {
        self.hi
    }
}
