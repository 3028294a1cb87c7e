//! Convergence: a session's analyses rerun at twice the resolution, and what changed.
//!
//! The doubled run is a session of its own, kept in `NAME.results/convergence.results/`
//! (checkpointed and resumable like any run, current until the session's settings change):
//! it never replaces the session's own result.

use serde::Serialize;

use super::results::{
    AttractorRow, BasinView, ContinuedView, HistoryView, ResponsePoint, ResultReader, ResultStatus,
    ResultView, branches,
};
use super::schema::{AnalysisEntry, Session};
use crate::model::ParamError;

/// Two amplitudes closer than this (in λ_I) are the same response seen at two resolutions;
/// distinct responses at one ω_e differ by far more, resolution errors by far less.
pub const SAME_RESPONSE: f64 = 1e-3;

/// `session` with every analysis at twice the resolution, its results in
/// `NAME.results/convergence.results/`. An error names the analysis and the setting that
/// doubling would take out of its range.
pub fn at_twice_the_resolution(session: &Session) -> Result<Session, ParamError> {
    let mut doubled = session.clone();
    doubled.path = session.results_dir().join("convergence.toml");
    for entry in &mut doubled.analyses {
        entry.settings = entry.settings.at_twice_the_resolution().map_err(|e| {
            let field = format!(
                "analysis '{}' at twice the resolution: {}",
                entry.name, e.field
            );
            ParamError { field, ..e }
        })?;
    }
    Ok(doubled)
}

/// The complete, current result of `entry` in `session`, as a view (`None` if there is none).
pub fn stored_view(session: &Session, entry: &AnalysisEntry) -> Option<ResultView> {
    let mut reader = ResultReader::new(entry);
    reader.poll(session, entry);
    (reader.status == ResultStatus::Complete)
        .then_some(reader.view)
        .flatten()
}

/// What changed between an analysis' result and the same at twice the resolution.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Changes {
    Basin(BasinChanges),
    /// A frequency response or a stepped sweep.
    Responses(ResponseChanges),
    Family {
        members: Vec<MemberChanges>,
    },
    /// A hunt: its frequency response, and its continued branches' bifurcations.
    Hunt {
        responses: ResponseChanges,
        bifurcations: NumberChanges,
    },
    /// A map: its cells' counts of stable responses and their largest amplitudes.
    Map(MapChanges),
    /// Time histories, chirp sweeps, continuations: the largest difference of the numbers.
    Numbers(NumberChanges),
    /// Force curves integrate nothing.
    Nothing,
}

/// An attractor or response, as the two runs are matched on.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Seen {
    /// ω_e, for a response of a frequency response.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub omega: Option<f64>,
    pub response_type: String,
    pub amplitude: Option<f64>,
}

/// A basin's cells whose attractor changed, and the attractors gained and lost.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BasinChanges {
    pub cells: usize,
    pub changed: usize,
    /// `changed` / `cells`.
    pub share: f64,
    pub gained: Vec<Seen>,
    pub lost: Vec<Seen>,
    /// The largest amplitude difference of an attractor found by both.
    pub largest_amplitude_difference: f64,
}

/// One branch whose ω_e edges moved: [at the resolution, at twice it].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EdgesMoved {
    pub response_type: String,
    pub omega_min: [f64; 2],
    pub omega_max: [f64; 2],
}

/// A frequency response's responses gained and lost, its branches' edges moved, and the
/// largest amplitude difference of a response found by both.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResponseChanges {
    /// Periodic responses, and other outcomes (collision, non-periodic) over the ω_e grid.
    pub responses: usize,
    pub outcomes: usize,
    pub gained: Vec<Seen>,
    pub lost: Vec<Seen>,
    pub branches: usize,
    pub edges_moved: Vec<EdgesMoved>,
    pub branches_gained: Vec<Seen>,
    pub branches_lost: Vec<Seen>,
    pub largest_amplitude_difference: f64,
}

/// A family member's changes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MemberChanges {
    pub value: f64,
    #[serde(flatten)]
    pub changes: ResponseChanges,
}

/// A map's cells whose count of stable responses or largest response changed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MapChanges {
    pub cells: usize,
    pub changed: usize,
    pub largest_amplitude_difference: f64,
}

/// The largest difference of an analysis' main numbers, and what they are.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NumberChanges {
    /// What was compared (`λ_I at each sample`...).
    pub of: String,
    /// How many numbers both runs have, and how many only one of them has.
    pub compared: usize,
    pub unmatched: usize,
    pub largest_difference: f64,
}

