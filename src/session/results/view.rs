//! What an analysis' result looks like once read back: plot-ready views, one type per kind
//! of result.

use std::collections::HashMap;

use crate::analysis::continuation::map::MapCell;
use crate::analysis::global::frequency_response::{Branch, Response};
use crate::analysis::orbit::attractor::AttractorTable;
use crate::analysis::orbit::time_history::{SteadySummary, periodic_summary, steady_summary};
use crate::analysis::{Ratio, SteadyState};

/// One response at one ω_e (a frequency response, a stepped sweep or a family member).
#[derive(Debug, Clone, PartialEq)]
pub struct ResponsePoint {
    pub omega: f64,
    /// Peak-to-peak amplitude of λ_I / 2 as in MODEL.md; `None` for collisions and
    /// non-periodic responses.
    pub amplitude: Option<f64>,
    /// `1:1`, `1:2`, `2:1`, `1:3 subharmonic`, `non-periodic`, `collision`...
    pub response_type: String,
    pub period: Option<usize>,
    pub ratio: Option<Ratio>,
    pub hidden: Option<bool>,
    pub branch: Option<usize>,
    /// Share of the sampled initial states that reached it.
    pub share: f64,
    /// A stroboscopic point of the orbit: where to start to see it again. The grid's two
    /// states ([λ_I, v]), then a written model's others in its order ([`start_of`]).
    pub start: Option<Vec<f64>>,
}

/// The first stroboscopic point of `s` as a [`ResponsePoint::start`]: its grid states (at
/// `grid` in the whole state), then the other states where `s` has them.
pub fn start_of(s: &SteadyState, grid: [usize; 2]) -> Option<Vec<f64>> {
    let mut start = s.poincare.first()?.to_vec();
    if let Some(x) = s.states.first() {
        start.extend(crate::model::system::outside_grid(x.len(), grid).map(|i| x[i]));
    }
    Some(start)
}

impl ResponsePoint {
    /// The point of a response of a model whose grid spans states `grid`.
    pub(crate) fn from_response(r: &Response, grid: [usize; 2]) -> Self {
        let mut p = Self::from_steady(r.omega, &r.steady, grid);
        p.hidden = r.hidden;
        p.branch = r.branch;
        p.share = r.share;
        p
    }

    fn from_steady(omega: f64, s: &SteadyState, grid: [usize; 2]) -> Self {
        ResponsePoint {
            omega,
            amplitude: s.amplitude,
            response_type: s.response_type(),
            period: s.period,
            ratio: s.ratio,
            hidden: None,
            branch: None,
            share: 0.0,
            start: start_of(s, grid),
        }
    }
}

/// The branches of `points` (grouped by branch id), as the frequency response made them.
pub fn branches(points: &[ResponsePoint]) -> Vec<Branch> {
    let mut by_id: Vec<Branch> = Vec::new();
    let mut hidden_count: HashMap<usize, usize> = HashMap::new();
    for p in points {
        let (Some(id), Some(a), Some(period), Some(ratio)) =
            (p.branch, p.amplitude, p.period, p.ratio)
        else {
            continue;
        };
        *hidden_count.entry(id).or_default() += usize::from(p.hidden == Some(true));
        match by_id.iter_mut().find(|b| b.id == id) {
            Some(b) => {
                b.omega_min = b.omega_min.min(p.omega);
                b.omega_max = b.omega_max.max(p.omega);
                b.points += 1;
                if a > b.peak_amplitude {
                    b.peak_amplitude = a;
                    b.peak_omega = p.omega;
                }
            }
            None => by_id.push(Branch {
                id,
                period,
                ratio,
                response_type: p.response_type.clone(),
                omega_min: p.omega,
                omega_max: p.omega,
                peak_amplitude: a,
                peak_omega: p.omega,
                points: 1,
                hidden: false,
                partly_hidden: false,
            }),
        }
    }
    for b in &mut by_id {
        let hidden = hidden_count[&b.id];
        b.hidden = hidden == b.points;
        b.partly_hidden = hidden > 0; // as the frequency response sets it: some, or all
    }
    by_id.sort_by_key(|b| b.id);
    by_id
}

/// One attractor of a basin, with its share of the cells.
#[derive(Debug, Clone, PartialEq)]
pub struct AttractorRow {
    pub id: usize,
    pub response_type: String,
    pub amplitude: Option<f64>,
    pub cells: usize,
    pub fraction: f64,
    /// As [`ResponsePoint::start`].
    pub start: Option<Vec<f64>>,
}

impl AttractorRow {
    /// The rows of `table`, each attractor's share counted over `cells` cells.
    pub(crate) fn of_table(
        table: &AttractorTable,
        cells: usize,
        grid: [usize; 2],
    ) -> Vec<AttractorRow> {
        table
            .attractors
            .iter()
            .map(|a| AttractorRow {
                id: a.id,
                response_type: a.response.response_type(),
                amplitude: a.response.amplitude,
                cells: a.count,
                fraction: a.count as f64 / cells as f64,
                start: start_of(&a.response, grid),
            })
            .collect()
    }
}

/// A basin map: `labels[i_dx · n_v + i_v]`, `None` for cells not computed yet.
#[derive(Debug, Clone, PartialEq)]
pub struct BasinView {
    pub dx: Vec<f64>,
    pub v: Vec<f64>,
    pub labels: Vec<Option<usize>>,
    pub attractors: Vec<AttractorRow>,
}

