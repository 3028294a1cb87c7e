//! Fig 4/5: the frequency response from many initial states. For each ω_e of a grid, a grid of
//! initial states is integrated to steady state and identical attractors are merged; each ω_e
//! is then seeded with the responses found at its neighbours so narrow branches are not
//! missed; stepped sweeps up and down mark the responses no sweep reaches as hidden; and
//! responses are chained across ω_e into branches.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::analysis::AnalysisError;
use crate::analysis::Ratio;
use crate::analysis::global::batch::KnownAttractors;
use crate::analysis::global::capture::Verification;
use crate::analysis::global::oscillator::Oscillator;
use crate::analysis::global::stepped_sweep::{SweepStep, stepped_sweep_over};
use crate::analysis::grid::Axis;
use crate::analysis::orbit::attractor::{SAME_POINT_TOL, same_attractor};
use crate::analysis::orbit::steady_state::{Class, SteadyState, SteadyStateSpec};
use crate::analysis::progress::Progress;
use crate::model::Params;
use crate::model::error::check;
use crate::model::limits;

/// Largest number of trajectories one frequency response may ask for.
pub const MAX_TRAJECTORIES: usize = 1 << 24;

/// Initial states per ω_e at most (128 × 128; the paper's grid is 15 × 15).
pub const MAX_STARTS: usize = 1 << 14;
/// Rounds of neighbour seeding at most (each is one pass up and one down).
const MAX_SEED_ROUNDS: usize = 4;
/// Poincaré sets of one branch at adjacent ω_e lie within this distance (max-norm), plus
/// half the larger amplitude: large orbits move faster with ω_e.
const BRANCH_LINK_DISTANCE: f64 = 0.15;

/// A frequency-response computation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FrequencyResponseSpec {
    /// Forcing frequencies ω_e.
    pub omega: Axis,
    /// Initial displacements Δλ of the grid of initial states.
    pub dx: Axis,
    /// Initial velocities of the grid.
    pub v: Axis,
    pub steady: SteadyStateSpec,
    /// Seed each ω_e with the responses found at its neighbours.
    pub seed_neighbours: bool,
    /// Run stepped sweeps up and down to mark hidden responses.
    pub sweeps: bool,
    /// Stop trajectories that enter a verified capture region of an attractor already found
    /// at the same ω_e.
    pub early_stop: bool,
    /// Largest capture-region radius for the early stop (Euclidean on [λ_I, v]).
    pub capture: f64,
}

impl Default for FrequencyResponseSpec {
    /// Fig 4: ω_e from 0.2 to 6 by 0.05, 15 × 15 initial states.
    fn default() -> Self {
        FrequencyResponseSpec {
            omega: Axis::new(0.2, 6.0, 117),
            dx: Axis::new(-0.8, 0.8, 15),
            v: Axis::new(-1.0, 1.0, 15),
            steady: SteadyStateSpec::default(),
            seed_neighbours: true,
            sweeps: true,
            early_stop: true,
            capture: 0.1,
        }
    }
}

impl FrequencyResponseSpec {
    /// Units of progress of one response: every trajectory of the grids (one grid of starts
    /// per ω_e), and every step of both sweeps.
    pub fn work(&self) -> usize {
        let omegas = self.omega.points;
        let sweeps = if self.sweeps { 2 * omegas } else { 0 };
        self.dx.points * self.v.points * omegas + sweeps
    }

