//! Shooting for periodic responses: a period-k response is a fixed point of the k-fold
//! stroboscopic map P^k, found by Newton with the monodromy matrix ∂P^k/∂x0 integrated beside
//! the state (the variational equations Φ' = A(τ)Φ). [`shoot`] works on any [`Shootable`]
//! model; this file holds the built-in model's flow, [`super::variational`] a written one's.
//!
//! In the built-in model the field is continuous where a membrane goes slack (the tension is zero there), so the
//! monodromy needs no saltation jump; but A(τ) jumps, so every switch of p_I or p_II is
//! located to round-off and a step never straddles one. Because tr A = ∂a/∂v = −c̃ · (number of
//! taut membranes), Liouville's formula gives an independent check:
//! det Φ(kT) = exp(−c̃ ∫ n_taut dτ), with the integral summed exactly over the located pieces.

use std::cell::Cell;

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::analysis::orbit::floquet::Multipliers;
use crate::model::Params;
use crate::model::system::StateVec;
use crate::solver::dopri_tableau::{A, C, E};
use crate::solver::field::{Field, Membrane, Mode};
use crate::solver::illinois::Illinois;
use crate::solver::isa::{self, Isa};
use crate::solver::{Collision, Tolerance};

/// Augmented state: [λ_I, v, Φ₀₀, Φ₀₁, Φ₁₀, Φ₁₁].
type Aug = [f64; 6];

/// Points per step at which the switching functions are scanned (cubic Hermite in x, v).
const SCAN_POINTS: usize = 4;
/// Most steps in one call (a guard against a stalled step size).
const MAX_STEPS: usize = 2_000_000;

/// The slope g'(λ) of the Gent tension g(λ) = J(λ⁴ − 1) / (λ((J + 2)λ² − λ⁴ − 1)).
pub fn gent_slope(lambda: f64, j: f64) -> f64 {
    let l2 = lambda * lambda;
    let l4 = l2 * l2;
    let num = j * (l4 - 1.0);
    let den = lambda * ((j + 2.0) * l2 - l4 - 1.0);
    let dnum = 4.0 * j * l2 * lambda;
    let dden = 3.0 * (j + 2.0) * l2 - 5.0 * l4 - 1.0;
    (dnum * den - num * dden) / (den * den)
}

/// A model at one parameter point whose periodic responses can be shot: the built-in DEA
/// ([`Params`]) or a written model ([`crate::model::equations::EquationSystem`]).
pub trait Shootable: Clone + Send + Sync {
    /// Number of state variables.
    fn dim(&self) -> usize;
    /// The forcing frequency ω (the period is 2π/ω).
    fn omega(&self) -> f64;
    /// The orbit from `x0` at τ = 0 over `k` forcing periods, with its monodromy, integrated
    /// to `tol`.
    fn period_flow(
        &self,
        x0: &[f64],
        k: usize,
        tol: Tolerance,
    ) -> Result<PeriodFlow, ShootingError>;
}

impl Shootable for Params {
    fn dim(&self) -> usize {
        2
    }

    fn omega(&self) -> f64 {
        Params::omega(self)
    }

    fn period_flow(
        &self,
        x0: &[f64],
        k: usize,
        tol: Tolerance,
    ) -> Result<PeriodFlow, ShootingError> {
        VariationalFlow::new(self, tol)
            .orbit([x0[0], x0[1]], k)
            .map_err(ShootingError::Collision)
    }
}

/// One k-period orbit followed from τ = 0 with its monodromy matrix.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodFlow {
    /// The state after k forcing periods.
    pub end: StateVec,
    /// ∂(end)/∂(start), n × n.
    pub monodromy: DMatrix<f64>,
    /// The stroboscopic points at τ = 0, T, …, (k − 1)T.
    pub poincare: Vec<StateVec>,
    /// Least and greatest value of the amplitude's output (λ_I for the built-in model).
    pub lambda_min: f64,
    pub lambda_max: f64,
    /// ∫ tr A dτ over the k periods (plus ln det of any saltation jump), from the located
    /// pieces: what ln det Φ must equal.
    pub trace_integral: f64,
    /// Switches met on the way.
    pub switches: usize,
}

