//! The k-period flow of any [`System`] with its monodromy, for shooting and continuation on
//! models written in the session: adaptive Dormand–Prince 5(4) on the state, the variational
//! equations Φ' = A(τ)Φ (A the model's symbolic Jacobian) and ∫ tr A dτ together.
//!
//! Every switch (a sign change of a switching function: an argument of `max`, `min`, `abs`,
//! `if`) is located to round-off on real steps, so no step straddles one and A(τ) is smooth on
//! every step. Where the field jumps at a switch (an `if` whose branches differ there) Φ takes
//! the saltation jump S = I + (f⁺ − f⁻) ∇hᵀ / (∇h·f⁻ + ∂h/∂τ); where it is continuous (every
//! `max`, `min` and `abs` kink) S = I. Liouville's formula checks the whole:
//! det Φ(kT) = exp(∫ tr A dτ) · Π det S, and det S = (∇h·f⁺ + ∂h/∂τ)/(∇h·f⁻ + ∂h/∂τ).

use nalgebra::DMatrix;

use crate::analysis::orbit::shooting::{PeriodFlow, Shootable, ShootingError};
use crate::model::equations::EquationSystem;
use crate::model::system::{Differentiable, MAX_DIM, Mode, StateVec, System, Vector};
use crate::solver::dopri_tableau::{A, C, E};
use crate::solver::isa::{self, Isa};
use crate::solver::{Collision, Tolerance};

/// The augmented state: x (n), Φ row-major (n²), ∫ tr A dτ (1); n ≤ [`MAX_DIM`].
const AUG: usize = MAX_DIM + MAX_DIM * MAX_DIM + 1;
type Aug = [f64; AUG];

/// Most switching functions (the bits of a mode).
const MAX_SWITCHES: usize = 64;
/// Points per step at which the switching functions are scanned (cubic Hermite in x).
const SCAN_POINTS: usize = 4;
/// Most steps in one call (a guard against a stalled step size).
const MAX_STEPS: usize = 2_000_000;
/// A jump of the field at a switch below this, relative to the field, is the round-off of a
/// continuous field (the state is just past the switch): no saltation.
const JUMP_TOLERANCE: f64 = 1e-9;

/// The orbit of `sys` from `x0` at τ = 0 over `k` forcing periods, with its monodromy.
pub fn period_flow<S: Differentiable>(
    sys: &S,
    x0: &[f64],
    k: usize,
    tol: Tolerance,
) -> Result<PeriodFlow, ShootingError> {
    let n = sys.dim();
    let mut flow = Flow {
        sys: sys.clone(),
        n,
        mask: sys.switch_mask(),
        tol,
        jac: [[0.0; MAX_DIM]; MAX_DIM],
        stages: vec![[0.0; AUG]; 7],
    };
    flow.orbit(&x0[..n], k)
}

impl Shootable for EquationSystem {
    fn dim(&self) -> usize {
        System::dim(self)
    }

    fn omega(&self) -> f64 {
        EquationSystem::omega(self)
    }

    fn period_flow(
        &self,
        x0: &[f64],
        k: usize,
        tol: Tolerance,
    ) -> Result<PeriodFlow, ShootingError> {
        period_flow(self, x0, k, tol)
    }
}

struct Flow<S: Differentiable> {
    sys: S,
    n: usize,
    mask: Mode,
    tol: Tolerance,
    /// Scratch for the Jacobian.
    jac: [Vector; MAX_DIM],
    /// Scratch for a step's seven stages.
    stages: Vec<Aug>,
}

/// The state part of an augmented state, padded.
fn state(y: &Aug, n: usize) -> Vector {
    let mut x = [0.0; MAX_DIM];
    x[..n].copy_from_slice(&y[..n]);
    x
}

impl<S: Differentiable> Flow<S> {
    /// Entries of the augmented state in use.
    fn used(&self) -> usize {
        self.n + self.n * self.n + 1
    }

    /// Whether the field `f` (and, with `jacobian`, the Jacobian last evaluated) is finite.
    #[inline(always)]
    fn defined(&self, f: &Vector, jacobian: bool) -> bool {
        let n = self.n;
        f[..n].iter().all(|v| v.is_finite())
            && (!jacobian
                || self.jac[..n]
                    .iter()
                    .all(|r| r[..n].iter().all(|v| v.is_finite())))
    }

