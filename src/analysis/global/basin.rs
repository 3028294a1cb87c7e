//! Fig 6: basins of attraction on a grid of initial states (Δλ, v) at τ = 0.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::analysis::AnalysisError;
use crate::analysis::global::batch::KnownAttractors;
use crate::analysis::global::capture::Verification;
use crate::analysis::global::oscillator::Oscillator;
use crate::analysis::grid::Axis;
use crate::analysis::orbit::attractor::{AttractorTable, SAME_POINT_TOL};
use crate::analysis::orbit::steady_state::{SteadyState, SteadyStateSpec};
use crate::analysis::progress::Progress;
use crate::analysis::windows::in_windows;
use crate::model::Params;
use crate::model::error::check;
use crate::model::limits;
use crate::solver::rk4::LANES;

/// Largest grid a basin may ask for (about 16 million cells).
pub const MAX_CELLS: usize = 1 << 24;
/// Cells per chunk (the unit of parallel work and of the store's partial results) in a grid
/// of `cells`: 512 to 2048 ([`super::units_per_chunk`]). The Fig 6A basin through its session
/// took 9 % less time in 25 chunks than in 99; the basins of Fig 6 are byte-identical either
/// way.
pub fn cells_per_chunk(cells: usize) -> usize {
    super::units_per_chunk(cells, 512, 2048)
}

/// A basin computation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BasinSpec {
    /// Initial displacements Δλ = λ_I − λ_p.
    pub dx: Axis,
    /// Initial velocities.
    pub v: Axis,
    pub steady: SteadyStateSpec,
    /// Stop trajectories that enter a verified capture region of an attractor already found
    /// (same classes, much faster). A grid of at most 12 × 12 cells is integrated in full
    /// either way.
    pub early_stop: bool,
    /// Largest capture-region radius for the early stop (Euclidean on [λ_I, v]).
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
            capture: 0.1,
        }
    }
}

impl BasinSpec {
    /// Checks the grid (at most 16384 points a side and [`MAX_CELLS`] cells), the capture
    /// radius and the steady-state settings.
    pub fn validate(&self) -> Result<(), crate::model::ParamError> {
        self.dx.validate("dx", 1 << 14)?;
        self.dx.check_within("dx", limits::DX)?;
        self.v.validate("v", 1 << 14)?;
        self.v.check_within("v", limits::V)?;
        let cells = self.dx.points * self.v.points;
        check(
            "cells",
            cells as f64,
            |c| c <= MAX_CELLS as f64,
            format!("<= {MAX_CELLS}"),
        )?;
        check("capture", self.capture, |c| c > 0.0 && c <= 1.0, "(0, 1]")?;
        self.steady.validate().map_err(|e| e.within("steady"))
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
pub fn basin<O: Oscillator>(
    params: &O,
    spec: &BasinSpec,
    progress: &Progress,
    on_chunk: &(dyn Fn(BasinChunk) + Sync),
) -> Result<Basin, AnalysisError> {
    let plan = BasinPlan::new(params, spec, progress)?;
    progress.grow_total(plan.cells());
    // a window of chunks at a time, in parallel, each classified in chunk order as it comes:
    // only a window's outcomes are held (not every cell's), whatever the grid's size
    let window = (WINDOW_CELLS / plan.per_chunk()).max(8 * rayon::current_num_threads());
    let chunks = in_windows(plan.chunks(), window, |n| {
        let out = plan.chunk(n, progress);
        if let Ok(outcomes) = &out {
            on_chunk(BasinChunk {
                start: n * plan.per_chunk(),
                outcomes: outcomes.clone(),
            });
        }
        out
    });
    let mut failed = None;
    let basin = plan.assemble(chunks.map_while(|chunk| chunk.map_err(|e| failed = Some(e)).ok()));
    match failed {
        Some(e) => Err(e),
        None => Ok(basin),
    }
}

/// Cells computed between two classifications (at least 8 chunks a thread; more with many
/// threads): the outcomes of 131 072 cells (about 30 MB) in memory at most. A window's last
/// chunks leave cores idle, so a window is large: the paper's 201 × 251 basin is one.
const WINDOW_CELLS: usize = 1 << 17;

/// A validated basin computation cut into chunks of [`cells_per_chunk`] cells, addressed by index,
/// so that chunks can be computed in any order, on any machine, and saved as they finish.
pub struct BasinPlan<'a, O: Oscillator = Params> {
    params: &'a O,
    spec: &'a BasinSpec,
    ics: Vec<O::State>,
    seeds: Option<KnownAttractors>,
}

impl<'a, O: Oscillator> BasinPlan<'a, O> {
    /// Validates the spec and finds the seed attractors every chunk starts from.
    pub fn new(
        params: &'a O,
        spec: &'a BasinSpec,
        progress: &Progress,
    ) -> Result<Self, AnalysisError> {
        spec.validate()?;
        let (dx, v) = (&spec.dx, &spec.v);
        let ics: Vec<O::State> = (0..dx.points * v.points)
            .map(|c| params.grid_start([dx.at(c / v.points), v.at(c % v.points)]))
            .collect();
        let seeds = match spec.early_stop {
            true => seed_attractors(params, spec, &ics, progress)?,
            false => None,
        };
        Ok(BasinPlan {
            params,
            spec,
            ics,
            seeds,
        })
    }

