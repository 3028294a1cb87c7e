//! The split step: an RK4 step in which a membrane switches between taut and slack, redone
//! on each side of the switch (MODEL.md §4b). The usual case (the step's end shows the
//! switch, and no second one follows) is written over [`Real`], so that the split steps of
//! several lanes are taken side by side in SIMD registers, each lane's arithmetic the same
//! as alone; anything less simple is taken one lane at a time.

use super::{MAX_SWITCHES_PER_STEP, NEWTON_TOLERANCE, Rk4, SWITCH_SCAN_POINTS, SWITCH_TOLERANCE};
use crate::solver::drive_table::{DriveWithRate, LocalDrive};
use crate::solver::field::{Membrane, Mode};
use crate::solver::hermite;
use crate::solver::lane::{Batch, Real};

/// A batch's conditions, one per lane.
type Mask = <SplitLanes as Real>::Mask;

/// The lanes whose split steps are taken side by side: four (batches of eight, in AVX-512
/// registers, took 1.46 times as long: the compiler's code for them spilled).
pub(super) type SplitLanes = Batch<4>;
/// How many lanes [`SplitLanes`] holds.
pub(super) const SPLIT_BATCH: usize = SplitLanes::LANES;

/// A step's start: state, acceleration and mode.
pub(super) type StepStart<T = f64, M = bool> = ([T; 2], T, Mode<M>);
/// A step's end: state and acceleration.
pub(super) type StepEnd<T = f64> = ([T; 2], T);
/// A step's end: state, acceleration and mode.
pub(super) type StepEnd3<T = f64, M = bool> = ([T; 2], T, Mode<M>);

/// Split steps of a batch of lanes: starts and unsplit ends side by side.
pub(super) type BatchStart = StepStart<SplitLanes, Mask>;
/// The unsplit ends of a batch's steps.
pub(super) type BatchEnd = StepEnd<SplitLanes>;
/// A batch's split ends, and the lanes where they are final.
pub(super) type BatchEnds = (StepEnd3<SplitLanes, Mask>, Mask);

/// The usual split of a step, lane by lane: its end, and where the switch was.
struct UsualSplit<T: Real> {
    end: StepEnd3<T, T::Mask>,
    /// The step's end shows a switch (else the switch, if any, was a brief excursion).
    shown: T::Mask,
    /// Shown, and no second switch follows: `end` is the split step's end.
    done: T::Mask,
    /// The state at the switch, the time into the step and the mode after it.
    at_switch: [T; 2],
    s: T,
    mode1: Mode<T::Mask>,
}

/// Two sub-steps either side of a switch.
struct Across<T: Real> {
    /// The state at the switch.
    at_switch: [T; 2],
    /// The mode after the switch.
    mode1: Mode<T::Mask>,
    /// The step's end: state, acceleration and mode.
    end: StepEnd3<T, T::Mask>,
}

impl Rk4 {
    /// RK4 step `k` of the period split where a membrane switches between taut and slack,
    /// each side integrated on its own smooth piece. `start` is the step's start (state,
    /// acceleration, mode); `unsplit` is the same step taken through the kink (its end state
    /// and true acceleration there): its cubic Hermite interpolant places the switch to O(h³),
    /// and a switch misplaced by δ costs only O(δ²), so two sub-steps finish the job. Anything
    /// less simple (no sign change on that interpolant, or another switch after the first)
    /// goes to [`Self::split_from`]. Returns the end state, its acceleration and mode.
    #[inline(always)]
    pub(super) fn split_step(&self, k: usize, start: StepStart, unsplit: StepEnd) -> StepEnd3 {
        let usual = self.usual_split::<f64>(k, start, unsplit);
        if usual.done {
            return usual.end;
        }
        let (drive, h) = (self.table.step_start(k), self.h);
        let phi_end = self.table.at(2 * k + 2);
        if usual.shown {
            // a second switch follows the first
            let y = self.split_from(drive, usual.at_switch, usual.s, h, usual.mode1);
            return self.end_of(y, phi_end);
        }
        let (y0, a0, mode0) = start;
        let drive_ends = self.table.step_ends(k);
        let Some(switch) = self.first_switch(drive, drive_ends, (y0, a0), unsplit, 0.0, h, mode0)
        else {
            return self.end_of(self.split_from(drive, y0, 0.0, h, mode0), phi_end);
        };
        let is_ii = switch.membrane == Membrane::Ii;
        let across = self.across::<f64>(k, start, switch.at, is_ii);
        if across.end.2 == across.mode1 {
            across.end
        } else {
            let y = self.split_from(drive, across.at_switch, switch.at, h, across.mode1);
            self.end_of(y, phi_end)
        }
    }

