//! Telling attractors apart: two steady states are the same attractor when they have the same
//! period and the same stroboscopic points, in any phase order.

use serde::Serialize;

use crate::analysis::orbit::steady_state::{Class, SteadyState};

/// Tolerance (max-norm on [λ_I, v]) within which stroboscopic points are the same point.
pub const SAME_POINT_TOL: f64 = 1e-5;

/// True when `a` and `b` are the same periodic attractor: same period, and b's points are a's
/// up to a cyclic shift, each within `tol`.
pub fn same_attractor(a: &SteadyState, b: &SteadyState, tol: f64) -> bool {
    if a.class != Class::Periodic || b.class != Class::Periodic || a.period != b.period {
        return false;
    }
    let (p, q) = (&a.poincare, &b.poincare);
    let k = p.len();
    k == q.len()
        && (0..k).any(|shift| {
            (0..k).all(|j| {
                let (u, w) = (p[j], q[(j + shift) % k]);
                (u[0] - w[0]).abs().max((u[1] - w[1]).abs()) < tol
            })
        })
}

/// One distinct outcome among many trajectories.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Attractor {
    /// Label used in result tables: 0, 1, 2... in order of first appearance.
    pub id: usize,
    /// A representative steady state (the first trajectory that reached it).
    pub response: SteadyState,
    /// How many of the sampled initial states reached it.
    pub count: usize,
}

/// Distinct outcomes: each periodic attractor on its own, all non-periodic responses as one,
/// all collisions as one.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct AttractorTable {
    pub attractors: Vec<Attractor>,
}

impl AttractorTable {
    /// The id of `s`'s attractor, adding it if new; counts one more arrival.
    pub fn classify(&mut self, s: &SteadyState, tol: f64) -> usize {
        let found = self.attractors.iter().position(|a| match s.class {
            Class::Periodic => same_attractor(&a.response, s, tol),
            other => a.response.class == other,
        });
        let i = found.unwrap_or_else(|| {
            self.attractors.push(Attractor {
                id: self.attractors.len(),
                response: s.clone(),
                count: 0,
            });
            self.attractors.len() - 1
        });
        self.attractors[i].count += 1;
        i
    }

    /// Total arrivals counted.
    pub fn total(&self) -> usize {
        self.attractors.iter().map(|a| a.count).sum()
    }
}
