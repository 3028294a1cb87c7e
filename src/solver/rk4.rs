//! Fixed-step RK4 over whole forcing periods, `L` trajectories at once in SIMD lanes.
//!
//! The step h = T/n divides the forcing period, so stroboscopic samples fall on steps and the
//! drive comes from a per-period table. The field is evaluated with one division per stage
//! ([`Field::accel`]) and the acceleration at the end of a step is reused as the first stage
//! of the next (4 evaluations per step). A step in which any stage sees a membrane switch
//! between taut and slack is redone for that lane alone: the switch is located on a cubic
//! Hermite interpolant of the switching function over the step, and the step is split there,
//! integrating each side on its own smooth piece. This restores fourth order on orbits that go
//! slack (MODEL.md §4b).

use super::Collision;
use super::drive_table::{DriveTable, DriveWithRate, LocalDrive};
use super::field::{Field, Membrane, Mode};
use super::hermite;
use super::isa::{self, Isa};
use super::resolution::Resolution;
use crate::model::Params;

/// Trajectories the batches integrate side by side.
pub const LANES: usize = 16;
/// Most switches handled inside one step before the rest of it is taken as it is.
const MAX_SWITCHES_PER_STEP: usize = 4;
/// Agreement of successive switch estimates, as a fraction of the step, that ends the search.
const SWITCH_TOLERANCE: f64 = 1e-6;
/// Agreement of successive Newton estimates of a switch, as a fraction of the step: Newton's
/// method converges quadratically, so the last estimate is then good to about 1e-8.
const NEWTON_TOLERANCE: f64 = 1e-4;
/// Samples of the switching functions per step when looking for a sign change.
const SWITCH_SCAN_POINTS: usize = 4;

/// The fixed-step integrator for one parameter set.
#[derive(Debug, Clone)]
pub struct Rk4 {
    params: Params,
    field: Field,
    table: DriveTable,
    n: usize,
    h: f64,
}

/// `L` trajectories advanced together, all at the same time τ = `period`·T.
#[derive(Debug, Clone)]
pub struct Lanes<const L: usize> {
    /// λ_I of each lane.
    pub x: [f64; L],
    /// dλ_I/dτ of each lane.
    pub v: [f64; L],
    /// Acceleration at the current state: the first RK4 stage of the next step.
    a: [f64; L],
    /// Mode at the current state as [`Mode::code`].
    mode: [f64; L],
    /// Set once a lane has left the model; such a lane is frozen.
    pub collision: [Option<Collision>; L],
    /// Whole forcing periods done.
    pub period: u64,
    /// The period at which each lane's trajectory started (collision times count from it).
    start_period: [u64; L],
}

impl<const L: usize> Lanes<L> {
    /// True if any lane is still inside the model.
    pub fn any_alive(&self) -> bool {
        self.collision.iter().any(Option::is_none)
    }
}

impl Rk4 {
    /// An integrator for `params`, with the step count per period from `resolution`.
    pub fn new(params: &Params, resolution: &Resolution) -> Self {
        let n = resolution.steps_for(params.period());
        Self::with_steps(params, n)
    }

    /// An integrator with exactly `n` steps per forcing period.
    pub fn with_steps(params: &Params, n: usize) -> Self {
        let n = n.max(1);
        let h = params.period() / n as f64;
        Rk4 {
            params: *params,
            field: Field::new(params),
            table: DriveTable::new(params, n, h),
            n,
            h,
        }
    }

    /// The right-hand side it integrates.
    pub fn field(&self) -> &Field {
        &self.field
    }

    /// The forcing tabulated at its steps and half-steps.
    pub fn table(&self) -> &DriveTable {
        &self.table
    }

    pub fn params(&self) -> &Params {
        &self.params
    }

    pub fn steps_per_period(&self) -> usize {
        self.n
    }

    /// Step length h = T/n.
    pub fn step(&self) -> f64 {
        self.h
    }

    /// Lanes starting at τ = 0 from the given states.
    pub fn start<const L: usize>(&self, x: [f64; L], v: [f64; L]) -> Lanes<L> {
        let (phi_i, phi_ii) = self.table.at(0);
        let mut lanes = Lanes {
            x,
            v,
            a: [0.0; L],
            mode: [0.0; L],
            collision: [None; L],
            period: 0,
            start_period: [0; L],
        };
        for i in 0..L {
            if !(x[i].is_finite() && v[i].is_finite() && self.field.inside(x[i])) {
                self.freeze(&mut lanes, i, 0.0, x[i]);
                continue;
            }
            (lanes.a[i], lanes.mode[i]) = self.field.accel_coded(x[i], v[i], phi_i, phi_ii);
        }
        lanes
    }

