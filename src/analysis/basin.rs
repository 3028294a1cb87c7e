//! Fig 6: basins of attraction on a grid of initial states (Δλ, v) at τ = 0.

use std::sync::Mutex;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::AnalysisError;
use super::attractor::{AttractorTable, SAME_POINT_TOL};
use super::batch::{KnownAttractors, steady_states};
use super::grid::Axis;
use super::progress::Progress;
use super::steady_state::{SteadyState, SteadyStateSpec};
use crate::model::Params;
use crate::model::error::check;

/// Largest grid a basin may ask for (about 16 million cells).
pub const MAX_CELLS: usize = 1 << 24;
/// Cells per unit of parallel work (and per partial result).
pub const CHUNK_CELLS: usize = 512;

/// A basin computation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BasinSpec {
    /// Initial displacements Δλ = λ_I − λ_p.
    pub dx: Axis,
    /// Initial velocities.
    pub v: Axis,
    pub steady: SteadyStateSpec,
    /// Stop trajectories that shadow an attractor already found (same classes, much faster).
    pub early_stop: bool,
    /// Shadowing distance for the early stop (max-norm on [λ_I, v]).
    pub capture: f64,
}

impl Default for BasinSpec {
    /// The paper's grid: 201 × 251 over Δλ ∈ [−0.8, 0.8], v ∈ [−1, 1].
    fn default() -> Self {
        BasinSpec {
            dx: Axis::new(-0.8, 0.8, 201),
            v: Axis::new(-1.0, 1.0, 251),
            steady: SteadyStateSpec::default(),
            early_stop: true,
            capture: 1e-3,
        }
    }
}

/// A finished basin: a label per cell (`labels[i_dx · n_v + i_v]`), and the attractors.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Basin {
    pub dx: Vec<f64>,
    pub v: Vec<f64>,
    pub labels: Vec<usize>,
    pub table: AttractorTable,
}

impl Basin {
    /// Share of the grid's cells that reach attractor `id`.
    pub fn fraction(&self, id: usize) -> f64 {
        self.table.attractors[id].count as f64 / self.labels.len() as f64
    }
}

/// Cells finished so far, for a live view: the outcomes of cells `start..start + len`.
#[derive(Debug, Clone)]
pub struct BasinChunk {
    pub start: usize,
    pub outcomes: Vec<SteadyState>,
}

/// Computes the basin of attraction of `params` over `spec`'s grid on the current rayon pool.
/// The result does not depend on the number of threads.
pub fn basin(
    params: &Params,
    spec: &BasinSpec,
    progress: &Progress,
    on_chunk: &(dyn Fn(BasinChunk) + Sync),
) -> Result<Basin, AnalysisError> {
    spec.dx.validate("dx", 1 << 14)?;
    spec.v.validate("v", 1 << 14)?;
    let cells = spec.dx.points * spec.v.points;
    check(
        "cells",
        cells as f64,
        |c| c <= MAX_CELLS as f64,
        format!("<= {MAX_CELLS}"),
    )?;
    check("capture", spec.capture, |c| c > 0.0 && c < 0.1, "(0, 0.1)")?;
    spec.steady.validate()?;
    let lambda_p = params.lambda_p();
    let ics: Vec<[f64; 2]> = (0..cells)
        .map(|c| {
            [
                lambda_p + spec.dx.at(c / spec.v.points),
                spec.v.at(c % spec.v.points),
            ]
        })
        .collect();
    progress.grow_total(cells);
    let seeds = if spec.early_stop {
        Some(seed_attractors(params, spec, &ics, progress)?)
    } else {
        None
    };
    let failed = Mutex::new(false);
    let chunks: Vec<Option<Vec<SteadyState>>> = ics
        .par_chunks(CHUNK_CELLS)
        .enumerate()
        .map(|(n, chunk)| {
            let mut known = seeds.clone();
            let out = steady_states(
                params,
                chunk,
                &spec.steady,
                known.as_mut(),
                progress.cancel_flag(),
                |_| progress.add(1),
            );
            if let Some(outcomes) = &out {
                on_chunk(BasinChunk {
                    start: n * CHUNK_CELLS,
                    outcomes: outcomes.clone(),
                });
            } else {
                *failed.lock().unwrap() = true;
            }
            out
        })
        .collect();
    if progress.is_cancelled() || *failed.lock().unwrap() {
        return Err(AnalysisError::Cancelled);
    }
    let mut table = AttractorTable::default();
    let labels = chunks
        .into_iter()
        .flat_map(|c| c.expect("not cancelled"))
        .map(|s| table.classify(&s, SAME_POINT_TOL))
        .collect();
    Ok(Basin {
        dx: spec.dx.values(),
        v: spec.v.values(),
        labels,
        table,
    })
}

/// Attractors found from a fixed 7 × 7 sub-grid, integrated in full: the starting knowledge of
/// every chunk, so results do not depend on which chunk runs first.
fn seed_attractors(
    params: &Params,
    spec: &BasinSpec,
    ics: &[[f64; 2]],
    progress: &Progress,
) -> Result<KnownAttractors, AnalysisError> {
    let (nx, nv) = (spec.dx.points, spec.v.points);
    let pick = |n: usize, j: usize| if n <= 1 { 0 } else { j * (n - 1) / 6 };
    let mut sample: Vec<[f64; 2]> = (0..49)
        .map(|j| ics[pick(nx, j / 7) * nv + pick(nv, j % 7)])
        .collect();
    sample.dedup();
    let outcomes = steady_states(
        params,
        &sample,
        &spec.steady,
        None,
        progress.cancel_flag(),
        |_| {},
    )
    .ok_or(AnalysisError::Cancelled)?;
    let mut known = KnownAttractors::new(spec.capture);
    for s in &outcomes {
        known.learn(s, SAME_POINT_TOL);
    }
    Ok(known)
}