/// A time history.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct HistoryView {
    pub tau: Vec<f64>,
    pub lambda: Vec<f64>,
    pub v: Vec<f64>,
    /// True from the start of the steady state on.
    pub steady: Vec<bool>,
    /// The steady part's period, amplitude and slack shares, for the orbit's model.
    pub summary: Option<SteadySummary>,
    /// The names of the two states drawn, for a written model (λ_I and v otherwise).
    pub states: Option<[String; 2]>,
    /// A written model's output whose max − min is the amplitude, at each sample (empty for
    /// the built-in model, whose amplitude is of λ_I).
    pub output: Vec<f64>,
    /// τ where a collision ended a written model's orbit (its last sample), if one did.
    pub collision: Option<f64>,
}

impl HistoryView {
    /// The view with its steady part summarised for the orbit's model `p`.
    pub fn summarised(mut self, p: &crate::model::Params) -> Self {
        self.summary = steady_summary(p, &self.tau, &self.lambda, &self.v, &self.steady);
        self
    }

    /// A written model's view with its steady part summarised, the model forced at `omega`.
    pub fn summarised_written(mut self, omega: f64) -> Self {
        self.summary = periodic_summary(omega, &self.tau, &self.output, &self.steady);
        self
    }

    /// A written model's orbit forced at `omega`, drawn in the two states its grid spans
    /// (`grid`), its steady part summarised.
    pub fn of_states(
        h: &crate::analysis::global::oscillator::history::StateHistory,
        grid: [usize; 2],
        omega: f64,
    ) -> Self {
        let state = |i: usize| h.samples.iter().map(|s| s.state[i]).collect();
        HistoryView {
            tau: h.samples.iter().map(|s| s.tau).collect(),
            lambda: state(grid[0]),
            v: state(grid[1]),
            steady: h.samples.iter().map(|s| s.steady).collect(),
            summary: None,
            states: Some(grid.map(|i| h.states[i].clone())),
            output: h.samples.iter().map(|s| s.output).collect(),
            collision: h.collision.as_ref().map(|c| c.tau),
        }
        .summarised_written(omega)
    }
}

impl From<&crate::analysis::orbit::time_history::TimeHistory> for HistoryView {
    fn from(h: &crate::analysis::orbit::time_history::TimeHistory) -> Self {
        HistoryView {
            tau: h.samples.iter().map(|s| s.tau).collect(),
            lambda: h.samples.iter().map(|s| s.lambda).collect(),
            v: h.samples.iter().map(|s| s.v).collect(),
            steady: h.samples.iter().map(|s| s.steady).collect(),
            summary: None,
            states: None,
            output: Vec::new(),
            collision: None,
        }
    }
}

/// A chirp sweep: the response sampled every `dt`, and its envelope per window.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ChirpView {
    pub dt: f64,
    pub omega: Vec<f64>,
    pub lambda: Vec<f64>,
    /// (ω_e, amplitude) per window.
    pub envelope: Vec<[f64; 2]>,
}

/// Force curves: (λ_p, φ_I, points (Δλ, f)).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ForceView {
    pub curves: Vec<(f64, f64, Vec<[f64; 2]>)>,
}

/// A family: each member's responses and branches.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FamilyView {
    pub parameter: String,
    pub members: Vec<(f64, Vec<ResponsePoint>)>,
}

/// A point along a continued branch.
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuedPoint {
    /// Value of the continuation parameter.
    pub parameter: f64,
    pub omega: f64,
    pub amplitude: f64,
    pub stable: bool,
    /// The orbit's state [λ_I, v] at τ = 0.
    pub start: [f64; 2],
}

/// A located bifurcation on a continued branch.
#[derive(Debug, Clone, PartialEq)]
pub struct BifurcationPoint {
    /// `fold`, `period-doubling`, `parent-period-doubling`, `neimark-sacker`.
    pub kind: String,
    pub parameter: f64,
    pub omega: f64,
    pub amplitude: f64,
}

/// One continued branch read back.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ContinuedView {
    pub period: usize,
    /// `isola`, `attached`, `half-attached` or `open`.
    pub verdict: String,
    /// In order along the branch.
    pub points: Vec<ContinuedPoint>,
    pub bifurcations: Vec<BifurcationPoint>,
}

/// Continued branches in one parameter.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ContinuationView {
    /// The continuation parameter's name (`omega`, `adr`, ...).
    pub parameter: String,
    pub branches: Vec<ContinuedView>,
}

/// A hunt: the frequency response's points and its subharmonic branches continued in ω_e.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct HuntView {
    pub responses: Vec<ResponsePoint>,
    pub continued: Vec<ContinuedView>,
}

/// A two-parameter curve read back: (ω_e, value) in order, and its turning points.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CurveView {
    /// `fold` or `period-doubling`.
    pub kind: String,
    pub period: usize,
    pub points: Vec<[f64; 2]>,
    /// (`minimum`/`maximum`, of which parameter, [ω_e, value]).
    pub extrema: Vec<(String, String, [f64; 2])>,
}

/// A map over x (ω_e or a model parameter) and a model parameter (y): its cells by row
/// (`rows[row][column]`, `None` for rows not computed yet) and the curves over it.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MapView {
    /// Names of x (`omega`, ...) and y.
    pub x: String,
    pub parameter: String,
    /// The values of x.
    pub omegas: Vec<f64>,
    pub values: Vec<f64>,
    pub rows: Vec<Option<Vec<MapCell>>>,
    pub curves: Vec<CurveView>,
}

/// Plot-ready data of one analysis.
#[derive(Debug, Clone, PartialEq)]
pub enum ResultView {
    Force(ForceView),
    History(HistoryView),
    Chirp(ChirpView),
    Stepped(Vec<ResponsePoint>),
    Response(Vec<ResponsePoint>),
    Basin(BasinView),
    Family(FamilyView),
    Continuation(ContinuationView),
    Hunt(HuntView),
    Map(MapView),
}