    /// [`Self::split_step`] of a batch of lanes side by side, where the switch is the usual
    /// one: the ends, bit for bit as one lane at a time, and the lanes where they are final
    /// (the others need [`Self::split_step`]).
    #[inline(always)]
    pub(super) fn split_batch(&self, k: usize, start: BatchStart, unsplit: BatchEnd) -> BatchEnds {
        let usual = self.usual_split::<SplitLanes>(k, start, unsplit);
        (usual.end, usual.done)
    }

    /// The usual split: the switch where the step's end shows it, on the switching
    /// function's cubic Hermite interpolant from its values and rates at both ends, and the
    /// two sub-steps either side of it.
    #[inline(always)]
    fn usual_split<T: Real>(
        &self,
        k: usize,
        start: StepStart<T, T::Mask>,
        (y1, a1): StepEnd<T>,
    ) -> UsualSplit<T> {
        let (y0, a0, mode0) = start;
        let [drive_start, drive_end] = self.table.step_ends(k).map(splat_drive::<T>);
        let g_start = self.switching(y0, drive_start.0, mode0);
        let g_end = self.switching(y1, drive_end.0, mode0);
        let zero = T::splat(0.0);
        let shown = g_end[0].lt(zero) | g_end[1].lt(zero);
        let ends = [(y0, a0, drive_start, g_start), (y1, a1, drive_end, g_end)];
        let h = T::splat(self.h);
        let (s_i, switches_i) = self.end_switch(Membrane::I, mode0, ends, h);
        let (s_ii, switches_ii) = self.end_switch(Membrane::Ii, mode0, ends, h);
        // the earlier of the two (membrane I's where they agree)
        let is_ii = switches_ii & (!switches_i | s_ii.lt(s_i));
        let s = T::select(is_ii, s_ii, s_i) * h;
        let Across {
            at_switch,
            mode1,
            end,
        } = self.across(k, start, s, is_ii);
        // the end's mode is the one after the switch: no second switch
        let kept =
            !(flip_where(end.2.taut_i, mode1.taut_i) | flip_where(end.2.taut_ii, mode1.taut_ii));
        UsualSplit {
            end,
            shown,
            done: shown & kept,
            at_switch,
            s,
            mode1,
        }
    }

    /// The two sub-steps of step `k` from `start` either side of a switch after `s`, of
    /// membrane II where `is_ii` holds (else I): the state at the switch, the mode after it,
    /// and the step's end with its acceleration and mode.
    #[inline(always)]
    fn across<T: Real>(
        &self,
        k: usize,
        (y0, a0, mode0): StepStart<T, T::Mask>,
        s: T,
        is_ii: T::Mask,
    ) -> Across<T> {
        let (f, h) = (&self.field, T::splat(self.h));
        let drive = self.table.step_start(k);
        let (pi, pii) = self.table.at(2 * k + 2);
        let phi_end = (T::splat(pi), T::splat(pii));
        let half = T::splat(0.5);
        let phi_s = drive.phi_sq(s);
        let at_switch = self.step_in_mode((y0, a0), s, drive.phi_sq(half * s), phi_s, mode0);
        let mode1 = Mode {
            taut_i: flip_where(mode0.taut_i, !is_ii),
            taut_ii: flip_where(mode0.taut_ii, is_ii),
        };
        let a_switch = f.accel_in_mode(at_switch[0], at_switch[1], phi_s.0, phi_s.1, mode1);
        let phi_mid = drive.phi_sq(half * (s + h));
        let end = self.step_in_mode((at_switch, a_switch), h - s, phi_mid, phi_end, mode1);
        let (a, mode) = f.accel_lanes(end[0], end[1], phi_end.0, phi_end.1);
        Across {
            at_switch,
            mode1,
            end: (end, a, mode),
        }
    }

