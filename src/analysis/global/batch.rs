//! Many trajectories to their steady states at once: RK4 in SIMD lanes, each lane running the
//! period test of [`crate::analysis::orbit::steady_state`] on its own and taking the next initial state as soon
//! as it is done.
//!
//! Optional early stop (the recurrence idea behind Attractors.jl's basins, made safe): once a
//! lane's stroboscopic point lies inside a verified capture region of a known periodic
//! response ([`crate::analysis::global::capture`]) in two consecutive forcing periods, the lane is given that
//! response's result without converging to 1e-9 itself. Responses are learnt from lanes that
//! converge in full, and earlier from the cycle found ahead of a lane that has nearly settled
//! ([`crate::analysis::global::cycle`]).

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use crate::analysis::global::capture::{CaptureRegion, Verification, capture_regions};
use crate::analysis::global::flow::Flow;
use crate::analysis::orbit::period_detector::PeriodDetector;
use crate::analysis::orbit::period_map::OrbitRecord;
use crate::analysis::orbit::steady_state::{
    Class, SteadyState, SteadyStateSpec, collided, from_record, steady_state,
};
use crate::model::Params;
use crate::solver::rk4::LANES;
use crate::solver::{Lanes, Resolution, Rk4};

/// A capture region's radius is at most this fraction of its point's distance to the nearest
/// point of another known response (or to its own response's other points), so regions of
/// different responses never overlap.
const CAPTURE_SEPARATION_FRACTION: f64 = 0.5;

/// A trajectory not yet captured whose stroboscopic points have settled on a k-cycle to one
/// of these (in turn) has the cycle found ahead of it by Newton's method
/// ([`crate::analysis::global::cycle`]) and learnt, so that it and the trajectories after it
/// are captured long before one of them converges to 1e-9 in full.
const SETTLED: [f64; 2] = [1e-3, 1e-6];

/// Lanes of a grid of more states than this: four times [`LANES`].
const WIDE: usize = 4 * LANES;

/// No cycle is sought ahead of a trajectory this close to a known response's point: it is
/// most likely on its way there.
const NEAR_KNOWN: f64 = 0.05;

/// Periodic responses found so far and their capture regions, for the early stop.
#[derive(Debug, Clone)]
pub struct KnownAttractors {
    /// Periodic steady states a trajectory may be captured by.
    responses: Vec<SteadyState>,
    /// Largest capture-region radius (regions are ellipses inside a ball of that radius).
    capture: f64,
    /// The map the regions are verified with: the integrator the trajectories run on.
    flow: Flow,
    /// Each response's regions, one per Poincaré point.
    regions: Vec<Vec<CaptureRegion>>,
}

impl KnownAttractors {
    /// No responses yet; regions will be verified for `params` integrated at `resolution`
    /// (the trajectories' own), at most `capture` in radius.
    pub fn new(params: &Params, resolution: &Resolution, capture: f64) -> Self {
        Self::with_flow(
            Flow::BuiltIn(Box::new(Rk4::new(params, resolution))),
            capture,
        )
    }

    /// No responses yet; regions will be verified with `flow`, at most `capture` in radius.
    pub fn with_flow(flow: Flow, capture: f64) -> Self {
        KnownAttractors {
            responses: Vec::new(),
            capture,
            flow,
            regions: Vec::new(),
        }
    }

    /// The responses known so far.
    pub fn responses(&self) -> &[SteadyState] {
        &self.responses
    }

    /// Adds a periodic response unless one with the same period and points is there already,
    /// and verifies its capture regions (and those of the others whose cap it lowers) over
    /// one return.
    pub fn learn(&mut self, s: &SteadyState, tol: f64) {
        self.learn_all(std::slice::from_ref(s), tol, Verification::OneReturn);
    }

    /// [`Self::learn`] for each of `states` in turn, the regions verified side by side, by
    /// `verification`.
    pub fn learn_all(&mut self, states: &[SteadyState], tol: f64, verification: Verification) {
        let before = self.responses.len();
        for s in states {
            let known = self
                .responses
                .iter()
                .any(|r| crate::analysis::orbit::attractor::same_attractor(r, s, tol));
            if s.class == Class::Periodic && !known {
                self.responses.push(s.clone());
                self.regions.push(Vec::new());
            }
        }
        if self.responses.len() == before {
            return;
        }
        // a region verified under a higher cap stays if it is within the new one
        let stale: Vec<(usize, Vec<f64>)> = (0..self.responses.len())
            .map(|a| (a, self.caps_of(a)))
            .filter(|(a, caps)| {
                let regions = &self.regions[*a];
                regions.is_empty() || regions.iter().zip(caps).any(|(r, &c)| r.radius() > c)
            })
            .collect();
        let verified: Vec<(usize, Vec<CaptureRegion>)> = stale
            .into_par_iter()
            .map(|(a, caps)| {
                let points = &self.responses[a].poincare;
                let regions = capture_regions(&self.flow, points, &caps, verification);
                (a, regions)
            })
            .collect();
        for (a, regions) in verified {
            self.regions[a] = regions;
        }
    }

