//! Fixed-step RK4 for any [`System`]: the step h = T/n divides the forcing period, and a step
//! in which a switching function changes sign is split where it does, each side integrated
//! on its own smooth piece. This keeps fourth order on models with kinks (MODEL.md §4b)
//! without the model naming them: they are the arguments of its `max`, `min`, `abs`, `if`.

use super::resolution::Resolution;
use crate::model::system::{END_SWITCHES, EndSwitching, GridStep, MAX_DIM, Mode, System, Vector};

/// Most switching functions (the bits of a mode).
const MAX_SWITCHES: usize = 64;
/// Switching functions a switch's probes hold when the model's varying ones are all among
/// the first this many (probes of all [`MAX_SWITCHES`] are copied at 8 times the cost).
const FEW_SWITCHES: usize = 8;
/// Most switches handled inside one step before the rest of it is taken as it is.
const MAX_SWITCHES_PER_STEP: usize = 6;
/// Width, as a fraction of the step, below which a switch's bracket on real sub-steps is
/// located.
const ROOT_TOLERANCE: f64 = 1e-13;
/// The same on the step's interpolant, whose own error (about h⁴) is larger anyway.
const INTERPOLANT_TOLERANCE: f64 = 1e-9;
/// How far past the real switching function's Newton estimate the sub-step aims, as a
/// fraction of the step, so that it ends across (the state error is of its square).
const NEWTON_MARGIN: f64 = 1e-9;
/// For a switch across which the field is continuous: the width of its bracket on the
/// interpolant, and how far past the estimate the sub-step aims (so that it mostly ends
/// across at once), as a fraction δ of the sub-step h, at most h^1.5. Past the switch by
/// δ·h, the sub-step errs by about (δ·h)² ≤ h⁵ times the jump in the field's rate: below
/// the step's own error, so fourth order holds (for h = 0.007, δ·h = 7e-9 and
/// (δ·h)² = 5e-17 against h⁵ = 2e-11).
const CONTINUOUS_TOLERANCE: f64 = 1e-6;
/// How little an estimate of a continuous switch on the step's interpolant must move, as a
/// fraction of the step, for the next to be taken: that one is then good to about the move's
/// square (the steps converge superlinearly), far less than the sub-step's aim past it.
const CONVERGED: f64 = 1e-6;
/// Probes of the step's interpolant spent estimating a continuous switch at most, before it
/// is bracketed instead.
const MAX_ESTIMATES: usize = 4;
/// Bisection-safeguarded iterations spent locating one switch at most.
const MAX_ROOT_ITERATIONS: usize = 60;
/// Steps beyond which a trajectory's stage times are left to the forcing's table to place
/// (it looks up times up to 10¹⁵ half-steps; far beyond any run).
pub(super) const MAX_COUNTED_STEPS: u64 = 1 << 40;
/// Fractions of a step tried when only an intermediate stage saw a switch.
const SCAN: [f64; 3] = [0.25, 0.5, 0.75];

/// Why a trajectory stopped.
#[derive(Debug, Clone, PartialEq)]
pub enum Stop {
    /// It met one of the model's collision conditions first at τ, in the state there
    /// (located within the step that met it).
    Collision { tau: f64, state: Vector },
    /// A value stopped being finite: at τ, from `state`, in the named expression if known.
    NonFinite {
        tau: f64,
        state: Vector,
        expression: Option<String>,
    },
}

/// One trajectory of a [`System`].
#[derive(Debug, Clone)]
pub struct Trajectory {
    /// The state at τ = `steps`·h.
    pub x: Vector,
    /// dx/dτ there, on `mode` (the first stage of the next step).
    pub(super) dx: Vector,
    /// The smooth piece in force.
    pub mode: Mode,
    /// Steps taken from τ = 0.
    pub steps: u64,
    /// The step within the forcing period it is at (`steps` modulo the period's).
    pub(super) phase: usize,
    /// Set once the trajectory has stopped; it is then frozen.
    pub stop: Option<Stop>,
}

impl Trajectory {
    /// A trajectory that holds nothing yet (all zeros, at τ = 0).
    pub(super) fn parked() -> Trajectory {
        Trajectory {
            x: [0.0; MAX_DIM],
            dx: [0.0; MAX_DIM],
            mode: 0,
            steps: 0,
            phase: 0,
            stop: None,
        }
    }
}