    /// One RK4 step of length `h` on the smooth piece `mode` from `y`, where the acceleration
    /// is `a`; `phi_mid` and `phi_end` are (φ_I², φ_II²) half-way and at the end.
    #[inline(always)]
    fn step_in_mode<T: Real>(
        &self,
        (y, a): ([T; 2], T),
        h: T,
        phi_mid: (T, T),
        phi_end: (T, T),
        mode: Mode<T::Mask>,
    ) -> [T; 2] {
        let f = &self.field;
        let c = T::splat;
        let [x, v] = y;
        let (x2, v2) = (x + c(0.5) * h * v, v + c(0.5) * h * a);
        let a2 = f.accel_in_mode(x2, v2, phi_mid.0, phi_mid.1, mode);
        let (x3, v3) = (x + c(0.5) * h * v2, v + c(0.5) * h * a2);
        let a3 = f.accel_in_mode(x3, v3, phi_mid.0, phi_mid.1, mode);
        let (x4, v4) = (x + h * v3, v + h * a3);
        let a4 = f.accel_in_mode(x4, v4, phi_end.0, phi_end.1, mode);
        [
            x + h / c(6.0) * (v + c(2.0) * v2 + c(2.0) * v3 + v4),
            v + h / c(6.0) * (a + c(2.0) * a2 + c(2.0) * a3 + a4),
        ]
    }

    /// A split step's end: its state, with the acceleration and mode there under the
    /// step's end drive `phi_end`.
    #[inline(always)]
    fn end_of(&self, end: [f64; 2], (pi, pii): (f64, f64)) -> StepEnd3 {
        let (a, mode) = self.field.accel(end[0], end[1], pi, pii);
        (end, a, mode)
    }

    /// The careful split: from time `t` of a step of length `h`, take trial steps on the
    /// current piece, locate the first switch on each, and go on from it. (No closures here
    /// or in what it calls: a closure is compiled on its own, without the instruction set of
    /// the step it serves, where it is not inlined.)
    #[inline(always)]
    fn split_from(&self, drive: &LocalDrive, y: [f64; 2], t: f64, h: f64, mode: Mode) -> [f64; 2] {
        let (mut y, mut t, mut mode) = (y, t, mode);
        for _ in 0..MAX_SWITCHES_PER_STEP {
            let hs = h - t;
            if hs <= 0.0 {
                return y;
            }
            // the drive at both ends, with its rates for locating a switch
            let drive_ends = [drive.phi_sq_with_rate(t), drive.phi_sq_with_rate(t + hs)];
            let start = (y, self.accel_on(y, drive_ends[0].0, mode));
            let y1 = self.sub_step(drive, start, t, hs, mode);
            let end = (y1, self.accel_on(y1, drive_ends[1].0, mode));
            match self.first_switch(drive, drive_ends, start, end, t, hs, mode) {
                None => return y1,
                Some(switch) => {
                    y = self.sub_step(drive, start, t, switch.at, mode);
                    t += switch.at;
                    mode = mode.flipped(switch.membrane);
                }
            }
        }
        let hs = h - t;
        if hs > 0.0 {
            let start = (y, self.accel_on(y, drive.phi_sq(t), mode));
            y = self.sub_step(drive, start, t, hs, mode);
        }
        y
    }

    /// The acceleration at `y` under drive (φ_I², φ_II²) on the piece `mode`.
    #[inline(always)]
    fn accel_on(&self, y: [f64; 2], (pi, pii): (f64, f64), mode: Mode) -> f64 {
        self.field.accel_in_mode(y[0], y[1], pi, pii, mode)
    }

    /// RK4 on the piece `mode` over `hs` from `t` within a step (the drive anchored at the
    /// step's start), from `y` with acceleration `a`.
    #[inline(always)]
    fn sub_step(
        &self,
        drive: &LocalDrive,
        (y, a): ([f64; 2], f64),
        t: f64,
        hs: f64,
        mode: Mode,
    ) -> [f64; 2] {
        let (mid, end) = (drive.phi_sq(t + 0.5 * hs), drive.phi_sq(t + hs));
        self.step_in_mode((y, a), hs, mid, end, mode)
    }

    /// Both membranes' switching functions at a state, positive while `mode` holds (each
    /// tension times its Gent denominator, so without a division).
    #[inline(always)]
    fn switching<T: Real>(&self, [x, v]: [T; 2], (pi, pii): (T, T), mode: Mode<T::Mask>) -> [T; 2] {
        let f = &self.field;
        [
            oriented(mode.taut_i, f.scaled_tension_of(Membrane::I, x, v, pi, pii)),
            oriented(
                mode.taut_ii,
                f.scaled_tension_of(Membrane::Ii, x, v, pi, pii),
            ),
        ]
    }