    /// Seeks the attracting k-cycle near `point` (a trajectory's stroboscopic point, settled
    /// on a k-cycle) unless a known response has a point near it; learns the response
    /// `steady` gives from the cycle's point, if it finds one. True if it learnt one.
    pub(super) fn learn_ahead(
        &mut self,
        point: [f64; 2],
        k: usize,
        steady: impl FnOnce([f64; 2]) -> Option<SteadyState>,
    ) -> bool {
        let near = self
            .responses
            .iter()
            .flat_map(|r| &r.poincare)
            .any(|q| (point[0] - q[0]).hypot(point[1] - q[1]) < NEAR_KNOWN);
        if near {
            return false;
        }
        let Some(p) = crate::analysis::global::cycle::attracting_cycle_near(&self.flow, point, k)
        else {
            return false;
        };
        let Some(s) = steady(p) else {
            return false;
        };
        let before = self.responses.len();
        self.learn(&s, crate::analysis::orbit::attractor::SAME_POINT_TOL);
        self.responses.len() > before
    }

    /// The radius cap of each of response `a`'s regions.
    fn caps_of(&self, a: usize) -> Vec<f64> {
        let own = &self.responses[a].poincare;
        own.iter()
            .enumerate()
            .map(|(j, p)| {
                let others = self.responses.iter().enumerate().flat_map(|(b, r)| {
                    r.poincare
                        .iter()
                        .enumerate()
                        .filter(move |&(i, _)| b != a || i != j)
                        .map(|(_, q)| q)
                });
                let nearest = others
                    .map(|q| (p[0] - q[0]).hypot(p[1] - q[1]))
                    .fold(f64::INFINITY, f64::min);
                self.capture.min(CAPTURE_SEPARATION_FRACTION * nearest)
            })
            .collect()
    }

    /// Known response `a`.
    pub(super) fn response(&self, a: usize) -> &SteadyState {
        &self.responses[a]
    }

    /// The response with a capture region holding `p`.
    pub(super) fn capturing(&self, p: [f64; 2]) -> Option<usize> {
        self.regions
            .iter()
            .position(|regions| regions.iter().any(|r| r.contains(p)))
    }
}

/// What one lane is doing.
#[derive(Debug, Clone)]
enum LaneState {
    Idle,
    Transient {
        ic: usize,
        detector: PeriodDetector,
        /// The response whose capture region held the last stroboscopic point.
        inside: Option<usize>,
        /// How many of the [`SETTLED`] tolerances a cycle was sought at.
        sought: usize,
    },
    Recording {
        ic: usize,
        class: Class,
        k: usize,
        transient: usize,
        rec: OrbitRecord,
        poincare: Vec<[f64; 2]>,
    },
}

/// Steady states from every initial state [λ_I, v] in `ics` (at τ = 0), in order. With
/// `known`, trajectories captured by a known response stop early, and attractors reached in
/// full are learnt; without it the result is exactly what [`crate::analysis::orbit::steady_state`] gives for
/// each state. Stops early (returning `None`) when `cancel` is set; `on_done` is called after
/// each result.
pub fn steady_states(
    params: &Params,
    ics: &[[f64; 2]],
    spec: &SteadyStateSpec,
    known: Option<&mut KnownAttractors>,
    cancel: &AtomicBool,
    on_done: &mut dyn FnMut(usize),
) -> Option<Vec<SteadyState>> {
    // a handful of states (a frequency response's seeds) runs in narrower lanes; more than
    // WIDE in WIDE lanes, so that several switch in the same step and are split side by side
    // (measured: a map's 7 × 7 grids gained nothing in 64 lanes, Fig 4's 15 × 15 grids gained
    // less in 32 than in 64, and the basin's chunks no more in 128)
    match ics.len() {
        0..=4 => in_lanes::<4>(params, ics, spec, known, cancel, on_done),
        5..=8 => in_lanes::<8>(params, ics, spec, known, cancel, on_done),
        9..=WIDE => in_lanes::<LANES>(params, ics, spec, known, cancel, on_done),
        _ => in_lanes::<WIDE>(params, ics, spec, known, cancel, on_done),
    }
}

