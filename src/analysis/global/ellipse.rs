//! The ellipse a capture region is: adapted to the linearised map at its point, so that
//! the map shrinks it.

use nalgebra::{Matrix2, Vector2};

use crate::analysis::orbit::floquet::Multipliers;

/// Most anisotropic ellipse used (ratio of its axes).
const MAX_CONDITION: f64 = 1e3;

/// An ellipse adapted to a stable linear map M: x − p = T u with |u| ≤ r, where |u|² shrinks
/// under M by at least `shrink` per application. T's largest singular value is 1, so the
/// ellipse lies inside the ball of radius r.
#[derive(Debug, Clone, Copy)]
pub struct Shape {
    pub t: Matrix2<f64>,
    pub(super) t_inv: Matrix2<f64>,
    pub shrink: f64,
}

impl Shape {
    /// The shape from M's real Jordan form (a focus: |u|² shrinks by |μ|² exactly; a node:
    /// by the larger μ²), or from the Lyapunov equation where the eigenvectors are nearly
    /// parallel; `None` unless both multipliers are inside the unit circle.
    pub fn of(m: &Matrix2<f64>) -> Option<Shape> {
        let mu = Multipliers::of(m);
        if !mu.stable() {
            return None;
        }
        let t = if mu.complex() {
            // columns Re w, Im w of an eigenvector w for μ = re + i·im
            let [re, im] = [mu.0[0].re, mu.0[0].im];
            if m[(0, 1)].abs() >= m[(1, 0)].abs() {
                Matrix2::new(m[(0, 1)], 0.0, re - m[(0, 0)], im)
            } else {
                Matrix2::new(re - m[(1, 1)], im, m[(1, 0)], 0.0)
            }
        } else {
            let w_1 = eigenvector(m, mu.0[0].re, 0);
            let w_2 = eigenvector(m, mu.0[1].re, 1);
            Matrix2::from_columns(&[w_1, w_2])
        };
        let shrink = mu.spectral_radius().powi(2);
        Shape::normalised(t, shrink).or_else(|| {
            // V = xᵀQx = |Lᵀx|² for Q = L Lᵀ, so T = L⁻ᵀ
            let q = lyapunov(m)?;
            let l_inv_t = q.cholesky()?.l().transpose().try_inverse()?;
            let lambda_max = q.symmetric_eigenvalues().max();
            Shape::normalised(l_inv_t, 1.0 - 1.0 / lambda_max)
        })
    }

    /// T scaled to a largest singular value of 1; `None` if T is singular or its condition
    /// number exceeds [`MAX_CONDITION`].
    fn normalised(t: Matrix2<f64>, shrink: f64) -> Option<Shape> {
        let sigma = t.singular_values();
        let (sigma_max, sigma_min) = (sigma.max(), sigma.min());
        if !(sigma_min > 0.0 && sigma_max / sigma_min < MAX_CONDITION) {
            return None;
        }
        let t = t / sigma_max;
        let t_inv = t.try_inverse()?;
        Some(Shape { t, t_inv, shrink })
    }
}

/// A unit eigenvector of M for the real eigenvalue `mu` (the `fallback` axis when M = μI).
fn eigenvector(m: &Matrix2<f64>, mu: f64, fallback: usize) -> Vector2<f64> {
    let by_row_1 = Vector2::new(m[(0, 1)], mu - m[(0, 0)]);
    let by_row_2 = Vector2::new(mu - m[(1, 1)], m[(1, 0)]);
    let w = if by_row_1.norm() >= by_row_2.norm() {
        by_row_1
    } else {
        by_row_2
    };
    w.try_normalize(1e-14)
        .unwrap_or_else(|| Vector2::ith(fallback, 1.0))
}

/// Q with Mᵀ Q M − Q = −I by Smith's doubling (Q = Σ (Mᵀ)ⁿ Mⁿ); `None` unless M's spectral
/// radius is below 1.
pub fn lyapunov(m: &Matrix2<f64>) -> Option<Matrix2<f64>> {
    let (mut q, mut a) = (Matrix2::identity(), *m);
    for _ in 0..64 {
        q += a.transpose() * q * a;
        a *= a;
        let size = a.amax();
        if !size.is_finite() || size > 1e12 {
            return None;
        }
        if size < 1e-17 {
            return Some(q);
        }
    }
    None
}
