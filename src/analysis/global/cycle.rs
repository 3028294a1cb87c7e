//! An attracting cycle of the period map found ahead of a trajectory: once a trajectory's
//! stroboscopic points have nearly settled on a k-cycle, Newton's method on the k-period map
//! of the integrator the trajectories run on (its Jacobian by differences) finds the cycle's
//! point to rounding, many forcing periods before the trajectory itself would converge to
//! 1e-9. The point is only a candidate: the early stop trusts it once capture regions are
//! verified around it ([`crate::analysis::global::capture`]), as for any learnt response.

use nalgebra::{Matrix2, Vector2};

use crate::analysis::global::flow::Flow;
use crate::analysis::orbit::floquet::Multipliers;

/// Largest Newton iterations tried.
const MAX_ITERATIONS: usize = 8;
/// Newton has converged once a correction is below this (max-norm on the grid states).
const CONVERGED: f64 = 1e-12;
/// A correction larger than this means Newton has left the neighbourhood it started in.
const LARGEST_CORRECTION: f64 = 0.25;
/// A Jacobian with a multiplier this far outside the unit circle means Newton is heading for
/// a cycle that is not attracting (a saddle on a basin's edge): it is given up at once.
const SADDLE_RADIUS: f64 = 1.1;
/// The difference step of the Jacobian, relative to the state (at least this absolute).
const DIFFERENCE_STEP: f64 = 1e-7;

/// The point near `p` that the k-period map of `flow` fixes, if Newton's method converges to
/// one whose multipliers lie inside the unit circle (an attracting cycle); `None` if it
/// does not converge, leaves `p`'s neighbourhood, meets a collision or finds a cycle that is
/// not attracting.
pub fn attracting_cycle_near(flow: &Flow, p: [f64; 2], k: usize) -> Option<[f64; 2]> {
    let mut x = p;
    for _ in 0..MAX_ITERATIONS {
        let d = [
            DIFFERENCE_STEP * x[0].abs().max(1.0),
            DIFFERENCE_STEP * x[1].abs().max(1.0),
        ];
        let starts = [
            Some(x),
            Some([x[0] + d[0], x[1]]),
            Some([x[0], x[1] + d[1]]),
        ];
        let ends = flow.iterate(&starts, k);
        let (f, fx, fv) = (ends[0]?, ends[1]?, ends[2]?);
        let jacobian = Matrix2::new(
            (fx[0] - f[0]) / d[0],
            (fv[0] - f[0]) / d[1],
            (fx[1] - f[1]) / d[0],
            (fv[1] - f[1]) / d[1],
        );
        let multipliers = Multipliers::of(&jacobian);
        if multipliers.spectral_radius() > SADDLE_RADIUS {
            return None;
        }
        let residual = Vector2::new(f[0] - x[0], f[1] - x[1]);
        let step = (jacobian - Matrix2::identity()).lu().solve(&(-residual))?;
        let size = step[0].abs().max(step[1].abs());
        if !size.is_finite() || size > LARGEST_CORRECTION {
            return None;
        }
        x = [x[0] + step[0], x[1] + step[1]];
        if size < CONVERGED {
            return multipliers.stable().then_some(x);
        }
    }
    None
}
