//! The covered verification of a capture region ([`crate::analysis::global::capture::Verification::Covered`]):
//! a polar grid of samples in the coordinates u of the region's shape, each mapped over many
//! returns with its Jacobian, whose first-order bounds cover the whole region.

use nalgebra::{Matrix2, Vector2};

use crate::analysis::global::ellipse::Shape;
use crate::analysis::global::flow::Flow;

/// Rings of the covered test: radii cap·2^(−j/2), j = 0 … COVER_RINGS − 1 (down to cap/64).
const COVER_RINGS: usize = 13;
/// Samples per ring of the covered test, at the same angles on every ring.
const COVER_POINTS: usize = 16;
/// The angle between neighbouring samples of a ring.
const ANGLE_STEP: f64 = std::f64::consts::TAU / COVER_POINTS as f64;
/// The covered test maps the samples over n returns, the fewest for which the linearised map
/// shrinks |u| a hundredfold (at most [`MAX_COVER_PERIODS`] forcing periods): the twist of
/// the nonlinear orbit (its angle turning with amplitude) grows ‖DF‖ only in proportion to
/// n, while the contraction shrinks it geometrically.
const COVER_CONTRACTION: f64 = 0.01;
/// Most forcing periods the covered test integrates.
const MAX_COVER_PERIODS: usize = 256;
/// Step of the finite-difference Jacobian of Pⁿᵏ, relative to the sample's |u|.
const COVER_JACOBIAN_STEP: f64 = 1e-5;

/// The radius of the largest ellipse of `shape` around `center`, of cap·2^(−j/2) (0 if
/// none), inside which the first-order bounds at a polar grid of samples prove that |u|
/// shrinks under the map F = Pⁿᵏ over n returns (the fewest for which the linear map shrinks
/// |u| by κ = cⁿᐟ² ≤ [`COVER_CONTRACTION`]). Each annular cell of the grid lies within h of
/// one of its corners, h half the cell's diagonal; a sample u on the rings of such cells
/// passes if |F(u)| + ‖DF(u)‖·h ≤ σ·(|u| − h), σ = (1 + κ)/2 (half-way between the linear
/// prediction and no decrease), so every point within h of it also shrinks, to first order.
/// The test rests on that first-order bound rather than on the samples being dense: near
/// another invariant set or a saddle's stable manifold, where a thin foreign basin could hide
/// between samples, Pⁿᵏ stretches so much that ‖DF‖·h alone exceeds the margin. (Fig 5 at ω_e 3.6: the 1:3
/// response, whose points lie 0.04–0.07 from the 1:1's, stays outside the 1:1's region.)
/// The disc inside the last ring (cap/64) is left to the linearisation. Where the largest
/// passing ring r is below the cap, one more ring at r·2^(1/4) is tried with the half-diagonal
/// of the thinner cells between the two ([`refined`]).
pub(super) fn covered_radius(
    flow: &Flow,
    center: [f64; 2],
    shape: &Shape,
    k: usize,
    cap: f64,
) -> f64 {
    let most = (MAX_COVER_PERIODS / k).max(1);
    let returns = (1..most)
        .find(|&n| shape.shrink.powi(n as i32).sqrt() <= COVER_CONTRACTION)
        .unwrap_or(most);
    let kappa = shape.shrink.powi(returns as i32).sqrt();
    let sigma = 0.5 * (1.0 + kappa);
    let radii: Vec<f64> = (0..COVER_RINGS)
        .map(|j| cap * 0.5f64.powf(0.5 * j as f64))
        .collect();
    let rings = Rings {
        flow,
        center,
        shape,
        periods: k * returns,
        sigma,
    };
    // a ring's samples cover the cells outside it (the outermost, the cells inside it)
    let ring_passes = rings.pass(&radii, |j| {
        half_diagonal(radii[j.saturating_sub(1)], std::f64::consts::FRAC_1_SQRT_2)
    });
    let inner = largest_passing(&radii, &ring_passes);
    refined(&rings, inner, cap)
}

/// Ratio of the ring tried beyond the largest passing one to it: 2^(1/4), half the ladder's
/// step. The Fig 6A 1:1 response's region passed at 0.0707 (cap/√2) and failed at 0.1; the
/// ring at 0.0841 passes, and the trajectories that reach that response take 4 % fewer
/// periods.
const REFINED_RATIO: f64 = 1.189_207_115_002_721;

