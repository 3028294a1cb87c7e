//! The vector field d²λ_I/dτ² = f_II − f_I in the forms the integrators need.

use super::lane::Real;
use crate::model::Params;
use crate::model::forces::gent_poles;

/// Which membranes are taut: selects the smooth piece of the piecewise-smooth field. `M` is
/// `bool` for one trajectory, a lane-wise mask ([`Real::Mask`]) for a batch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Mode<M = bool> {
    pub taut_i: M,
    pub taut_ii: M,
}

/// One membrane of the pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Membrane {
    I,
    Ii,
}

impl Membrane {
    /// This membrane's member of a pair given as (I, II).
    #[inline(always)]
    pub fn of<T>(self, (i, ii): (T, T)) -> T {
        match self {
            Membrane::I => i,
            Membrane::Ii => ii,
        }
    }
}

impl Mode {
    /// taut_I + 2·taut_II as a float (selects, which vectorise better than casts).
    #[inline(always)]
    pub fn code(m: Mode) -> f64 {
        let code_i = if m.taut_i { 1.0 } else { 0.0 };
        let code_ii = if m.taut_ii { 2.0 } else { 0.0 };
        code_i + code_ii
    }

    /// The mode a [`Mode::code`] stands for.
    pub fn from_code(c: f64) -> Mode {
        Mode {
            taut_i: c == 1.0 || c == 3.0,
            taut_ii: c >= 2.0,
        }
    }

    /// (taut_I, taut_II), to pick one with [`Membrane::of`].
    pub fn pair(self) -> (bool, bool) {
        (self.taut_i, self.taut_ii)
    }

    /// The same mode with one membrane's state flipped.
    pub fn flipped(self, m: Membrane) -> Mode {
        match m {
            Membrane::I => Mode {
                taut_i: !self.taut_i,
                ..self
            },
            Membrane::Ii => Mode {
                taut_ii: !self.taut_ii,
                ..self
            },
        }
    }
}

/// The model's constants arranged for fast evaluation.
#[derive(Debug, Clone, Copy)]
pub struct Field {
    two_lambda_p: f64,
    j: f64,
    j_plus_2: f64,
    c_tilde: f64,
    upper_pole: f64,
}

/// Gent tension as a fraction: g(λ) = num/den with
/// num = J(λ⁴ − 1), den = λ((J + 2)λ² − λ⁴ − 1); den > 0 exactly between the poles.
#[inline(always)]
fn gent_fraction<T: Real>(lambda: T, j: f64, j_plus_2: f64) -> (T, T) {
    let l2 = lambda * lambda;
    let l4 = l2 * l2;
    let (j, j_plus_2) = (T::splat(j), T::splat(j_plus_2));
    (
        j.mul_add(l4, -j),
        lambda * (j_plus_2.mul_add(l2, -l4) - T::splat(1.0)),
    )
}

impl Field {
    pub fn new(p: &Params) -> Self {
        Field {
            two_lambda_p: 2.0 * p.lambda_p(),
            j: p.j(),
            j_plus_2: p.j() + 2.0,
            c_tilde: p.c_tilde(),
            upper_pole: gent_poles(p.j()).1,
        }
    }

    /// Acceleration and the mode as a number (taut_I + 2·taut_II), for the SIMD loop where
    /// floating-point lanes vectorise better than booleans.
    #[inline(always)]
    pub fn accel_coded(&self, x: f64, v: f64, phi_sq_i: f64, phi_sq_ii: f64) -> (f64, f64) {
        let (a, m) = self.accel(x, v, phi_sq_i, phi_sq_ii);
        (a, Mode::code(m))
    }

    /// Acceleration f_II − f_I and the mode it was evaluated in, with one division: each
    /// tension is kept as P = p·den (same sign as p where den > 0), and
    /// f_II − f_I = (P_II·den_I − P_I·den_II)/(den_I·den_II) with slack terms dropped.
    #[inline(always)]
    pub fn accel(&self, x: f64, v: f64, phi_sq_i: f64, phi_sq_ii: f64) -> (f64, Mode) {
        let t = self.scaled_tensions(x, v, phi_sq_i, phi_sq_ii);
        let taut_i = t.big_p_i > 0.0 && t.den_i > 0.0;
        let taut_ii = t.big_p_ii > 0.0 && t.den_ii > 0.0;
        // the selects are written out here, not through `net_force`: the 16-lane loop
        // vectorises worse through the call (Fig 6A basin on one core 5.85 → 6.55 s)
        let d_i = if taut_i { t.den_i } else { 1.0 };
        let d_ii = if taut_ii { t.den_ii } else { 1.0 };
        let q_i = if taut_i { t.big_p_i } else { 0.0 };
        let q_ii = if taut_ii { t.big_p_ii } else { 0.0 };
        (
            q_ii.mul_add(d_i, -q_i * d_ii) / (d_i * d_ii),
            Mode { taut_i, taut_ii },
        )
    }

