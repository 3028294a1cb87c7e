//! Many trajectories to their steady states at once: RK4 in SIMD lanes, each lane running the
//! period test of [`super::steady_state`] on its own and taking the next initial state as soon
//! as it is done.
//!
//! Optional early stop (the recurrence idea behind Attractors.jl's basins): once a lane's
//! stroboscopic point has stayed within `capture` of a point of an attractor already found,
//! with the attractor's own phase order, for `CAPTURE_PERIODS` periods in a row, the lane is
//! given that attractor's result without converging to 1e-9 itself.

use std::sync::atomic::{AtomicBool, Ordering};

use super::period_detector::PeriodDetector;
use super::period_map::OrbitRecord;
use super::steady_state::{Class, SteadyState, SteadyStateSpec, collided, from_record};
use crate::model::Params;
use crate::solver::Rk4;

/// Trajectories integrated side by side.
pub const LANES: usize = 16;
/// Response periods (of k forcing periods each), plus one forcing period, that a trajectory
/// must shadow a known attractor in its phase order before it takes its result. A transient
/// spiralling into one attractor can pass near another's points for a period or two (a 1:1
/// focus with multipliers near e^{±2πi/3} mimics the period-3 orbit born beside it), but not
/// for several rounds inside a ball much smaller than the attractors' separation.
const CAPTURE_CYCLES: usize = 3;
/// An attractor's capture ball is at most this fraction of its distance to the nearest point
/// of another known attractor (or between its own points).
const CAPTURE_SEPARATION_FRACTION: f64 = 0.25;
/// ... and at most this times (1 − its contraction per response period): an attractor that
/// draws trajectories in slowly (near a fold, where a saddle and its basin boundary are close)
/// gets a small ball, one that contracts fast a large one.
const CAPTURE_CONTRACTION_SCALE: f64 = 0.15;

/// Attractors found so far, for the early stop.
#[derive(Debug, Clone, Default)]
pub struct KnownAttractors {
    /// Periodic steady states whose Poincaré points a trajectory may shadow.
    pub responses: Vec<SteadyState>,
    /// Largest distance (max-norm on [λ_I, v]) within which a point shadows an attractor's
    /// point.
    pub capture: f64,
    /// Each attractor's own capture radius: `capture`, or less when other points are near.
    radius: Vec<f64>,
}

impl KnownAttractors {
    pub fn new(capture: f64) -> Self {
        KnownAttractors {
            responses: Vec::new(),
            capture,
            radius: Vec::new(),
        }
    }

    /// Adds a periodic response unless one with the same period and points is there already.
    pub fn learn(&mut self, s: &SteadyState, tol: f64) {
        if s.class == Class::Periodic
            && !self
                .responses
                .iter()
                .any(|r| super::attractor::same_attractor(r, s, tol))
        {
            self.responses.push(s.clone());
            self.update_radii();
        }
    }

    /// Shrinks each attractor's capture ball below its separation from every other point.
    fn update_radii(&mut self) {
        let points: Vec<(usize, [f64; 2])> = self
            .responses
            .iter()
            .enumerate()
            .flat_map(|(a, r)| r.poincare.iter().map(move |&p| (a, p)))
            .collect();
        self.radius = (0..self.responses.len())
            .map(|a| {
                let mut nearest = f64::INFINITY;
                for (i, &(ai, p)) in points.iter().enumerate() {
                    for (j, &(_, q)) in points.iter().enumerate() {
                        if ai == a && i != j {
                            nearest = nearest.min((p[0] - q[0]).abs().max((p[1] - q[1]).abs()));
                        }
                    }
                }
                let contraction = self.responses[a].contraction.unwrap_or(1.0);
                self.capture
                    .min(CAPTURE_SEPARATION_FRACTION * nearest)
                    .min(CAPTURE_CONTRACTION_SCALE * (1.0 - contraction))
            })
            .collect();
    }

    /// (attractor index, phase j) with `p` within the attractor's radius of its point j.
    fn nearest(&self, p: [f64; 2]) -> Option<(usize, usize)> {
        self.responses.iter().enumerate().find_map(|(a, r)| {
            r.poincare
                .iter()
                .position(|q| (p[0] - q[0]).abs().max((p[1] - q[1]).abs()) < self.radius[a])
                .map(|j| (a, j))
        })
    }
}

/// What one lane is doing.
#[derive(Debug, Clone)]
enum LaneState {
    Idle,
    Transient {
        ic: usize,
        detector: PeriodDetector,
        shadow: Option<Shadow>,
    },
    Recording {
        ic: usize,
        contraction: Option<f64>,
        class: Class,
        k: usize,
        transient: usize,
        rec: OrbitRecord,
        poincare: Vec<[f64; 2]>,
    },
}

