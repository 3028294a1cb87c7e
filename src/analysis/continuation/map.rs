//! Two-parameter maps: over x (ω_e or a model parameter) × y (a model parameter), how many
//! stable responses coexist, the largest amplitude and its type, and whether a hidden
//! response exists there (one that neither a forward nor a backward quasi-static sweep of x
//! reaches: with x = ω_e the paper's definition), each row a response from many initial
//! states; with the fold and period-doubling curves of the subharmonic branches (and, if
//! asked, the hidden ones of any period) continued in both parameters drawn over it.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::analysis::AnalysisError;
use crate::analysis::continuation::bifurcation_curve::{
    BifurcationCurve, CurveSpec, continue_bifurcation,
};
use crate::analysis::continuation::branch::{
    BifurcationKind, BranchEnd, ContinuationSpec, ContinuedBranch, continue_branch,
};
use crate::analysis::continuation::model::Continuable;
use crate::analysis::global::frequency_response::{
    FrequencyResponse, FrequencyResponseSpec, Work, frequency_response_over,
};
use crate::analysis::grid::Axis;
use crate::analysis::orbit::steady_state::Class;
use crate::analysis::parameter::ContinuationParameter;
use crate::analysis::parameter::FamilyParameter;
use crate::analysis::progress::Progress;
use crate::model::error::ParamError;
use crate::model::system::StateVec;

/// Points a curve may take each way in a map (they are drawn, not studied).
const MAP_CURVE_POINTS: usize = 400;

/// A map over the response's grid of `x` (its `omega` axis holds x's values) and `values`
/// of `parameter` (y).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MapSpec {
    /// The parameter along each row (ω_e unless given).
    #[serde(default = "omega")]
    pub x: ContinuationParameter,
    pub parameter: FamilyParameter,
    pub values: Axis,
    #[serde(default)]
    pub response: FrequencyResponseSpec,
    /// Continue the folds and period doublings of the subharmonic branches in both
    /// parameters (from the row with the most such branches).
    #[serde(default = "yes")]
    pub curves: bool,
    /// Continue the hidden branches of any period too (a 1:1 isola, as a Duffing
    /// oscillator's, is not subharmonic).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub hidden_branches: bool,
}

fn yes() -> bool {
    true
}

fn omega() -> ContinuationParameter {
    ContinuationParameter::Omega
}

impl MapSpec {
    /// Checks the values (each a valid model with `base`, 1 to 1000 rows) and the response.
    pub fn validate<M: Continuable>(&self, base: &M) -> Result<(), ParamError> {
        let rows = base.resolve(ContinuationParameter::Model(self.parameter))?;
        let x = base.resolve(self.x).map_err(|e| e.within("x"))?;
        if x == rows {
            return Err(ParamError {
                field: "x".into(),
                value: ParamError::NOT_NUMERIC,
                allowed: format!(
                    "a parameter other than the rows' ({})",
                    self.parameter.name()
                ),
            });
        }
        self.values.validate("values", 1000)?;
        for (field, v) in [
            ("values.min", self.values.min),
            ("values.max", self.values.max),
        ] {
            base.with(rows, v).map_err(|e| e.as_value_of(field))?;
        }
        if x != base.frequency() {
            for (field, v) in [
                ("response.omega.min", self.response.omega.min),
                ("response.omega.max", self.response.omega.max),
            ] {
                base.with(x, v).map_err(|e| e.as_value_of(field))?;
            }
        }
        self.response.validate().map_err(|e| e.within("response"))
    }
}

/// One cell: the responses at one (ω_e, value).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapCell {
    /// Distinct periodic responses (attractors, so stable).
    pub stable: usize,
    pub largest_amplitude: Option<f64>,
    /// e.g. `1:2` of the largest.
    pub largest_type: Option<String>,
    /// A periodic response there that neither stepped sweep reaches.
    pub hidden: bool,
    /// A response of period ≥ 2 there.
    pub subharmonic: bool,
    /// Share of the sampled initial states that collide.
    pub collision_share: f64,
    /// Share that end non-periodic.
    pub non_periodic_share: f64,
}