    /// The augmented state's derivative at (t, y) on `mode` into `dy` (its entries in use;
    /// the rest are left as they are).
    #[inline(always)]
    fn deriv(&mut self, t: f64, y: &Aug, mode: Mode, dy: &mut Aug) {
        let n = self.n;
        let x = state(y, n);
        let mut f = [0.0; MAX_DIM];
        self.sys
            .field_and_jacobian(t, &x, mode, &mut f, &mut self.jac);
        if !self.defined(&f, true) {
            // a stage strayed off the piece to where it is not defined: the stage takes the
            // piece it is on (the step crosses a switch, located as any other)
            let seen = self.sys.mode_at(t, &x) & self.mask;
            if seen != mode & self.mask {
                let mode = (mode & !self.mask) | seen;
                self.sys
                    .field_and_jacobian(t, &x, mode, &mut f, &mut self.jac);
            }
        }
        dy[..n].copy_from_slice(&f[..n]);
        for i in 0..n {
            for j in 0..n {
                let mut acc = 0.0;
                for l in 0..n {
                    acc += self.jac[i][l] * y[n + l * n + j];
                }
                dy[n + i * n + j] = acc;
            }
        }
        dy[n + n * n] = (0..n).map(|i| self.jac[i][i]).sum();
    }

    /// The state part of [`Self::step`] alone (the state does not depend on Φ, so its bits
    /// are the same): what probes locating a switch or a turning point need.
    #[inline(always)]
    fn state_step(&mut self, t: f64, y: &Aug, k1: &Aug, h: f64, mode: Mode) -> Vector {
        let n = self.n;
        let mut k = [[0.0; MAX_DIM]; 7];
        k[0][..n].copy_from_slice(&k1[..n]);
        let mut x1 = [0.0; MAX_DIM];
        for s in 1..7 {
            let mut xs = state(y, n);
            for (kj, &aj) in k.iter().zip(A[s - 1]) {
                for c in 0..n {
                    xs[c] += h * aj * kj[c];
                }
            }
            if s == 6 {
                x1 = xs;
            }
            let mut f = [0.0; MAX_DIM];
            let seen = self.sys.field(t + C[s] * h, &xs, mode, &mut f);
            if seen != mode && !self.defined(&f, false) {
                // as in `deriv`: the piece the stage is on
                self.sys.field(t + C[s] * h, &xs, seen, &mut f);
            }
            k[s] = f;
        }
        x1
    }

    /// One Dormand–Prince step of length `h` on `mode` from `y` (derivative `k1`): the new
    /// state into `end` and its derivative into `end_rate` (the entries in use); returns the
    /// scaled error (of the state and Φ; infinite where a value is not finite).
    #[inline(always)]
    fn step(
        &mut self,
        t: f64,
        [y, k1]: [&Aug; 2],
        h: f64,
        mode: Mode,
        [end, end_rate]: [&mut Aug; 2],
    ) -> f64 {
        let m = self.used();
        // only the entries in use are read or written: the stages are kept between steps
        // (no 4 kB cleared at every step), and the rest of every state stays zero
        let mut k = std::mem::take(&mut self.stages);
        k[0][..m].copy_from_slice(&k1[..m]);
        let mut ys = [0.0; AUG];
        for s in 1..7 {
            ys[..m].copy_from_slice(&y[..m]);
            for (kj, &aj) in k.iter().zip(A[s - 1]) {
                for c in 0..m {
                    ys[c] += h * aj * kj[c];
                }
            }
            self.deriv(t + C[s] * h, &ys, mode, &mut k[s]);
        }
        // the sixth stage's state is the step's end
        end[..m].copy_from_slice(&ys[..m]);
        let y1 = &*end;
        let controlled = m - 1;
        let mut err_sq = 0.0;
        for c in 0..controlled {
            let e: f64 = (0..7).map(|i| E[i] * k[i][c]).sum::<f64>() * h;
            let scale = self.tol.atol + self.tol.rtol * y[c].abs().max(y1[c].abs());
            err_sq += (e / scale) * (e / scale);
        }
        let err = (err_sq / controlled as f64).sqrt();
        let finite = y1[..m].iter().chain(&k[6][..m]).all(|v| v.is_finite());
        end_rate[..m].copy_from_slice(&k[6][..m]);
        self.stages = k;
        if finite { err } else { f64::INFINITY }
    }