/// The general fixed-step integrator at one step length.
#[derive(Debug, Clone, Copy)]
pub struct GeneralRk4 {
    n: usize,
    h: f64,
}

impl GeneralRk4 {
    /// An integrator for `sys`'s period, with the step count from `resolution`.
    pub fn new(sys: &impl System, resolution: &Resolution) -> Self {
        Self::with_steps(sys, resolution.steps_for(sys.period()))
    }

    /// Exactly `n` steps per forcing period.
    pub fn with_steps(sys: &impl System, n: usize) -> Self {
        let n = n.max(1);
        GeneralRk4 {
            n,
            h: sys.period() / n as f64,
        }
    }

    pub fn steps_per_period(&self) -> usize {
        self.n
    }

    /// Step length h = T/n.
    pub fn step(&self) -> f64 {
        self.h
    }

    /// τ after `steps` steps.
    pub fn tau(&self, steps: u64) -> f64 {
        steps as f64 * self.h
    }

    /// The step after `steps` steps, at step `phase` of the period (`steps` modulo the
    /// period's steps, as a trajectory keeps it): its times.
    pub fn grid_step(&self, steps: u64, phase: usize) -> GridStep {
        let (t, t_end) = (self.tau(steps), self.tau(steps + 1));
        let h = t_end - t;
        GridStep {
            phase,
            steps_per_period: self.n,
            h,
            t_half: t + 0.5 * h,
            t_end,
        }
    }

    /// A trajectory from `x0` at τ = 0 (stopped at once if `x0` is outside the model).
    pub fn start<S: System>(&self, sys: &mut S, x0: &[f64]) -> Trajectory {
        self.start_at(sys, x0, 0)
    }

    /// A trajectory from `x0` at τ = `steps`·h (its piece found there afresh).
    pub fn start_at<S: System>(&self, sys: &mut S, x0: &[f64], steps: u64) -> Trajectory {
        sys.tabulate(self.n);
        let mut x = [0.0; MAX_DIM];
        x[..x0.len()].copy_from_slice(x0);
        let tau = self.tau(steps);
        let mut traj = Trajectory {
            x,
            dx: [0.0; MAX_DIM],
            mode: 0,
            steps,
            phase: (steps % self.n as u64) as usize,
            stop: None,
        };
        if x0.iter().any(|v| !v.is_finite()) {
            traj.stop = Some(self.non_finite(sys, tau, &x));
            return traj;
        }
        if sys.collided(tau, &x) {
            traj.stop = Some(collision(sys, tau, &x));
            return traj;
        }
        traj.mode = sys.mode_at(tau, &x) & sys.switch_mask();
        sys.field(tau, &x, traj.mode, &mut traj.dx);
        if traj.dx.iter().any(|v| !v.is_finite()) {
            traj.stop = Some(self.non_finite(sys, tau, &x));
        }
        traj
    }

    /// Advances `n` steps (one forcing period); `each_step(sys, before, after)` sees each
    /// step's ends. Stops early when the trajectory stops.
    pub fn advance_period<S: System>(
        &self,
        sys: &mut S,
        traj: &mut Trajectory,
        mut each_step: impl FnMut(&mut S, &StepEnd, &StepEnd),
    ) {
        for _ in 0..self.n {
            if traj.stop.is_some() {
                return;
            }
            let before = StepEnd::of(self, traj);
            self.advance_step(sys, traj);
            if traj.stop.is_none() {
                each_step(sys, &before, &StepEnd::of(self, traj));
            }
        }
    }

    /// One step h, split at every switch inside it.
    pub fn advance_step<S: System>(&self, sys: &mut S, traj: &mut Trajectory) {
        self.advance_step_after(sys, traj, None);
    }