    /// Checks the ω grid (positive), the grid of starts, the total number of trajectories,
    /// the capture radius and the steady-state settings.
    pub fn validate(&self) -> Result<(), crate::model::ParamError> {
        self.omega.validate("omega", 100_000)?;
        self.dx.validate("dx", 4096)?;
        self.dx.check_within("dx", limits::DX)?;
        self.v.validate("v", 4096)?;
        self.v.check_within("v", limits::V)?;
        // one ω_e's grid is one chunk of work: keep it to minutes even in the worst case
        let starts = self.dx.points * self.v.points;
        check(
            "dx.points",
            self.dx.points as f64,
            |_| starts <= MAX_STARTS,
            format!(
                "at most {MAX_STARTS} initial states per ω_e (dx.points × v.points = {starts}); \
                 a basin maps finer grids"
            ),
        )?;
        self.steady.validate().map_err(|e| e.within("steady"))?;
        check("capture", self.capture, |c| c > 0.0 && c <= 1.0, "(0, 1]")?;
        let total = self.dx.points * self.v.points * self.omega.points;
        check(
            "trajectories",
            total as f64,
            |t| t <= MAX_TRAJECTORIES as f64,
            format!("<= {MAX_TRAJECTORIES} (ω points × initial states)"),
        )?;
        Ok(())
    }
}

/// One distinct steady response at one ω_e.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Response {
    pub omega_index: usize,
    pub omega: f64,
    pub steady: SteadyState,
    /// Initial states of the grid that reached it.
    pub count: usize,
    /// count over the grid's size.
    pub share: f64,
    /// First found from a neighbour's response rather than from the grid.
    pub seeded: bool,
    /// Neither stepped sweep reaches it (periodic responses, when sweeps were run).
    pub hidden: Option<bool>,
    /// The branch it belongs to (periodic responses).
    pub branch: Option<usize>,
}

/// Responses of one type chained across adjacent ω_e.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Branch {
    pub id: usize,
    pub period: usize,
    pub ratio: Ratio,
    pub response_type: String,
    pub omega_min: f64,
    pub omega_max: f64,
    pub peak_amplitude: f64,
    pub peak_omega: f64,
    pub points: usize,
    /// Every response on it is hidden.
    pub hidden: bool,
    /// Some response on it is hidden.
    pub partly_hidden: bool,
}

impl Branch {
    /// A subharmonic branch: its responses repeat every two forcing periods or more.
    pub fn is_subharmonic(&self) -> bool {
        self.period >= 2
    }

    /// A branch the isola hunter continues: a subharmonic one, or one that is hidden
    /// whatever its period (a 1:1 isola, as a Duffing oscillator's, is reached by no sweep).
    pub fn may_be_an_isola(&self) -> bool {
        self.is_subharmonic() || self.hidden
    }

    /// One line: type, ω range, peak, and whether the sweeps reach it.
    pub fn describe(&self) -> String {
        let reach = if self.hidden {
            "hidden"
        } else if self.partly_hidden {
            "attached, partly hidden"
        } else {
            "attached"
        };
        format!(
            "{} ω {:.2}–{:.2} peak {:.3} {reach}",
            self.response_type, self.omega_min, self.omega_max, self.peak_amplitude
        )
    }
}

/// The full result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrequencyResponse {
    pub omegas: Vec<f64>,
    /// Ordered by ω_e, then by first appearance.
    pub responses: Vec<Response>,
    pub branches: Vec<Branch>,
    pub forward: Vec<SweepStep>,
    pub backward: Vec<SweepStep>,
}

impl FrequencyResponse {
    /// The responses at ω_e index `i`.
    pub fn at(&self, i: usize) -> impl Iterator<Item = &Response> {
        self.responses.iter().filter(move |r| r.omega_index == i)
    }

    /// The largest response of branch `id`.
    pub fn peak(&self, id: usize) -> Option<&Response> {
        let amplitude = |r: &Response| r.steady.amplitude.unwrap_or(f64::NEG_INFINITY);
        self.responses
            .iter()
            .filter(|r| r.branch == Some(id))
            .max_by(|a, b| amplitude(a).total_cmp(&amplitude(b)))
    }
}

/// Computes the frequency response of `params` (its ω_e is replaced by the spec's grid).
pub fn frequency_response<O: Oscillator>(
    params: &O,
    spec: &FrequencyResponseSpec,
    progress: &Progress,
) -> Result<FrequencyResponse, AnalysisError> {
    frequency_response_live(params, spec, progress, &|_| {})
}