/// `inner` (the largest passing ring of the ladder) or, if it is below `cap`, the ring at
/// inner·[`REFINED_RATIO`] if its samples pass with the half-diagonal of the cells between
/// the two. The samples of the ring at `inner` passed with the half-diagonal of the larger
/// cells outside it, so they cover the thinner cells too.
fn refined(rings: &Rings, inner: f64, cap: f64) -> f64 {
    let outer = inner * REFINED_RATIO;
    if inner == 0.0 || outer > cap {
        return inner;
    }
    let passes = rings.pass(&[outer], |_| half_diagonal(outer, REFINED_RATIO.recip()));
    if passes[0] { outer } else { inner }
}

/// Half the diagonal of the annular cell between the rings of radius r·`ratio` and r, one
/// angle step wide: every point of the cell lies within it of one of the cell's corners.
fn half_diagonal(r: f64, ratio: f64) -> f64 {
    0.5 * (r * (1.0 - ratio)).hypot(2.0 * r * (0.5 * ANGLE_STEP).sin())
}

/// Rings of [`COVER_POINTS`] samples around a response's point, in the coordinates u of the
/// region's shape, tested over `periods` forcing periods.
struct Rings<'a> {
    flow: &'a Flow,
    center: [f64; 2],
    shape: &'a Shape,
    periods: usize,
    /// Required shrink of |u| (see [`covered_radius`]).
    sigma: f64,
}

impl Rings<'_> {
    /// For each ring of `radii`, true if every sample on it passes the first-order test with
    /// half-diagonal `h(j)` for ring j. The rings' samples are integrated side by side.
    fn pass(&self, radii: &[f64], h: impl Fn(usize) -> f64) -> Vec<bool> {
        // each sample in u, and the starts in x: the sample and a step along each axis of u
        let samples: Vec<Vector2<f64>> = radii
            .iter()
            .flat_map(|&r| {
                (0..COVER_POINTS).map(move |i| {
                    let (sin, cos) = (ANGLE_STEP * i as f64).sin_cos();
                    Vector2::new(r * cos, r * sin)
                })
            })
            .collect();
        let p = Vector2::from(self.center);
        let fd_step = |u: &Vector2<f64>| COVER_JACOBIAN_STEP * u.norm();
        let starts: Vec<Option<[f64; 2]>> = samples
            .iter()
            .flat_map(|u| {
                let step = fd_step(u);
                [*u, u + Vector2::new(step, 0.0), u + Vector2::new(0.0, step)]
                    .map(|w| Some((p + self.shape.t * w).into()))
            })
            .collect();
        let images = self.flow.iterate(&starts, self.periods);
        let to_u = |x: [f64; 2]| self.shape.t_inv * (Vector2::from(x) - p);
        let passes = |h: f64, u: &Vector2<f64>, ends: &[Option<[f64; 2]>]| {
            let [Some(f), Some(f_1), Some(f_2)] = [ends[0], ends[1], ends[2]] else {
                return false;
            };
            let (f_u, step) = (to_u(f), fd_step(u));
            let column = |f_i: [f64; 2]| (to_u(f_i) - f_u) / step;
            let jacobian = Matrix2::from_columns(&[column(f_1), column(f_2)]);
            let stretch = jacobian.singular_values().max();
            f_u.norm() + stretch * h <= self.sigma * (u.norm() - h)
        };
        samples
            .chunks(COVER_POINTS)
            .zip(images.chunks(3 * COVER_POINTS))
            .enumerate()
            .map(|(j, (ring, ends))| {
                ring.iter()
                    .zip(ends.chunks(3))
                    .all(|(u, ends)| passes(h(j), u, ends))
            })
            .collect()
    }
}

/// The largest of `radii` (outermost first) inside which every ring passes: `ring_passes`
/// holds from the innermost ring out to it. 0 if the innermost ring fails.
fn largest_passing(radii: &[f64], ring_passes: &[bool]) -> f64 {
    radii
        .iter()
        .zip(ring_passes)
        .rev()
        .take_while(|&(_, &passes)| passes)
        .last()
        .map_or(0.0, |(&r, _)| r)
}
