//! φ² of both membranes tabulated over one forcing period at the RK4 half-steps, so the hot
//! loop never calls cos().

use crate::model::Params;

/// φ_I² and φ_II² at τ = k·h/2, k = 0..=2n, over one period T = n·h.
#[derive(Debug, Clone)]
pub struct DriveTable {
    phi_sq_i: Vec<f64>,
    phi_sq_ii: Vec<f64>,
}

impl DriveTable {
    /// Tabulates the drive for `n` steps per period.
    pub fn new(p: &Params, n: usize) -> Self {
        let half_step = p.period() / (2 * n) as f64;
        let (phi_sq_i, phi_sq_ii) = (0..=2 * n)
            .map(|k| p.phi_sq_at(k as f64 * half_step))
            .unzip();
        DriveTable {
            phi_sq_i,
            phi_sq_ii,
        }
    }

    /// (φ_I², φ_II²) at half-step `k` of the period.
    #[inline(always)]
    pub fn at(&self, k: usize) -> (f64, f64) {
        (self.phi_sq_i[k], self.phi_sq_ii[k])
    }
}