    /// The switching functions at (t, x) on `mode`, each signed to be positive on `mode`'s
    /// side, and the bits whose sign says another piece.
    #[inline(always)]
    fn crossed(&mut self, t: f64, x: &Vector, mode: Mode) -> (Mode, [f64; MAX_SWITCHES]) {
        let mut s = [0.0; MAX_SWITCHES];
        let seen = self.sys.switching(t, x, mode, &mut s);
        // only the switches the mask holds are ever read
        let used = MAX_SWITCHES - self.mask.leading_zeros() as usize;
        for (k, v) in s.iter_mut().enumerate().take(used) {
            if mode & (1 << k) == 0 {
                *v = -*v;
            }
        }
        ((seen ^ mode) & self.mask, s)
    }

    /// The shortest sub-step σ in (lo, hi] that ends on another piece, to round-off, by
    /// false position (Illinois) on real steps; `hi` ends on another piece. Returns σ and the
    /// bits that differ there.
    fn locate_switch(
        &mut self,
        t: f64,
        y: &Aug,
        k1: &Aug,
        mode: Mode,
        (mut lo, mut hi): (f64, f64),
    ) -> (f64, Mode) {
        let n = self.n;
        let probe = |flow: &mut Self, sigma: f64| {
            let end = if sigma == 0.0 {
                state(y, n)
            } else {
                flow.state_step(t, y, k1, sigma, mode)
            };
            flow.crossed(t + sigma, &end, mode)
        };
        let (c_lo, mut g_lo) = probe(self, lo);
        if c_lo != 0 {
            // the scan's interpolant was optimistic: search from the start of the step
            lo = 0.0;
            g_lo = probe(self, 0.0).1;
        }
        let (mut c_hi, mut g_hi) = probe(self, hi);
        let mut weight = (1.0, 1.0);
        let mut side = 0;
        for _ in 0..200 {
            if hi - lo <= 4.0 * f64::EPSILON * (t.abs() + hi) {
                break;
            }
            let bit = c_hi.trailing_zeros() as usize;
            let (a, b) = (g_lo[bit] * weight.0, g_hi[bit] * weight.1);
            let mut sigma = if a > 0.0 && b <= 0.0 && a - b > 0.0 {
                lo + (hi - lo) * a / (a - b)
            } else {
                0.5 * (lo + hi)
            };
            if !(sigma > lo && sigma < hi) {
                sigma = 0.5 * (lo + hi);
            }
            let (c, g) = probe(self, sigma);
            if c != 0 {
                if c.trailing_zeros() != c_hi.trailing_zeros() {
                    weight = (1.0, 1.0);
                    side = 0;
                }
                (hi, c_hi, g_hi) = (sigma, c, g);
                weight = (if side == -1 { weight.0 * 0.5 } else { 1.0 }, 1.0);
                side = -1;
            } else {
                (lo, g_lo) = (sigma, g);
                weight = (1.0, if side == 1 { weight.1 * 0.5 } else { 1.0 });
                side = 1;
            }
        }
        (hi, c_hi)
    }

    /// The sub-step σ in (0, h) where the output's rate `rate(σ)` passes zero (it has the
    /// sign of `sign` at 0 and the other at h), by false position on real steps.
    fn locate_turning(&mut self, t: f64, y: &Aug, k1: &Aug, mode: Mode, h: f64, sign: f64) -> f64 {
        let n = self.n;
        let rate = |flow: &mut Self, sigma: f64| {
            let end = flow.state_step(t, y, k1, sigma, mode);
            sign * flow.sys.output(t + sigma, &end, mode).1
        };
        let x0 = state(y, n);
        let r_lo = sign * self.sys.output(t, &x0, mode).1;
        let r_hi = rate(self, h);
        crate::solver::illinois::illinois(t, (0.0, h), (r_lo, r_hi), |s| rate(self, s))
    }