/// [`steady_states`] with `L` trajectories side by side. Once every state has started, the
/// lanes still running move to narrower lanes as they thin out (at most half of `L`
/// running), each lane's trajectory unchanged, so that idle lanes are not integrated.
fn in_lanes<const L: usize>(
    params: &Params,
    ics: &[[f64; 2]],
    spec: &SteadyStateSpec,
    known: Option<&mut KnownAttractors>,
    cancel: &AtomicBool,
    on_done: &mut dyn FnMut(usize),
) -> Option<Vec<SteadyState>> {
    let rk = Rk4::new(params, &spec.resolution);
    let mut grid = Grid {
        params,
        ics,
        spec,
        rk: &rk,
        known,
        cancel,
        on_done,
        results: vec![None; ics.len()],
        next_ic: 0,
    };
    let mut lanes = rk.start([params.lambda_p(); L], [0.0; L]);
    let mut state: Vec<LaneState> = vec![LaneState::Idle; L];
    for (i, s) in state.iter_mut().enumerate() {
        *s = grid.fill(i, &mut lanes);
    }
    if L == WIDE {
        // to half as many lanes, and half again, as they finish
        grid.run(&mut lanes, &mut state, 2 * LANES)?;
        let (mut lanes, mut state) = narrowed::<L, { 2 * LANES }>(&rk, &lanes, state);
        grid.run(&mut lanes, &mut state, LANES)?;
        let (mut lanes, mut state) = narrowed::<{ 2 * LANES }, LANES>(&rk, &lanes, state);
        grid.run(&mut lanes, &mut state, 0)?;
    } else {
        grid.run(&mut lanes, &mut state, 0)?;
    }
    Some(
        grid.results
            .into_iter()
            .map(|r| r.expect("every state finished"))
            .collect(),
    )
}

/// The lanes of `lanes` still running, in order, moved to `M` lanes with their states.
fn narrowed<const L: usize, const M: usize>(
    rk: &Rk4,
    lanes: &Lanes<L>,
    mut state: Vec<LaneState>,
) -> (Lanes<M>, Vec<LaneState>) {
    let running: Vec<usize> = (0..L)
        .filter(|&i| !matches!(state[i], LaneState::Idle))
        .collect();
    let narrow = rk.narrowed::<L, M>(lanes, &running);
    let mut moved: Vec<LaneState> = running
        .iter()
        .map(|&i| std::mem::replace(&mut state[i], LaneState::Idle))
        .collect();
    moved.resize(M, LaneState::Idle);
    (narrow, moved)
}

/// A grid of initial states on its way to its steady states.
struct Grid<'a> {
    params: &'a Params,
    ics: &'a [[f64; 2]],
    spec: &'a SteadyStateSpec,
    rk: &'a Rk4,
    known: Option<&'a mut KnownAttractors>,
    cancel: &'a AtomicBool,
    on_done: &'a mut dyn FnMut(usize),
    results: Vec<Option<SteadyState>>,
    /// The first initial state not yet started.
    next_ic: usize,
}

