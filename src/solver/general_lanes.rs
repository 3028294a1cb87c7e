//! [`GeneralRk4`] on `L` trajectories of a written model at once: every lane's plain step in
//! one pass of the tapes over the lanes; a lane whose step meets a switch (or a value that is
//! not finite) is redone alone by the scalar integrator, which splits it. Each lane's result
//! is bit for bit the scalar integrator's.

use super::general::{GeneralRk4, MAX_COUNTED_STEPS, Stop, Trajectory, Trial};
use super::isa::{self, Isa};
use crate::model::equations::EquationSystem;
use crate::model::equations::lanes::{EquationLanes, LaneSwitching, LaneTimes, LaneVectors};
use crate::model::equations::time_table::GridTime;
use crate::model::system::{END_SWITCHES, EndSwitching, MAX_DIM, Mode, System, Vector};

/// `L` trajectories, each on its own clock (τ counts from the lane's own start).
#[derive(Debug, Clone)]
pub struct Lanes<const L: usize> {
    /// Each lane's state and mode, to read: a lane is set by [`GeneralRk4::restart_lane`] or
    /// [`GeneralRk4::park_lane`], which keep what the lanes know of it in step.
    pub x: LaneVectors<L>,
    dx: LaneVectors<L>,
    pub mode: [Mode; L],
    /// Steps each lane has taken since it started, counted in f64 (exact below 2⁵³ steps,
    /// far beyond any run), so that its τ = steps·h needs no conversion each step.
    steps: [f64; L],
    /// Each lane's step within the forcing period (its steps modulo the period's).
    phase: [usize; L],
    /// Why a lane stopped; a stopped or idle lane is frozen.
    stop: [Option<Stop>; L],
    /// Lanes integrating: with a trajectory that has not stopped.
    live: [bool; L],
    /// Lanes whose last step was a plain compiled one: their switching values now are that
    /// step's at its end ([`Stages::switching`]).
    start_known: [bool; L],
    /// A step's stages, kept between steps so that a step neither clears nor copies whole
    /// arrays: only the model's states are written, the rows beyond stay zero.
    /// (Taken out of the lanes during a step.)
    stages: Option<Box<Stages<L>>>,
}

/// The vectors of one RK4 step of `L` lanes.
#[derive(Debug, Clone)]
struct Stages<const L: usize> {
    y: LaneVectors<L>,
    k2: LaneVectors<L>,
    k3: LaneVectors<L>,
    k4: LaneVectors<L>,
    end: LaneVectors<L>,
    dx: LaneVectors<L>,
    /// The switching values at the ends of the last two compiled steps (the step writes
    /// one, the other is at the lanes' starts), so that a lane split after a plain step
    /// need not evaluate them at its start again.
    switching: [LaneSwitching<L>; 2],
    /// Which of `switching` is at the lanes' starts.
    at_start: usize,
}

/// One lane's ends of a step, for recording.
pub type LaneEnds<const L: usize> = ([f64; L], LaneVectors<L>, [Mode; L]);

impl<const L: usize> Lanes<L> {
    /// Every lane idle, parked at `rest` (any finite state of the model).
    pub fn idle(rest: &Vector) -> Self {
        let mut x = [[0.0; L]; MAX_DIM];
        for (xi, &r) in x.iter_mut().zip(rest) {
            *xi = [r; L];
        }
        Lanes {
            x,
            dx: [[0.0; L]; MAX_DIM],
            mode: [0; L],
            steps: [0.0; L],
            phase: [0; L],
            stop: std::array::from_fn(|_| None),
            live: [false; L],
            start_known: [false; L],
            stages: Some(Box::new(Stages {
                y: [[0.0; L]; MAX_DIM],
                k2: [[0.0; L]; MAX_DIM],
                k3: [[0.0; L]; MAX_DIM],
                k4: [[0.0; L]; MAX_DIM],
                end: [[0.0; L]; MAX_DIM],
                dx: [[0.0; L]; MAX_DIM],
                switching: [[[0.0; L]; END_SWITCHES]; 2],
                at_start: 0,
            })),
        }
    }

    /// Every lane's τ, state and mode now (a step's ends, for recording).
    pub fn ends(&self, rk: &GeneralRk4) -> LaneEnds<L> {
        (
            std::array::from_fn(|l| self.steps[l] * rk.step()),
            self.x,
            self.mode,
        )
    }