/// The same, handing the grid's responses at each ω_e to `on_omega` as soon as they are known
/// (before seeding, sweeps and branches), for a live view.
pub fn frequency_response_live<O: Oscillator>(
    params: &O,
    spec: &FrequencyResponseSpec,
    progress: &Progress,
    on_omega: &(dyn Fn(&[Response]) + Sync),
) -> Result<FrequencyResponse, AnalysisError> {
    let plan = ResponsePlan::new(params, spec)?;
    progress.grow_total(plan.work());
    run_plan(&plan, progress, on_omega)
}

/// The response against `parameter` (its values on the spec's `omega` grid) at the model's
/// ω_e: see [`ResponsePlan::over`].
///
/// `work` says who announces its [`FrequencyResponseSpec::work`] on `progress`: the call
/// itself, or its caller (the rows of a map, the members of a family: announced together, so
/// that a gauge runs once from 0 to 100 %).
pub fn frequency_response_over<O: Oscillator>(
    params: &O,
    spec: &FrequencyResponseSpec,
    parameter: O::Parameter,
    progress: &Progress,
    work: Work,
) -> Result<FrequencyResponse, AnalysisError> {
    let plan = ResponsePlan::over(params, spec, parameter)?;
    if work == Work::Own {
        progress.grow_total(plan.work());
    }
    run_plan(&plan, progress, &|_| {})
}

/// Who announces a call's work on its progress.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Work {
    /// The call, as it starts.
    Own,
    /// Its caller, already.
    Announced,
}

/// Runs a plan whose work is announced already.
fn run_plan<O: Oscillator>(
    plan: &ResponsePlan<O>,
    progress: &Progress,
    on_omega: &(dyn Fn(&[Response]) + Sync),
) -> Result<FrequencyResponse, AnalysisError> {
    let per_omega: Vec<Result<Vec<Response>, AnalysisError>> = (0..plan.chunks())
        .into_par_iter()
        .map(|i| {
            let found = plan.grid_at(i, progress)?;
            on_omega(&found);
            Ok(found)
        })
        .collect();
    let per_omega: Vec<Vec<Response>> = per_omega.into_iter().collect::<Result<_, _>>()?;
    plan.finish(per_omega, progress)
}

/// ω_e per chunk of the results store for a grid of `points` values: 1, 2 or 4
/// ([`super::units_per_chunk`]; chunks of 2 were no faster than of 4 for Fig 4).
pub fn omegas_per_chunk(points: usize) -> usize {
    super::units_per_chunk(points, 1, 4)
}

/// The ω_e indices of the store's chunk `i` of a grid of `points` values.
pub fn chunk_omegas(points: usize, i: usize) -> std::ops::Range<usize> {
    let per_chunk = omegas_per_chunk(points);
    (i * per_chunk).min(points)..((i + 1) * per_chunk).min(points)
}

/// A validated frequency response cut into chunks, one per ω_e of the grid (its grid of initial
/// states); seeding, sweeps and branches follow once every chunk is done.
pub struct ResponsePlan<'a, O: Oscillator = Params> {
    params: &'a O,
    spec: &'a FrequencyResponseSpec,
    omegas: Vec<f64>,
    at_omega: Vec<O>,
    ics: Vec<O::State>,
}

impl<'a, O: Oscillator> ResponsePlan<'a, O> {
    pub fn new(params: &'a O, spec: &'a FrequencyResponseSpec) -> Result<Self, AnalysisError> {
        Self::over(params, spec, params.frequency())
    }