impl PeriodFlow {
    /// |det Φ − exp(∫ tr A)|: the Liouville check of the variational integration.
    pub fn liouville_error(&self) -> f64 {
        (self.monodromy.determinant() - self.trace_integral.exp()).abs()
    }
}

/// The flow of the state with its variational equations, under one parameter set.
#[derive(Debug, Clone)]
pub struct VariationalFlow {
    params: Params,
    field: Field,
    tol: Tolerance,
    h_max: f64,
    /// The drive's (φ_I², φ_II²) at the last τ asked, by τ's bits: a step's last two stages,
    /// the end of its switching scan and the next step's first stage share one τ.
    last_phi_sq: Cell<(u64, (f64, f64))>,
}

impl VariationalFlow {
    pub fn new(params: &Params, tol: Tolerance) -> Self {
        VariationalFlow {
            params: *params,
            field: Field::new(params),
            tol,
            h_max: params.period() / 16.0,
            last_phi_sq: Cell::new((f64::NAN.to_bits(), (f64::NAN, f64::NAN))),
        }
    }

    /// The drive's (φ_I², φ_II²) at τ = `t`, computed once per distinct τ in a row.
    #[inline]
    fn phi_sq_at(&self, t: f64) -> (f64, f64) {
        let (bits, phi_sq) = self.last_phi_sq.get();
        if bits == t.to_bits() {
            return phi_sq;
        }
        let phi_sq = self.params.phi_sq_at(t);
        self.last_phi_sq.set((t.to_bits(), phi_sq));
        phi_sq
    }

    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Acceleration and its partials (∂a/∂x, ∂a/∂v) on the smooth piece `mode`.
    #[inline(always)]
    fn accel_jacobian(&self, t: f64, x: f64, v: f64, mode: Mode) -> (f64, f64, f64) {
        let (pi, pii) = self.phi_sq_at(t);
        let a = self.field.accel_in_mode(x, v, pi, pii, mode);
        let j = self.params.j();
        let c = self.params.c_tilde();
        let (mut ax, mut av) = (0.0, 0.0);
        if mode.taut_i {
            ax -= gent_slope(x, j) - pi;
            av -= c;
        }
        if mode.taut_ii {
            ax -= gent_slope(self.field.two_lambda_p() - x, j) - pii;
            av -= c;
        }
        (a, ax, av)
    }

    #[inline(always)]
    fn deriv(&self, t: f64, y: &Aug, mode: Mode) -> Aug {
        let (a, ax, av) = self.accel_jacobian(t, y[0], y[1], mode);
        // Φ' = [[0, 1], [ax, av]] Φ
        [
            y[1],
            a,
            y[4],
            y[5],
            ax * y[2] + av * y[4],
            ax * y[3] + av * y[5],
        ]
    }

    /// One Dormand–Prince step: the new state, its derivative and the scaled error.
    #[inline(always)]
    fn step(&self, t: f64, y: &Aug, k1: &Aug, h: f64, mode: Mode) -> (Aug, Aug, f64) {
        let mut k = [[0.0; 6]; 7];
        k[0] = *k1;
        let mut y1 = *y;
        for s in 1..7 {
            let mut ys = *y;
            for (kj, &aj) in k.iter().zip(A[s - 1]) {
                for c in 0..6 {
                    ys[c] += h * aj * kj[c];
                }
            }
            if s == 6 {
                y1 = ys;
            }
            k[s] = self.deriv(t + C[s] * h, &ys, mode);
        }
        let mut err_sq = 0.0;
        for c in 0..6 {
            let e: f64 = (0..7).map(|i| E[i] * k[i][c]).sum::<f64>() * h;
            let scale = self.tol.atol + self.tol.rtol * y[c].abs().max(y1[c].abs());
            err_sq += (e / scale) * (e / scale);
        }
        (y1, k[6], (err_sq / 6.0).sqrt())
    }