    /// Φ ← S Φ at a switch from `old` to `new` at (t, y), where the field jumps; returns
    /// ln |det S| (0 where it does not jump).
    fn saltation(&mut self, t: f64, y: &mut Aug, old: Mode, new: Mode, bit: usize) -> f64 {
        let n = self.n;
        let x = state(y, n);
        let (mut f_old, mut f_new) = ([0.0; MAX_DIM], [0.0; MAX_DIM]);
        self.sys.field(t, &x, old, &mut f_old);
        self.sys.field(t, &x, new, &mut f_new);
        let scale = 1.0 + f_old[..n].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let jump = (0..n).fold(0.0f64, |m, i| m.max((f_new[i] - f_old[i]).abs()));
        if jump <= JUMP_TOLERANCE * scale {
            return 0.0;
        }
        let mut grad = [0.0; MAX_DIM];
        let h_t = self.sys.switch_gradient(t, &x, old, bit, &mut grad);
        let rate = |f: &Vector| (0..n).map(|j| grad[j] * f[j]).sum::<f64>() + h_t;
        let (before, after) = (rate(&f_old), rate(&f_new));
        if !before.is_finite() || before.abs() <= f64::EPSILON * scale {
            // grazing: the trajectory touches the switch tangentially
            return 0.0;
        }
        // Φ_ij += (f⁺ − f⁻)_i (∇h · Φ_·j) / ḣ⁻
        for j in 0..n {
            let g_phi: f64 = (0..n).map(|l| grad[l] * y[n + l * n + j]).sum();
            for i in 0..n {
                y[n + i * n + j] += (f_new[i] - f_old[i]) * g_phi / before;
            }
        }
        (after / before).abs().ln()
    }

    /// The orbit from `x0` over `k` forcing periods, in the version compiled for this
    /// process's instruction set ([`isa::chosen`]).
    fn orbit(&mut self, x0: &[f64], k: usize) -> Result<PeriodFlow, ShootingError> {
        match isa::chosen() {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the chosen instruction set is one this CPU has, and v4 includes v3
            Isa::X86_64V3 | Isa::X86_64V4 => unsafe { self.orbit_v3(x0, k) },
            _ => self.orbit_body(x0, k),
        }
    }

    /// [`Self::orbit`] with AVX2 and FMA for the engine around the model (the written model's
    /// own code is compiled for this CPU already); the same bits.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe,f16c")]
    fn orbit_v3(&mut self, x0: &[f64], k: usize) -> Result<PeriodFlow, ShootingError> {
        self.orbit_body(x0, k)
    }

