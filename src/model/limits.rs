//! The ranges a model parameter may take: wide enough for any dielectric elastomer actuator
//! a user would model, narrow enough that every number the integrators form stays finite and
//! a forcing period is resolved in a bounded number of steps. Each is closed, [lo, hi].

use std::f64::consts::PI;

/// Gent constant J (the pre-stretch must also lie between its poles).
pub const J: (f64, f64) = (0.5, 1e4);
/// Non-dimensional damping c̃: 250 times the paper's 0.04 is heavily over-damped, and keeps
/// the RK4 step (≤ 0.05) stable.
pub const C_TILDE: (f64, f64) = (0.0, 10.0);
/// Non-dimensional forcing frequency ω_e: periods from 0.063 to 628 (the paper: 0.2 to 6).
pub const OMEGA: (f64, f64) = (0.01, 100.0);
/// Mean-square voltage E_a (φ_rms = 1 is 12.7 kV on the paper's device, past breakdown).
pub const E_A: (f64, f64) = (0.0, 1.0);
/// AC-to-DC ratio (a pure AC drive is written with `phi_dc = 0`).
pub const ADR: (f64, f64) = (0.0, 1000.0);
/// DC and AC amplitudes of the non-dimensional voltage.
pub const PHI_DC: (f64, f64) = (0.0, 1.0);
pub const PHI_AC: (f64, f64) = (0.0, 1.5);
/// Phase lead of membrane II's AC voltage, radians.
pub const PHASE: (f64, f64) = (-2.0 * PI, 2.0 * PI);
/// An initial displacement Δλ = λ_I − λ_p (states beyond the frames are collisions at once).
pub const DX: (f64, f64) = (-10.0, 10.0);
/// An initial velocity dλ/dτ.
pub const V: (f64, f64) = (-100.0, 100.0);

/// Device material and geometry (SI units): every physical conversion stays finite.
pub const MU: (f64, f64) = (1e2, 1e10);
pub const LENGTH: (f64, f64) = (1e-7, 10.0);
pub const MASS: (f64, f64) = (1e-9, 1e4);
pub const EPSILON: (f64, f64) = (1e-13, 1e-8);