    pub fn cells(&self) -> usize {
        self.ics.len()
    }

    /// Cells per chunk ([`cells_per_chunk`]).
    pub fn per_chunk(&self) -> usize {
        cells_per_chunk(self.ics.len())
    }

    pub fn chunks(&self) -> usize {
        self.ics.len().div_ceil(self.per_chunk())
    }

    /// The initial states of chunk `n`.
    pub fn chunk_cells(&self, n: usize) -> &[O::State] {
        let (start, per_chunk) = (n * self.per_chunk(), self.per_chunk());
        &self.ics[start..(start + per_chunk).min(self.ics.len())]
    }

    /// The outcomes of chunk `n`'s cells.
    pub fn chunk(&self, n: usize, progress: &Progress) -> Result<Vec<SteadyState>, AnalysisError> {
        let cells = self.chunk_cells(n);
        let mut known = self.seeds.clone();
        self.params.steady_states(
            cells,
            &self.spec.steady,
            known.as_mut(),
            progress.cancel_flag(),
            &mut |_| progress.add(1),
        )
    }

    /// The basin from every chunk's outcomes, in chunk order; the chunks are taken one at a
    /// time, so only their labels stay in memory.
    pub fn assemble(&self, chunks: impl IntoIterator<Item = Vec<SteadyState>>) -> Basin {
        let mut table = AttractorTable::default();
        let mut labels = Vec::with_capacity(self.cells());
        for chunk in chunks {
            labels.extend(chunk.iter().map(|s| table.classify(s, SAME_POINT_TOL)));
        }
        Basin {
            dx: self.spec.dx.values(),
            v: self.spec.v.values(),
            labels,
            table,
        }
    }
}

/// Side of the sub-grid whose cells are integrated in full before the chunks run.
const SEED_SIDE: usize = 12;

/// Attractors found from a fixed [`SEED_SIDE`]² sub-grid, integrated in full (in parallel):
/// the starting knowledge of every chunk, so results do not depend on which chunk runs first.
/// The more attractors known up front, the fewer regions each chunk verifies on its own.
/// None for a grid of at most [`SEED_SIDE`] × [`SEED_SIDE`] cells: the sub-grid would be every
/// cell, so the chunks integrate each in full without verifying a region (a 3 × 3 basin took
/// 0.48 s of CPU, nearly all of it verifying regions no other cell would use; now 0.02 s).
fn seed_attractors<O: Oscillator>(
    params: &O,
    spec: &BasinSpec,
    ics: &[O::State],
    progress: &Progress,
) -> Result<Option<KnownAttractors>, AnalysisError> {
    let Some(mut known) = params.known_attractors(&spec.steady, spec.capture) else {
        return Ok(None);
    };
    let (nx, nv) = (spec.dx.points, spec.v.points);
    if nx <= SEED_SIDE && nv <= SEED_SIDE {
        return Ok(None);
    }
    let last = SEED_SIDE - 1;
    let pick = |n: usize, j: usize| if n <= 1 { 0 } else { j * (n - 1) / last };
    // each cell once (a grid narrower than the sub-grid picks some many times), in grid order
    let mut cells: Vec<usize> = (0..SEED_SIDE * SEED_SIDE)
        .map(|j| pick(nx, j / SEED_SIDE) * nv + pick(nv, j % SEED_SIDE))
        .collect();
    cells.sort_unstable();
    cells.dedup();
    let sample: Vec<O::State> = cells.into_iter().map(|c| ics[c]).collect();
    let outcomes: Vec<SteadyState> = sample
        .par_chunks(LANES)
        .map(|part| {
            params.steady_states(
                part,
                &spec.steady,
                None,
                progress.cancel_flag(),
                &mut |_| {},
            )
        })
        .collect::<Result<Vec<Vec<_>>, _>>()?
        .concat();
    known.learn_all(&outcomes, SAME_POINT_TOL, Verification::Covered);
    Ok(Some(known))
}
