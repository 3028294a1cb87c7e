//! Capture regions for the early stop. Around each Poincaré point p of a stable periodic
//! response (period k), an ellipse E = {x : |T⁻¹(x − p)|² < r²} adapted to the response's
//! linearised return map M = DPᵏ(p): in the coordinates u = T⁻¹(x − p) of M's real Jordan
//! form, V = |u|² shrinks under M by the factor c = |μ|² (a focus) or max μ² (a node).
//!
//! [`Verification::OneReturn`]: the radius r is the largest of cap, cap/2, cap/4, … for which
//! sample points on that ring and on every smaller ring, integrated k forcing periods with the
//! trajectories' own integrator, all end with V below 1 − (1 − c)/8 of where they started: at
//! least an eighth of the linearised map's decrease. V then decreases at every sampled point
//! of E, by a margin much larger than it can vary between neighbouring samples (over one
//! return the map is nearly linear at these radii): the nonlinear map still contracts there,
//! so E holds no other invariant set (no other attractor, no saddle whose stable manifold
//! could bound p's basin) and every point of E goes to p. Where no ring passes, the region is
//! empty. Below the cap, the ring √2 times larger than the largest that passes is tested too
//! (half-way, in ratio, to the one that failed), and taken if it passes. The same test over many returns is not safe: the map then grows steep near a
//! foreign invariant set, and a thin basin slips between the rings (Fig 5's 1:3 response at
//! ω_e 3.55–3.65 was lost that way).
//!
//! [`Verification::Covered`], for a basin's seeds: many returns, with each sample's Jacobian
//! bounding the map between samples (`capture_cover.rs`), so steepness fails the test
//! instead of hiding from it.

use nalgebra::{Matrix2, Vector2};
use rayon::prelude::*;

use crate::analysis::global::capture_cover::covered_radius;
use crate::analysis::global::ellipse::Shape;
use crate::analysis::global::flow::Flow;

/// Sample points per ring.
const RING_POINTS: usize = 32;
/// Rings sampled, at radii cap, cap/2, cap/4, …
const RINGS: usize = 6;
/// Relative step of the finite-difference Jacobian of the return map.
const JACOBIAN_STEP: f64 = 1e-6;

/// An ellipse around one Poincaré point of a response, inside that response's basin.
#[derive(Debug, Clone, PartialEq)]
pub struct CaptureRegion {
    /// The Poincaré point (Δλ, v).
    pub center: [f64; 2],
    /// Q as (q₁₁, q₁₂, q₂₂).
    q: [f64; 3],
    /// r²; 0 for an empty region.
    radius_sq: f64,
}

impl CaptureRegion {
    /// A region that holds nothing.
    fn empty(center: [f64; 2]) -> Self {
        CaptureRegion {
            center,
            q: [1.0, 0.0, 1.0],
            radius_sq: 0.0,
        }
    }

    /// The ellipse {x : |T⁻¹(x − center)|² < radius_sq} of `shape`.
    pub fn new(center: [f64; 2], shape: &Shape, radius_sq: f64) -> Self {
        let q = shape.t_inv.transpose() * shape.t_inv;
        CaptureRegion {
            center,
            q: [q[(0, 0)], q[(0, 1)], q[(1, 1)]],
            radius_sq,
        }
    }

    /// V(x) = (x − p)ᵀ Q (x − p).
    pub fn v(&self, x: [f64; 2]) -> f64 {
        let (dx, dv) = (x[0] - self.center[0], x[1] - self.center[1]);
        let [a, b, c] = self.q;
        a * dx * dx + 2.0 * b * dx * dv + c * dv * dv
    }

    /// True if `x` lies inside the region.
    pub fn contains(&self, x: [f64; 2]) -> bool {
        self.v(x) < self.radius_sq
    }

    /// The region's radius r (0 when empty); Euclidean distances inside it are at most r.
    pub fn radius(&self) -> f64 {
        self.radius_sq.sqrt()
    }
}

/// How a capture region is verified.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verification {
    /// Rings of samples over one return (the module's description): cheap, for the few
    /// trajectories of a frequency response's ω_e or of one chunk.
    OneReturn,
    /// A cover of first-order bounds over many returns (`capture_cover.rs`): regions several
    /// times larger, at a few hundred times the cost (Fig 6A's 1:1: 624 starts over 75
    /// periods, against 192 over one), repaid by the tens of thousands of cells of a basin.
    Covered,
}