    /// Switching functions, positive while the piece `mode` holds: p_I and p_II signed by
    /// the mode, and the room left to the frames and the Gent limits.
    #[inline(always)]
    fn event_values(&self, t: f64, x: f64, v: f64, mode: Mode) -> [f64; 3] {
        let (pi, pii) = self.phi_sq_at(t);
        let p_i = self.field.tension_of(Membrane::I, x, v, pi, pii);
        let p_ii = self.field.tension_of(Membrane::Ii, x, v, pi, pii);
        let x_ii = self.field.two_lambda_p() - x;
        let upper = crate::model::forces::gent_poles(self.params.j()).1;
        [
            if mode.taut_i { p_i } else { -p_i },
            if mode.taut_ii { p_ii } else { -p_ii },
            x.min(x_ii).min(upper - x).min(upper - x_ii),
        ]
    }

    /// Step length σ in (lo, hi] at which the quantity `what` of the stepped state first
    /// turns negative (`g_lo` ≥ 0 > `g_hi`, the state after a step of `hi` being `y_hi`),
    /// by Illinois false position on real steps; returns the negative side and the state
    /// there. (No closure: one called in several places is compiled on its own, without the
    /// instruction set of the orbit.)
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn locate(
        &self,
        t: f64,
        y: &Aug,
        k1: &Aug,
        mode: Mode,
        (mut lo, mut g_lo): (f64, f64),
        (hi, g_hi, y_hi): (f64, f64, Aug),
        what: Located,
    ) -> (f64, Aug) {
        if g_lo < 0.0 {
            // the scan's interpolant was optimistic: search from the start of the step
            lo = 0.0;
            g_lo = self.located_value(what, t, y, mode).max(0.0);
        }
        let mut search = Illinois::new(t, (lo, hi), (g_lo, g_hi));
        let mut at_root = y_hi;
        while let Some(s) = search.probe() {
            let at = self.step(t, y, k1, s, mode).0;
            let g = self.located_value(what, t + s, &at, mode);
            if g < 0.0 {
                at_root = at;
            }
            search.record(s, g);
        }
        (search.root(), at_root)
    }

    /// The quantity `what` at state `y` at τ = `t`.
    #[inline(always)]
    fn located_value(&self, what: Located, t: f64, y: &Aug, mode: Mode) -> f64 {
        match what {
            Located::Event(e) => self.event_values(t, y[0], y[1], mode)[e],
            Located::Rate(sign) => sign * y[1],
        }
    }

    /// Follows [λ_I, v] = `x0` from τ = 0 over `k` forcing periods with Φ(0) = I, in the
    /// version compiled for this process's instruction set ([`isa::chosen`]): with FMA where
    /// the CPU has it, a `mul_add` is one instruction instead of a call, and the same bits.
    pub fn orbit(&self, x0: [f64; 2], k: usize) -> Result<PeriodFlow, Collision> {
        match isa::chosen() {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the chosen instruction set is one this CPU has, and v4 includes v3
            Isa::X86_64V3 | Isa::X86_64V4 => unsafe { self.orbit_v3(x0, k) },
            _ => self.orbit_body(x0, k),
        }
    }

    /// [`Self::orbit_body`] compiled for x86-64-v3.
    ///
    /// # Safety
    /// The CPU must have x86-64-v3's features.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe,f16c")]
    pub fn orbit_v3(&self, x0: [f64; 2], k: usize) -> Result<PeriodFlow, Collision> {
        self.orbit_body(x0, k)
    }