    /// The same with the grid's values taken as values of `parameter` (a response against a
    /// model parameter at the model's ω_e; its sweeps step that parameter quasi-statically,
    /// and each response's `omega` holds the value).
    pub fn over(
        params: &'a O,
        spec: &'a FrequencyResponseSpec,
        parameter: O::Parameter,
    ) -> Result<Self, AnalysisError> {
        spec.validate()?;
        let omegas = spec.omega.values();
        let at_omega = omegas
            .iter()
            .map(|&w| params.with(parameter, w))
            .collect::<Result<_, _>>()?;
        let (dx, v) = (&spec.dx, &spec.v);
        let ics = (0..dx.points * v.points)
            .map(|c| params.grid_start([dx.at(c / v.points), v.at(c % v.points)]))
            .collect();
        Ok(ResponsePlan {
            params,
            spec,
            omegas,
            at_omega,
            ics,
        })
    }

    /// One chunk per ω_e (the results store keeps [`omegas_per_chunk`] of them to a file).
    pub fn chunks(&self) -> usize {
        self.omegas.len()
    }

    /// Units of progress: [`FrequencyResponseSpec::work`].
    pub fn work(&self) -> usize {
        debug_assert_eq!(self.ics.len(), self.spec.dx.points * self.spec.v.points);
        self.spec.work()
    }

    /// The distinct responses from the grid of initial states at ω_e index `i`.
    pub fn grid_at(&self, i: usize, progress: &Progress) -> Result<Vec<Response>, AnalysisError> {
        let spec = self.spec;
        let at_omega = &self.at_omega[i];
        let mut known = spec
            .early_stop
            .then(|| at_omega.known_attractors(&spec.steady, spec.capture))
            .flatten();
        let outcomes = at_omega.steady_states(
            &self.ics,
            &spec.steady,
            known.as_mut(),
            progress.cancel_flag(),
            &mut |_| progress.add(1),
        )?;
        let mut found: Vec<Response> = Vec::new();
        for s in outcomes {
            match found.iter_mut().find(|r| same_response(&r.steady, &s)) {
                Some(r) => r.count += 1,
                None => found.push(Response {
                    omega_index: i,
                    omega: self.omegas[i],
                    steady: s,
                    count: 1,
                    share: 0.0,
                    seeded: false,
                    hidden: None,
                    branch: None,
                }),
            }
        }
        for r in &mut found {
            r.share = r.count as f64 / self.ics.len() as f64;
        }
        Ok(found)
    }

    /// Seeds each ω_e from its neighbours, runs the sweeps, marks hidden responses and links
    /// branches.
    pub fn finish(
        &self,
        mut per_omega: Vec<Vec<Response>>,
        progress: &Progress,
    ) -> Result<FrequencyResponse, AnalysisError> {
        let (spec, omegas, params) = (self.spec, &self.omegas, self.params);
        let cancel = progress.cancel_flag();
        if spec.seed_neighbours && omegas.len() > 1 {
            let mut seeding: Vec<Seeding> = vec![Seeding::default(); omegas.len()];
            for _ in 0..MAX_SEED_ROUNDS {
                let mut new = 0;
                let up: Vec<usize> = (1..omegas.len()).collect();
                let down: Vec<usize> = (0..omegas.len() - 1).rev().collect();
                for (order, from) in [(up, -1isize), (down, 1)] {
                    for i in order {
                        let j = (i as isize + from) as usize;
                        let at = (omegas[i], &self.at_omega[i]);
                        let done = &mut seeding[i];
                        new += seed_from(&mut per_omega, done, i, j, at, spec, cancel)?;
                    }
                }
                if new == 0 {
                    break;
                }
            }
        }
        let (forward, backward) = if spec.sweeps {
            let rest = params.rest();
            let up: Vec<(f64, O)> = omegas.iter().copied().zip(self.at_omega.clone()).collect();
            let down: Vec<(f64, O)> = up.iter().rev().cloned().collect();
            let capture = spec.early_stop.then_some(spec.capture);
            let sweep = |steps: &[(f64, O)]| {
                stepped_sweep_over(steps, rest, &spec.steady, capture, cancel, |_| {
                    progress.add(1)
                })
            };
            let (fw, bw) = rayon::join(|| sweep(&up), || sweep(&down));
            let (fw, mut bw) = (fw?, bw?);
            bw.reverse();
            for (i, responses) in per_omega.iter_mut().enumerate() {
                for r in responses
                    .iter_mut()
                    .filter(|r| r.steady.class == Class::Periodic)
                {
                    let reached = [&fw[i], &bw[i]]
                        .iter()
                        .any(|step| same_attractor(&step.steady, &r.steady, SWEEP_MATCH_TOL));
                    r.hidden = Some(!reached);
                }
            }
            (fw, bw)
        } else {
            (Vec::new(), Vec::new())
        };
        let mut responses: Vec<Response> = per_omega.into_iter().flatten().collect();
        let branches = link_branches(&mut responses, omegas.len());
        Ok(FrequencyResponse {
            omegas: omegas.clone(),
            responses,
            branches,
            forward,
            backward,
        })
    }
}

