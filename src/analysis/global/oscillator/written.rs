//! A model written in the session as an [`Oscillator`]: each trajectory on the general
//! engine ([`GeneralRk4`]) to full convergence, with the period test and the orbit record of
//! the built-in.

use std::sync::atomic::{AtomicBool, Ordering};

use super::Oscillator;
use crate::analysis::AnalysisError;
use crate::analysis::global::batch::{KnownAttractors, adopt, settled_cycle};
use crate::analysis::global::flow::Flow;
use crate::analysis::orbit::attractor::SAME_POINT_TOL;
use crate::analysis::orbit::period_detector::PeriodDetector;
use crate::analysis::orbit::period_map::OrbitRecord;
use crate::analysis::orbit::steady_state::{
    Class, SteadyState, SteadyStateSpec, collided, from_record,
};
use crate::analysis::parameter::ContinuationParameter;
use crate::model::ParamError;
use crate::model::equations::EquationSystem;
use crate::model::equations::lanes::EquationLanes;
use crate::model::equations::tape::FEW_LANES;
use crate::model::system::{MAX_DIM, StateVec, System, Vector};
use crate::solver::Collision;
use crate::solver::general::{GeneralRk4, Stop, Trajectory};
use crate::solver::general_lanes::Lanes;

/// The steady state of `sys` from `start` at τ = 0 (MODEL.md §4b's two-stage period test over
/// every state variable); `grid` names the two states its Poincaré points keep.
pub fn steady_state_of<S: System>(
    sys: &mut S,
    start: &Vector,
    grid: [usize; 2],
    spec: &SteadyStateSpec,
) -> Result<SteadyState, AnalysisError> {
    let rk = GeneralRk4::new(sys, &spec.resolution);
    let dim = sys.dim();
    let mut traj = rk.start(sys, &start[..dim]);
    let mut detector = spec.period_detector::<MAX_DIM>();
    if let Some(stop) = &traj.stop {
        return stopped(sys, stop, 0, grid);
    }
    while detector.periods() < spec.max_forcing_periods {
        rk.advance_period(sys, &mut traj, |_, _, _| {});
        if let Some(stop) = &traj.stop {
            return stopped(sys, stop, detector.periods() + 1, grid);
        }
        if let Some(k) = detector.push(traj.x) {
            return record(
                sys,
                &rk,
                &mut traj,
                k,
                detector.periods(),
                Class::Periodic,
                grid,
            );
        }
    }
    let (k, n) = (spec.max_period, spec.max_forcing_periods);
    record(sys, &rk, &mut traj, k, n, Class::NonPeriodic, grid)
}

/// Follows the response `k` more periods, recording its output, and builds the result.
fn record<S: System>(
    sys: &mut S,
    rk: &GeneralRk4,
    traj: &mut Trajectory,
    k: usize,
    n: usize,
    class: Class,
    grid: [usize; 2],
) -> Result<SteadyState, AnalysisError> {
    let h = rk.step();
    let dim = sys.dim();
    let mut rec = OrbitRecord::new(rk.steps_per_period());
    let (mut poincare, mut states) = (Vec::with_capacity(k), Vec::new());
    for _ in 0..k {
        rk.advance_period(sys, traj, |sys, before, after| {
            let (y0, rate0) = sys.output(before.tau, &before.x, before.mode);
            let (y1, rate1) = sys.output(after.tau, &after.x, after.mode);
            rec.add_step(y0, rate0, y1, rate1, h);
        });
        if let Some(stop) = &traj.stop {
            return stopped(sys, stop, n, grid);
        }
        poincare.push([traj.x[grid[0]], traj.x[grid[1]]]);
        if dim > 2 {
            states.push(traj.x[..dim].to_vec());
        }
    }
    let mut s = from_record(&rec, poincare, k, n, class);
    s.states = states;
    Ok(s)
}

/// A collision as a result; a value that is not finite as an error naming where.
fn stopped(
    sys: &impl System,
    stop: &Stop,
    periods: usize,
    grid: [usize; 2],
) -> Result<SteadyState, AnalysisError> {
    match stop {
        Stop::Collision { tau, state } => Ok(collided(
            Collision {
                tau: *tau,
                lambda_i: state[grid[0]],
            },
            periods,
        )),
        Stop::NonFinite {
            tau,
            state,
            expression,
        } => Err(AnalysisError::not_finite(sys, *tau, state, expression)),
    }
}

impl Oscillator for EquationSystem {
    type State = Vector;
    type Parameter = usize;

    fn frequency(&self) -> usize {
        self.model().frequency()
    }

    fn with(&self, parameter: usize, value: f64) -> Result<Self, ParamError> {
        let mut values = self.values().to_vec();
        values[parameter] = value;
        self.model().system(&values)
    }

    fn resolve(&self, parameter: ContinuationParameter) -> Result<usize, ParamError> {
        let model = self.model();
        let named = match parameter {
            ContinuationParameter::Omega => return Ok(model.frequency()),
            ContinuationParameter::Model(p) => p,
        };
        let name = named.name();
        model.parameter(name).ok_or_else(|| {
            let names: Vec<&str> = model.parameters().iter().map(|p| p.name.as_str()).collect();
            ParamError {
                field: format!("parameter `{name}`"),
                value: ParamError::NOT_NUMERIC,
                allowed: format!("one of the model's: {}", names.join(", ")),
            }
        })
    }

