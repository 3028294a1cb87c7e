//! Adaptive Dormand–Prince 5(4) with dense output and event location: the accurate path for
//! time histories and the reference every fixed-step result is checked against.
//!
//! Each step is taken on one smooth piece of the field (a fixed [`Mode`]). After a step the
//! switching functions p_I, p_II and the frame distance are scanned along the dense output; the
//! first sign change is located to round-off and the step is cut there, the mode flipped (or the
//! collision reported), and integration goes on from the switch.

use serde::{Deserialize, Serialize};

use super::Collision;
use super::dopri_tableau::{A, B, C, D, E};
use super::field::{Field, Membrane, Mode};
use crate::model::error::{ParamError, check};
use crate::model::{Forcing, Params};

/// Local error tolerance per step, relative and absolute.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tolerance {
    pub rtol: f64,
    pub atol: f64,
}

impl Default for Tolerance {
    fn default() -> Self {
        Tolerance {
            rtol: 1e-10,
            atol: 1e-12,
        }
    }
}

impl Tolerance {
    /// Checks both are in (0, 1).
    pub fn validate(&self) -> Result<(), ParamError> {
        check("rtol", self.rtol, |t| t > 1e-15 && t < 1.0, "(1e-15, 1)")?;
        check("atol", self.atol, |t| t > 1e-16 && t < 1.0, "(1e-16, 1)")?;
        Ok(())
    }
}

/// A trajectory's state between calls: time, λ_I, velocity, active piece and next step size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    pub tau: f64,
    pub x: f64,
    pub v: f64,
    pub mode: Mode,
    h: f64,
}

/// One accepted step's continuous extension, valid on [t0, t1].
#[derive(Debug, Clone, Copy)]
pub struct DenseStep {
    pub t0: f64,
    pub t1: f64,
    h: f64,
    rcont: [[f64; 5]; 2],
}

impl DenseStep {
    /// [λ_I, v] at time `t` in [t0, t1].
    pub fn at(&self, t: f64) -> [f64; 2] {
        let th = (t - self.t0) / self.h;
        let th1 = 1.0 - th;
        let r = &self.rcont;
        [0, 1].map(|c| r[c][0] + th * (r[c][1] + th1 * (r[c][2] + th * (r[c][3] + th1 * r[c][4]))))
    }
}

/// Points per step at which the event functions are checked for a sign change.
const EVENT_SCAN_POINTS: usize = 4;
/// Most step attempts in one call before it gives up (a guard, never met in practice).
const MAX_ATTEMPTS: usize = 50_000_000;

/// What stopped a step short.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Event {
    Switch(Membrane),
    Collision,
}

/// The adaptive integrator for one parameter set, under its periodic drive or another
/// [`Forcing`] (a chirp).
#[derive(Debug, Clone)]
pub struct Dopri5<F: Forcing = Params> {
    params: Params,
    forcing: F,
    field: Field,
    tol: Tolerance,
    h_max: f64,
}

impl Dopri5<Params> {
    pub fn new(params: &Params, tol: Tolerance) -> Self {
        Self::with_forcing(params, *params, tol, (params.period() / 16.0).min(0.1))
    }
}

impl<F: Forcing> Dopri5<F> {
    /// The model of `params` driven by `forcing`, steps at most `h_max`.
    pub fn with_forcing(params: &Params, forcing: F, tol: Tolerance, h_max: f64) -> Self {
        Dopri5 {
            params: *params,
            forcing,
            field: Field::new(params),
            tol,
            h_max,
        }
    }

    pub fn params(&self) -> &Params {
        &self.params
    }

    /// A state at time `tau`, in the mode its tensions give.
    pub fn state(&self, tau: f64, x: f64, v: f64) -> State {
        let (pi, pii) = self.forcing.phi_sq(tau);
        State {
            tau,
            x,
            v,
            mode: self.field.mode_at(x, v, pi, pii),
            h: 1e-3f64.min(self.h_max),
        }
    }

    fn deriv(&self, t: f64, y: [f64; 2], mode: Mode) -> [f64; 2] {
        let (pi, pii) = self.forcing.phi_sq(t);
        [y[1], self.field.accel_in_mode(y[0], y[1], pi, pii, mode)]
    }