/// Sweep states converge to 1e-9 like the grid's; allow a little more for the different start.
const SWEEP_MATCH_TOL: f64 = 1e-4;

/// Same attractor, or the same non-periodic/collision class.
fn same_response(a: &SteadyState, b: &SteadyState) -> bool {
    match a.class {
        Class::Periodic => same_attractor(a, b, SAME_POINT_TOL),
        other => b.class == other,
    }
}

/// What the neighbour seeding of one ω_e has done so far.
#[derive(Debug, Clone, Default)]
struct Seeding {
    /// Responses of the neighbours below and above already integrated here.
    used: [usize; 2],
    /// This ω_e's responses with their capture regions, verified once and kept (None
    /// inside for a model that cannot verify them).
    known: Option<Option<KnownAttractors>>,
}

/// Integrates the periodic responses of ω_e index `from` not yet seeded at index `i`; adds
/// what is new.
fn seed_from<O: Oscillator>(
    per_omega: &mut [Vec<Response>],
    seeding: &mut Seeding,
    i: usize,
    from: usize,
    (omega, params): (f64, &O),
    spec: &FrequencyResponseSpec,
    cancel: &std::sync::atomic::AtomicBool,
) -> Result<usize, AnalysisError> {
    let used = &mut seeding.used[usize::from(from > i)];
    let seeds: Vec<O::State> = per_omega[from][*used..]
        .iter()
        .filter(|r| r.steady.class == Class::Periodic)
        .flat_map(|r| params.poincare_states(&r.steady))
        .collect();
    *used = per_omega[from].len();
    if seeds.is_empty() {
        return Ok(0);
    }
    // the responses found here, and those seeding adds (learnt as they are reached)
    let known = seeding.known.get_or_insert_with(|| {
        let mut known = params.known_attractors(&spec.steady, spec.capture)?;
        let found: Vec<SteadyState> = per_omega[i].iter().map(|r| r.steady.clone()).collect();
        known.learn_all(&found, SAME_POINT_TOL, Verification::OneReturn);
        Some(known)
    });
    let outcomes =
        params.steady_states(&seeds, &spec.steady, known.as_mut(), cancel, &mut |_| {})?;
    let mut new = 0;
    for s in outcomes {
        if s.class == Class::Periodic && !per_omega[i].iter().any(|r| same_response(&r.steady, &s))
        {
            per_omega[i].push(Response {
                omega_index: i,
                omega,
                steady: s,
                count: 0,
                share: 0.0,
                seeded: true,
                hidden: None,
                branch: None,
            });
            new += 1;
        }
    }
    Ok(new)
}

/// Distance between two periodic responses' Poincaré sets (best cyclic alignment).
fn set_distance(a: &SteadyState, b: &SteadyState) -> f64 {
    let (p, q) = (&a.poincare, &b.poincare);
    let k = p.len();
    if k == 0 || k != q.len() {
        return f64::INFINITY;
    }
    (0..k)
        .map(|shift| {
            (0..k)
                .map(|j| {
                    let (u, w) = (p[j], q[(j + shift) % k]);
                    (u[0] - w[0]).abs().max((u[1] - w[1]).abs())
                })
                .fold(0.0, f64::max)
        })
        .fold(f64::INFINITY, f64::min)
}

