//! A coarse first picture of a basin or a frequency response, for the workbench to draw at
//! once while the full result is computed: about [`BUDGET`] trajectories, each integrated to
//! full convergence (no early stop, no seeding or sweeps), in memory. A basin's grid is
//! thinned alike along both axes, a response's starts to about every [`STRIDE`]th point a side
//! and then its ω to fit the budget; ends are kept, and every k-th point is taken exactly where
//! a k near the wanted stride divides the axis' steps (so the preview's starts are starts of the
//! full grid). It is never stored and never shown as
//! the result: the workbench draws it muted, under the result as it comes, and names it a
//! preview.

use std::sync::atomic::AtomicBool;

use rayon::prelude::*;

use super::results::{AttractorRow, BasinView, ResponsePoint, ResultView};
use super::schema::{AnalysisEntry, Session, Settings};
use super::written::ModelPoint;
use crate::analysis::global::basin::BasinSpec;
use crate::analysis::global::frequency_response::{FrequencyResponseSpec, ResponsePlan};
use crate::analysis::grid::Axis;
use crate::analysis::orbit::attractor::{AttractorTable, SAME_POINT_TOL};
use crate::analysis::{AnalysisError, Oscillator, Progress};

/// Trajectories in a preview, about: a few tens of milliseconds on two cores for the paper's
/// model.
pub const BUDGET: usize = 200;
/// A response's starts: about one in this many a side.
pub const STRIDE: usize = 8;
/// Starts integrated together (the lanes of the integrator), and handed to a core at a time.
const CELLS_PER_TASK: usize = 8;