    /// Lane `l` as a scalar trajectory.
    fn lane(&self, l: usize) -> Trajectory {
        let mut traj = Trajectory::parked();
        for i in 0..MAX_DIM {
            traj.x[i] = self.x[i][l];
            traj.dx[i] = self.dx[i][l];
        }
        traj.mode = self.mode[l];
        traj.steps = self.steps[l] as u64;
        traj.phase = self.phase[l];
        traj.stop = self.stop[l].clone();
        traj
    }

    /// Puts a scalar trajectory into lane `l`, running unless it has stopped.
    fn set_lane(&mut self, l: usize, traj: Trajectory) {
        for i in 0..MAX_DIM {
            self.x[i][l] = traj.x[i];
            self.dx[i][l] = traj.dx[i];
        }
        self.mode[l] = traj.mode;
        self.steps[l] = traj.steps as f64;
        self.phase[l] = traj.phase;
        self.stop[l] = traj.stop;
        self.live[l] = self.stop[l].is_none();
        self.start_known[l] = false;
    }

    /// Why lane `l` stopped, if it has.
    pub fn stop(&self, l: usize) -> Option<&Stop> {
        self.stop[l].as_ref()
    }

    /// Whether lane `l` is integrating.
    pub fn running(&self, l: usize) -> bool {
        self.live[l]
    }
}

impl<const L: usize> Stages<L> {
    /// Every lane's plain step stage by stage (each stage one run of the field's tape over
    /// the lanes): the ends and their derivatives into `self.end` and `self.dx`; returns
    /// each lane's mode bits seen to differ from its mode, and whether it collided. `at`:
    /// the grid times of the step's middle and end, if every lane's are the same.
    #[allow(clippy::too_many_arguments)]
    fn step(
        &mut self,
        dim: usize,
        eval: &mut EquationLanes<L>,
        times: &LaneTimes<L>,
        [at_half, at_end]: [Option<GridTime>; 2],
        x: &LaneVectors<L>,
        k1: &LaneVectors<L>,
        mode: &[Mode; L],
    ) -> ([Mode; L], [bool; L]) {
        let Stages {
            y,
            k2,
            k3,
            k4,
            end,
            dx,
            ..
        } = self;
        let LaneTimes { h, t_half, t_end } = times;
        for i in 0..dim {
            for l in 0..L {
                y[i][l] = x[i][l] + 0.5 * h[l] * k1[i][l];
            }
        }
        let mut seen = eval.field(t_half, at_half, y, mode, k2);
        let mut seen_diff: [Mode; L] = std::array::from_fn(|l| seen[l] ^ mode[l]);
        for i in 0..dim {
            for l in 0..L {
                y[i][l] = x[i][l] + 0.5 * h[l] * k2[i][l];
            }
        }
        seen = eval.field(t_half, at_half, y, mode, k3);
        (0..L).for_each(|l| seen_diff[l] |= seen[l] ^ mode[l]);
        for i in 0..dim {
            for l in 0..L {
                y[i][l] = x[i][l] + h[l] * k3[i][l];
            }
        }
        seen = eval.field(t_end, at_end, y, mode, k4);
        (0..L).for_each(|l| seen_diff[l] |= seen[l] ^ mode[l]);
        for i in 0..dim {
            for l in 0..L {
                end[i][l] =
                    x[i][l] + h[l] / 6.0 * (k1[i][l] + 2.0 * (k2[i][l] + k3[i][l]) + k4[i][l]);
            }
        }
        seen = eval.field(t_end, at_end, end, mode, dx);
        (0..L).for_each(|l| seen_diff[l] |= seen[l] ^ mode[l]);
        (seen_diff, eval.collided(t_end, end))
    }
}

impl GeneralRk4 {
    /// Starts lane `l` at `x0`, τ = 0 on its clock.
    pub fn restart_lane<const L: usize>(
        &self,
        sys: &mut EquationSystem,
        lanes: &mut Lanes<L>,
        l: usize,
        x0: &Vector,
    ) {
        let traj = self.start(sys, &x0[..sys.dim()]);
        lanes.set_lane(l, traj);
    }

    /// Leaves lane `l` without a trajectory (parked where it is, or at `rest`).
    pub fn park_lane<const L: usize>(&self, lanes: &mut Lanes<L>, l: usize, rest: &Vector) {
        let mut traj = Trajectory::parked();
        traj.x = *rest;
        lanes.set_lane(l, traj);
        lanes.live[l] = false;
    }