    /// Integrates `state` to `tau_end`, calling `on_step` with each accepted piece of
    /// trajectory. Returns the collision if the mass leaves the model first; the state is
    /// then at the located collision.
    pub fn integrate(
        &self,
        state: &mut State,
        tau_end: f64,
        mut on_step: impl FnMut(&DenseStep),
    ) -> Result<(), Collision> {
        if !self.field.inside(state.x) {
            return Err(Collision {
                tau: state.tau,
                lambda_i: state.x,
            });
        }
        let mut k1 = self.deriv(state.tau, [state.x, state.v], state.mode);
        for _ in 0..MAX_ATTEMPTS {
            let remaining = tau_end - state.tau;
            if remaining <= 1e-14 * tau_end.abs().max(1.0) {
                return Ok(());
            }
            let mut h = state.h.min(self.h_max);
            let last = h >= remaining;
            if last {
                h = remaining;
            }
            let (t, y0, mode) = (state.tau, [state.x, state.v], state.mode);
            let (y1, k7, err, dense) = self.try_step(t, y0, k1, h, mode);
            let fac = if err == 0.0 {
                5.0
            } else {
                (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
            };
            if err > 1.0 {
                state.h = h * fac.min(1.0);
                continue;
            }
            let t1 = if last { tau_end } else { t + h };
            match self.first_event(&dense, t, t1, mode) {
                None => {
                    on_step(&DenseStep { t1, ..dense });
                    (state.tau, state.x, state.v) = (t1, y1[0], y1[1]);
                    k1 = k7;
                }
                Some((te, event)) => {
                    on_step(&DenseStep { t1: te, ..dense });
                    let y = dense.at(te);
                    (state.tau, state.x, state.v) = (te, y[0], y[1]);
                    match event {
                        Event::Collision => {
                            return Err(Collision {
                                tau: te,
                                lambda_i: y[0],
                            });
                        }
                        Event::Switch(m) => state.mode = mode.flipped(m),
                    }
                    k1 = self.deriv(te, y, state.mode);
                }
            }
            if !last {
                state.h = h * fac;
            }
        }
        panic!("dopri5 exceeded {MAX_ATTEMPTS} step attempts");
    }

    /// One Dormand–Prince step: new state, its derivative, scaled error and dense output.
    fn try_step(
        &self,
        t: f64,
        y: [f64; 2],
        k1: [f64; 2],
        h: f64,
        mode: Mode,
    ) -> ([f64; 2], [f64; 2], f64, DenseStep) {
        let comb = |ks: &[[f64; 2]], a: &[f64]| -> [f64; 2] {
            let mut out = y;
            for (k, &ai) in ks.iter().zip(a) {
                out[0] += h * ai * k[0];
                out[1] += h * ai * k[1];
            }
            out
        };
        let mut k = [[0.0; 2]; 7];
        k[0] = k1;
        k[1] = self.deriv(t + C[1] * h, comb(&k[..1], A[0]), mode);
        k[2] = self.deriv(t + C[2] * h, comb(&k[..2], A[1]), mode);
        k[3] = self.deriv(t + C[3] * h, comb(&k[..3], A[2]), mode);
        k[4] = self.deriv(t + C[4] * h, comb(&k[..4], A[3]), mode);
        k[5] = self.deriv(t + C[5] * h, comb(&k[..5], A[4]), mode);
        let y1 = comb(&k[..6], &B);
        k[6] = self.deriv(t + h, y1, mode);
        let mut err_sq = 0.0;
        let mut rcont = [[0.0; 5]; 2];
        for c in 0..2 {
            let e: f64 = (0..7).map(|i| E[i] * k[i][c]).sum::<f64>() * h;
            let scale = self.tol.atol + self.tol.rtol * y[c].abs().max(y1[c].abs());
            err_sq += (e / scale) * (e / scale);
            let dy = y1[c] - y[c];
            let r3 = h * k[0][c] - dy;
            rcont[c] = [
                y[c],
                dy,
                r3,
                dy - h * k[6][c] - r3,
                h * (0..7).map(|i| D[i] * k[i][c]).sum::<f64>(),
            ];
        }
        let dense = DenseStep {
            t0: t,
            t1: t + h,
            h,
            rcont,
        };
        (y1, k[6], (0.5 * err_sq).sqrt(), dense)
    }

    /// Event functions, all positive while the step may go on: p_I and p_II signed by the
    /// mode, and the distance to the frames and Gent limits.
    fn event_values(&self, t: f64, y: [f64; 2], mode: Mode) -> [f64; 3] {
        let (pi, pii) = self.forcing.phi_sq(t);
        let (p_i, p_ii) = self.field.tensions(y[0], y[1], pi, pii);
        let x_ii = self.field.two_lambda_p() - y[0];
        let upper = crate::model::forces::gent_poles(self.params.j()).1;
        let room = y[0].min(x_ii).min(upper - y[0]).min(upper - x_ii);
        [
            if mode.taut_i { p_i } else { -p_i },
            if mode.taut_ii { p_ii } else { -p_ii },
            room,
        ]
    }

    /// The earliest event in (t0, t1] along `dense`, located to round-off.
    fn first_event(&self, dense: &DenseStep, t0: f64, t1: f64, mode: Mode) -> Option<(f64, Event)> {
        let value = |t: f64| self.event_values(t, dense.at(t), mode);
        let mut t_prev = t0;
        for j in 1..=EVENT_SCAN_POINTS {
            let t = t0 + (t1 - t0) * j as f64 / EVENT_SCAN_POINTS as f64;
            let g = value(t);
            if g.iter().any(|&gi| gi < 0.0) {
                let mut best: Option<(f64, Event)> = None;
                for (idx, event) in [
                    (0, Event::Switch(Membrane::I)),
                    (1, Event::Switch(Membrane::Ii)),
                    (2, Event::Collision),
                ] {
                    if g[idx] < 0.0 {
                        let te = bisect_sign(|t| value(t)[idx], t_prev, t);
                        if best.is_none_or(|(tb, _)| te < tb) {
                            best = Some((te, event));
                        }
                    }
                }
                return best;
            }
            t_prev = t;
        }
        None
    }
}

/// The first point where `g` is negative, bracketed in (lo, hi] with g(hi) < 0: bisection
/// to round-off, returning the negative side.
fn bisect_sign(g: impl Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    let (mut a, mut b) = (lo, hi);
    if g(a) < 0.0 {
        return a;
    }
    for _ in 0..80 {
        let c = 0.5 * (a + b);
        if c <= a || c >= b {
            break;
        }
        if g(c) < 0.0 {
            b = c;
        } else {
            a = c;
        }
    }
    b
}

/// A root of `g` in [lo, hi] where g changes sign, `g_lo` being g(lo): bisection to
/// round-off. Used to find turning points (v = 0) on the dense output.
pub fn root_of(g: impl Fn(f64) -> f64, lo: f64, hi: f64, g_lo: f64) -> f64 {
    let (mut a, mut b) = (lo, hi);
    for _ in 0..80 {
        let c = 0.5 * (a + b);
        if c <= a || c >= b {
            break;
        }
        if (g(c) < 0.0) == (g_lo < 0.0) {
            a = c;
        } else {
            b = c;
        }
    }
    0.5 * (a + b)
}