    /// [`Self::advance_step`], given the step's plain trial if it was taken already.
    pub(super) fn advance_step_after<S: System>(
        &self,
        sys: &mut S,
        traj: &mut Trajectory,
        first: Option<&Trial>,
    ) {
        if traj.stop.is_some() {
            return;
        }
        if first.is_none() && traj.steps < MAX_COUNTED_STEPS {
            let mask = sys.switch_mask();
            // the model's compiled step, taken as it is where it stays on its piece
            let step = self.grid_step(traj.steps, traj.phase);
            let (t, t_end) = (self.tau(traj.steps), step.t_end);
            let (mut end, mut dx) = ([0.0; MAX_DIM], [0.0; MAX_DIM]);
            if let Some((seen_diff, collided, switching)) =
                sys.compiled_step(&step, &traj.x, &traj.dx, traj.mode, &mut end, &mut dx)
            {
                let dim = sys.dim();
                let finite = end[..dim].iter().chain(&dx[..dim]).all(|v| v.is_finite());
                if seen_diff & mask == 0 && finite {
                    self.count_step(traj);
                    if collided {
                        traj.stop = Some(collision_in_step(
                            sys,
                            [t, t_end],
                            [&traj.x, &traj.dx],
                            [&end, &dx],
                        ));
                    }
                    (traj.x, traj.dx) = (end, dx);
                    return;
                }
                let trial = Trial {
                    x: end,
                    dx,
                    seen: traj.mode ^ seen_diff,
                    finite,
                    switching: Some(switching),
                    start_switching: None,
                };
                return self.split_step(sys, traj, Some(&trial));
            }
        }
        self.split_step(sys, traj, first);
    }

    /// [`Self::advance_step_after`] stage by stage, and where a switch is met (out of line:
    /// its probes take a large frame the plain steps need not set up).
    #[inline(never)]
    fn split_step<S: System>(&self, sys: &mut S, traj: &mut Trajectory, mut first: Option<&Trial>) {
        let mask = sys.switch_mask();
        let t_end = self.tau(traj.steps + 1);
        let mut t = self.tau(traj.steps);
        let (mut x, mut dx, mut mode) = (traj.x, traj.dx, traj.mode);
        let dim = sys.dim();
        // the start of the step's last smooth piece: where a collision met at its end is
        // located
        let mut piece = (t, x, dx);
        for _ in 0..MAX_SWITCHES_PER_STEP {
            piece = (t, x, dx);
            let rem = t_end - t;
            let made;
            let trial = match first.take() {
                Some(trial) => trial,
                None => {
                    made = rk4(sys, dim, t, &x, &dx, rem, mode, true);
                    &made
                }
            };
            if trial.seen & mask == mode & mask && trial.finite {
                (x, dx) = (trial.x, trial.dx);
                t = t_end;
                break;
            }
            let located = if mask >> FEW_SWITCHES == 0 {
                self.locate::<S, FEW_SWITCHES>(sys, dim, t, &x, &dx, rem, mode, mask, trial)
            } else {
                self.locate::<S, MAX_SWITCHES>(sys, dim, t, &x, &dx, rem, mode, mask, trial)
            };
            match located {
                Some((theta, flipped, at)) => {
                    t += theta * rem;
                    x = at;
                    mode ^= flipped;
                    sys.field(t, &x, mode, &mut dx);
                }
                None if trial.finite => {
                    // only a stage strayed across: the trajectory itself stays on this piece
                    (x, dx) = (trial.x, trial.dx);
                    t = t_end;
                    break;
                }
                None => {
                    traj.stop = Some(self.non_finite_ahead(sys, t, &x, &dx, rem, mode));
                    return;
                }
            }
        }
        if t < t_end {
            // more switches than handled: the rest of the step as it is
            piece = (t, x, dx);
            let trial = rk4(sys, dim, t, &x, &dx, t_end - t, mode, true);
            (x, dx) = (trial.x, trial.dx);
            mode = sys.mode_at(t_end, &x) & mask;
            sys.field(t_end, &x, mode, &mut dx);
        }
        self.count_step(traj);
        traj.x = x;
        traj.dx = dx;
        traj.mode = mode;
        if x.iter().chain(&dx).any(|v| !v.is_finite()) {
            traj.stop = Some(self.non_finite(sys, t_end, &x));
        } else if sys.collided(t_end, &x) {
            let (t0, x0, f0) = piece;
            traj.stop = Some(collision_in_step(sys, [t0, t_end], [&x0, &f0], [&x, &dx]));
        }
    }