    /// Where membrane `m`'s switching function, negative at the step's end, crosses zero
    /// (as a fraction of the step `h`), and whether it is negative there: the root of its
    /// cubic Hermite interpolant from its values and rates at both `ends`; 0 if it is
    /// negative at the start too. A method rather than a closure, so that it is compiled
    /// into each instruction set's version of the step.
    #[inline(always)]
    fn end_switch<T: Real>(
        &self,
        m: Membrane,
        mode: Mode<T::Mask>,
        ends: [SwitchEnd<T>; 2],
        h: T,
    ) -> (T, T::Mask) {
        let [(y0, a0, drive_start, g_start), (y1, a1, drive_end, g_end)] = ends;
        let i = m.of((0, 1));
        let taut = m.of((mode.taut_i, mode.taut_ii));
        let zero = T::splat(0.0);
        // written as `< 0` so that a NaN is no switch
        let (negative_end, negative_start) = (g_end[i].lt(zero), g_start[i].lt(zero));
        let f = &self.field;
        let (d0, d1) = (
            f.scaled_tension_rate(m, [y0[0], y0[1], a0], drive_start.0, drive_start.1),
            f.scaled_tension_rate(m, [y1[0], y1[1], a1], drive_end.0, drive_end.1),
        );
        let (d0, d1) = (oriented(taut, d0), oriented(taut, d1));
        let searched = negative_end & !negative_start;
        let root = hermite::crossing(g_start[i], d0, g_end[i], d1, h, NEWTON_TOLERANCE, searched);
        (T::select(negative_start, zero, root), negative_end)
    }

    /// The first time inside a step from (`y0`, acceleration `a0`) at τ₀ + `t0` to (`y1`, `a1`)
    /// after `h`, on piece `mode`, where a membrane's tension crosses zero against its mode:
    /// (offset from t0, membrane). Where the step's end shows the switch (the usual case), it
    /// is the root of the switching function's cubic Hermite interpolant from its values and
    /// rates at both ends (O(h³), like the state's own interpolant); otherwise the switching
    /// functions are scanned along the state's interpolant for a brief excursion.
    /// `drive_ends`: the drive's values and rates at τ₀ + t0 and τ₀ + t0 + h.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn first_switch(
        &self,
        drive: &LocalDrive,
        [drive_start, drive_end]: [DriveWithRate; 2],
        (y0, a0): ([f64; 2], f64),
        (y1, a1): ([f64; 2], f64),
        t0: f64,
        h: f64,
        mode: Mode,
    ) -> Option<Switch> {
        let step = Interpolant {
            ends: [(y0, a0), (y1, a1)],
            t0,
            h,
        };
        let negative = |g: [f64; 2]| g[0] < 0.0 || g[1] < 0.0;
        // usually the end of the step already shows the switch
        let g_start = self.switching(y0, drive_start.0, mode);
        let g_end = self.switching(y1, drive_end.0, mode);
        let (s_root_i, s_root_ii) = if negative(g_end) {
            // the switching function's cubic Hermite interpolant from its values and rates at
            // both ends: no evaluation inside the step (rates only for a membrane that switches)
            let ends = [(y0, a0, drive_start, g_start), (y1, a1, drive_end, g_end)];
            // no closure here: one called twice may stay out of line, without the step's
            // instruction set
            let (s_i, switches_i) = self.end_switch(Membrane::I, mode, ends, h);
            let (s_ii, switches_ii) = self.end_switch(Membrane::Ii, mode, ends, h);
            (switches_i.then_some(s_i), switches_ii.then_some(s_ii))
        } else {
            // a brief excursion: scan the switching functions along the state's interpolant
            let (mut s_prev, mut g_prev) = (0.0, g_start);
            let mut found = None;
            for j in 1..SWITCH_SCAN_POINTS {
                let s = j as f64 / SWITCH_SCAN_POINTS as f64;
                let g = self.switching_along(drive, &step, mode, s);
                if negative(g) {
                    found = Some((s_prev, s, g_prev, g));
                    break;
                }
                (s_prev, g_prev) = (s, g);
            }
            let (lo, hi, g_lo, g_hi) = found?;
            let mut roots = [None; 2];
            for (m, root) in roots.iter_mut().enumerate() {
                if g_hi[m] < 0.0 {
                    let (lo, hi) = ((lo, g_lo[m]), (hi, g_hi[m]));
                    *root = Some(self.crossing(drive, &step, mode, m, lo, hi));
                }
            }
            (roots[0], roots[1])
        };
        let (s_root, membrane) = match (s_root_i, s_root_ii) {
            (Some(a), Some(b)) if b < a => (b, Membrane::Ii),
            (Some(a), _) => (a, Membrane::I),
            (None, Some(b)) => (b, Membrane::Ii),
            (None, None) => unreachable!("one switching function is negative"),
        };
        Some(Switch {
            at: s_root * h,
            membrane,
        })
    }

    /// Both switching functions (as [`Self::switching`]) at the fraction `s` of `step`, on
    /// the state's cubic Hermite interpolant.
    #[inline(always)]
    fn switching_along(
        &self,
        drive: &LocalDrive,
        step: &Interpolant,
        mode: Mode,
        s: f64,
    ) -> [f64; 2] {
        let [([x0, v0], a0), ([x1, v1], a1)] = step.ends;
        let x = hermite::value(x0, v0, x1, v1, step.h, s);
        let v = hermite::value(v0, a0, v1, a1, step.h, s);
        self.switching([x, v], drive.phi_sq(step.t0 + s * step.h), mode)
    }

    /// The point where membrane `m`'s switching function along `step` turns negative in
    /// (lo, hi], from its values there, g(hi) < 0 (if g(lo) < 0 too, lo itself): regula falsi
    /// with the Anderson–Björck correction, stopped when successive estimates agree to
    /// [`SWITCH_TOLERANCE`] of the step. A switch misplaced by δ costs only O(δ²), and the
    /// interpolant itself is good to O(h³), so more digits would buy nothing.
    #[inline(always)]
    fn crossing(
        &self,
        drive: &LocalDrive,
        step: &Interpolant,
        mode: Mode,
        m: usize,
        (lo, g_lo): (f64, f64),
        (hi, g_hi): (f64, f64),
    ) -> f64 {
        let (mut a, mut b) = (lo, hi);
        let (mut ga, mut gb) = (g_lo, g_hi);
        if ga < 0.0 {
            return a;
        }
        let mut last = f64::NAN;
        for _ in 0..60 {
            let c = (a * gb - b * ga) / (gb - ga);
            let c = if c > a && c < b { c } else { 0.5 * (a + b) };
            if (c - last).abs() < SWITCH_TOLERANCE || b - a < SWITCH_TOLERANCE {
                return c;
            }
            last = c;
            let gc = self.switching_along(drive, step, mode, c)[m];
            if gc < 0.0 {
                // the root is in (a, c): keep a, scale its value if it was kept before
                let k = 1.0 - gc / gb;
                b = c;
                gb = gc;
                ga *= if k > 0.0 { k } else { 0.5 };
            } else {
                let k = 1.0 - gc / ga;
                a = c;
                ga = gc;
                gb *= if k > 0.0 { k } else { 0.5 };
            }
        }
        b
    }
}

