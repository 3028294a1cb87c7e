//! Fixed-step RK4 over whole forcing periods, `L` trajectories at once in SIMD lanes.
//!
//! The step h = T/n divides the forcing period, so stroboscopic samples fall on steps and the
//! drive comes from a per-period table. The field is evaluated with one division per stage
//! ([`Field::accel`]) and the acceleration at the end of a step is reused as the first stage
//! of the next (4 evaluations per step). A step in which any stage sees a membrane switch
//! between taut and slack is redone for the lanes that saw it (`split`), four side by side:
//! the switch is located on a cubic Hermite interpolant of the switching function over the
//! step, and the step is split there, integrating each side on its own smooth piece. This
//! restores fourth order on orbits that go slack (MODEL.md §4b).

use super::Collision;
use super::drive_table::DriveTable;
use super::field::{Field, Membrane, Mode};
use super::isa::{self, Isa};
use super::lane::Real;
use super::resolution::Resolution;
use crate::model::Params;
use split::{
    BatchEnd, BatchEnds, BatchStart, SPLIT_BATCH, SplitLanes, StepEnd, StepEnd3, StepStart,
};

mod split;

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
            _ => self.advance_period_body(
                lanes,
                observe,
                |k, start, unsplit| self.split_batch_baseline(k, start, unsplit),
                |k, start, unsplit| self.split_step_baseline(k, start, unsplit),
            ),
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe,f16c")]
    fn advance_period_v3<const L: usize>(&self, lanes: &mut Lanes<L>, observe: Observer<'_, L>) {
        // a closure here has these instructions too
        self.advance_period_body(
            lanes,
            observe,
            |k, start, unsplit| self.split_batch_v3(k, start, unsplit),
            |k, start, unsplit| self.split_step_v3(k, start, unsplit),
        );
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe,f16c")]
    fn split_batch_v3(&self, k: usize, start: BatchStart, unsplit: BatchEnd) -> BatchEnds {
        self.split_batch(k, start, unsplit)
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
        self.advance_period_body(
            lanes,
            observe,
            |k, start, unsplit| self.split_batch_v4(k, start, unsplit),
            |k, start, unsplit| self.split_step_v4(k, start, unsplit),
        );
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(
        enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe,f16c,avx512f,avx512bw,avx512cd,avx512dq,avx512vl"
    )]
    fn split_batch_v4(&self, k: usize, start: BatchStart, unsplit: BatchEnd) -> BatchEnds {
        self.split_batch(k, start, unsplit)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(
        enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe,f16c,avx512f,avx512bw,avx512cd,avx512dq,avx512vl"
    )]
    fn split_step_v4(&self, k: usize, start: StepStart, unsplit: StepEnd) -> StepEnd3 {
        self.split_step(k, start, unsplit)
    }

    #[inline(never)]
    fn split_batch_baseline(&self, k: usize, start: BatchStart, unsplit: BatchEnd) -> BatchEnds {
        self.split_batch(k, start, unsplit)
    }

    #[inline(never)]
    fn split_step_baseline(&self, k: usize, start: StepStart, unsplit: StepEnd) -> StepEnd3 {
        self.split_step(k, start, unsplit)
    }

    /// The one body of every version of [`Self::advance_period`], inlined into each so that
    /// each is compiled for its instruction set; `split_batch` is [`Self::split_batch`] and
    /// `split` [`Self::split_step`] (for the lanes a batch leaves) compiled for the same (out
    /// of line: a lane switches in few steps).
    #[inline(always)]
    fn advance_period_body<const L: usize>(
        &self,
        lanes: &mut Lanes<L>,
        mut observe: Observer<'_, L>,
        split_batch: impl Fn(usize, BatchStart, BatchEnd) -> BatchEnds,
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
                self.split_switched(k, &before, &mode0, &switched, lanes, &split_batch, &split);
                for i in 0..L {
                    if lanes.collision[i].is_some() {
                        continue;
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

    /// Redoes step `k` of the lanes that `switched` (and are still inside the model) as
    /// split steps from `before` (modes `mode0`): a batch at a time side by side, a lane the
    /// batch leaves alone.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn split_switched<const L: usize>(
        &self,
        k: usize,
        before: &StepEnds<L>,
        mode0: &[f64; L],
        switched: &[bool; L],
        lanes: &mut Lanes<L>,
        split_batch: &impl Fn(usize, BatchStart, BatchEnd) -> BatchEnds,
        split: &impl Fn(usize, StepStart, StepEnd) -> StepEnd3,
    ) {
        let (x0, v0, a0) = (&before.x, &before.v, &before.a);
        // the lanes to split, a batch at a time side by side
        let mut todo = [0; L];
        let mut count = 0;
        for (i, &switched) in switched.iter().enumerate() {
            if switched && lanes.collision[i].is_none() {
                todo[count] = i;
                count += 1;
            }
        }
        for batch in todo[..count].chunks(SPLIT_BATCH) {
            // unused places repeat the batch's last lane
            let lane = |j: usize| batch[j.min(batch.len() - 1)];
            let pick = |values: &[f64; L]| SplitLanes::gather(|j| values[lane(j)]);
            let taut_of = |membrane: Membrane| {
                let taut = |j| membrane.of(Mode::from_code(mode0[lane(j)]).pair());
                SplitLanes::gather_mask(taut)
            };
            let mode = Mode {
                taut_i: taut_of(Membrane::I),
                taut_ii: taut_of(Membrane::Ii),
            };
            let start = ([pick(x0), pick(v0)], pick(a0), mode);
            let unsplit = ([pick(&lanes.x), pick(&lanes.v)], pick(&lanes.a));
            let (([x1, v1], a1, mode1), done) = split_batch(k, start, unsplit);
            for (j, &i) in batch.iter().enumerate() {
                let (end, a_end, mode_end) = if SplitLanes::lane_holds(done, j) {
                    let mode = Mode {
                        taut_i: SplitLanes::lane_holds(mode1.taut_i, j),
                        taut_ii: SplitLanes::lane_holds(mode1.taut_ii, j),
                    };
                    ([x1.lane(j), v1.lane(j)], a1.lane(j), mode)
                } else {
                    // a second switch, or one the step's end does not show
                    let start = ([x0[i], v0[i]], a0[i], Mode::from_code(mode0[i]));
                    split(k, start, ([lanes.x[i], lanes.v[i]], lanes.a[i]))
                };
                [lanes.x[i], lanes.v[i]] = end;
                (lanes.a[i], lanes.mode[i]) = (a_end, Mode::code(mode_end));
            }
        }
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

    /// Lanes `picks` of `lanes`, in that order, moved to `M` lanes (the rest parked): each
    /// goes on bit for bit as it would have.
    pub fn narrowed<const L: usize, const M: usize>(
        &self,
        lanes: &Lanes<L>,
        picks: &[usize],
    ) -> Lanes<M> {
        assert!(picks.len() <= M, "{} lanes into {M}", picks.len());
        let mut narrow = self.start([self.params.lambda_p(); M], [0.0; M]);
        narrow.period = lanes.period;
        for (j, &i) in picks.iter().enumerate() {
            narrow.x[j] = lanes.x[i];
            narrow.v[j] = lanes.v[i];
            narrow.a[j] = lanes.a[i];
            narrow.mode[j] = lanes.mode[i];
            narrow.collision[j] = lanes.collision[i];
            narrow.start_period[j] = lanes.start_period[i];
        }
        for j in picks.len()..M {
            self.park_lane(&mut narrow, j);
        }
        narrow
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
