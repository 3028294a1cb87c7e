//! φ² of both membranes tabulated over one forcing period at the RK4 half-steps, so the hot
//! loop never calls cos().

use super::isa::{self, Isa};
use super::lane::Real;
use crate::model::Params;

/// (φ_I², φ_II²) and their rates d(φ²)/dτ at one instant.
pub type DriveWithRate<T = f64> = ((T, T), (T, T));

/// φ_I² and φ_II² at τ = k·h/2, k = 0..=2n, over one period T = n·h, and the drive
/// anchored at each step's start for the split steps, with its values and rates at the
/// step's ends.
#[derive(Debug, Clone)]
pub struct DriveTable {
    phi_sq_i: Vec<f64>,
    phi_sq_ii: Vec<f64>,
    step_starts: Vec<LocalDrive>,
    step_ends: Vec<[DriveWithRate; 2]>,
}

impl DriveTable {
    /// Tabulates the drive for `n` steps per period of length `h` (T/n, as the integrator
    /// has it), with FMA where the CPU has it (a `mul_add` is then one instruction instead
    /// of a call, and the same bits).
    pub fn new(p: &Params, n: usize, h: f64) -> Self {
        match isa::chosen() {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the chosen instruction set is one this CPU has, and v4 includes v3
            Isa::X86_64V3 | Isa::X86_64V4 => unsafe { Self::new_v3(p, n, h) },
            _ => Self::new_body(p, n, h),
        }
    }

    /// [`Self::new_body`] compiled for x86-64-v3.
    ///
    /// # Safety
    /// The CPU must have x86-64-v3's features.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe,f16c")]
    fn new_v3(p: &Params, n: usize, h: f64) -> Self {
        Self::new_body(p, n, h)
    }

    /// The table, in plain loops: an iterator's closures would be compiled on their own,
    /// without [`Self::new_v3`]'s instructions.
    #[inline(always)]
    fn new_body(p: &Params, n: usize, h: f64) -> Self {
        let half_step = p.period() / (2 * n) as f64;
        let (mut phi_sq_i, mut phi_sq_ii) =
            (Vec::with_capacity(2 * n + 1), Vec::with_capacity(2 * n + 1));
        for k in 0..=2 * n {
            let (i, ii) = p.phi_sq_at(k as f64 * half_step);
            phi_sq_i.push(i);
            phi_sq_ii.push(ii);
        }
        let (mut step_starts, mut step_ends) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for k in 0..n {
            let d = LocalDrive::new(p, 2.0 * k as f64 * half_step);
            step_starts.push(d);
            step_ends.push([d.phi_sq_with_rate(0.0), d.phi_sq_with_rate(h)]);
        }
        DriveTable {
            phi_sq_i,
            phi_sq_ii,
            step_starts,
            step_ends,
        }
    }

    /// [`LocalDrive::phi_sq_with_rate`] of step `k`'s drive at the step's start and end (the
    /// same numbers, computed once).
    #[inline(always)]
    pub fn step_ends(&self, k: usize) -> [DriveWithRate; 2] {
        self.step_ends[k]
    }

    /// The drive anchored at the start of step `k`.
    #[inline(always)]
    pub fn step_start(&self, k: usize) -> &LocalDrive {
        &self.step_starts[k]
    }

    /// (φ_I², φ_II²) at half-step `k` of the period.
    #[inline(always)]
    pub fn at(&self, k: usize) -> (f64, f64) {
        (self.phi_sq_i[k], self.phi_sq_ii[k])
    }
}

/// The drive near one instant τ₀, for the split steps: φ² at τ₀ + δ from cos/sin of the
/// phase at τ₀ and a short series in ω·δ, instead of cos() at every evaluation.
#[derive(Debug, Clone, Copy)]
pub struct LocalDrive {
    omega: f64,
    dc: [f64; 2],
    ac: [f64; 2],
    cos0: [f64; 2],
    sin0: [f64; 2],
}

impl LocalDrive {
    /// Anchors the drive of `p` at `tau0`.
    pub fn new(p: &Params, tau0: f64) -> Self {
        let theta = p.omega() * tau0;
        let (di, dii) = (p.drive_i(), p.drive_ii());
        let (s_i, c_i) = theta.sin_cos();
        let (s_ii, c_ii) = if dii.is_off() {
            (0.0, 1.0)
        } else {
            (theta + p.phase_ii()).sin_cos()
        };
        LocalDrive {
            omega: p.omega(),
            dc: [di.phi_dc(), dii.phi_dc()],
            ac: [di.phi_ac(), dii.phi_ac()],
            cos0: [c_i, c_ii],
            sin0: [s_i, s_ii],
        }
    }

    /// (φ_I², φ_II²) at τ₀ + `delta`, for |ω·δ| ≤ π/4 (a step of 8 or more per period).
    #[inline(always)]
    pub fn phi_sq<T: Real>(&self, delta: T) -> (T, T) {
        // the unused rates are optimised away
        self.phi_sq_with_rate(delta).0
    }

    /// (φ_I², φ_II²) and their rates d(φ²)/dτ at τ₀ + `delta`, for |ω·δ| ≤ π/4.
    #[inline(always)]
    pub fn phi_sq_with_rate<T: Real>(&self, delta: T) -> DriveWithRate<T> {
        let omega = T::splat(self.omega);
        let (sd, cd) = small_sin_cos(omega * delta);
        let ((phi_sq_i, rate_i), (phi_sq_ii, rate_ii)) =
            (self.membrane_at(0, sd, cd), self.membrane_at(1, sd, cd));
        ((phi_sq_i, phi_sq_ii), (rate_i, rate_ii))
    }

    /// Membrane `m`'s φ² and its rate where the phase has moved on by an angle of sine `sd`
    /// and cosine `cd`.
    #[inline(always)]
    fn membrane_at<T: Real>(&self, m: usize, sd: T, cd: T) -> (T, T) {
        let (cos0, sin0) = (T::splat(self.cos0[m]), T::splat(self.sin0[m]));
        let (ac, dc) = (T::splat(self.ac[m]), T::splat(self.dc[m]));
        let c = cos0 * cd - sin0 * sd;
        let s = sin0 * cd + cos0 * sd;
        let phi = ac.mul_add(c, dc);
        (
            phi * phi,
            T::splat(-2.0) * phi * ac * T::splat(self.omega) * s,
        )
    }
}

/// sin and cos of |x| ≤ π/4 by their Taylor series to x¹⁷ / x¹⁶ (error < 1e-17), in
/// Horner form on x² with fused multiply-adds (the split steps' latency is in this chain).
#[inline(always)]
pub fn small_sin_cos<T: Real>(x: T) -> (T, T) {
    let x2 = x * x;
    let mut s = T::splat(INVERSE_FACTORIALS[17]);
    let mut c = T::splat(INVERSE_FACTORIALS[16]);
    for k in [15, 13, 11, 9, 7, 5, 3, 1] {
        // s ← 1/k! − x² s, c ← 1/(k−1)! − x² c
        s = (-x2).mul_add(s, T::splat(INVERSE_FACTORIALS[k]));
        c = (-x2).mul_add(c, T::splat(INVERSE_FACTORIALS[k - 1]));
    }
    (x * s, c)
}

/// 1/n! for n = 0..=17.
const INVERSE_FACTORIALS: [f64; 18] = {
    let mut t = [1.0; 18];
    let mut factorial = 1.0;
    let mut n = 1;
    while n < 18 {
        factorial *= n as f64;
        t[n] = 1.0 / factorial;
        n += 1;
    }
    t
};