    /// The k-period orbit from `x0` with its monodromy, for whichever instruction set it
    /// is inlined into.
    #[inline(always)]
    pub fn orbit_body(&self, x0: [f64; 2], k: usize) -> Result<PeriodFlow, Collision> {
        let period = self.params.period();
        let (pi, pii) = self.params.phi_sq_at(0.0);
        if !self.field.inside(x0[0]) {
            return Err(Collision {
                tau: 0.0,
                lambda_i: x0[0],
            });
        }
        let mut mode = self.field.mode_at(x0[0], x0[1], pi, pii);
        let mut y: Aug = [x0[0], x0[1], 1.0, 0.0, 0.0, 1.0];
        let mut t = 0.0;
        let mut h = (period / 64.0).min(self.h_max);
        let mut out = PeriodFlow {
            end: StateVec::from(x0),
            monodromy: DMatrix::identity(2, 2),
            poincare: vec![StateVec::from(x0)],
            lambda_min: x0[0],
            lambda_max: x0[0],
            trace_integral: 0.0,
            switches: 0,
        };
        let n_taut = |m: Mode| (m.taut_i as u8 + m.taut_ii as u8) as f64;
        let c = self.params.c_tilde();
        let mut k1 = self.deriv(t, &y, mode);
        let mut j_period = 1;
        for _ in 0..MAX_STEPS {
            let t_end = j_period as f64 * period;
            let remaining = t_end - t;
            let last = h >= remaining;
            let hs = if last { remaining } else { h };
            let (y1, k7, err) = self.step(t, &y, &k1, hs, mode);
            let fac = if err == 0.0 {
                5.0
            } else {
                (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
            };
            if err > 1.0 {
                h = hs * fac.min(1.0);
                continue;
            }
            // scan the switching functions along the cubic Hermite interpolant of (x, v)
            let mut bracket = None;
            let mut event = 0;
            let mut s_prev = 0.0;
            // the end first, while the drive there is the one the step's last stage computed
            let g_end = self.event_values(t + hs, y1[0], y1[1], mode);
            for i in 1..=SCAN_POINTS {
                let s = i as f64 / SCAN_POINTS as f64;
                let g = if i == SCAN_POINTS {
                    g_end
                } else {
                    let x = crate::solver::hermite::value(y[0], y[1], y1[0], y1[1], hs, s);
                    let v = crate::solver::hermite::value(y[1], k1[1], y1[1], k7[1], hs, s);
                    self.event_values(t + s * hs, x, v, mode)
                };
                if let Some(idx) = (0..3)
                    .filter(|&e| g[e] < 0.0)
                    .min_by(|&a, &b| g[a].partial_cmp(&g[b]).unwrap_or(std::cmp::Ordering::Equal))
                {
                    bracket = Some((s_prev * hs, s * hs));
                    event = idx;
                    break;
                }
                s_prev = s;
            }
            let (h_taken, y_new, crossed) = match bracket {
                None => (hs, y1, false),
                Some((lo, hi)) => {
                    // the events at both ends of the bracket, on real steps, once for all
                    let g_lo = if lo > 0.0 {
                        let at = self.step(t, &y, &k1, lo, mode).0;
                        self.event_values(t + lo, at[0], at[1], mode)
                    } else {
                        self.event_values(t, y[0], y[1], mode)
                    };
                    let y_hi = self.step(t, &y, &k1, hi, mode).0;
                    let g_hi = self.event_values(t + hi, y_hi[0], y_hi[1], mode);
                    // locate the earliest of the events that fired within the bracket
                    let mut best = (f64::INFINITY, y_hi);
                    let mut which = event;
                    for e in 0..3 {
                        if g_hi[e] < 0.0 || e == event {
                            let (lo, hi) = ((lo, g_lo[e]), (hi, g_hi[e], y_hi));
                            let found = self.locate(t, &y, &k1, mode, lo, hi, Located::Event(e));
                            if found.0 < best.0 {
                                best = found;
                                which = e;
                            }
                        }
                    }
                    event = which;
                    (best.0, best.1, true)
                }
            };
            // a turning point of λ_I inside the step: refine it on real steps
            if y[1] * y_new[1] < 0.0 {
                let what = Located::Rate(y[1].signum());
                let g_lo = self.located_value(what, t, &y, mode);
                let g_hi = self.located_value(what, t + h_taken, &y_new, mode);
                let (lo, hi) = ((0.0, g_lo), (h_taken, g_hi, y_new));
                let xe = self.locate(t, &y, &k1, mode, lo, hi, what).1[0];
                out.lambda_min = out.lambda_min.min(xe);
                out.lambda_max = out.lambda_max.max(xe);
            }
            out.lambda_min = out.lambda_min.min(y_new[0]);
            out.lambda_max = out.lambda_max.max(y_new[0]);
            out.trace_integral -= c * n_taut(mode) * h_taken;
            let reached_end = !crossed && last;
            let t_step = t;
            t = if reached_end { t_end } else { t + h_taken };
            y = y_new;
            if crossed {
                if event == 2 {
                    return Err(Collision {
                        tau: t,
                        lambda_i: y[0],
                    });
                }
                mode = mode.flipped(if event == 0 {
                    Membrane::I
                } else {
                    Membrane::Ii
                });
                out.switches += 1;
            } else if !last {
                h = hs * fac;
            }
            // the step's last stage is the next one's first where it ends on the same τ
            // (C[6] = 1) in the same piece
            k1 = if !crossed && t.to_bits() == (t_step + hs).to_bits() {
                k7
            } else {
                self.deriv(t, &y, mode)
            };
            if reached_end {
                if j_period == k {
                    out.end = StateVec::from([y[0], y[1]]);
                    out.monodromy = DMatrix::from_row_slice(2, 2, &[y[2], y[3], y[4], y[5]]);
                    return Ok(out);
                }
                out.poincare.push(StateVec::from([y[0], y[1]]));
                j_period += 1;
            }
        }
        panic!("variational flow exceeded {MAX_STEPS} steps");
    }

    /// P^k(x0) alone (the monodromy is integrated too; the cost is the same order).
    pub fn map(&self, x0: [f64; 2], k: usize) -> Result<[f64; 2], Collision> {
        self.orbit(x0, k).map(|o| o.end.pair())
    }
}

/// What [`VariationalFlow::locate`] finds the first zero of along a step.
#[derive(Debug, Clone, Copy)]
enum Located {
    /// Switching function `e` of [`VariationalFlow::event_values`].
    Event(usize),
    /// The velocity times this sign (a turning point of λ_I).
    Rate(f64),
}

/// How Newton's method on the k-fold map is run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ShootingSpec {
    /// Tolerance of the variational integrator.
    pub tol: Tolerance,
    /// Converged when the max-norm of P^k(x) − x and of the last Newton step fall below this.
    pub newton_tol: f64,
    /// Newton iterations at most.
    pub max_iterations: usize,
}