    fn value_of(&self, parameter: usize) -> f64 {
        self.values()[parameter]
    }

    fn state_vec(&self, state: &Vector) -> StateVec {
        StateVec::of(state, System::dim(self))
    }

    fn grid_start(&self, offset: [f64; 2]) -> Vector {
        let mut x = *self.origin();
        let [a, b] = self.model().grid();
        x[a] += offset[0];
        if b != a {
            x[b] += offset[1];
        }
        x
    }

    fn poincare_states(&self, s: &SteadyState) -> Vec<Vector> {
        if !s.states.is_empty() {
            return s
                .states
                .iter()
                .map(|state| {
                    let mut x = [0.0; MAX_DIM];
                    x[..state.len()].copy_from_slice(state);
                    x
                })
                .collect();
        }
        let [a, b] = self.model().grid();
        s.poincare
            .iter()
            .map(|p| {
                let mut x = *self.origin();
                (x[a], x[b]) = (p[0], p[1]);
                x
            })
            .collect()
    }

    fn steady_state(
        &self,
        start: Vector,
        spec: &SteadyStateSpec,
    ) -> Result<SteadyState, AnalysisError> {
        steady_state_of(&mut self.clone(), &start, self.model().grid(), spec)
    }

    fn steady_states(
        &self,
        starts: &[Vector],
        spec: &SteadyStateSpec,
        known: Option<&mut KnownAttractors>,
        cancel: &AtomicBool,
        on_done: &mut dyn FnMut(usize),
    ) -> Result<Vec<SteadyState>, AnalysisError> {
        match starts.len() {
            0..=FEW_LANES => in_lanes::<FEW_LANES>(self, starts, spec, known, cancel, on_done),
            _ => in_lanes::<LANES>(self, starts, spec, known, cancel, on_done),
        }
    }

    /// Regions are verified on the model's own integrator, for a model whose state is its
    /// two grid states.
    fn known_attractors(&self, spec: &SteadyStateSpec, capture: f64) -> Option<KnownAttractors> {
        Flow::written(self, &spec.resolution).map(|flow| KnownAttractors::with_flow(flow, capture))
    }
}

/// Trajectories of a written model integrated side by side: as many as its tapes are
/// compiled for.
const LANES: usize = crate::model::equations::tape::NATIVE_LANES;

/// What one lane is doing.
enum Job {
    Idle,
    Transient {
        start: usize,
        detector: Box<PeriodDetector<MAX_DIM>>,
        /// The response whose capture region held the last stroboscopic point.
        inside: Option<usize>,
        /// Tolerances a cycle was sought at ([`settled_cycle`]).
        sought: usize,
    },
    Recording {
        start: usize,
        class: Class,
        k: usize,
        transient: usize,
        rec: OrbitRecord,
        poincare: Vec<[f64; 2]>,
        states: Vec<Vec<f64>>,
    },
}