/// What changed from `base` to `doubled`, the same analysis at twice the resolution.
pub fn compare(base: &ResultView, doubled: &ResultView) -> Changes {
    match (base, doubled) {
        (ResultView::Basin(a), ResultView::Basin(b)) => Changes::Basin(basin_changes(a, b)),
        (ResultView::Response(a), ResultView::Response(b))
        | (ResultView::Stepped(a), ResultView::Stepped(b)) => {
            Changes::Responses(response_changes(a, b))
        }
        (ResultView::Family(a), ResultView::Family(b)) => Changes::Family {
            members: a
                .members
                .iter()
                .zip(&b.members)
                .map(|((value, a), (_, b))| MemberChanges {
                    value: *value,
                    changes: response_changes(a, b),
                })
                .collect(),
        },
        (ResultView::Hunt(a), ResultView::Hunt(b)) => Changes::Hunt {
            responses: response_changes(&a.responses, &b.responses),
            bifurcations: bifurcation_changes(&a.continued, &b.continued),
        },
        (ResultView::Continuation(a), ResultView::Continuation(b)) => {
            Changes::Numbers(bifurcation_changes(&a.branches, &b.branches))
        }
        (ResultView::History(a), ResultView::History(b)) => Changes::Numbers(history_changes(a, b)),
        (ResultView::Chirp(a), ResultView::Chirp(b)) => Changes::Numbers(differences(
            "the envelope's amplitude in each window",
            &a.envelope.iter().map(|e| e[1]).collect::<Vec<_>>(),
            &b.envelope.iter().map(|e| e[1]).collect::<Vec<_>>(),
        )),
        (ResultView::Map(a), ResultView::Map(b)) => {
            let cells: Vec<_> = a.rows.iter().flatten().flatten().collect();
            let other: Vec<_> = b.rows.iter().flatten().flatten().collect();
            let mut changes = MapChanges {
                cells: cells.len(),
                changed: 0,
                largest_amplitude_difference: 0.0,
            };
            for (x, y) in cells.iter().zip(&other) {
                let same_largest = match (x.largest_amplitude, y.largest_amplitude) {
                    (Some(p), Some(q)) if (p - q).abs() <= SAME_RESPONSE => {
                        changes.largest_amplitude_difference =
                            changes.largest_amplitude_difference.max((p - q).abs());
                        x.largest_type == y.largest_type
                    }
                    (None, None) => true,
                    _ => false,
                };
                changes.changed += usize::from(x.stable != y.stable || !same_largest);
            }
            Changes::Map(changes)
        }
        _ => Changes::Nothing,
    }
}

/// Pairs `a`'s items with `b`'s of the same type whose amplitudes are within
/// [`SAME_RESPONSE`], nearest first: `pairs[i]` is the index in `b` matched to `a[i]`.
fn match_seen(a: &[Seen], b: &[Seen]) -> Vec<Option<usize>> {
    let mut candidates: Vec<(f64, usize, usize)> = Vec::new();
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            if x.response_type != y.response_type || x.omega != y.omega {
                continue;
            }
            let gap = match (x.amplitude, y.amplitude) {
                (Some(p), Some(q)) => (p - q).abs(),
                (None, None) => 0.0,
                _ => continue,
            };
            if gap <= SAME_RESPONSE {
                candidates.push((gap, i, j));
            }
        }
    }
    candidates.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut pairs = vec![None; a.len()];
    let mut taken = vec![false; b.len()];
    for (_, i, j) in candidates {
        if pairs[i].is_none() && !taken[j] {
            pairs[i] = Some(j);
            taken[j] = true;
        }
    }
    pairs
}

/// The items of `b` no item of `a` is matched to.
fn unmatched(b: &[Seen], pairs: &[Option<usize>]) -> Vec<Seen> {
    (0..b.len())
        .filter(|j| !pairs.contains(&Some(*j)))
        .map(|j| b[j].clone())
        .collect()
}

/// The largest amplitude difference over the matched pairs.
fn largest_gap(a: &[Seen], b: &[Seen], pairs: &[Option<usize>]) -> f64 {
    pairs
        .iter()
        .enumerate()
        .filter_map(|(i, j)| Some((a[i].amplitude? - b[(*j)?].amplitude?).abs()))
        .fold(0.0, f64::max)
}

fn attractor_seen(r: &AttractorRow) -> Seen {
    Seen {
        omega: None,
        response_type: r.response_type.clone(),
        amplitude: r.amplitude,
    }
}