impl Default for ShootingSpec {
    fn default() -> Self {
        ShootingSpec {
            tol: Tolerance {
                rtol: 1e-11,
                atol: 1e-13,
            },
            newton_tol: 1e-10,
            max_iterations: 25,
        }
    }
}

impl ShootingSpec {
    /// Checks every field.
    pub fn validate(&self) -> Result<(), crate::model::ParamError> {
        use crate::model::error::check;
        self.tol.validate().map_err(|e| e.within("tol"))?;
        check(
            "newton_tol",
            self.newton_tol,
            |t| t > 1e-15 && t < 1e-3,
            "(1e-15, 1e-3)",
        )?;
        check(
            "max_iterations",
            self.max_iterations as f64,
            |n| (1.0..=1000.0).contains(&n),
            "[1, 1000]",
        )?;
        Ok(())
    }
}

/// Why a periodic response could not be found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShootingError {
    #[error("the orbit reaches a frame or the Gent limit at τ = {:.4} (λ_I = {:.4})", .0.tau, .0.lambda_i)]
    Collision(Collision),
    #[error("Newton did not converge in {iterations} iterations (residual {residual:.2e})")]
    NoConvergence { iterations: usize, residual: f64 },
    #[error("the k-fold map has a multiplier at +1 here (singular Newton matrix)")]
    Singular,
    #[error("the model gives a value that is not finite at τ = {tau}: {detail}")]
    NonFinite { tau: f64, detail: String },
    #[error(
        "the integration stalled at τ = {tau} (step size below round-off): the field or its \
         Jacobian grows without bound there, as `sqrt(2 - x)`'s slope does at x = 2, or changes \
         faster than any step can follow"
    )]
    Stalled { tau: f64 },
}