    #[inline(always)]
    fn orbit_body(&mut self, x0: &[f64], k: usize) -> Result<PeriodFlow, ShootingError> {
        let n = self.n;
        let period = self.sys.period();
        let x_start = StateVec::from_slice(x0);
        let padded = x_start.padded();
        if self.sys.collided(0.0, &padded) {
            return Err(ShootingError::Collision(Collision {
                tau: 0.0,
                lambda_i: x0[0],
            }));
        }
        let mut mode = self.sys.mode_at(0.0, &padded) & self.mask;
        let mut y = [0.0; AUG];
        y[..n].copy_from_slice(x0);
        for i in 0..n {
            y[n + i * n + i] = 1.0;
        }
        let mut t = 0.0;
        let mut h = period / 64.0;
        let h_max = period / 16.0;
        let (out0, mut rate) = self.sys.output(0.0, &padded, mode);
        let mut out = PeriodFlow {
            end: x_start,
            monodromy: DMatrix::identity(n, n),
            poincare: vec![x_start],
            lambda_min: out0,
            lambda_max: out0,
            trace_integral: 0.0,
            switches: 0,
        };
        let mut salted = 0.0;
        let mut k1 = [0.0; AUG];
        self.deriv(t, &y, mode, &mut k1);
        // the state a step ends on and its derivative there (zero beyond the entries in
        // use, m)
        let m = self.used();
        let (mut y1, mut k7) = ([0.0; AUG], [0.0; AUG]);
        let mut j_period = 1;
        for _ in 0..MAX_STEPS {
            let t_end = j_period as f64 * period;
            let remaining = t_end - t;
            let last = h >= remaining;
            let hs = if last { remaining } else { h };
            let err = self.step(t, [&y, &k1], hs, mode, [&mut y1, &mut k7]);
            // rejected, or not finite (err is infinite then, never NaN)
            if err > 1.0 || err.is_nan() {
                let fac = if err.is_finite() {
                    (0.9 * err.powf(-0.2)).clamp(0.2, 1.0)
                } else {
                    0.2
                };
                h = hs * fac;
                if h < 1e-14 * period {
                    let x = state(&y, n);
                    return Err(if err.is_finite() {
                        ShootingError::Stalled { tau: t }
                    } else {
                        ShootingError::NonFinite {
                            tau: t,
                            detail: self
                                .sys
                                .explain_non_finite(t, &x)
                                .unwrap_or_else(|| "a value of the model".into()),
                        }
                    });
                }
                continue;
            }
            let fac = if err == 0.0 {
                5.0
            } else {
                (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
            };
            // scan the switching functions along the cubic Hermite interpolant of the state
            let mut bracket = None;
            let mut s_prev = 0.0;
            for i in 1..=SCAN_POINTS {
                let s = i as f64 / SCAN_POINTS as f64;
                let x = if i == SCAN_POINTS {
                    state(&y1, n)
                } else {
                    let mut x = [0.0; MAX_DIM];
                    for c in 0..n {
                        x[c] = crate::solver::hermite::value(y[c], k1[c], y1[c], k7[c], hs, s);
                    }
                    x
                };
                if self.crossed(t + s * hs, &x, mode).0 != 0 {
                    bracket = Some((s_prev * hs, s * hs));
                    break;
                }
                s_prev = s;
            }
            // a bracket only the interpolant saw is checked on real steps: the first real
            // step to the bracket's end or the step's end that lands on another piece
            let event = bracket.and_then(|(lo, hi)| {
                let lands = |flow: &mut Self, sigma: f64| {
                    let end = flow.state_step(t, &y, &k1, sigma, mode);
                    flow.crossed(t + sigma, &end, mode).0 != 0
                };
                if lands(self, hi) {
                    Some((lo, hi))
                } else if hi < hs && self.crossed(t + hs, &state(&y1, n), mode).0 != 0 {
                    Some((hi, hs))
                } else {
                    None
                }
            });
            // the step taken: the whole step, or the sub-step to the switch in its place
            let (h_taken, flipped) = match event {
                None => (hs, 0),
                Some(b) => {
                    let (sigma, flipped) = self.locate_switch(t, &y, &k1, mode, b);
                    self.step(t, [&y, &k1], sigma, mode, [&mut y1, &mut k7]);
                    (sigma, flipped)
                }
            };
            // a turning point of the output inside the step: refine it on real steps
            let x_new = state(&y1, n);
            let (out_new, rate_new) = self.sys.output(t + h_taken, &x_new, mode);
            if rate * rate_new < 0.0 {
                let sign = rate.signum();
                let s = self.locate_turning(t, &y, &k1, mode, h_taken, sign);
                let end = self.state_step(t, &y, &k1, s, mode);
                let o = self.sys.output(t + s, &end, mode).0;
                out.lambda_min = out.lambda_min.min(o);
                out.lambda_max = out.lambda_max.max(o);
            }
            out.lambda_min = out.lambda_min.min(out_new);
            out.lambda_max = out.lambda_max.max(out_new);
            let crossed = flipped != 0;
            let reached_end = !crossed && last;
            let stepped_to = t + h_taken;
            t = if reached_end { t_end } else { stepped_to };
            // the last stage of a whole step is the next step's first, and the output's rate
            // at its end the next start's, where the time and the piece are the same
            let fsal = !crossed && t == stepped_to;
            if crossed {
                let new = mode ^ flipped;
                let bit = flipped.trailing_zeros() as usize;
                salted += self.saltation(t, &mut y1, mode, new, bit);
                mode = new;
                out.switches += 1;
            } else if !last {
                h = (hs * fac).min(h_max);
            }
            y[..m].copy_from_slice(&y1[..m]);
            let x = state(&y, n);
            if self.sys.collided(t, &x) {
                return Err(ShootingError::Collision(Collision {
                    tau: t,
                    lambda_i: x[0],
                }));
            }
            if fsal {
                k1[..m].copy_from_slice(&k7[..m]);
                rate = rate_new;
            } else {
                self.deriv(t, &y, mode, &mut k1);
                rate = self.sys.output(t, &x, mode).1;
            }
            if reached_end {
                let end = StateVec::from_slice(&y[..n]);
                if j_period == k {
                    out.end = end;
                    out.monodromy = DMatrix::from_row_slice(n, n, &y[n..n + n * n]);
                    out.trace_integral = y[n + n * n] + salted;
                    return Ok(out);
                }
                out.poincare.push(end);
                j_period += 1;
            }
        }
        Err(ShootingError::Stalled { tau: t })
    }
}
