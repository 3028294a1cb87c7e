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
//! empty. The same test over many returns is not safe: the map then grows steep near a
//! foreign invariant set, and a thin basin slips between the rings (Fig 5's 1:3 response at
//! ω_e 3.55–3.65 was lost that way).
//!
//! [`Verification::Covered`], for a basin's seeds: many returns, with each sample's Jacobian
//! bounding the map between samples (`capture_cover.rs`), so steepness fails the test
//! instead of hiding from it.

use nalgebra::{Matrix2, Vector2};

use crate::analysis::global::capture_cover::{covered_radius, largest_passing};
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
    center: [f64; 2],
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
    fn new(center: [f64; 2], shape: &Shape, radius_sq: f64) -> Self {
        let q = shape.t_inv.transpose() * shape.t_inv;
        CaptureRegion {
            center,
            q: [q[(0, 0)], q[(0, 1)], q[(1, 1)]],
            radius_sq,
        }
    }

    /// V(x) = (x − p)ᵀ Q (x − p).
    fn v(&self, x: [f64; 2]) -> f64 {
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
/// k = its length), each at most `caps[j]` in radius.
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
/// together with every smaller ring: all rings are integrated at once, one pass.
fn one_return_radius(flow: &Flow, center: [f64; 2], shape: &Shape, k: usize, cap: f64) -> f64 {
    // the ellipse's V, whatever its radius
    let region = CaptureRegion::new(center, shape, 0.0);
    // V must shrink by at least an eighth of what the linearised map takes off
    let required = 1.0 - (1.0 - shape.shrink) / 8.0;
    let t = shape.t;
    let radii: Vec<f64> = (0..RINGS).map(|n| cap * 0.5f64.powi(n as i32)).collect();
    let samples: Vec<[f64; 2]> = radii
        .iter()
        .enumerate()
        .flat_map(|(n, &r)| {
            (0..RING_POINTS).map(move |i| {
                // rings staggered so that no two samples share a direction
                let turn = (i as f64 + n as f64 / RINGS as f64) / RING_POINTS as f64;
                let (sin, cos) = (std::f64::consts::TAU * turn).sin_cos();
                let d = t * Vector2::new(cos, sin);
                [center[0] + r * d[0], center[1] + r * d[1]]
            })
        })
        .collect();
    let starts: Vec<Option<[f64; 2]>> = samples.iter().copied().map(Some).collect();
    let images = flow.iterate(&starts, k);
    let ring_passes: Vec<bool> = samples
        .chunks(RING_POINTS)
        .zip(images.chunks(RING_POINTS))
        .map(|(from, to)| {
            from.iter()
                .zip(to)
                .all(|(&x, y)| y.is_some_and(|y| region.v(y) <= required * region.v(x)))
        })
        .collect();
    largest_passing(&radii, &ring_passes)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::orbit::attractor::same_attractor;
    use crate::analysis::orbit::steady_state::{SteadyState, SteadyStateSpec, steady_state};
    use crate::model::Params;
    use crate::solver::Resolution;

    /// The Jordan-form shape shrinks |u|² by |μ|² for a focus and by max μ² for a node, and
    /// its ellipse lies in the unit ball with V = 1 on its boundary.
    #[test]
    fn shape_follows_the_linear_map() {
        for (m, shrink) in [
            (Matrix2::new(0.6, -1.4, 0.35, 0.6), 0.36 + 0.49),
            (Matrix2::new(0.9, 0.3, 0.0, -0.5), 0.81),
        ] {
            let shape = Shape::of(&m).expect("stable");
            assert!((shape.shrink - shrink).abs() < 1e-12, "{m:?}");
            let region = CaptureRegion::new([0.0, 0.0], &shape, 1.0);
            for i in 0..12 {
                let (sin, cos) = (i as f64).sin_cos();
                let d = shape.t * Vector2::new(cos, sin);
                assert!((region.v(d.into()) - 1.0).abs() < 1e-12);
                assert!(d.norm() <= 1.0 + 1e-12);
                // |T⁻¹ M d|² = shrink · |T⁻¹ d|² for a focus, at most that for a node
                let md = m * d;
                assert!(region.v(md.into()) <= shrink + 1e-12, "{m:?}");
            }
        }
        assert!(Shape::of(&Matrix2::new(1.1, 0.0, 0.0, 0.5)).is_none());
    }

    /// The responses of `params` from `starts` (near their Poincaré points).
    fn responses_from(p: &Params, starts: &[[f64; 2]]) -> Vec<SteadyState> {
        let spec = SteadyStateSpec::default();
        starts
            .iter()
            .map(|s| steady_state(p, s[0], s[1], &spec))
            .collect()
    }

    /// Every region of every response (capped as the early stop caps them: at most half-way
    /// to another response's point, at most 0.1) is at least `least` of its cap in radius,
    /// holds no point of another response, and starts spread over it, integrated to full
    /// convergence on their own, all reach the region's response.
    fn regions_hold_only_their_response(
        p: &Params,
        responses: &[SteadyState],
        verification: Verification,
        least: f64,
    ) {
        let spec = SteadyStateSpec::default();
        let rk = Flow::BuiltIn(Box::new(crate::solver::Rk4::new(p, &Resolution::default())));
        for r in responses {
            let caps: Vec<f64> = r
                .poincare
                .iter()
                .map(|p| {
                    let others = responses.iter().filter(|o| *o != r);
                    let nearest = others
                        .flat_map(|o| o.poincare.iter())
                        .map(|q| (p[0] - q[0]).hypot(p[1] - q[1]))
                        .fold(f64::INFINITY, f64::min);
                    (0.5 * nearest).min(0.1)
                })
                .collect();
            for (region, cap) in capture_regions(&rk, &r.poincare, &caps, verification)
                .iter()
                .zip(&caps)
            {
                assert!(region.radius() >= least * cap, "{region:?} under {cap}");
                for other in responses.iter().filter(|o| *o != r) {
                    assert!(other.poincare.iter().all(|&q| !region.contains(q)));
                }
                // 24 starts on rings at 0.95, 0.6 and 0.3 of the radius, along the ellipse
                for i in 0..24 {
                    let (sin, cos) = (i as f64 * 0.7).sin_cos();
                    let fraction = [0.95, 0.6, 0.3][i % 3];
                    let d = region.radius() * fraction;
                    // step out along (cos, sin) until just inside the ellipse's boundary
                    let mut x = [region.center[0] + d * cos, region.center[1] + d * sin];
                    while !region.contains(x) {
                        x = [
                            0.5 * (x[0] + region.center[0]),
                            0.5 * (x[1] + region.center[1]),
                        ];
                    }
                    let end = steady_state(p, x[0], x[1], &spec);
                    assert!(same_attractor(&end, r, 1e-6), "from {x:?}: {end:?}");
                }
            }
        }
    }

    /// Fig 6B's model (a 1:3 response born beside the 1:1 focus), both verifications: the 1:1,
    /// 1:2 and 1:3 responses (from near their points, `isola basin --adr 1 --omega 3.6`).
    #[test]
    fn fig6b_regions_hold_only_their_response() {
        let p = Params::paper(1.0, 3.6).unwrap();
        let responses = responses_from(&p, &[[1.017, 0.001], [1.1208, 0.4402], [1.02594, 0.06897]]);
        let periods: Vec<usize> = responses.iter().map(|r| r.poincare.len()).collect();
        assert_eq!(periods, [1, 2, 3]);
        regions_hold_only_their_response(&p, &responses, Verification::OneReturn, 1.0 / 32.0);
        regions_hold_only_their_response(&p, &responses, Verification::Covered, 1.0 / 64.0);
    }

    /// Fig 6A's model, covered: the 1:1 and 1:2 regions reach at least 0.7 of their cap 0.1
    /// (0.025 and 0.05 over one return) and hold only their response.
    #[test]
    fn fig6a_covered_regions_hold_only_their_response() {
        let p = Params::paper(0.6, 3.7).unwrap();
        let responses = responses_from(&p, &[[1.02, 0.0], [1.32, 0.0]]);
        let periods: Vec<usize> = responses.iter().map(|r| r.poincare.len()).collect();
        assert_eq!(periods, [1, 2]);
        regions_hold_only_their_response(&p, &responses, Verification::Covered, 0.7);
    }

    /// Fig 5's model at ω_e 3.55–3.65 with the 1:1 response alone known (as when no start has
    /// reached the 1:3 yet): its covered region (cap 0.1) keeps out the 1:3 response, whose
    /// points lie 0.04–0.07 from the 1:1's and whose thin basin a test of samples alone
    /// misses, yet is larger than the one-return region.
    #[test]
    fn covered_region_keeps_out_a_nearby_1_3_response() {
        for (omega, one, three) in [
            (3.55, [1.016559, 0.001233], [1.030497, 0.074272]),
            (3.6, [1.016985, 0.001140], [1.025937, 0.068965]),
            (3.65, [1.017377, 0.001059], [1.024182, 0.062779]),
        ] {
            let p = Params::paper(1.0, omega).unwrap();
            let rk = Flow::BuiltIn(Box::new(crate::solver::Rk4::new(
                &p,
                &Resolution::default(),
            )));
            let found = responses_from(&p, &[one, three]);
            let [r_1, r_3] = [&found[0], &found[1]];
            assert_eq!((r_1.poincare.len(), r_3.poincare.len()), (1, 3));
            let covered = &capture_regions(&rk, &r_1.poincare, &[0.1], Verification::Covered)[0];
            let one_return =
                &capture_regions(&rk, &r_1.poincare, &[0.1], Verification::OneReturn)[0];
            assert!(
                covered.radius() > one_return.radius(),
                "ω {omega}: {covered:?}"
            );
            for &q in &r_3.poincare {
                assert!(!covered.contains(q), "ω {omega}: {q:?} in {covered:?}");
            }
        }
    }
}