/// The chain (union-find root) response `i` belongs to.
fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// One pass of joins across gaps of one ω_e step (see [`link_branches`]); returns how many
/// chains were joined.
fn join_across_gaps(
    responses: &[Response],
    parent: &mut [usize],
    by_omega: &[Vec<usize>],
) -> usize {
    let mut joined = 0;
    for w in 1..by_omega.len().saturating_sub(1) {
        let mut pairs = Vec::new();
        for &a in &by_omega[w - 1] {
            for &b in &by_omega[w + 1] {
                let (ra, rb) = (root(parent, a), root(parent, b));
                let missing_here = by_omega[w].iter().all(|&r| {
                    let rr = root(parent, r);
                    rr != ra && rr != rb
                });
                if ra == rb || !missing_here {
                    continue;
                }
                let slopes = [
                    chain_step(responses, parent, by_omega, a, -1),
                    chain_step(responses, parent, by_omega, b, 1),
                ];
                if let Some(mismatch) =
                    gap_mismatch(&responses[a].steady, &responses[b].steady, slopes)
                {
                    pairs.push((mismatch, a, b));
                }
            }
        }
        joined += join_closest(parent, pairs);
    }
    joined
}

/// Links the pairs `(mismatch, a, b)`, least mismatch first, each response at most once on
/// each side; returns how many links were made.
fn join_closest(parent: &mut [usize], mut pairs: Vec<(f64, usize, usize)>) -> usize {
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
    let (mut used_a, mut used_b) = (Vec::new(), Vec::new());
    for (_, a, b) in pairs {
        if !used_a.contains(&a) && !used_b.contains(&b) {
            used_a.push(a);
            used_b.push(b);
            let (ra, rb) = (root(parent, a), root(parent, b));
            parent[rb.max(ra)] = ra.min(rb);
        }
    }
    used_a.len()
}

/// How response `r`'s chain changes per ω_e step next to it, towards `side` (−1 below, +1
/// above): the change of amplitude and the distance between the Poincaré sets, from the
/// chain's nearest member within two steps; `None` where the chain has none there.
fn chain_step(
    responses: &[Response],
    parent: &mut [usize],
    by_omega: &[Vec<usize>],
    r: usize,
    side: isize,
) -> Option<(f64, f64)> {
    let w = responses[r].omega_index as isize;
    let chain = root(parent, r);
    (1..=2).find_map(|steps: isize| {
        let at = usize::try_from(w + side * steps).ok()?;
        let &m = by_omega
            .get(at)?
            .iter()
            .find(|&&m| root(parent, m) == chain)?;
        let (x, y) = (&responses[r].steady, &responses[m].steady);
        let amplitude = (x.amplitude? - y.amplitude?).abs();
        Some((amplitude / steps as f64, set_distance(x, y) / steps as f64))
    })
}

/// Whether periodic responses `a` and `b`, two ω_e steps apart with none between, continue
/// each other: the same period and ratio, and the amplitude and the Poincaré set changing
/// across the two steps by at most three times the larger change per step next to the gap
/// (`slopes`: below `a`, above `b`; twice a step's change, and as much again for the
/// curvature). Returns how far they are from that bound (0 to 1, less is closer), `None`
/// where they do not continue each other or no step next to the gap is known.
fn gap_mismatch(a: &SteadyState, b: &SteadyState, slopes: [Option<(f64, f64)>; 2]) -> Option<f64> {
    let same = a.class == Class::Periodic
        && b.class == Class::Periodic
        && a.period == b.period
        && a.ratio == b.ratio;
    if !same {
        return None;
    }
    let known: Vec<(f64, f64)> = slopes.into_iter().flatten().collect();
    if known.is_empty() {
        return None;
    }
    let step_amplitude = known.iter().map(|s| s.0).fold(0.0, f64::max);
    let step_set = known.iter().map(|s| s.1).fold(0.0, f64::max);
    let amplitude = (a.amplitude? - b.amplitude?).abs() / (GAP_SLACK * step_amplitude);
    let set = set_distance(a, b) / (GAP_SLACK * step_set);
    let mismatch = amplitude.max(set);
    (mismatch <= 1.0).then_some(mismatch)
}