    /// The first switch within the trial step `trial` of length `rem` from (t, x): the
    /// fraction θ of the step just past it, the mode bits that flip there, and the state
    /// there. None if the trajectory stays on this piece (only a stage strayed across).
    ///
    /// The switch is located on the step's cubic Hermite interpolant (one evaluation of the
    /// switching functions per estimate; its O(h⁴) error moves the switch by far less than
    /// the step's own error): estimated by [`converge`] where one continuous switch alone
    /// was seen, else bracketed. Then the state is taken by a real sub-step to just past it,
    /// located on real sub-steps where the interpolant crossed early.
    #[allow(clippy::too_many_arguments)]
    fn locate<S: System, const N: usize>(
        &self,
        sys: &mut S,
        dim: usize,
        t: f64,
        x: &Vector,
        dx: &Vector,
        rem: f64,
        mode: Mode,
        mask: Mode,
        trial: &Trial,
    ) -> Option<(f64, Mode, Vector)> {
        let at = |sys: &mut S, theta: f64, end: Vector| -> Probe<N> {
            let mut s = [0.0; N];
            let seen = sys.switching(t + theta * rem, &end, mode, &mut s) & mask;
            let finite = end[..dim].iter().all(|v| v.is_finite());
            let crossed = if finite {
                seen ^ (mode & mask)
            } else {
                mask | 1
            };
            Probe {
                theta,
                end,
                s,
                crossed,
                finite,
            }
        };
        let real = |sys: &mut S, theta: f64| {
            let end = rk4(sys, dim, t, x, dx, theta * rem, mode, false).x;
            at(sys, theta, end)
        };
        let continuous = sys.continuous_switches();
        let loose = CONTINUOUS_TOLERANCE.min(rem * rem.sqrt());
        // how close the interpolant's estimate must be, and how far past it to aim, given
        // the switches crossed at its end
        let tolerance = |hi: &Probe<N>| {
            if hi.finite && hi.crossed & !continuous == 0 {
                loose
            } else {
                INTERPOLANT_TOLERANCE
            }
        };
        // what `at` would find at θ where compiled code gave the values there: the step
        // before's end (the start), the trial's own end
        let given = |theta: f64, end: Vector, given: &EndSwitching| -> Probe<N> {
            let mut s = [0.0; N];
            s.copy_from_slice(&given.s[..N]);
            Probe {
                theta,
                end,
                s,
                crossed: (given.seen ^ mode) & mask,
                finite: true,
            }
        };
        let start = match &trial.start_switching {
            Some(values) if N <= END_SWITCHES => given(0.0, *x, values),
            _ => at(sys, 0.0, *x),
        };
        if !trial.finite {
            // no interpolant to trust: bisect on real sub-steps to where values stop being
            // finite or the piece changes
            let hi = real(sys, 1.0);
            let (_, hi) = bracket(sys, &real, start, hi, |_| ROOT_TOLERANCE);
            return (hi.finite && hi.crossed != 0).then_some((hi.theta, hi.crossed, hi.end));
        }
        let interpolated = |sys: &mut S, theta: f64| {
            at(
                sys,
                theta,
                hermite_state(dim, x, dx, &trial.x, &trial.dx, rem, theta),
            )
        };
        let end = match &trial.switching {
            Some(values) if N <= END_SWITCHES => given(1.0, trial.x, values),
            _ => at(sys, 1.0, trial.x),
        };
        // the first switch on the interpolant: its estimate (a fraction of the step), the
        // switch, its switching function's slope there and how far past it to aim. Where one
        // continuous switch alone was seen, its estimate once it settles (some three probes);
        // else a bracket to the tolerance's width (some five)
        let seen = (trial.seen ^ mode) & mask;
        let k = end.crossed.trailing_zeros() as usize;
        let alone = end.crossed.is_power_of_two() && seen == end.crossed && k < N;
        let from_secants = if alone && end.finite && end.crossed & continuous != 0 {
            converge(sys, &interpolated, &start, &end, k, CONVERGED)
        } else {
            None
        };
        let (estimate, k, slope, margin) = match from_secants {
            Some((theta, slope)) => (theta, k, slope, tolerance(&end).max(NEWTON_MARGIN)),
            None => {
                let mut hi = end.clone();
                if hi.crossed == 0 {
                    hi = SCAN
                        .iter()
                        .map(|&theta| interpolated(sys, theta))
                        .find(|p| p.crossed != 0)?;
                }
                let (lo, hi) = bracket(sys, &interpolated, start, hi, tolerance);
                let k = hi.crossed.trailing_zeros() as usize;
                let slope = (hi.s[k] - lo.s[k]) / (hi.theta - lo.theta);
                (hi.theta, k, slope, tolerance(&hi).max(NEWTON_MARGIN))
            }
        };
        // a real sub-step to the estimate (past a continuous switch's by its tolerance): past
        // the switch by at most the estimate's error (a state error of its square), or else
        // one Newton step on the real switching function with the estimate's slope
        let aim = if margin > NEWTON_MARGIN {
            (estimate + margin).min(1.0)
        } else {
            estimate
        };
        let mut past = real(sys, aim);
        if past.crossed == 0 && slope.is_finite() && slope != 0.0 {
            let theta = past.theta - past.s[k] / slope + margin;
            if theta > past.theta && theta <= 1.0 {
                let next = real(sys, theta);
                if next.crossed != 0 {
                    return Some((next.theta, next.crossed, next.end));
                }
                past = next;
            }
        }
        if past.crossed != 0 {
            return Some((past.theta, past.crossed, past.end));
        }
        // the interpolant crossed early by more: bracket on real sub-steps up to the end
        if end.crossed == 0 {
            return None;
        }
        let (_, past) = bracket(sys, &real, past, end, |_| ROOT_TOLERANCE);
        Some((past.theta, past.crossed, past.end))
    }