    /// [`Self::accel`] over any [`Real`]: lane by lane the same operations, so the same bits
    /// (the plain step keeps its own, whose selects vectorise better written out).
    #[inline(always)]
    pub fn accel_lanes<T: Real>(
        &self,
        x: T,
        v: T,
        phi_sq_i: T,
        phi_sq_ii: T,
    ) -> (T, Mode<T::Mask>) {
        let t = self.scaled_tensions(x, v, phi_sq_i, phi_sq_ii);
        let zero = T::splat(0.0);
        let taut_i = t.big_p_i.gt(zero) & t.den_i.gt(zero);
        let taut_ii = t.big_p_ii.gt(zero) & t.den_ii.gt(zero);
        (
            t.net_force(Mode { taut_i, taut_ii }),
            Mode { taut_i, taut_ii },
        )
    }

    /// Acceleration on one smooth piece: taut membranes pull with p even where p < 0. This
    /// smooth extension keeps an integrator's order up to a located switch. Below a lower
    /// Gent pole a taut membrane pulls with p = −1, as [`Self::tension_of`] says.
    #[inline(always)]
    pub fn accel_in_mode<T: Real>(
        &self,
        x: T,
        v: T,
        phi_sq_i: T,
        phi_sq_ii: T,
        mode: Mode<T::Mask>,
    ) -> T {
        let t = self.scaled_tensions(x, v, phi_sq_i, phi_sq_ii);
        let (zero, one) = (T::splat(0.0), T::splat(1.0));
        let (below_i, below_ii) = (t.den_i.le(zero), t.den_ii.le(zero));
        let t = ScaledTensions {
            big_p_i: T::select(below_i, -one, t.big_p_i),
            big_p_ii: T::select(below_ii, -one, t.big_p_ii),
            den_i: T::select(below_i, one, t.den_i),
            den_ii: T::select(below_ii, one, t.den_ii),
        };
        t.net_force(mode)
    }

    /// Both membranes' tensions as P = p·den and den, without a division.
    #[inline(always)]
    pub fn scaled_tensions<T: Real>(
        &self,
        x: T,
        v: T,
        phi_sq_i: T,
        phi_sq_ii: T,
    ) -> ScaledTensions<T> {
        let (big_p_i, den_i) = self.scaled_tension(x, v, phi_sq_i);
        let (big_p_ii, den_ii) =
            self.scaled_tension(T::splat(self.two_lambda_p) - x, -v, phi_sq_ii);
        ScaledTensions {
            big_p_i,
            big_p_ii,
            den_i,
            den_ii,
        }
    }

    /// One membrane's P = p·den = num − den·(φ²λ − c̃λ̇) and den, at its own stretch λ and
    /// stretch rate λ̇.
    #[inline(always)]
    fn scaled_tension<T: Real>(&self, lambda: T, lambda_dot: T, phi_sq: T) -> (T, T) {
        let (num, den) = gent_fraction(lambda, self.j, self.j_plus_2);
        let damping = T::splat(self.c_tilde) * lambda_dot;
        let big_p = (-phi_sq.mul_add(lambda, -damping)).mul_add(den, num);
        (big_p, den)
    }

    /// Membrane `m`'s stretch and the sign of its rate (λ̇_m = sign·λ̇_I) when λ_I = `x`:
    /// λ_II = 2λ_p − λ_I.
    #[inline(always)]
    fn stretch_of<T: Real>(&self, m: Membrane, x: T) -> (T, T) {
        m.of((
            (x, T::splat(1.0)),
            (T::splat(self.two_lambda_p) - x, T::splat(-1.0)),
        ))
    }

    /// Tension p of one membrane (−1 below its lower Gent pole): one switching function.
    #[inline(always)]
    pub fn tension_of(&self, m: Membrane, x: f64, v: f64, phi_sq_i: f64, phi_sq_ii: f64) -> f64 {
        let (lambda, sign) = self.stretch_of(m, x);
        let (phi_sq, lambda_dot) = (m.of((phi_sq_i, phi_sq_ii)), sign * v);
        let (num, den) = gent_fraction(lambda, self.j, self.j_plus_2);
        if den > 0.0 {
            num / den - phi_sq * lambda + self.c_tilde * lambda_dot
        } else {
            -1.0
        }
    }