fn basin_changes(a: &BasinView, b: &BasinView) -> BasinChanges {
    let seen_a: Vec<Seen> = a.attractors.iter().map(attractor_seen).collect();
    let seen_b: Vec<Seen> = b.attractors.iter().map(attractor_seen).collect();
    let pairs = match_seen(&seen_a, &seen_b);
    // attractor id in `a` → the id of the same attractor in `b`
    let same = |id: usize| {
        let i = a.attractors.iter().position(|r| r.id == id)?;
        Some(b.attractors[pairs[i]?].id)
    };
    let changed = a
        .labels
        .iter()
        .zip(&b.labels)
        .filter(|&(x, y)| x.is_none() || x.and_then(same) != *y)
        .count();
    let cells = a.labels.len();
    BasinChanges {
        cells,
        changed,
        share: changed as f64 / cells.max(1) as f64,
        lost: (0..seen_a.len())
            .filter(|&i| pairs[i].is_none())
            .map(|i| seen_a[i].clone())
            .collect(),
        gained: unmatched(&seen_b, &pairs),
        largest_amplitude_difference: largest_gap(&seen_a, &seen_b, &pairs),
    }
}

fn response_seen(p: &ResponsePoint) -> Seen {
    Seen {
        omega: Some(p.omega),
        response_type: p.response_type.clone(),
        amplitude: p.amplitude,
    }
}

fn response_changes(a: &[ResponsePoint], b: &[ResponsePoint]) -> ResponseChanges {
    let seen_a: Vec<Seen> = a.iter().map(response_seen).collect();
    let seen_b: Vec<Seen> = b.iter().map(response_seen).collect();
    let pairs = match_seen(&seen_a, &seen_b);
    let (branches_a, branches_b) = (branches(a), branches(b));
    // a branch is matched to the branch of the same type that shares most of its ω_e range
    let mut edges_moved = Vec::new();
    let mut matched_b = vec![false; branches_b.len()];
    let mut branches_lost = Vec::new();
    for x in &branches_a {
        let overlap = |y: &crate::analysis::global::frequency_response::Branch| {
            x.omega_max.min(y.omega_max) - x.omega_min.max(y.omega_min)
        };
        let best = branches_b
            .iter()
            .enumerate()
            .filter(|(j, y)| !matched_b[*j] && y.response_type == x.response_type)
            .filter(|(_, y)| overlap(y) >= 0.0)
            .max_by(|(_, y), (_, z)| overlap(y).total_cmp(&overlap(z)));
        match best {
            Some((j, y)) => {
                matched_b[j] = true;
                if (x.omega_min, x.omega_max) != (y.omega_min, y.omega_max) {
                    edges_moved.push(EdgesMoved {
                        response_type: x.response_type.clone(),
                        omega_min: [x.omega_min, y.omega_min],
                        omega_max: [x.omega_max, y.omega_max],
                    });
                }
            }
            None => branches_lost.push(Seen {
                omega: Some(x.peak_omega),
                response_type: x.response_type.clone(),
                amplitude: Some(x.peak_amplitude),
            }),
        }
    }
    let branches_gained = branches_b
        .iter()
        .zip(&matched_b)
        .filter(|(_, m)| !**m)
        .map(|(y, _)| Seen {
            omega: Some(y.peak_omega),
            response_type: y.response_type.clone(),
            amplitude: Some(y.peak_amplitude),
        })
        .collect();
    ResponseChanges {
        responses: a.iter().filter(|p| p.period.is_some()).count(),
        outcomes: a.iter().filter(|p| p.period.is_none()).count(),
        lost: (0..seen_a.len())
            .filter(|&i| pairs[i].is_none())
            .map(|i| seen_a[i].clone())
            .collect(),
        gained: unmatched(&seen_b, &pairs),
        branches: branches_a.len(),
        edges_moved,
        branches_gained,
        branches_lost,
        largest_amplitude_difference: largest_gap(&seen_a, &seen_b, &pairs),
    }
}

/// The located bifurcations (their parameter values), branch by branch and in order.
fn bifurcation_changes(a: &[ContinuedView], b: &[ContinuedView]) -> NumberChanges {
    let values = |branches: &[ContinuedView]| -> Vec<f64> {
        branches
            .iter()
            .flat_map(|c| c.bifurcations.iter().map(|p| p.parameter))
            .collect()
    };
    differences(
        "the continuation parameter at each located bifurcation",
        &values(a),
        &values(b),
    )
}

/// The first grid state (λ_I, or a written model's own) at each sample.
fn history_changes(a: &HistoryView, b: &HistoryView) -> NumberChanges {
    let state = a.states.as_ref().map_or("λ_I", |[first, _]| first.as_str());
    differences(&format!("{state} at each sample"), &a.lambda, &b.lambda)
}

/// The largest difference of `a` and `b` over the numbers both have.
fn differences(of: &str, a: &[f64], b: &[f64]) -> NumberChanges {
    NumberChanges {
        of: of.into(),
        compared: a.len().min(b.len()),
        unmatched: a.len().abs_diff(b.len()),
        largest_difference: a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max),
    }
}