    /// One more step on `traj`'s clock.
    fn count_step(&self, traj: &mut Trajectory) {
        traj.steps += 1;
        traj.phase = self.next_phase(traj.phase);
    }

    /// The step within the period after step `phase`.
    pub(super) fn next_phase(&self, phase: usize) -> usize {
        if phase + 1 == self.n { 0 } else { phase + 1 }
    }

    /// [`Self::non_finite`] for a step from (τ, x) whose values stop being finite within it:
    /// where every value at x is finite, the expression that is not is named where the step
    /// heads (x + θ·rem·dx for θ = ¼, ½, 1, on the step's piece, then on the one it is on).
    fn non_finite_ahead<S: System>(
        &self,
        sys: &mut S,
        tau: f64,
        x: &Vector,
        dx: &Vector,
        rem: f64,
        mode: Mode,
    ) -> Stop {
        let stop = self.non_finite(sys, tau, x);
        if !matches!(
            stop,
            Stop::NonFinite {
                expression: None,
                ..
            }
        ) {
            return stop;
        }
        let dim = sys.dim();
        for theta in [0.25, 0.5, 1.0] {
            let t = tau + theta * rem;
            let mut ahead = *x;
            for i in 0..dim {
                ahead[i] += theta * rem * dx[i];
            }
            let mut f = [0.0; MAX_DIM];
            sys.field(t, &ahead, mode, &mut f);
            if f[..dim].iter().all(|v| v.is_finite()) {
                continue;
            }
            if let Some(expression) = sys.explain_non_finite(t, &ahead) {
                let at = sys
                    .state_names()
                    .iter()
                    .zip(&ahead)
                    .map(|(name, v)| format!("{name} = {v:.6}"))
                    .collect::<Vec<_>>()
                    .join(", ");
                return Stop::NonFinite {
                    tau,
                    state: *x,
                    expression: Some(format!(
                        "{expression} where the step from there heads (τ = {t:.6}, {at}): the \
                         orbit leaves the model's domain"
                    )),
                };
            }
        }
        stop
    }

    fn non_finite<S: System>(&self, sys: &mut S, tau: f64, x: &Vector) -> Stop {
        Stop::NonFinite {
            tau,
            state: *x,
            expression: sys.explain_non_finite(tau, x),
        }
    }
}

/// How a trajectory its collision conditions stopped at (τ, x) ends: a collision, or a value
/// that is not finite where a condition has no truth value.
pub(super) fn collision<S: System>(sys: &mut S, tau: f64, x: &Vector) -> Stop {
    match sys.undefined_collision(tau, x) {
        Some(expression) => Stop::NonFinite {
            tau,
            state: *x,
            expression: Some(expression),
        },
        None => Stop::Collision { tau, state: *x },
    }
}

/// Where a step from (τ0, x0, f0) to (τ1, x1, f1) that ends on a collision first meets one:
/// bisection of the step's cubic Hermite interpolant (its error about h⁴, as the step's own)
/// to round-off in τ, the step's start being clear of them all; the collision there, as
/// [`collision`] ends a trajectory.
pub(super) fn collision_in_step<S: System>(
    sys: &mut S,
    [t0, t1]: [f64; 2],
    [x0, f0]: [&Vector; 2],
    [x1, f1]: [&Vector; 2],
) -> Stop {
    let (dim, h) = (sys.dim(), t1 - t0);
    let at = |theta| hermite_state(dim, x0, f0, x1, f1, h, theta);
    let theta = super::hermite::first_where(|theta| sys.collided(t0 + theta * h, &at(theta)));
    collision(sys, t0 + theta * h, &at(theta))
}