/// Where a subharmonic branch of a row can be continued from: its largest response.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BranchSeed {
    pub period: usize,
    /// The value of x there.
    pub at: f64,
    /// The response's state at τ = 0.
    pub x: StateVec,
}

/// A row of the map: one value of the parameter.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapRow {
    pub value: f64,
    /// One per value of x.
    pub cells: Vec<MapCell>,
    pub seeds: Vec<BranchSeed>,
}

/// The cells of a response (against ω_e or another x), one per value, and the seeds of its
/// subharmonic branches (and of its hidden ones, with `hidden`).
pub fn summarise<M: Continuable>(
    model: &M,
    value: f64,
    fr: &FrequencyResponse,
    hidden: bool,
) -> MapRow {
    let cells = (0..fr.omegas.len())
        .map(|i| {
            let here: Vec<_> = fr.at(i).collect();
            let periodic: Vec<_> = here
                .iter()
                .filter(|r| r.steady.class == Class::Periodic)
                .collect();
            let share = |class: Class| {
                here.iter()
                    .filter(|r| r.steady.class == class)
                    .map(|r| r.share)
                    .fold(0.0, |a, b| a + b)
            };
            let largest = periodic
                .iter()
                .filter(|r| r.steady.amplitude.is_some())
                .max_by(|a, b| amplitude(a).total_cmp(&amplitude(b)));
            MapCell {
                stable: periodic.len(),
                largest_amplitude: largest.and_then(|r| r.steady.amplitude),
                largest_type: largest.map(|r| {
                    let t = r.steady.response_type();
                    t.split_whitespace().next().unwrap_or(&t).to_string()
                }),
                hidden: periodic.iter().any(|r| r.hidden == Some(true)),
                subharmonic: periodic.iter().any(|r| r.steady.period.unwrap_or(1) >= 2),
                collision_share: share(Class::Collision),
                non_periodic_share: share(Class::NonPeriodic),
            }
        })
        .collect();
    let seeds = fr
        .branches
        .iter()
        .filter(|b| b.is_subharmonic() || (hidden && b.hidden))
        .filter_map(|b| {
            let peak = fr.peak(b.id)?;
            Some(BranchSeed {
                period: b.period,
                at: peak.omega,
                x: model.state_vec(model.poincare_states(&peak.steady).first()?),
            })
        })
        .collect();
    MapRow {
        value,
        cells,
        seeds,
    }
}

/// Row `i` of the map (on the whole pool); its work, [`FrequencyResponseSpec::work`], is
/// announced on `progress` by the caller.
pub fn map_row<M: Continuable>(
    params: &M,
    spec: &MapSpec,
    i: usize,
    progress: &Progress,
) -> Result<MapRow, AnalysisError> {
    let value = spec.values.at(i);
    let p = params.with(
        params.resolve(ContinuationParameter::Model(spec.parameter))?,
        value,
    )?;
    let x = p.resolve(spec.x)?;
    let fr = frequency_response_over(&p, &spec.response, x, progress, Work::Announced)?;
    Ok(summarise(&p, value, &fr, spec.hidden_branches))
}

/// A map's curves, and the subharmonic branches its x window cuts.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MapCurves {
    pub curves: Vec<BifurcationCurve>,
    /// Branches of the row the curves start from that reach an edge of the x window: their
    /// folds and period doublings beyond it, and so their curves, are not drawn.
    pub cut: Vec<WindowCut>,
}

/// A subharmonic branch that leaves a map's x window.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WindowCut {
    pub period: usize,
    /// The map parameter's value of the row it was continued at.
    pub value: f64,
    /// Where it reaches the window's edges, in x.
    pub edges: Vec<f64>,
}