/// The settings of the kinds that have a preview.
#[derive(Clone, Copy)]
enum Kind<'a> {
    Basin(&'a BasinSpec),
    Response(&'a FrequencyResponseSpec),
}

impl<'a> Kind<'a> {
    fn of(settings: &'a Settings) -> Option<Self> {
        match settings {
            Settings::Basin(spec) => Some(Kind::Basin(spec)),
            Settings::FrequencyResponse(spec) => Some(Kind::Response(spec)),
            _ => None,
        }
    }
}

/// True for the kinds [`coarse`] draws: basins and frequency responses.
pub fn available(settings: &Settings) -> bool {
    Kind::of(settings).is_some()
}

/// The coarse picture of `entry` (a basin or a frequency response), on the full grid of its
/// settings; `None` for the other kinds.
pub fn coarse(
    session: &Session,
    entry: &AnalysisEntry,
    progress: &Progress,
) -> Option<anyhow::Result<ResultView>> {
    let kind = Kind::of(&entry.settings)?;
    let named = |e: AnalysisError| anyhow::anyhow!("{}: {e}", entry.name);
    let grid = session.grid();
    Some(match session.point(Some(entry)) {
        Ok(ModelPoint::BuiltIn(params)) => picture(&params, kind, grid, progress).map_err(named),
        Ok(ModelPoint::Written(sys)) => picture(&sys, kind, grid, progress).map_err(named),
        Err(e) => Err(anyhow::anyhow!("{}: {e}", entry.name)),
    })
}

/// `axis` with about every `stride`-th point, its ends kept: every k-th point for the k in
/// [stride/2, 2·stride] nearest `stride` that divides its steps and gives no more points than
/// the stride itself would, else evenly spaced.
pub fn thinned(axis: &Axis, stride: usize) -> Axis {
    if axis.points <= 2 || stride <= 1 {
        return *axis;
    }
    let steps = axis.points - 1;
    let plain = steps.div_ceil(stride) + 1;
    let exact = (stride.div_ceil(2)..=2 * stride)
        .filter(|&k| steps.is_multiple_of(k) && steps / k < plain)
        .min_by_key(|k| k.abs_diff(stride));
    let points = exact.map_or(plain, |k| steps / k + 1);
    Axis::new(axis.min, axis.max, points)
}

/// The stride that brings `count` trajectories within [`BUDGET`] when applied along `axes`
/// axes alike.
pub fn stride_for(count: usize, axes: u32) -> usize {
    let shrink = count.div_ceil(BUDGET);
    (1..).find(|s: &usize| s.pow(axes) >= shrink).unwrap_or(1)
}

/// The index on `coarse` nearest to `value`.
pub fn nearest(coarse: &Axis, value: f64) -> usize {
    if coarse.points <= 1 || coarse.max == coarse.min {
        return 0;
    }
    let at = (value - coarse.min) / (coarse.max - coarse.min) * (coarse.points - 1) as f64;
    (at.round().max(0.0) as usize).min(coarse.points - 1)
}

/// The coarse picture of `kind` on `osc`, whose grid spans states `grid`.
fn picture<O: Oscillator>(
    osc: &O,
    kind: Kind,
    grid: [usize; 2],
    progress: &Progress,
) -> Result<ResultView, AnalysisError> {
    match kind {
        Kind::Basin(spec) => basin_picture(osc, spec, grid, progress),
        Kind::Response(spec) => response_picture(osc, spec, grid, progress),
    }
}

/// Every cell of the full grid takes the label of the nearest coarse start.
fn basin_picture<O: Oscillator>(
    osc: &O,
    spec: &BasinSpec,
    grid: [usize; 2],
    progress: &Progress,
) -> Result<ResultView, AnalysisError> {
    spec.validate()?;
    let stride = stride_for(spec.dx.points * spec.v.points, 2);
    let (coarse_dx, coarse_v) = (thinned(&spec.dx, stride), thinned(&spec.v, stride));
    let starts: Vec<O::State> = (0..coarse_dx.points * coarse_v.points)
        .map(|c| {
            let (i, j) = (c / coarse_v.points, c % coarse_v.points);
            osc.grid_start([coarse_dx.at(i), coarse_v.at(j)])
        })
        .collect();
    progress.grow_total(starts.len());
    let cancel: &AtomicBool = progress.cancel_flag();
    // a few starts per task, not the basin's chunks of 512 to 2048 cells: a coarse grid is one
    // or two of those
    let outcomes = starts
        .par_chunks(CELLS_PER_TASK)
        .map(|c| osc.steady_states(c, &spec.steady, None, cancel, &mut |_| progress.add(1)))
        .collect::<Result<Vec<_>, _>>()?;
    let mut table = AttractorTable::default();
    let coarse_labels: Vec<usize> = outcomes
        .iter()
        .flatten()
        .map(|s| table.classify(s, SAME_POINT_TOL))
        .collect();
    let (dx, v) = (spec.dx.values(), spec.v.values());
    let labels = dx
        .iter()
        .flat_map(|&x| {
            let ix = nearest(&coarse_dx, x);
            v.iter().map(move |&y| (ix, nearest(&coarse_v, y)))
        })
        .map(|(ix, iv)| coarse_labels.get(ix * coarse_v.points + iv).copied())
        .collect();
    let attractors = AttractorRow::of_table(&table, coarse_labels.len().max(1), grid);
    Ok(ResultView::Basin(BasinView {
        dx,
        v,
        labels,
        attractors,
    }))
}

/// The responses reached from the thinned grid of starts at the thinned ω.
fn response_picture<O: Oscillator>(
    osc: &O,
    spec: &FrequencyResponseSpec,
    grid: [usize; 2],
    progress: &Progress,
) -> Result<ResultView, AnalysisError> {
    let (dx, v) = (thinned(&spec.dx, STRIDE), thinned(&spec.v, STRIDE));
    let omega = thinned(
        &spec.omega,
        stride_for(spec.omega.points * dx.points * v.points, 1),
    );
    let coarse = FrequencyResponseSpec {
        omega,
        dx,
        v,
        early_stop: false,
        seed_neighbours: false,
        sweeps: false,
        ..spec.clone()
    };
    let plan = ResponsePlan::new(osc, &coarse)?;
    let per_omega = (0..coarse.omega.points)
        .into_par_iter()
        .map(|i| plan.grid_at(i, progress))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(ResultView::Response(
        per_omega
            .iter()
            .flatten()
            .map(|r| ResponsePoint::from_response(r, grid))
            .collect(),
    ))
}