/// A step's end as the recording callbacks see it.
#[derive(Debug, Clone, Copy)]
pub struct StepEnd {
    pub tau: f64,
    pub x: Vector,
    pub mode: Mode,
}

impl StepEnd {
    fn of(rk: &GeneralRk4, traj: &Trajectory) -> StepEnd {
        StepEnd {
            tau: rk.tau(traj.steps),
            x: traj.x,
            mode: traj.mode,
        }
    }
}

/// The first switch in a step where switching function `k` alone changed sign, from its
/// values at `start` and `end` (on this piece at the one, across at the other): secant, then
/// inverse quadratic estimates through the last three probes, kept inside the bracket, until
/// one moves less than `tolerance`. The estimate and the switching function's slope there (by
/// the last two probes); `None` if another switch or a value that is not finite shows first,
/// or it does not settle within [`MAX_ESTIMATES`] probes.
fn converge<S: System, const N: usize>(
    sys: &mut S,
    probe: &impl Fn(&mut S, f64) -> Probe<N>,
    start: &Probe<N>,
    end: &Probe<N>,
    k: usize,
    tolerance: f64,
) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = ((start.theta, start.s[k]), (end.theta, end.s[k]));
    let secant = |(a, fa): (f64, f64), (b, fb): (f64, f64)| a - fa * (b - a) / (fb - fa);
    let mut theta = secant(lo, hi);
    for _ in 0..MAX_ESTIMATES {
        let p = probe(sys, theta);
        if !p.finite || p.crossed & !(1 << k) != 0 {
            return None;
        }
        let here = (theta, p.s[k]);
        let dropped = if p.crossed != 0 {
            std::mem::replace(&mut hi, here)
        } else {
            std::mem::replace(&mut lo, here)
        };
        let next = inverse_quadratic(lo, hi, dropped)
            .filter(|&next| next > lo.0 && next < hi.0)
            .unwrap_or_else(|| secant(lo, hi));
        if (next - theta).abs() < tolerance {
            let slope = (here.1 - dropped.1) / (here.0 - dropped.0);
            return Some((next, slope));
        }
        theta = next;
    }
    None
}

/// The root of the quadratic in f through three points (θ, f), if their values differ.
fn inverse_quadratic((a, fa): (f64, f64), (b, fb): (f64, f64), (c, fc): (f64, f64)) -> Option<f64> {
    let (ab, ac, bc) = (fa - fb, fa - fc, fb - fc);
    (ab != 0.0 && ac != 0.0 && bc != 0.0)
        .then(|| a * fb * fc / (ab * ac) - b * fa * fc / (ab * bc) + c * fa * fb / (ac * bc))
}

/// Narrows [`lo`, `hi`] (on this piece at `lo`, across at `hi`) around the first switch:
/// regula falsi with the Illinois weighting on the switch that crossed at `hi`, bisection
/// where a probe cannot say (a value that is not finite).
fn bracket<S: System, const N: usize>(
    sys: &mut S,
    probe: &impl Fn(&mut S, f64) -> Probe<N>,
    mut lo: Probe<N>,
    mut hi: Probe<N>,
    tolerance: impl Fn(&Probe<N>) -> f64,
) -> (Probe<N>, Probe<N>) {
    let mut weight = (1.0, 1.0);
    let mut last_side = 0i8;
    for _ in 0..MAX_ROOT_ITERATIONS {
        let width = hi.theta - lo.theta;
        if width <= tolerance(&hi) {
            break;
        }
        let theta = match hi.finite.then(|| hi.crossed.trailing_zeros() as usize) {
            Some(k) if k < N => {
                let (a, b) = (lo.s[k] * weight.0, hi.s[k] * weight.1);
                let guess = lo.theta + width * a / (a - b);
                if guess.is_finite() {
                    guess.clamp(lo.theta + 1e-3 * width, hi.theta - 1e-3 * width)
                } else {
                    0.5 * (lo.theta + hi.theta)
                }
            }
            _ => 0.5 * (lo.theta + hi.theta),
        };
        let p = probe(sys, theta);
        if p.crossed != 0 {
            if p.crossed.trailing_zeros() != hi.crossed.trailing_zeros() {
                weight = (1.0, 1.0);
                last_side = 0;
            }
            hi = p;
            weight.0 = if last_side == 1 { weight.0 * 0.5 } else { 1.0 };
            weight.1 = 1.0;
            last_side = 1;
        } else {
            lo = p;
            weight.1 = if last_side == -1 { weight.1 * 0.5 } else { 1.0 };
            weight.0 = 1.0;
            last_side = -1;
        }
    }
    (lo, hi)
}