/// A periodic response found by shooting.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PeriodicOrbit {
    /// Forcing frequency ω_e.
    pub omega: f64,
    /// Response period in forcing periods.
    pub period: usize,
    /// The k stroboscopic states ([λ_I, v] for the built-in model) at τ = 0, T, …,
    /// (k − 1)T; the first is the fixed point Newton solved for.
    pub poincare: Vec<StateVec>,
    /// max − min of the amplitude's output (λ_I) over the k periods (MODEL.md §4), turning
    /// points located.
    pub amplitude: f64,
    pub lambda_min: f64,
    pub lambda_max: f64,
    /// Floquet multipliers of the k-fold map.
    pub multipliers: Multipliers,
    /// The monodromy matrix, row by row.
    pub monodromy: Vec<Vec<f64>>,
    /// exp(∫ tr A dτ), what det(monodromy) must equal.
    pub liouville_det: f64,
    /// Max-norm of P^k(x) − x at the solution.
    pub residual: f64,
    /// Newton iterations used.
    pub iterations: usize,
}

impl PeriodicOrbit {
    /// Assembles the result from a flow started at the fixed point.
    pub fn from_flow(omega: f64, period: usize, flow: &PeriodFlow, iterations: usize) -> Self {
        let m = &flow.monodromy;
        let x = flow.poincare[0];
        PeriodicOrbit {
            omega,
            period,
            poincare: flow.poincare.clone(),
            amplitude: flow.lambda_max - flow.lambda_min,
            lambda_min: flow.lambda_min,
            lambda_max: flow.lambda_max,
            multipliers: Multipliers::of_matrix(m),
            monodromy: m.row_iter().map(|r| r.iter().copied().collect()).collect(),
            liouville_det: flow.trace_integral.exp(),
            residual: flow
                .end
                .iter()
                .zip(x.iter())
                .fold(0.0, |r, (e, x)| f64::max(r, (e - x).abs())),
            iterations,
        }
    }

    /// The monodromy as a matrix.
    pub fn monodromy_matrix(&self) -> DMatrix<f64> {
        let n = self.monodromy.len();
        DMatrix::from_fn(n, n, |r, c| self.monodromy[r][c])
    }

    /// det(monodromy) − exp(∫ tr A dτ).
    pub fn liouville_error(&self) -> f64 {
        self.monodromy_matrix().determinant() - self.liouville_det
    }

    /// All multipliers inside the unit circle.
    pub fn stable(&self) -> bool {
        self.multipliers.stable()
    }
}

/// The period-`k` response through the seed state at τ = 0 ([λ_I, v] for the built-in
/// model), by Newton on P^k(x) − x = 0.
pub fn shoot<M: Shootable>(
    model: &M,
    k: usize,
    seed: &[f64],
    spec: &ShootingSpec,
) -> Result<PeriodicOrbit, ShootingError> {
    let n = model.dim();
    let mut x = DVector::from_column_slice(&seed[..n]);
    let mut residual = f64::INFINITY;
    for it in 0..spec.max_iterations {
        let orbit = model.period_flow(x.as_slice(), k, spec.tol)?;
        let r = DVector::from_fn(n, |i, _| orbit.end[i] - x[i]);
        residual = r.amax();
        let jac = &orbit.monodromy - DMatrix::identity(n, n);
        let dx = jac.try_inverse().ok_or(ShootingError::Singular)? * (-r);
        if residual < spec.newton_tol && dx.amax() < spec.newton_tol {
            return Ok(PeriodicOrbit::from_flow(model.omega(), k, &orbit, it));
        }
        // keep a wild step from leaving the basin of Newton's method
        let scale = (0.2 / dx.amax()).min(1.0);
        x += dx * scale;
    }
    Err(ShootingError::NoConvergence {
        iterations: spec.max_iterations,
        residual,
    })
}
