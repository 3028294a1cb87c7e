//! The one-period map that capture regions are verified with: the integrator the
//! trajectories themselves run on, built-in (RK4 lanes) or a written model of two states
//! (the general engine's lanes), so that a region's verdict holds for the trajectories it
//! stops.

use rayon::prelude::*;

use crate::model::equations::EquationSystem;
use crate::model::equations::lanes::EquationLanes;
use crate::model::system::{System, Vector};
use crate::solver::general::GeneralRk4;
use crate::solver::general_lanes::Lanes;
use crate::solver::rk4::LANES;
use crate::solver::{Resolution, Rk4};

/// Trajectories of a written model verified side by side: as many as its tapes are compiled
/// for.
const WRITTEN_LANES: usize = crate::model::equations::tape::NATIVE_LANES;

/// A one-period map on the two grid states.
#[derive(Debug, Clone)]
pub enum Flow {
    BuiltIn(Box<Rk4>),
    /// A written model whose state is its two grid states.
    Written(Box<EquationSystem>, GeneralRk4),
}

impl Flow {
    /// The map of a written model at `resolution`; `None` unless its grid states are its
    /// whole state (regions in a projection would prove nothing).
    pub fn written(sys: &EquationSystem, resolution: &Resolution) -> Option<Flow> {
        let [a, b] = sys.model().grid();
        (sys.dim() == 2 && a != b)
            .then(|| Flow::Written(Box::new(sys.clone()), GeneralRk4::new(sys, resolution)))
    }

    /// Each start integrated `periods` forcing periods from phase 0; `None` where it stops
    /// (or started as `None`).
    pub fn iterate(&self, starts: &[Option<[f64; 2]>], periods: usize) -> Vec<Option<[f64; 2]>> {
        match self {
            Flow::BuiltIn(rk) => iterate_built_in(rk, starts, periods),
            Flow::Written(sys, rk) => starts
                .par_chunks(WRITTEN_LANES)
                .flat_map_iter(|batch| iterate_written(sys, rk, batch, periods))
                .collect(),
        }
    }
}

fn iterate_built_in(
    rk: &Rk4,
    starts: &[Option<[f64; 2]>],
    periods: usize,
) -> Vec<Option<[f64; 2]>> {
    starts
        .par_chunks(LANES)
        .flat_map_iter(|batch| {
            let mut x = [rk.params().lambda_p(); LANES];
            let mut v = [0.0; LANES];
            for (i, s) in batch.iter().enumerate() {
                if let Some(s) = s {
                    (x[i], v[i]) = (s[0], s[1]);
                }
            }
            let mut lanes = rk.start(x, v);
            for _ in 0..periods {
                rk.advance_period(&mut lanes, None);
            }
            let ends: Vec<Option<[f64; 2]>> = batch
                .iter()
                .enumerate()
                .map(|(i, s)| {
                    let free = s.is_some() && lanes.collision[i].is_none();
                    free.then_some([lanes.x[i], lanes.v[i]])
                })
                .collect();
            ends
        })
        .collect()
}

/// Up to [`WRITTEN_LANES`] starts of a written model, in lanes.
fn iterate_written(
    sys: &EquationSystem,
    rk: &GeneralRk4,
    batch: &[Option<[f64; 2]>],
    periods: usize,
) -> Vec<Option<[f64; 2]>> {
    let mut sys = sys.clone();
    let [a, b] = sys.model().grid();
    let rest = *sys.origin();
    let mut eval = EquationLanes::<WRITTEN_LANES>::new(&sys);
    let mut lanes = Lanes::<WRITTEN_LANES>::idle(&rest);
    for (l, s) in batch.iter().enumerate() {
        if let Some(p) = s {
            let mut x: Vector = rest;
            (x[a], x[b]) = (p[0], p[1]);
            rk.restart_lane(&mut sys, &mut lanes, l, &x);
        }
    }
    for _ in 0..periods * rk.steps_per_period() {
        rk.advance_lanes(&mut sys, &mut eval, &mut lanes);
    }
    batch
        .iter()
        .enumerate()
        .map(|(l, s)| (s.is_some() && lanes.running(l)).then(|| [lanes.x[a][l], lanes.x[b][l]]))
        .collect()
}