/// The cubic Hermite interpolant of a step of length `h` from (x0, f0) to (x1, f1), at the
/// fraction θ of the step.
fn hermite_state(
    dim: usize,
    x0: &Vector,
    f0: &Vector,
    x1: &Vector,
    f1: &Vector,
    h: f64,
    theta: f64,
) -> Vector {
    let mut x = [0.0; MAX_DIM];
    for i in 0..dim {
        x[i] = super::hermite::value(x0[i], f0[i], x1[i], f1[i], h, theta);
    }
    x
}

/// A sub-step's end while a switch is located.
#[derive(Clone)]
struct Probe<const N: usize> {
    theta: f64,
    end: Vector,
    /// The switching functions there, on the step's piece.
    s: [f64; N],
    /// Mode bits that differ there from the step's piece (all, where the end is not finite).
    crossed: Mode,
    finite: bool,
}

/// A trial RK4 step: the end state, its derivative on the same piece, and the modes the
/// stages and the end saw (or-ed).
pub(super) struct Trial {
    pub x: Vector,
    pub dx: Vector,
    /// The step's mode with every bit a stage or the end saw differ flipped.
    pub seen: Mode,
    pub finite: bool,
    /// The switching functions at the end, where the model's compiled step gave them.
    pub switching: Option<EndSwitching>,
    /// The switching functions at the start, where the step before gave them: the end of a
    /// plain compiled step, on the same piece (the mode bits they show are the piece's).
    pub start_switching: Option<EndSwitching>,
}

/// One stage: dx/dτ at (t, y) held on `mode`, and the mode y is on. Where y has strayed off
/// `mode`'s piece to where that piece is not defined (the branch not taken of
/// `if(x < 2, sqrt(2 - x), 0)` past x = 2), the stage takes the piece y is on: the step
/// crosses a switch there, and is located as any other.
#[inline]
fn stage<S: System>(
    sys: &mut S,
    dim: usize,
    t: f64,
    y: &Vector,
    mode: Mode,
    k: &mut Vector,
) -> Mode {
    let seen = sys.field(t, y, mode, k);
    if seen != mode && k[..dim].iter().any(|v| !v.is_finite()) {
        sys.field(t, y, seen, k);
    }
    seen
}

/// One RK4 step of length `h` from (t, x) with first stage `k1`, held on `mode`; with
/// `with_end`, the derivative at its end too.
#[allow(clippy::too_many_arguments)]
#[inline]
fn rk4<S: System>(
    sys: &mut S,
    dim: usize,
    t: f64,
    x: &Vector,
    k1: &Vector,
    h: f64,
    mode: Mode,
    with_end: bool,
) -> Trial {
    let mut y = [0.0; MAX_DIM];
    let (mut k2, mut k3, mut k4) = ([0.0; MAX_DIM], [0.0; MAX_DIM], [0.0; MAX_DIM]);
    for i in 0..dim {
        y[i] = x[i] + 0.5 * h * k1[i];
    }
    let mut seen_diff = stage(sys, dim, t + 0.5 * h, &y, mode, &mut k2) ^ mode;
    for i in 0..dim {
        y[i] = x[i] + 0.5 * h * k2[i];
    }
    seen_diff |= stage(sys, dim, t + 0.5 * h, &y, mode, &mut k3) ^ mode;
    for i in 0..dim {
        y[i] = x[i] + h * k3[i];
    }
    seen_diff |= stage(sys, dim, t + h, &y, mode, &mut k4) ^ mode;
    let mut end = [0.0; MAX_DIM];
    for i in 0..dim {
        end[i] = x[i] + h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
    }
    let mut dx = [0.0; MAX_DIM];
    if with_end {
        seen_diff |= stage(sys, dim, t + h, &end, mode, &mut dx) ^ mode;
    }
    let finite = end[..dim].iter().chain(&dx[..dim]).all(|v| v.is_finite());
    Trial {
        x: end,
        dx,
        seen: mode ^ seen_diff,
        finite,
        switching: None,
        start_switching: None,
    }
}