    /// One step of every running lane, in the version compiled for this process's
    /// instruction set ([`isa::chosen`]): the same bits in each.
    #[inline]
    pub fn advance_lanes<const L: usize>(
        &self,
        sys: &mut EquationSystem,
        eval: &mut EquationLanes<L>,
        lanes: &mut Lanes<L>,
    ) {
        match isa::chosen() {
            // SAFETY: the chosen instruction set is one this CPU has (a v4 CPU has v3's
            // instructions; the bookkeeping has no AVX-512 version of its own)
            #[cfg(target_arch = "x86_64")]
            Isa::X86_64V3 | Isa::X86_64V4 => unsafe { self.advance_lanes_v3(sys, eval, lanes) },
            _ => self.advance_lanes_body(sys, eval, lanes),
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe,f16c")]
    fn advance_lanes_v3<const L: usize>(
        &self,
        sys: &mut EquationSystem,
        eval: &mut EquationLanes<L>,
        lanes: &mut Lanes<L>,
    ) {
        self.advance_lanes_body(sys, eval, lanes);
    }

    /// The one body of every version of [`Self::advance_lanes`]: the lanes' bookkeeping
    /// around the compiled step, lane by lane without a branch, so that it is compiled to
    /// the instruction set's vectors.
    #[inline(always)]
    fn advance_lanes_body<const L: usize>(
        &self,
        sys: &mut EquationSystem,
        eval: &mut EquationLanes<L>,
        lanes: &mut Lanes<L>,
    ) {
        eval.follow_table(sys);
        let dim = sys.dim();
        let mask = sys.switch_mask();
        // τ = steps·h at the step's ends, as the scalar integrator's `tau`
        let t: [f64; L] = std::array::from_fn(|l| lanes.steps[l] * self.step());
        let h: [f64; L] = std::array::from_fn(|l| (lanes.steps[l] + 1.0) * self.step() - t[l]);
        let mut stages = lanes.stages.take().expect("stages between steps");
        let (x, k1, mode) = (&lanes.x, &lanes.dx, &lanes.mode);
        let times = LaneTimes {
            h,
            t_half: std::array::from_fn(|l| t[l] + 0.5 * h[l]),
            t_end: std::array::from_fn(|l| t[l] + h[l]),
        };
        let running = lanes.live;
        let shared = Self::shared_phase(lanes, &running);
        #[cfg(target_arch = "x86_64")]
        let compiled = match shared {
            // (not a closure: one would be compiled apart, for the baseline)
            Some(phase) => {
                let n = self.steps_per_period();
                let Stages {
                    end,
                    dx,
                    switching,
                    at_start,
                    ..
                } = &mut *stages;
                let switching = &mut switching[1 - *at_start];
                eval.compiled_step(phase, n, &times, x, k1, mode, end, dx, switching)
            }
            None => None,
        };
        #[cfg(not(target_arch = "x86_64"))]
        let compiled = None;
        // the mode bits each lane's end saw, where the compiled step gave its switching values
        let (seen_diff, hit, end_seen) = match compiled {
            Some((seen_diff, hit, end_seen)) => (seen_diff, hit, Some(end_seen)),
            None => {
                let n = self.steps_per_period();
                let at = [1, 2].map(|s| shared.map(|p| GridTime::in_step(p, s, n)));
                let (seen_diff, hit) = stages.step(dim, eval, &times, at, x, k1, mode);
                (seen_diff, hit, None)
            }
        };
        let Stages {
            end,
            dx,
            switching: [at_0, at_1],
            at_start,
            ..
        } = &*stages;
        let (at_start, at_end) = if *at_start == 0 {
            (at_0, at_1)
        } else {
            (at_1, at_0)
        };
        // which lanes' ends are finite, row by row as the step wrote them: v·0 is 0 where v
        // is finite and NaN where it is not
        let mut stray = [0.0; L];
        for i in 0..dim {
            for l in 0..L {
                stray[l] += end[i][l] * 0.0 + dx[i][l] * 0.0;
            }
        }
        let finite: [bool; L] = std::array::from_fn(|l| stray[l] == 0.0);
        // the lanes that take their step as it is; the others (a switch in the step, or a
        // value to explain) are redone alone. Written without a branch per lane: every
        // lane's operation is the same, and the rare lanes are visited after.
        let plain: [bool; L] =
            std::array::from_fn(|l| running[l] & (seen_diff[l] & mask == 0) & finite[l]);
        let collided = any_lane::<L>(&std::array::from_fn(|l| plain[l] & hit[l]));
        let redone = any_lane::<L>(&std::array::from_fn(|l| running[l] & !plain[l]));
        if collided {
            for l in (0..L).filter(|&l| plain[l] && hit[l]) {
                // located within the step, from its start
                let lane = |v: &[[f64; L]; MAX_DIM]| -> Vector { std::array::from_fn(|i| v[i][l]) };
                lanes.stop[l] = Some(super::general::collision_in_step(
                    sys,
                    [t[l], times.t_end[l]],
                    [&lane(&lanes.x), &lane(&lanes.dx)],
                    [&lane(end), &lane(dx)],
                ));
                lanes.live[l] = false;
            }
        }
        for i in 0..dim {
            take_lanes(&mut lanes.x[i], &end[i], &plain);
            take_lanes(&mut lanes.dx[i], &dx[i], &plain);
        }
        let n = self.steps_per_period();
        // indexed rather than zipped: zipped, these loops cost 2.6 % more instructions in all
        #[allow(clippy::needless_range_loop)]
        for l in 0..L {
            lanes.steps[l] += if plain[l] { 1.0 } else { 0.0 };
            let next = lanes.phase[l] + 1;
            let next = if next == n { 0 } else { next };
            lanes.phase[l] = if plain[l] { next } else { lanes.phase[l] };
        }
        if redone {
            for l in (0..L).filter(|&l| running[l] && !plain[l]) {
                // the scalar integrator, from this trial
                let mut traj = lanes.lane(l);
                let trial = Trial {
                    x: std::array::from_fn(|i| end[i][l]),
                    dx: std::array::from_fn(|i| dx[i][l]),
                    seen: lanes.mode[l] ^ seen_diff[l],
                    finite: finite[l],
                    switching: end_seen.map(|seen| EndSwitching {
                        s: std::array::from_fn(|k| at_end[k][l]),
                        seen: seen[l],
                    }),
                    // on the same piece: the mode bits they show are the lane's mode
                    start_switching: lanes.start_known[l].then(|| EndSwitching {
                        s: std::array::from_fn(|k| at_start[k][l]),
                        seen: lanes.mode[l],
                    }),
                };
                self.advance_step_after(sys, &mut traj, Some(&trial));
                lanes.set_lane(l, traj);
            }
        }
        // the compiled step's values at its end are at the plain lanes' starts now
        if end_seen.is_some() {
            lanes.start_known = plain;
            stages.at_start = 1 - stages.at_start;
        } else {
            lanes.start_known = [false; L];
        }
        lanes.stages = Some(stages);
    }

    /// The step of its period every `running` lane is at, if they agree (their clocks then
    /// differ by whole periods: one row of a time table serves them all) and their step
    /// counts are within what a time table looks up.
    #[inline(always)]
    fn shared_phase<const L: usize>(lanes: &Lanes<L>, running: &[bool; L]) -> Option<usize> {
        let first = (0..L).find(|&l| running[l])?;
        let phase = lanes.phase[first];
        let mut agree = true;
        #[allow(clippy::needless_range_loop)]
        for l in 0..L {
            let counted = lanes.steps[l] < MAX_COUNTED_STEPS as f64;
            agree &= !running[l] | (lanes.phase[l] == phase) & counted;
        }
        agree.then_some(phase)
    }
}

/// Whether any lane is marked, eight lanes' bytes to a word.
#[inline(always)]
fn any_lane<const L: usize>(marked: &[bool; L]) -> bool {
    let bytes = marked.map(u8::from);
    let (words, rest) = bytes.as_chunks::<8>();
    let mut any = rest.iter().fold(0, |any, &b| any | b) as u64;
    for w in words {
        any |= u64::from_ne_bytes(*w);
    }
    any != 0
}

/// `to` takes `from`'s values in the lanes `take` marks (a blend, without a branch).
#[inline(always)]
fn take_lanes<const L: usize>(to: &mut [f64; L], from: &[f64; L], take: &[bool; L]) {
    for l in 0..L {
        let mask = u64::from(take[l]).wrapping_neg(); // all ones where taken
        to[l] = f64::from_bits(from[l].to_bits() & mask | to[l].to_bits() & !mask);
    }
}