impl Grid<'_> {
    /// Starts the next initial state in lane `i`, or parks the lane if none is left.
    fn fill<const L: usize>(&mut self, i: usize, lanes: &mut Lanes<L>) -> LaneState {
        if self.next_ic < self.ics.len() {
            let ic = self.next_ic;
            self.next_ic += 1;
            self.rk
                .restart_lane(lanes, i, self.ics[ic][0], self.ics[ic][1]);
            LaneState::Transient {
                ic,
                detector: self.spec.period_detector(),
                inside: None,
                sought: 0,
            }
        } else {
            self.rk.park_lane(lanes, i);
            LaneState::Idle
        }
    }

    /// Advances the lanes a period at a time until none is running, or until every state
    /// has started and at most `narrow_at` are running. `None` if cancelled.
    fn run<const L: usize>(
        &mut self,
        lanes: &mut Lanes<L>,
        state: &mut [LaneState],
        narrow_at: usize,
    ) -> Option<()> {
        let (rk, h) = (self.rk, self.rk.step());
        let (params, spec) = (self.params, self.spec);
        loop {
            let running = state
                .iter()
                .filter(|s| !matches!(s, LaneState::Idle))
                .count();
            if running == 0 || (self.next_ic == self.ics.len() && running <= narrow_at) {
                return Some(());
            }
            if self.cancel.load(Ordering::Relaxed) {
                return None;
            }
            let recording = state
                .iter()
                .any(|s| matches!(s, LaneState::Recording { .. }));
            if recording {
                rk.advance_period(
                    lanes,
                    Some(&mut |_, b, e| {
                        for (i, s) in state.iter_mut().enumerate() {
                            if let LaneState::Recording { rec, .. } = s {
                                rec.add_step(b.x[i], b.v[i], e.x[i], e.v[i], h);
                            }
                        }
                    }),
                );
            } else {
                rk.advance_period(lanes, None);
            }
            // lanes, their states and the results are updated together by index
            #[allow(clippy::needless_range_loop)]
            for i in 0..L {
                let point = [lanes.x[i], lanes.v[i]];
                let finished: Option<(usize, SteadyState)> = match &mut state[i] {
                    LaneState::Idle => None,
                    LaneState::Transient {
                        ic,
                        detector,
                        inside,
                        sought,
                    } => {
                        if let Some(c) = lanes.collision[i] {
                            Some((*ic, collided(c, detector.periods() + 1)))
                        } else if let Some(k) = detector.push(point) {
                            let n = detector.periods();
                            state[i] = recording_state(*ic, Class::Periodic, k, n, rk);
                            None
                        } else if detector.periods() >= self.spec.max_forcing_periods {
                            let (k, n) = (self.spec.max_period, detector.periods());
                            state[i] = recording_state(*ic, Class::NonPeriodic, k, n, rk);
                            None
                        } else if let Some(known) = self.known.as_deref_mut() {
                            let mut now = known.capturing(point);
                            if now.is_none()
                                && let Some(k) = settled_cycle(detector, sought)
                            {
                                let steady =
                                    |p: [f64; 2]| Some(steady_state(params, p[0], p[1], spec));
                                if known.learn_ahead(point, k, steady) {
                                    now = known.capturing(point);
                                }
                            }
                            let captured = now.filter(|&a| *inside == Some(a));
                            *inside = now;
                            captured.map(|a| {
                                (*ic, adopt(&known.responses[a], detector.periods(), point))
                            })
                        } else {
                            None
                        }
                    }
                    LaneState::Recording {
                        ic,
                        class,
                        k,
                        transient,
                        rec,
                        poincare,
                    } => {
                        if let Some(c) = lanes.collision[i] {
                            Some((*ic, collided(c, *transient)))
                        } else {
                            poincare.push(point);
                            (poincare.len() == *k).then(|| {
                                let p = std::mem::take(poincare);
                                (*ic, from_record(rec, p, *k, *transient, *class))
                            })
                        }
                    }
                };
                if let Some((ic, result)) = finished {
                    if let Some(known) = self.known.as_deref_mut() {
                        known.learn(&result, crate::analysis::orbit::attractor::SAME_POINT_TOL);
                    }
                    self.results[ic] = Some(result);
                    (self.on_done)(ic);
                    state[i] = self.fill(i, lanes);
                }
            }
        }
    }
}

fn recording_state(ic: usize, class: Class, k: usize, transient: usize, rk: &Rk4) -> LaneState {
    LaneState::Recording {
        ic,
        class,
        k,
        transient,
        rec: OrbitRecord::new(rk.steps_per_period()),
        poincare: Vec::with_capacity(k),
    }
}

/// The k of the cycle a trajectory's points have settled on, at the next of the [`SETTLED`]
/// tolerances not yet used (`sought` counts them), if they have.
pub(super) fn settled_cycle<const N: usize>(
    detector: &PeriodDetector<N>,
    sought: &mut usize,
) -> Option<usize> {
    let k = detector.settling(*SETTLED.get(*sought)?)?;
    *sought += 1;
    Some(k)
}

/// A known attractor's result for a trajectory that reached it after `periods` and is now at
/// `at`: its Poincaré points in the trajectory's own order, ending with the one `at` is
/// nearest, where the trajectory's own record would end.
pub(super) fn adopt(attractor: &SteadyState, periods: usize, at: [f64; 2]) -> SteadyState {
    let mut s = SteadyState {
        transient_periods: periods,
        ..attractor.clone()
    };
    let distance = |p: &[f64; 2]| (p[0] - at[0]).hypot(p[1] - at[1]);
    let nearest = (0..s.poincare.len())
        .min_by(|&a, &b| distance(&s.poincare[a]).total_cmp(&distance(&s.poincare[b])));
    if let Some(j) = nearest {
        let shift = (j + 1) % s.poincare.len();
        s.poincare.rotate_left(shift);
        if s.states.len() == s.poincare.len() {
            s.states.rotate_left(shift);
        }
    }
    s
}