/// The drive's values and rates, the same in every lane.
#[inline(always)]
fn splat_drive<T: Real>(((pi, pii), (ri, rii)): DriveWithRate) -> DriveWithRate<T> {
    ((T::splat(pi), T::splat(pii)), (T::splat(ri), T::splat(rii)))
}

/// A membrane's switching function `g` signed to be positive where it agrees with its
/// mode: negated where it is slack.
#[inline(always)]
fn oriented<T: Real>(taut: T::Mask, g: T) -> T {
    T::select(taut, g, -g)
}

/// `taut` with its lanes flipped where `flip` holds.
#[inline(always)]
fn flip_where<M>(taut: M, flip: M) -> M
where
    M: Copy
        + std::ops::BitAnd<Output = M>
        + std::ops::BitOr<Output = M>
        + std::ops::Not<Output = M>,
{
    (taut & !flip) | (!taut & flip)
}

/// A (sub-)step's ends as (state, acceleration), from τ₀ + `t0` over `h`: its state's cubic
/// Hermite interpolant.
#[derive(Debug, Clone, Copy)]
struct Interpolant {
    ends: [([f64; 2], f64); 2],
    t0: f64,
    h: f64,
}

/// One end of a step for [`Rk4::end_switch`]: state, acceleration, the drive's (φ_I², φ_II²)
/// and their rates, and both switching functions.
type SwitchEnd<T> = ([T; 2], T, DriveWithRate<T>, [T; 2]);

/// A located switch inside a step.
#[derive(Debug, Clone, Copy)]
struct Switch {
    /// Time from the start of the (sub-)step.
    at: f64,
    membrane: Membrane,
}