/// Steady states from every initial state [λ_I, v] in `ics` (at τ = 0), in order. With
/// `known`, trajectories that shadow a known attractor stop early, and attractors reached in
/// full are learnt; without it the result is exactly what [`super::steady_state`] gives for
/// each state. Stops early (returning `None`) when `cancel` is set; `on_done` is called after
/// each result.
pub fn steady_states(
    params: &Params,
    ics: &[[f64; 2]],
    spec: &SteadyStateSpec,
    mut known: Option<&mut KnownAttractors>,
    cancel: &AtomicBool,
    mut on_done: impl FnMut(usize),
) -> Option<Vec<SteadyState>> {
    let rk = Rk4::new(params, &spec.resolution);
    let h = rk.step();
    let mut results: Vec<Option<SteadyState>> = vec![None; ics.len()];
    let mut lanes = rk.start([params.lambda_p(); LANES], [0.0; LANES]);
    let mut state: Vec<LaneState> = vec![LaneState::Idle; LANES];
    let mut next_ic = 0;
    let fill = |i: usize, lanes: &mut crate::solver::Lanes<LANES>, next_ic: &mut usize| {
        if *next_ic < ics.len() {
            let ic = *next_ic;
            *next_ic += 1;
            rk.restart_lane(lanes, i, ics[ic][0], ics[ic][1]);
            LaneState::Transient {
                ic,
                detector: PeriodDetector::new(spec),
                shadow: None,
            }
        } else {
            rk.park_lane(lanes, i);
            LaneState::Idle
        }
    };
    for (i, s) in state.iter_mut().enumerate() {
        *s = fill(i, &mut lanes, &mut next_ic);
    }
    while state.iter().any(|s| !matches!(s, LaneState::Idle)) {
        if cancel.load(Ordering::Relaxed) {
            return None;
        }
        let recording = state
            .iter()
            .any(|s| matches!(s, LaneState::Recording { .. }));
        if recording {
            rk.advance_period(&mut lanes, |_, b, e| {
                for (i, s) in state.iter_mut().enumerate() {
                    if let LaneState::Recording { rec, .. } = s {
                        rec.add_step(b.x[i], b.v[i], e.x[i], e.v[i], h);
                    }
                }
            });
        } else {
            rk.advance_period(&mut lanes, |_, _, _| {});
        }
        // lanes, their states and the results are updated together by index
        #[allow(clippy::needless_range_loop)]
        for i in 0..LANES {
            let point = [lanes.x[i], lanes.v[i]];
            let finished: Option<(usize, SteadyState)> = match &mut state[i] {
                LaneState::Idle => None,
                LaneState::Transient {
                    ic,
                    detector,
                    shadow,
                } => {
                    if let Some(c) = lanes.collision[i] {
                        Some((*ic, collided(c, detector.periods() + 1)))
                    } else if let Some(k) = detector.push(point) {
                        let n = detector.periods();
                        let contraction = detector.contraction(k);
                        state[i] = recording_state(*ic, Class::Periodic, k, n, &rk);
                        if let LaneState::Recording { contraction: c, .. } = &mut state[i] {
                            *c = contraction;
                        }
                        None
                    } else if detector.periods() >= spec.max_forcing_periods {
                        let (k, n) = (spec.max_period, detector.periods());
                        state[i] = recording_state(*ic, Class::NonPeriodic, k, n, &rk);
                        None
                    } else if let Some(known) = known.as_deref() {
                        shadow_step(known, point, shadow)
                            .map(|a| (*ic, adopt(&known.responses[a], detector.periods())))
                    } else {
                        None
                    }
                }
                LaneState::Recording {
                    ic,
                    contraction,
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
                            let mut s = from_record(rec, p, *k, *transient, *class);
                            s.contraction = *contraction;
                            (*ic, s)
                        })
                    }
                }
            };
            if let Some((ic, result)) = finished {
                if let Some(known) = known.as_deref_mut() {
                    known.learn(&result, super::attractor::SAME_POINT_TOL);
                }
                results[ic] = Some(result);
                on_done(ic);
                state[i] = fill(i, &mut lanes, &mut next_ic);
            }
        }
    }
    Some(
        results
            .into_iter()
            .map(|r| r.expect("every state finished"))
            .collect(),
    )
}

fn recording_state(ic: usize, class: Class, k: usize, transient: usize, rk: &Rk4) -> LaneState {
    LaneState::Recording {
        ic,
        contraction: None,
        class,
        k,
        transient,
        rec: OrbitRecord::new(rk.steps_per_period()),
        poincare: Vec::with_capacity(k),
    }
}

