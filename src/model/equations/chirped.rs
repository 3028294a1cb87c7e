//! A written model driven by a chirp (Fig 3's sweeps on any model): its frequency parameter
//! moved through a [`Sweep`] and its time read as θ(τ)/ω(τ), θ the sweep's phase.
//!
//! A model periodic in time ([`super::graph::Graph::periodic_in_time`]) has its time only as
//! k·ω·t (plus a fixed phase) inside `sin`, `cos` or `tan`; there every k·ω·t becomes
//! k·ω(τ)·θ(τ)/ω(τ) = k·θ(τ), the sweep's instantaneous phase, as the built-in chirp drives
//! its membranes. Wherever else the model uses its frequency (an amplitude ω²·F of a base
//! excitation), it has the instantaneous ω(τ).

use super::system::EquationSystem;
use crate::model::ParamError;
use crate::model::Sweep;
use crate::model::system::{Mode, System, Vector};

/// A written model under a chirp, as the general engine integrates it. Its [`System::period`]
/// is the sweep's sample interval: an integrator's steps per period are its steps per sample.
#[derive(Debug, Clone)]
pub struct ChirpedSystem {
    sys: EquationSystem,
    sweep: Sweep,
    sample: f64,
    /// τ at which the frequency was last set, and the model's time there.
    at: f64,
    model_time: f64,
}

impl ChirpedSystem {
    /// Whether `sys` can be swept by `sweep`. Errors: a model whose time is not periodic, a
    /// sweep end out of the frequency parameter's range or not above 0 (named `omega_start`
    /// or `omega_end`).
    pub fn check(sys: &EquationSystem, sweep: &Sweep) -> Result<(), ParamError> {
        let model = sys.model();
        if !model.periodic_in_time() {
            return Err(ParamError {
                field: "model".into(),
                value: ParamError::NOT_NUMERIC,
                allowed: format!(
                    "a model whose time t enters only as k*{w}*t (k a whole number, plus a \
                     fixed phase) inside sin, cos or tan: a chirp sweep reads {w}*t as its \
                     phase",
                    w = model.frequency_name()
                ),
            });
        }
        for (field, omega) in [
            ("omega_start", sweep.omega_start),
            ("omega_end", sweep.omega_end),
        ] {
            let mut values = sys.values().to_vec();
            values[model.frequency()] = omega;
            model.system(&values).map_err(|e| e.as_value_of(field))?;
        }
        Ok(())
    }

    /// `sys` swept by `sweep`, sampled every `sample`, where [`Self::check`] allows it.
    pub fn new(sys: &EquationSystem, sweep: Sweep, sample: f64) -> Result<Self, ParamError> {
        Self::check(sys, &sweep)?;
        Ok(ChirpedSystem {
            sys: sys.clone(),
            sweep,
            sample,
            // (set at the first time asked)
            at: f64::NAN,
            model_time: 0.0,
        })
    }

    /// The model's time at τ, its frequency parameter set to ω(τ).
    #[inline]
    fn set_time(&mut self, tau: f64) -> f64 {
        if tau.to_bits() != self.at.to_bits() {
            let omega = self.sweep.omega_at(tau);
            self.sys.set_frequency(omega);
            self.at = tau;
            self.model_time = self.sweep.phase_at(tau) / omega;
        }
        self.model_time
    }
}

impl System for ChirpedSystem {
    fn dim(&self) -> usize {
        self.sys.dim()
    }

    fn state_names(&self) -> &[String] {
        self.sys.state_names()
    }

    fn period(&self) -> f64 {
        self.sample
    }

    fn switch_mask(&self) -> Mode {
        self.sys.switch_mask()
    }

    fn continuous_switches(&self) -> Mode {
        self.sys.continuous_switches()
    }

    fn mode_at(&mut self, tau: f64, x: &Vector) -> Mode {
        let t = self.set_time(tau);
        self.sys.mode_at(t, x)
    }

    #[inline]
    fn field(&mut self, tau: f64, x: &Vector, mode: Mode, dx: &mut Vector) -> Mode {
        let t = self.set_time(tau);
        self.sys.field(t, x, mode, dx)
    }

    fn switching(&mut self, tau: f64, x: &Vector, mode: Mode, s: &mut [f64]) -> Mode {
        let t = self.set_time(tau);
        self.sys.switching(t, x, mode, s)
    }

    fn output(&mut self, tau: f64, x: &Vector, mode: Mode) -> (f64, f64) {
        let t = self.set_time(tau);
        self.sys.output(t, x, mode)
    }

    fn collided(&mut self, tau: f64, x: &Vector) -> bool {
        let t = self.set_time(tau);
        self.sys.collided(t, x)
    }

    fn undefined_collision(&mut self, tau: f64, x: &Vector) -> Option<String> {
        let t = self.set_time(tau);
        self.sys.undefined_collision(t, x)
    }

    fn explain_non_finite(&mut self, tau: f64, x: &Vector) -> Option<String> {
        let t = self.set_time(tau);
        self.sys.explain_non_finite(t, x)
    }
}