/// Across a gap of one ω_e step (two steps from one side to the other), a branch's amplitude
/// and Poincaré set may change by this many times their change per step next to the gap.
const GAP_SLACK: f64 = 3.0;

/// Chains periodic responses of the same period and ratio across adjacent ω_e (closest pairs
/// first, each response linked at most once each way), joins chains across one ω_e where
/// neither has a response and they continue each other ([`gap_mismatch`]), and summarises
/// each chain.
fn link_branches(responses: &mut [Response], n_omega: usize) -> Vec<Branch> {
    let n = responses.len();
    let mut parent: Vec<usize> = (0..n).collect();
    let by_omega: Vec<Vec<usize>> = (0..n_omega)
        .map(|w| (0..n).filter(|&r| responses[r].omega_index == w).collect())
        .collect();
    for w in 1..n_omega {
        let mut pairs = Vec::new();
        for &a in &by_omega[w - 1] {
            for &b in &by_omega[w] {
                let (ra, rb) = (&responses[a].steady, &responses[b].steady);
                if ra.class == Class::Periodic
                    && rb.class == Class::Periodic
                    && ra.period == rb.period
                    && ra.ratio == rb.ratio
                {
                    let d = set_distance(ra, rb);
                    let amp = ra.amplitude.unwrap_or(0.0).max(rb.amplitude.unwrap_or(0.0));
                    if d < BRANCH_LINK_DISTANCE + 0.5 * amp {
                        pairs.push((d, a, b));
                    }
                }
            }
        }
        join_closest(&mut parent, pairs);
    }
    // chains broken by one ω_e where no start and no seed found the response (a coarse grid
    // of starts): joined across it where they continue each other, until no more join (a
    // join gives a chain the neighbour that tells how it changes next to another gap)
    while join_across_gaps(responses, &mut parent, &by_omega) > 0 {}
    let mut branches: Vec<Branch> = Vec::new();
    let mut id_of_root: Vec<Option<usize>> = vec![None; n];
    #[allow(clippy::needless_range_loop)] // r is also a node of the union-find
    for r in 0..n {
        if responses[r].steady.class != Class::Periodic {
            continue;
        }
        let root_r = root(&mut parent, r);
        let id = *id_of_root[root_r].get_or_insert_with(|| {
            let s = &responses[r].steady;
            branches.push(Branch {
                id: branches.len(),
                period: s.period.unwrap_or(0),
                ratio: s.ratio.unwrap_or(Ratio::new(0, 1)),
                response_type: s.response_type(),
                omega_min: f64::INFINITY,
                omega_max: f64::NEG_INFINITY,
                peak_amplitude: f64::NEG_INFINITY,
                peak_omega: 0.0,
                points: 0,
                hidden: true,
                partly_hidden: false,
            });
            branches.len() - 1
        });
        let resp = &mut responses[r];
        resp.branch = Some(id);
        let b = &mut branches[id];
        b.omega_min = b.omega_min.min(resp.omega);
        b.omega_max = b.omega_max.max(resp.omega);
        let amp = resp.steady.amplitude.unwrap_or(0.0);
        if amp > b.peak_amplitude {
            b.peak_amplitude = amp;
            b.peak_omega = resp.omega;
        }
        b.points += 1;
        let hidden = resp.hidden.unwrap_or(false);
        b.hidden &= hidden;
        b.partly_hidden |= hidden;
    }
    branches
}