/// [`steady_state_of`] from each of `starts`, `L` at a time in lanes (each lane's result is
/// bit for bit the scalar one's); a lane takes the next start as soon as it is done. With
/// `known`, a trajectory whose stroboscopic point lies in a verified capture region of a
/// known response two periods running gets that response's result, as the built-in batches
/// do, and responses reached in full are learnt.
fn in_lanes<const L: usize>(
    sys: &EquationSystem,
    starts: &[Vector],
    spec: &SteadyStateSpec,
    mut known: Option<&mut KnownAttractors>,
    cancel: &AtomicBool,
    on_done: &mut dyn FnMut(usize),
) -> Result<Vec<SteadyState>, AnalysisError> {
    let mut sys = sys.clone();
    let grid = sys.model().grid();
    let dim = sys.dim();
    let rk = GeneralRk4::new(&sys, &spec.resolution);
    let h = rk.step();
    let mut eval = EquationLanes::<L>::new(&sys);
    let rest = *sys.origin();
    let mut lanes = Lanes::<L>::idle(&rest);
    let mut jobs: Vec<Job> = (0..L).map(|_| Job::Idle).collect();
    let mut results: Vec<Option<SteadyState>> = vec![None; starts.len()];
    let mut next = 0;
    // a lane's next start (or idle); a start that stops at once is done at once
    let fill = |l: usize, sys: &mut EquationSystem, lanes: &mut Lanes<L>, next: &mut usize| {
        let mut done = Vec::new();
        while *next < starts.len() {
            let start = *next;
            *next += 1;
            rk.restart_lane(sys, lanes, l, &starts[start]);
            match lanes.stop(l) {
                Some(stop) => done.push((start, stopped(sys, stop, 0, grid))),
                None => {
                    let detector = Box::new(spec.period_detector());
                    let job = Job::Transient {
                        start,
                        detector,
                        inside: None,
                        sought: 0,
                    };
                    return (job, done);
                }
            }
        }
        rk.park_lane(lanes, l, &rest);
        (Job::Idle, done)
    };
    let mut finish = |start: usize,
                      result: Result<SteadyState, AnalysisError>,
                      known: &mut Option<&mut KnownAttractors>| {
        let result = result?;
        if let Some(known) = known.as_deref_mut() {
            known.learn(&result, SAME_POINT_TOL);
        }
        results[start] = Some(result);
        on_done(start);
        Ok::<(), AnalysisError>(())
    };
    for (l, job) in jobs.iter_mut().enumerate() {
        let (started, done) = fill(l, &mut sys, &mut lanes, &mut next);
        *job = started;
        for (start, r) in done {
            finish(start, r, &mut known)?;
        }
    }
    while jobs.iter().any(|j| !matches!(j, Job::Idle)) {
        if cancel.load(Ordering::Relaxed) {
            return Err(AnalysisError::Cancelled);
        }
        let recording = jobs.iter().any(|j| matches!(j, Job::Recording { .. }));
        for _ in 0..rk.steps_per_period() {
            let was_running: [bool; L] = std::array::from_fn(|l| lanes.running(l));
            let before = recording.then(|| lanes.ends(&rk));
            rk.advance_lanes(&mut sys, &mut eval, &mut lanes);
            if let Some(before) = before {
                let after = lanes.ends(&rk);
                let (y0, rate0) = eval.output(&before.0, &before.1, &before.2);
                let (y1, rate1) = eval.output(&after.0, &after.1, &after.2);
                for (l, job) in jobs.iter_mut().enumerate() {
                    if let Job::Recording { rec, .. } = job
                        && was_running[l]
                        && lanes.running(l)
                    {
                        rec.add_step(y0[l], rate0[l], y1[l], rate1[l], h);
                    }
                }
            }
        }
        // lanes, their jobs and the results are updated together by index
        #[allow(clippy::needless_range_loop)]
        for l in 0..L {
            let point: Vector = std::array::from_fn(|i| lanes.x[i][l]);
            let finished: Option<(usize, Result<SteadyState, AnalysisError>)> = match &mut jobs[l] {
                Job::Idle => None,
                Job::Transient {
                    start,
                    detector,
                    inside,
                    sought,
                } => {
                    if let Some(stop) = lanes.stop(l) {
                        Some((*start, stopped(&sys, stop, detector.periods() + 1, grid)))
                    } else if let Some(k) = detector.push(point) {
                        let n = detector.periods();
                        jobs[l] = recording_job(*start, Class::Periodic, k, n, &rk);
                        None
                    } else if detector.periods() >= spec.max_forcing_periods {
                        let (k, n) = (spec.max_period, spec.max_forcing_periods);
                        jobs[l] = recording_job(*start, Class::NonPeriodic, k, n, &rk);
                        None
                    } else if let Some(known) = known.as_deref_mut() {
                        let at = [point[grid[0]], point[grid[1]]];
                        let mut now = known.capturing(at);
                        if now.is_none()
                            && let Some(k) = settled_cycle(detector, sought)
                        {
                            let steady = |p: [f64; 2]| {
                                let mut x = rest;
                                (x[grid[0]], x[grid[1]]) = (p[0], p[1]);
                                steady_state_of(&mut sys.clone(), &x, grid, spec).ok()
                            };
                            if known.learn_ahead(at, k, steady) {
                                now = known.capturing(at);
                            }
                        }
                        let captured = now.filter(|&a| *inside == Some(a));
                        *inside = now;
                        captured
                            .map(|a| (*start, Ok(adopt(known.response(a), detector.periods(), at))))
                    } else {
                        None
                    }
                }
                Job::Recording {
                    start,
                    class,
                    k,
                    transient,
                    rec,
                    poincare,
                    states,
                } => {
                    if let Some(stop) = lanes.stop(l) {
                        Some((*start, stopped(&sys, stop, *transient, grid)))
                    } else {
                        poincare.push([point[grid[0]], point[grid[1]]]);
                        if dim > 2 {
                            states.push(point[..dim].to_vec());
                        }
                        (poincare.len() == *k).then(|| {
                            let p = std::mem::take(poincare);
                            let mut s = from_record(rec, p, *k, *transient, *class);
                            s.states = std::mem::take(states);
                            (*start, Ok(s))
                        })
                    }
                }
            };
            if let Some((start, result)) = finished {
                finish(start, result, &mut known)?;
                let (job, done) = fill(l, &mut sys, &mut lanes, &mut next);
                jobs[l] = job;
                for (start, r) in done {
                    finish(start, r, &mut known)?;
                }
            }
        }
    }
    Ok(results
        .into_iter()
        .map(|r| r.expect("every start finished"))
        .collect())
}

fn recording_job(start: usize, class: Class, k: usize, transient: usize, rk: &GeneralRk4) -> Job {
    Job::Recording {
        start,
        class,
        k,
        transient,
        rec: OrbitRecord::new(rk.steps_per_period()),
        poincare: Vec::with_capacity(k),
        states: Vec::new(),
    }
}