impl WindowCut {
    /// `the 1:2 branch at adr = 0.6 leaves the omega window at omega = 4.5: ...`.
    pub fn describe(&self, x: &str, parameter: &str) -> String {
        let edges: Vec<String> = self.edges.iter().map(|e| e.to_string()).collect();
        format!(
            "the 1:{} branch at {parameter} = {} leaves the {x} window at {x} = {}: its folds \
             and period doublings beyond are not in the map (widen the window to draw their \
             curves)",
            self.period,
            self.value,
            edges.join(" and ")
        )
    }
}

/// The fold and period-doubling curves of the subharmonic branches of the row with the most
/// of them, continued over the map's ω_e and parameter ranges, and which of those branches
/// the window cuts. Branches that cannot be continued are skipped (a map is drawn even if a
/// curve is missing). Branches of different periods, and curves of different kinds or
/// periods, are continued side by side; the result is the one of taking them in turn.
pub fn map_curves<M: Continuable>(
    params: &M,
    spec: &MapSpec,
    rows: &[MapRow],
    progress: &Progress,
) -> Result<MapCurves, AnalysisError> {
    let Some(row) = rows.iter().rev().max_by_key(|r| r.seeds.len()) else {
        return Ok(MapCurves::default());
    };
    let (w_lo, w_hi) = (
        spec.response.omega.min.min(spec.response.omega.max),
        spec.response.omega.min.max(spec.response.omega.max),
    );
    let (v_lo, v_hi) = (
        spec.values.min.min(spec.values.max),
        spec.values.min.max(spec.values.max),
    );
    let base = params.with(
        params.resolve(ContinuationParameter::Model(spec.parameter))?,
        row.value,
    )?;
    let x = base.resolve(spec.x)?;
    // arclength steps no longer than a fiftieth of the window in x (a third of the narrower
    // window for the curves), so that a narrow window is not stepped across
    let branch_default = ContinuationSpec::default();
    let step_max = branch_default.step_max.min((w_hi - w_lo) / 50.0);
    let in_x = ContinuationSpec {
        parameter: spec.x,
        min: w_lo,
        max: w_hi,
        step: branch_default.step.min(step_max),
        step_max,
        ..branch_default
    };
    let curve_default = CurveSpec::default();
    let curve_step_max = curve_default
        .step_max
        .min((w_hi - w_lo).min(v_hi - v_lo) / 3.0);
    let curve_spec = CurveSpec {
        second: ContinuationParameter::Model(spec.parameter),
        min: v_lo,
        max: v_hi,
        first_min: w_lo,
        first_max: w_hi,
        step: curve_default.step.min(curve_step_max),
        step_max: curve_step_max,
        step_min: curve_default.step_min.min(0.01 * curve_step_max),
        max_points: MAP_CURVE_POINTS,
        ..curve_default
    };
    // a seed lies on a branch already continued only if of its period
    let branches = in_turn_by_group(
        row.seeds.iter(),
        |seed| seed.period,
        |found: &[ContinuedBranch], seed| {
            let on_known = found
                .iter()
                .any(|b| b.passes_through(&base, seed.at, &[seed.x], 1e-4, &in_x.shooting));
            if on_known {
                return Ok(None);
            }
            let p = base.with(x, seed.at)?;
            Ok(continue_branch(&p, seed.period, &seed.x, &in_x, progress).ok())
        },
    )?;
    let cut = branches
        .iter()
        .filter_map(|b| {
            // both ends of a cut isola may stop at the same edge
            let mut edges: Vec<f64> = b
                .ends
                .iter()
                .filter_map(|e| match e {
                    BranchEnd::Bound { value } => Some(*value),
                    _ => None,
                })
                .collect();
            edges.sort_by(f64::total_cmp);
            edges.dedup();
            (!edges.is_empty()).then_some(WindowCut {
                period: b.period,
                value: row.value,
                edges,
            })
        })
        .collect();
    let kind_of = |k: BifurcationKind| match k {
        BifurcationKind::Fold => BifurcationKind::Fold,
        _ => BifurcationKind::PeriodDoubling,
    };
    let starts = branches.iter().flat_map(|b| {
        b.bifurcations.iter().filter(|f| {
            matches!(
                f.kind,
                BifurcationKind::Fold
                    | BifurcationKind::PeriodDoubling
                    | BifurcationKind::ParentPeriodDoubling
            )
        })
    });
    // a curve is drawn already only by one of its kind and period
    let curves = in_turn_by_group(
        starts,
        |bif| (kind_of(bif.kind), bif.period),
        |found: &[BifurcationCurve], bif| {
            // already drawn: a curve of the same kind and period through this point
            let drawn = found.iter().any(|c| {
                c.points.windows(2).any(|w| {
                    let (a, z) = (&w[0], &w[1]);
                    (a.second - row.value) * (z.second - row.value) <= 0.0
                        && (a.first.min(z.first) - 1e-6..=a.first.max(z.first) + 1e-6)
                            .contains(&bif.parameter)
                })
            });
            if drawn {
                return Ok(None);
            }
            match continue_bifurcation(&base, spec.x, bif, &curve_spec, progress) {
                Ok(c) => Ok(Some(c)),
                Err(crate::analysis::continuation::branch::ContinuationError::Cancelled) => {
                    Err(AnalysisError::Cancelled)
                }
                Err(e) => {
                    tracing::warn!(at = bif.parameter, "no curve from this bifurcation: {e}");
                    Ok(None)
                }
            }
        },
    )?;
    Ok(MapCurves { curves, cut })
}