/// The capture region of each of a periodic response's Poincaré points `poincare` (period
/// k = its length), each at most `caps[j]` in radius; the points' regions side by side (a
/// basin's seeds verify Fig 6B's 1:3 response's three in 92 ms one after another).
pub fn capture_regions(
    flow: &Flow,
    poincare: &[[f64; 2]],
    caps: &[f64],
    verification: Verification,
) -> Vec<CaptureRegion> {
    let k = poincare.len();
    let Some(jacobians) = one_period_jacobians(flow, poincare) else {
        return poincare.iter().map(|&p| CaptureRegion::empty(p)).collect();
    };
    (0..k)
        .into_par_iter()
        .map(|j| {
            // the return map at p_j: J_{j+k−1} ⋯ J_{j+1} J_j
            let m = (1..k).fold(jacobians[j], |m, i| jacobians[(j + i) % k] * m);
            let Some(shape) = Shape::of(&m) else {
                return CaptureRegion::empty(poincare[j]);
            };
            let radius = match verification {
                Verification::OneReturn => one_return_radius(flow, poincare[j], &shape, k, caps[j]),
                Verification::Covered => covered_radius(flow, poincare[j], &shape, k, caps[j]),
            };
            CaptureRegion::new(poincare[j], &shape, radius * radius)
        })
        .collect()
}

/// The radius of the largest ellipse of `shape` around `center`, of `cap`, cap/2, cap/4, …
/// (0 if none), whose ring of samples passes the one-return test of the module's description
/// together with every smaller ring; below the cap, grown to the ring √2 times larger if that
/// one passes too. The rings are integrated from the innermost out, one at a time, up to the
/// first that fails: the rings beyond it could not count (most regions stop at cap/8 or
/// cap/16, so this integrates half to two thirds of the samples of all six).
fn one_return_radius(flow: &Flow, center: [f64; 2], shape: &Shape, k: usize, cap: f64) -> f64 {
    // the ellipse's V, whatever its radius
    let region = CaptureRegion::new(center, shape, 0.0);
    // V must shrink by at least an eighth of what the linearised map takes off
    let required = 1.0 - (1.0 - shape.shrink) / 8.0;
    let t = shape.t;
    // the ring of radius cap·2^(−rung)
    let ring = |rung: f64| -> Vec<[f64; 2]> {
        let r = cap * 0.5f64.powf(rung);
        (0..RING_POINTS)
            .map(|i| {
                // rings staggered so that no two samples share a direction
                let turn = (i as f64 + rung / RINGS as f64) / RING_POINTS as f64;
                let (sin, cos) = (std::f64::consts::TAU * turn).sin_cos();
                let d = t * Vector2::new(cos, sin);
                [center[0] + r * d[0], center[1] + r * d[1]]
            })
            .collect()
    };
    let passes = |samples: &[[f64; 2]]| {
        let starts: Vec<Option<[f64; 2]>> = samples.iter().copied().map(Some).collect();
        let images = flow.iterate(&starts, k);
        samples
            .iter()
            .zip(&images)
            .all(|(&x, y)| y.is_some_and(|y| region.v(y) <= required * region.v(x)))
    };
    let Some(n) = (0..RINGS)
        .rev()
        .take_while(|&n| passes(&ring(n as f64)))
        .last()
    else {
        return 0.0;
    };
    // below the cap, the ring half-way (in ratio) to the rung that failed
    let rung = match n {
        0 => 0.0,
        n if passes(&ring(n as f64 - 0.5)) => n as f64 - 0.5,
        n => n as f64,
    };
    cap * 0.5f64.powf(rung)
}

/// The Jacobian of the one-period map at each point, by central differences.
fn one_period_jacobians(flow: &Flow, points: &[[f64; 2]]) -> Option<Vec<Matrix2<f64>>> {
    let steps: Vec<[f64; 2]> = points
        .iter()
        .map(|p| {
            [
                JACOBIAN_STEP * p[0].abs().max(1.0),
                JACOBIAN_STEP * p[1].abs().max(1.0),
            ]
        })
        .collect();
    let starts: Vec<Option<[f64; 2]>> = points
        .iter()
        .zip(&steps)
        .flat_map(|(p, e)| {
            [
                [p[0] + e[0], p[1]],
                [p[0] - e[0], p[1]],
                [p[0], p[1] + e[1]],
                [p[0], p[1] - e[1]],
            ]
            .map(Some)
        })
        .collect();
    let ends: Vec<[f64; 2]> = flow
        .iterate(&starts, 1)
        .into_iter()
        .collect::<Option<_>>()?;
    Some(
        ends.chunks(4)
            .zip(&steps)
            .map(|(e, h)| {
                let column = |plus: [f64; 2], minus: [f64; 2], h: f64| {
                    (Vector2::from(plus) - Vector2::from(minus)) / (2.0 * h)
                };
                Matrix2::from_columns(&[column(e[0], e[1], h[0]), column(e[2], e[3], h[1])])
            })
            .collect(),
    )
}