    /// One membrane's switching function without a division: its tension p times its Gent
    /// denominator (the sign of p between the poles), −1 below its lower pole as in
    /// [`Self::tension_of`].
    #[inline(always)]
    pub fn scaled_tension_of<T: Real>(
        &self,
        m: Membrane,
        x: T,
        v: T,
        phi_sq_i: T,
        phi_sq_ii: T,
    ) -> T {
        let (lambda, sign) = self.stretch_of(m, x);
        let (big_p, den) = self.scaled_tension(lambda, sign * v, m.of((phi_sq_i, phi_sq_ii)));
        T::select(den.gt(T::splat(0.0)), big_p, T::splat(-1.0))
    }

    /// The rate d/dτ of [`Self::scaled_tension_of`] along a trajectory at (`x`, `v`) with
    /// acceleration `a`, under drive `phi_sq` changing at `phi_sq_rate` (both as (I, II));
    /// 0 below the lower pole, where the switching function is the constant −1.
    #[inline(always)]
    pub fn scaled_tension_rate<T: Real>(
        &self,
        m: Membrane,
        [x, v, a]: [T; 3],
        phi_sq: (T, T),
        phi_sq_rate: (T, T),
    ) -> T {
        let (lambda, sign) = self.stretch_of(m, x);
        let (lambda_dot, lambda_ddot) = (sign * v, sign * a);
        let (phi_sq, phi_sq_rate) = (m.of(phi_sq), m.of(phi_sq_rate));
        let (_, den) = gent_fraction(lambda, self.j, self.j_plus_2);
        let (j, j2, c_tilde) = (
            T::splat(self.j),
            T::splat(self.j_plus_2),
            T::splat(self.c_tilde),
        );
        let l2 = lambda * lambda;
        let l4 = l2 * l2;
        // P = num − den·E with num = J(λ⁴ − 1), E = φ²λ − c̃λ̇
        let num_rate = T::splat(4.0) * j * l2 * lambda * lambda_dot;
        let den_rate = (T::splat(3.0) * j2 * l2 - T::splat(5.0) * l4 - T::splat(1.0)) * lambda_dot;
        let e = phi_sq * lambda - c_tilde * lambda_dot;
        let e_rate = phi_sq_rate * lambda + phi_sq * lambda_dot - c_tilde * lambda_ddot;
        let rate = num_rate - den_rate * e - den * e_rate;
        T::select(den.le(T::splat(0.0)), T::splat(0.0), rate)
    }

    /// Tensions (p_I, p_II) a taut membrane would carry; below the lower Gent pole, where a
    /// membrane is slack whatever the formula says, −1. These are the switching functions.
    pub fn tensions(&self, x: f64, v: f64, phi_sq_i: f64, phi_sq_ii: f64) -> (f64, f64) {
        (
            self.tension_of(Membrane::I, x, v, phi_sq_i, phi_sq_ii),
            self.tension_of(Membrane::Ii, x, v, phi_sq_i, phi_sq_ii),
        )
    }

    /// The mode the state is in: which tensions are positive.
    pub fn mode_at(&self, x: f64, v: f64, phi_sq_i: f64, phi_sq_ii: f64) -> Mode {
        self.accel(x, v, phi_sq_i, phi_sq_ii).1
    }

    /// True while λ_I = `x` keeps the mass off both frames and both membranes below the Gent
    /// limit (see [`crate::model::forces::outside_model`]).
    #[inline(always)]
    pub fn inside(&self, x: f64) -> bool {
        let x_ii = self.two_lambda_p - x;
        x > 0.0 && x_ii > 0.0 && x < self.upper_pole && x_ii < self.upper_pole
    }

    /// 2 λ_p, so that λ_II = 2 λ_p − λ_I.
    pub fn two_lambda_p(&self) -> f64 {
        self.two_lambda_p
    }
}

/// Tensions p = P/den of both membranes, kept as the pair (P, den).
#[derive(Debug, Clone, Copy)]
pub struct ScaledTensions<T = f64> {
    pub big_p_i: T,
    pub big_p_ii: T,
    pub den_i: T,
    pub den_ii: T,
}

impl<T: Real> ScaledTensions<T> {
    /// f_II − f_I with the membranes `mode` says are taut pulling, in one division.
    #[inline(always)]
    fn net_force(&self, mode: Mode<T::Mask>) -> T {
        let (zero, one) = (T::splat(0.0), T::splat(1.0));
        let d_i = T::select(mode.taut_i, self.den_i, one);
        let d_ii = T::select(mode.taut_ii, self.den_ii, one);
        let q_i = T::select(mode.taut_i, self.big_p_i, zero);
        let q_ii = T::select(mode.taut_ii, self.big_p_ii, zero);
        q_ii.mul_add(d_i, -q_i * d_ii) / (d_i * d_ii)
    }
}