/// A trajectory following a known attractor's points.
#[derive(Debug, Clone)]
struct Shadow {
    attractor: usize,
    /// The attractor's point the next stroboscopic point should be near.
    next: usize,
    /// Consecutive periods shadowed.
    periods: usize,
    /// Distance at the last visit of each of the attractor's points.
    last_distance: Vec<f64>,
}

/// Advances the shadowing; returns the attractor once it has been shadowed for
/// `CAPTURE_CYCLES` response periods.
fn shadow_step(
    known: &KnownAttractors,
    point: [f64; 2],
    shadow: &mut Option<Shadow>,
) -> Option<usize> {
    let distance = |a: usize, j: usize| {
        let q = known.responses[a].poincare[j];
        (point[0] - q[0]).abs().max((point[1] - q[1]).abs())
    };
    let continued = shadow.as_mut().and_then(|s| {
        let d = distance(s.attractor, s.next);
        (d < known.radius[s.attractor]).then(|| {
            s.last_distance[s.next] = d;
            s.next = (s.next + 1) % s.last_distance.len();
            s.periods += 1;
        })
    });
    if continued.is_none() {
        *shadow = known.nearest(point).map(|(a, j)| {
            let k = known.responses[a].poincare.len();
            let mut last_distance = vec![f64::NAN; k];
            last_distance[j] = distance(a, j);
            Shadow {
                attractor: a,
                next: (j + 1) % k,
                periods: 1,
                last_distance,
            }
        });
    }
    shadow.as_ref().and_then(|s| {
        let needed = CAPTURE_CYCLES * s.last_distance.len() + 1;
        (s.periods >= needed).then_some(s.attractor)
    })
}

/// A known attractor's result for a trajectory that reached it after `periods`.
fn adopt(attractor: &SteadyState, periods: usize) -> SteadyState {
    SteadyState {
        transient_periods: periods,
        ..attractor.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::steady_state;

    fn grid(n: usize, lambda_p: f64) -> Vec<[f64; 2]> {
        (0..n * n)
            .map(|i| {
                let (a, b) = (i / n, i % n);
                [
                    lambda_p - 0.8 + 1.6 * a as f64 / (n - 1) as f64,
                    -1.0 + 2.0 * b as f64 / (n - 1) as f64,
                ]
            })
            .collect()
    }

    /// Without early stop the batch gives exactly the single-trajectory results, bit for bit.
    #[test]
    fn batch_equals_one_by_one() {
        let p = Params::baseline();
        let spec = SteadyStateSpec::default();
        let ics = grid(6, p.lambda_p());
        let never = AtomicBool::new(false);
        let batch = steady_states(&p, &ics, &spec, None, &never, |_| {}).unwrap();
        for (ic, b) in ics.iter().zip(&batch) {
            let one = steady_state(&p, ic[0], ic[1], &spec);
            assert_eq!(&one, b, "from {ic:?}");
        }
    }

    /// With early stop every trajectory gets the same class, period and amplitude (to 1e-7:
    /// the attractor's own, converged to 1e-9 from another start) as the plain method, in
    /// fewer periods.
    #[test]
    fn early_stop_keeps_classes_and_amplitudes() {
        let p = Params::baseline();
        let spec = SteadyStateSpec::default();
        let ics = grid(8, p.lambda_p());
        let never = AtomicBool::new(false);
        let plain = steady_states(&p, &ics, &spec, None, &never, |_| {}).unwrap();
        let mut known = KnownAttractors::new(1e-4);
        for s in &plain {
            known.learn(s, 1e-6);
        }
        assert!(known.responses.len() >= 2);
        let fast = steady_states(&p, &ics, &spec, Some(&mut known), &never, |_| {}).unwrap();
        let (mut periods_plain, mut periods_fast) = (0, 0);
        for (a, b) in plain.iter().zip(&fast) {
            assert_eq!(a.class, b.class);
            assert_eq!(a.period, b.period);
            if let (Some(x), Some(y)) = (a.amplitude, b.amplitude) {
                assert!((x - y).abs() < 1e-7, "{x} vs {y}");
            }
            periods_plain += a.transient_periods;
            periods_fast += b.transient_periods;
        }
        assert!(
            periods_fast * 10 < periods_plain * 7,
            "{periods_fast} vs {periods_plain}"
        );
    }

    #[test]
    fn cancel_stops_at_once() {
        let p = Params::baseline();
        let cancel = AtomicBool::new(true);
        let ics = grid(4, p.lambda_p());
        assert!(
            steady_states(&p, &ics, &SteadyStateSpec::default(), None, &cancel, |_| {}).is_none()
        );
    }
}