    /// Advances every lane one forcing period. After each step `observe(k, before, after)`,
    /// if given, sees step `k`'s end points as (x, v, a) arrays, for recording. Runs the
    /// version compiled for this process's instruction set ([`isa::chosen`]).
    #[inline]
    pub fn advance_period<const L: usize>(&self, lanes: &mut Lanes<L>, observe: Observer<'_, L>) {
        // SAFETY: the chosen instruction set is one this CPU has
        unsafe { self.advance_period_unchecked(isa::chosen(), lanes, observe) }
    }

    /// [`Self::advance_period`] in the version compiled for `isa` (to compare them).
    ///
    /// # Panics
    /// If this CPU lacks `isa`'s instructions.
    #[inline]
    pub fn advance_period_in<const L: usize>(
        &self,
        isa: Isa,
        lanes: &mut Lanes<L>,
        observe: Observer<'_, L>,
    ) {
        assert!(
            isa.available(),
            "{} instructions on a CPU without them",
            isa.name()
        );
        // SAFETY: the CPU has the instructions (asserted above)
        unsafe { self.advance_period_unchecked(isa, lanes, observe) }
    }

    /// The dispatch itself, without asking the CPU (a dozen feature look-ups: done once per
    /// process for the chosen set, not once per period).
    ///
    /// # Safety
    /// The CPU must have `isa`'s instructions.
    #[inline]
    unsafe fn advance_period_unchecked<const L: usize>(
        &self,
        isa: Isa,
        lanes: &mut Lanes<L>,
        observe: Observer<'_, L>,
    ) {
        match isa {
            // SAFETY: the caller guarantees the CPU has the instructions
            #[cfg(target_arch = "x86_64")]
            Isa::X86_64V4 => unsafe { self.advance_period_v4(lanes, observe) },
            #[cfg(target_arch = "x86_64")]
            Isa::X86_64V3 => unsafe { self.advance_period_v3(lanes, observe) },
            _ => self.advance_period_body(lanes, observe, |k, start, unsplit| {
                self.split_step_baseline(k, start, unsplit)
            }),
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe,f16c")]
    fn advance_period_v3<const L: usize>(&self, lanes: &mut Lanes<L>, observe: Observer<'_, L>) {
        // a closure here has these instructions too
        self.advance_period_body(lanes, observe, |k, start, unsplit| {
            self.split_step_v3(k, start, unsplit)
        });
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe,f16c")]
    fn split_step_v3(&self, k: usize, start: StepStart, unsplit: StepEnd) -> StepEnd3 {
        self.split_step(k, start, unsplit)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(
        enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe,f16c,avx512f,avx512bw,avx512cd,avx512dq,avx512vl"
    )]
    fn advance_period_v4<const L: usize>(&self, lanes: &mut Lanes<L>, observe: Observer<'_, L>) {
        // a closure here has these instructions too
        self.advance_period_body(lanes, observe, |k, start, unsplit| {
            self.split_step_v4(k, start, unsplit)
        });
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(
        enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe,f16c,avx512f,avx512bw,avx512cd,avx512dq,avx512vl"
    )]
    fn split_step_v4(&self, k: usize, start: StepStart, unsplit: StepEnd) -> StepEnd3 {
        self.split_step(k, start, unsplit)
    }

    #[inline(never)]
    fn split_step_baseline(&self, k: usize, start: StepStart, unsplit: StepEnd) -> StepEnd3 {
        self.split_step(k, start, unsplit)
    }

    /// The one body of every version of [`Self::advance_period`], inlined into each so that
    /// each is compiled for its instruction set; `split` is [`Self::split_step`] compiled for
    /// the same (out of line: a lane switches in few steps).
    #[inline(always)]
    fn advance_period_body<const L: usize>(
        &self,
        lanes: &mut Lanes<L>,
        mut observe: Observer<'_, L>,
        split: impl Fn(usize, StepStart, StepEnd) -> StepEnd3,
    ) {
        let (h, f) = (self.h, &self.field);
        let half = 0.5 * h;
        let sixth = h / 6.0;
        for k in 0..self.n {
            let (phi_i_mid, phi_ii_mid) = self.table.at(2 * k + 1);
            let (phi_i_end, phi_ii_end) = self.table.at(2 * k + 2);
            let before = StepEnds {
                x: lanes.x,
                v: lanes.v,
                a: lanes.a,
            };
            let (x0, v0, a0) = (&before.x, &before.v, &before.a);
            let mode0 = lanes.mode;
            let mut switched = [false; L];
            let mut x1 = [0.0; L];
            let mut v1 = [0.0; L];
            // One loop per stage over all lanes, so independent lanes overlap in the pipeline.
            let mut a2 = [0.0; L];
            let mut a3 = [0.0; L];
            let mut a4 = [0.0; L];
            let mut vs2 = [0.0; L];
            let mut vs3 = [0.0; L];
            for i in 0..L {
                let (xs, vs) = (half.mul_add(v0[i], x0[i]), half.mul_add(a0[i], v0[i]));
                let (a, m) = f.accel_coded(xs, vs, phi_i_mid, phi_ii_mid);
                (a2[i], vs2[i]) = (a, vs);
                switched[i] = m != mode0[i];
            }
            for i in 0..L {
                let (xs, vs) = (half.mul_add(vs2[i], x0[i]), half.mul_add(a2[i], v0[i]));
                let (a, m) = f.accel_coded(xs, vs, phi_i_mid, phi_ii_mid);
                (a3[i], vs3[i]) = (a, vs);
                switched[i] |= m != mode0[i];
            }
            for i in 0..L {
                let (xs, vs) = (h.mul_add(vs3[i], x0[i]), h.mul_add(a3[i], v0[i]));
                let (a, m) = f.accel_coded(xs, vs, phi_i_end, phi_ii_end);
                a4[i] = a;
                switched[i] |= m != mode0[i];
            }
            for i in 0..L {
                // stage velocities: v0, v0 + h/2 a0, v0 + h/2 a2, v0 + h a3
                let a23 = a2[i] + a3[i];
                x1[i] = sixth.mul_add(6.0f64.mul_add(v0[i], h * (a0[i] + a23)), x0[i]);
                v1[i] = sixth.mul_add(2.0f64.mul_add(a23, a0[i] + a4[i]), v0[i]);
            }
            let mut trouble = false;
            for i in 0..L {
                let (a_end, m_end) = f.accel_coded(x1[i], v1[i], phi_i_end, phi_ii_end);
                switched[i] |= m_end != mode0[i];
                trouble |= switched[i] | !f.inside(x1[i]);
                lanes.x[i] = x1[i];
                lanes.v[i] = v1[i];
                lanes.a[i] = a_end;
                lanes.mode[i] = m_end;
            }
            if trouble {
                // the drive is T-periodic: split steps are anchored at the step's phase within
                // the period, so a trajectory never depends on how many periods its lane ran
                let phase_tau = k as f64 * h;
                for i in 0..L {
                    if lanes.collision[i].is_some() {
                        continue;
                    }
                    if switched[i] {
                        let start = ([x0[i], v0[i]], a0[i], Mode::from_code(mode0[i]));
                        let unsplit = ([lanes.x[i], lanes.v[i]], lanes.a[i]);
                        let (end, a_end, mode_end) = split(k, start, unsplit);
                        [lanes.x[i], lanes.v[i]] = end;
                        (lanes.a[i], lanes.mode[i]) = (a_end, Mode::code(mode_end));
                    }
                    if !(f.inside(lanes.x[i]) && lanes.v[i].is_finite()) {
                        let periods = (lanes.period - lanes.start_period[i]) as f64;
                        let step_start = periods * self.params.period() + phase_tau;
                        // where in the step it left the model, if the step's end says
                        let (theta, lambda_i) = if lanes.x[i].is_finite() && lanes.v[i].is_finite()
                        {
                            self.exit_in_step(h, [x0[i], v0[i]], [lanes.x[i], lanes.v[i]])
                        } else {
                            (1.0, lanes.x[i])
                        };
                        self.freeze(lanes, i, step_start + theta * h, lambda_i);
                    }
                }
            }
            if let Some(observe) = observe.as_deref_mut() {
                let after = StepEnds {
                    x: lanes.x,
                    v: lanes.v,
                    a: lanes.a,
                };
                observe(k, &before, &after);
            }
        }
        lanes.period += 1;
    }

    /// Puts a new trajectory in lane `i`, starting at the current period boundary (forcing
    /// phase 0, as at τ = 0).
    pub fn restart_lane<const L: usize>(&self, lanes: &mut Lanes<L>, i: usize, x: f64, v: f64) {
        lanes.collision[i] = None;
        lanes.start_period[i] = lanes.period;
        lanes.x[i] = x;
        lanes.v[i] = v;
        if !(x.is_finite() && v.is_finite() && self.field.inside(x)) {
            self.freeze(lanes, i, 0.0, x);
            return;
        }
        let (phi_i, phi_ii) = self.table.at(0);
        (lanes.a[i], lanes.mode[i]) = self.field.accel_coded(x, v, phi_i, phi_ii);
    }

    /// Parks lane `i` with no trajectory in it (reported as a collision at τ = 0).
    pub fn park_lane<const L: usize>(&self, lanes: &mut Lanes<L>, i: usize) {
        self.freeze(lanes, i, 0.0, lanes.x[i]);
    }

    /// Marks lane `i` as collided at `tau`, λ_I being `lambda_i` there, and parks it at rest
    /// at λ_p.
    fn freeze<const L: usize>(&self, lanes: &mut Lanes<L>, i: usize, tau: f64, lambda_i: f64) {
        lanes.collision[i] = Some(Collision { tau, lambda_i });
        lanes.x[i] = self.params.lambda_p();
        lanes.v[i] = 0.0;
        lanes.a[i] = 0.0;
    }

    /// Where a step of length `h` from (λ_I, v) = (x0, v0), inside the model, to (x1, v1),
    /// outside it, leaves it: bisection of the step's cubic Hermite interpolant of λ_I (its
    /// error about h⁴, as the step's own) to round-off. The fraction of the step, and λ_I
    /// there (just past the frame or the locking stretch).
    fn exit_in_step(&self, h: f64, [x0, v0]: [f64; 2], [x1, v1]: [f64; 2]) -> (f64, f64) {
        let at = |theta| super::hermite::value(x0, v0, x1, v1, h, theta);
        let theta = super::hermite::first_where(|theta| !self.field.inside(at(theta)));
        (theta, at(theta))
    }

    /// One RK4 step of length `h` on the smooth piece `mode` from `y`, where the acceleration
    /// is `a`; `phi_mid` and `phi_end` are (φ_I², φ_II²) half-way and at the end.
    #[inline(always)]
    fn step_in_mode(
        &self,
        (y, a): ([f64; 2], f64),
        h: f64,
        phi_mid: (f64, f64),
        phi_end: (f64, f64),
        mode: Mode,
    ) -> [f64; 2] {
        let f = &self.field;
        let [x, v] = y;
        let (x2, v2) = (x + 0.5 * h * v, v + 0.5 * h * a);
        let a2 = f.accel_in_mode(x2, v2, phi_mid.0, phi_mid.1, mode);
        let (x3, v3) = (x + 0.5 * h * v2, v + 0.5 * h * a2);
        let a3 = f.accel_in_mode(x3, v3, phi_mid.0, phi_mid.1, mode);
        let (x4, v4) = (x + h * v3, v + h * a3);
        let a4 = f.accel_in_mode(x4, v4, phi_end.0, phi_end.1, mode);
        [
            x + h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4),
            v + h / 6.0 * (a + 2.0 * a2 + 2.0 * a3 + a4),
        ]
    }

    /// RK4 step `k` of the period split where a membrane switches between taut and slack,
    /// each side integrated on its own smooth piece. `start` is the step's start (state,
    /// acceleration, mode); `unsplit` is the same step taken through the kink (its end state
    /// and true acceleration there): its cubic Hermite interpolant places the switch to O(h³),
    /// and a switch misplaced by δ costs only O(δ²), so two sub-steps finish the job. Anything
    /// less simple (no sign change on that interpolant, or another switch after the first)
    /// goes to [`Self::split_from`]. Returns the end state, its acceleration and mode.
    #[inline(always)]
    fn split_step(&self, k: usize, (start, a0, mode0): StepStart, unsplit: StepEnd) -> StepEnd3 {
        let (f, h) = (&self.field, self.h);
        let drive = self.table.step_start(k);
        let drive_ends = self.table.step_ends(k);
        let phi_end = self.table.at(2 * k + 2);
        let first = self.first_switch(drive, drive_ends, (start, a0), unsplit, 0.0, h, mode0);
        let Some(switch) = first else {
            return self.end_of(self.split_from(drive, start, 0.0, h, mode0), phi_end);
        };
        let s = switch.at;
        let phi_s = drive.phi_sq(s);
        let at_switch = self.step_in_mode((start, a0), s, drive.phi_sq(0.5 * s), phi_s, mode0);
        let mode1 = mode0.flipped(switch.membrane);
        let a_switch = f.accel_in_mode(at_switch[0], at_switch[1], phi_s.0, phi_s.1, mode1);
        let phi_mid = drive.phi_sq(0.5 * (s + h));
        let end = self.step_in_mode((at_switch, a_switch), h - s, phi_mid, phi_end, mode1);
        let end = self.end_of(end, phi_end);
        if end.2 == mode1 {
            end
        } else {
            self.end_of(self.split_from(drive, at_switch, s, h, mode1), phi_end)
        }
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
    fn switching(&self, [x, v]: [f64; 2], (pi, pii): (f64, f64), mode: Mode) -> [f64; 2] {
        let g = |m| mode.oriented(m, self.field.scaled_tension_of(m, x, v, pi, pii));
        [g(Membrane::I), g(Membrane::Ii)]
    }

    /// Where membrane `m`'s switching function, negative at the step's end, crosses zero
    /// (as a fraction of the step `h`): the root of its cubic Hermite interpolant from its
    /// values and rates at both `ends`; 0 if it is negative at the start too, `None` if it is
    /// not negative at the end. A method rather than a closure, so that it is compiled into
    /// each instruction set's version of the step.
    #[inline(always)]
    fn end_switch(&self, m: Membrane, mode: Mode, ends: [SwitchEnd; 2], h: f64) -> Option<f64> {
        let [(y0, a0, drive_start, g_start), (y1, a1, drive_end, g_end)] = ends;
        let i = m.of((0, 1));
        // written as `< 0` so that a NaN is no switch
        if g_end[i] < 0.0 {
            if g_start[i] < 0.0 {
                return Some(0.0);
            }
            // no closure here either: a closure called twice may stay out of line
            let f = &self.field;
            let (d0, d1) = (
                f.scaled_tension_rate(m, [y0[0], y0[1], a0], drive_start.0, drive_start.1),
                f.scaled_tension_rate(m, [y1[0], y1[1], a1], drive_end.0, drive_end.1),
            );
            let (d0, d1) = (mode.oriented(m, d0), mode.oriented(m, d1));
            Some(hermite::crossing(
                g_start[i],
                d0,
                g_end[i],
                d1,
                h,
                NEWTON_TOLERANCE,
            ))
        } else {
            None
        }
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
            (
                self.end_switch(Membrane::I, mode, ends, h),
                self.end_switch(Membrane::Ii, mode, ends, h),
            )
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
type SwitchEnd = ([f64; 2], f64, DriveWithRate, [f64; 2]);

/// A step's start: state, acceleration and mode.
type StepStart = ([f64; 2], f64, Mode);
/// A step's end: state and acceleration.
type StepEnd = ([f64; 2], f64);
/// A step's end: state, acceleration and mode.
type StepEnd3 = ([f64; 2], f64, Mode);

/// A located switch inside a step.
#[derive(Debug, Clone, Copy)]
struct Switch {
    /// Time from the start of the (sub-)step.
    at: f64,
    membrane: Membrane,
}

/// The end points of one RK4 step: λ_I, velocity and acceleration of each lane.
#[derive(Debug, Clone, Copy)]
pub struct StepEnds<const L: usize> {
    pub x: [f64; L],
    pub v: [f64; L],
    pub a: [f64; L],
}

/// What sees each step's end points `(k, before, after)`, if anything (a `dyn`, so that the
/// integrator is compiled once per lane count, not once per caller).
pub type Observer<'a, const L: usize> =
    Option<&'a mut dyn FnMut(usize, &StepEnds<L>, &StepEnds<L>)>;