/// What `take` finds from `items` taken in turn, `take` seeing what it found before from
/// items of the same `key` (only those can make it skip one): the groups of equal keys side
/// by side, each in turn, and what they find put back in the items' order. The same as one
/// loop over `items` whose `take` looked only at its own group's findings.
fn in_turn_by_group<T: Send, K: PartialEq, R: Send>(
    items: impl Iterator<Item = T>,
    key: impl Fn(&T) -> K,
    take: impl Fn(&[R], &T) -> Result<Option<R>, AnalysisError> + Sync,
) -> Result<Vec<R>, AnalysisError> {
    let mut groups: Vec<(K, Vec<(usize, T)>)> = Vec::new();
    for (i, item) in items.enumerate() {
        let k = key(&item);
        match groups.iter_mut().find(|(g, _)| *g == k) {
            Some((_, members)) => members.push((i, item)),
            None => groups.push((k, vec![(i, item)])),
        }
    }
    let groups: Vec<Vec<(usize, T)>> = groups.into_iter().map(|(_, members)| members).collect();
    let found: Vec<Vec<(usize, R)>> = groups
        .into_par_iter()
        .map(|members| {
            let (mut at, mut found) = (Vec::new(), Vec::new());
            for (i, item) in members {
                if let Some(r) = take(&found, &item)? {
                    at.push(i);
                    found.push(r);
                }
            }
            Ok(at.into_iter().zip(found).collect())
        })
        .collect::<Result<_, AnalysisError>>()?;
    let mut all: Vec<(usize, R)> = found.into_iter().flatten().collect();
    all.sort_by_key(|(i, _)| *i);
    Ok(all.into_iter().map(|(_, r)| r).collect())
}

/// A response's amplitude, −∞ for none (collision, non-periodic).
fn amplitude(r: &crate::analysis::global::frequency_response::Response) -> f64 {
    r.steady.amplitude.unwrap_or(f64::NEG_INFINITY)
}

/// The whole map: rows side by side (each also spreads its frequencies over the pool, but
/// its seeding and sweeps are mostly sequential), in order, then the curves.
pub fn map<M: Continuable>(
    params: &M,
    spec: &MapSpec,
    progress: &Progress,
) -> Result<(Vec<MapRow>, MapCurves), AnalysisError> {
    spec.validate(params)?;
    progress.grow_total(spec.values.points * spec.response.work());
    let rows = (0..spec.values.points)
        .into_par_iter()
        .map(|i| map_row(params, spec, i, progress))
        .collect::<Result<Vec<_>, _>>()?;
    let curves = if spec.curves {
        map_curves(params, spec, &rows, progress)?
    } else {
        MapCurves::default()
    };
    Ok((rows, curves))
}
