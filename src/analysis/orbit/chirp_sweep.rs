//! Fig 3A/B: a frequency sweep as in the lab: ω_e moves linearly over a span of time while the
//! response is recorded; its envelope is the amplitude per window against the instantaneous
//! frequency.

use std::sync::atomic::{AtomicBool, Ordering};

use serde::{Deserialize, Serialize};

use crate::analysis::AnalysisError;
use crate::model::error::{check, check_in};
use crate::model::{Chirp, Params};
use crate::solver::{Dopri5, Tolerance};

/// A chirp sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ChirpSpec {
    pub omega_start: f64,
    pub omega_end: f64,
    /// Duration of the sweep in τ.
    pub span: f64,
    /// Sampling interval of the recorded response.
    pub dt: f64,
    /// Length of the envelope windows in τ.
    pub window: f64,
    /// Initial state (Δλ, v).
    pub dx0: f64,
    pub v0: f64,
    pub tolerance: Tolerance,
}

impl Default for ChirpSpec {
    /// The paper's forward sweep: ω_e 0 → 6 over τ = 12000.
    fn default() -> Self {
        ChirpSpec {
            omega_start: 0.0,
            omega_end: 6.0,
            span: 12000.0,
            dt: 0.05,
            window: 20.0,
            dx0: 0.0,
            v0: 0.0,
            tolerance: Tolerance {
                rtol: 1e-8,
                atol: 1e-10,
            },
        }
    }
}

/// The recorded sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChirpSweep {
    pub dt: f64,
    /// λ_I at τ = j·dt.
    pub lambda: Vec<f64>,
    /// Instantaneous ω_e at each sample.
    pub omega: Vec<f64>,
    /// One row per window: (τ at its centre, ω_e there, max − min of λ_I in it).
    pub envelope: Vec<[f64; 3]>,
    /// Samples per envelope window.
    pub window_samples: usize,
    /// Where the mass met a frame, if it did (the record stops there).
    pub collision_tau: Option<f64>,
}

impl ChirpSpec {
    /// Checks every setting; the error names the first bad one.
    pub fn validate(&self) -> Result<(), crate::model::ParamError> {
        let omega_max = crate::model::limits::OMEGA.1;
        check_in("omega_start", self.omega_start, 0.0, omega_max)?;
        check_in("omega_end", self.omega_end, 0.0, omega_max)?;
        check("span", self.span, |s| s > 0.0 && s <= 1e7, "(0, 1e7]")?;
        check(
            "dt",
            self.dt,
            |d| d > 0.0 && self.span / d <= 5e7,
            "> 0, at most 5e7 samples",
        )?;
        check(
            "window",
            self.window,
            |w| w >= self.dt && w <= self.span,
            "[dt, span]",
        )?;
        self.tolerance
            .validate()
            .map_err(|e| e.within("tolerance"))?;
        Ok(())
    }
}

/// Runs the sweep with the adaptive integrator (located switches, dense output sampling).
pub fn chirp_sweep(
    params: &Params,
    spec: &ChirpSpec,
    cancel: &AtomicBool,
    mut on_progress: impl FnMut(f64),
) -> Result<ChirpSweep, AnalysisError> {
    spec.validate()?;
    let chirp = Chirp {
        params: *params,
        omega_start: spec.omega_start,
        omega_end: spec.omega_end,
        span: spec.span,
    };
    let dopri = Dopri5::with_forcing(params, chirp, spec.tolerance, 0.05);
    let mut state = dopri.state(0.0, params.lambda_p() + spec.dx0, spec.v0);
    let n = (spec.span / spec.dt).round() as usize + 1;
    let mut lambda = Vec::with_capacity(n);
    lambda.push(state.x);
    let mut collision_tau = None;
    // integrate in slices so cancellation and progress are seen often
    let slice = 50.0f64.max(spec.dt);
    let mut t_end = 0.0;
    while t_end < spec.span && collision_tau.is_none() {
        if cancel.load(Ordering::Relaxed) {
            return Err(AnalysisError::Cancelled);
        }
        t_end = (t_end + slice).min(spec.span);
        let result = dopri.integrate(&mut state, t_end, |d| {
            while lambda.len() < n {
                let t = lambda.len() as f64 * spec.dt;
                if t > d.t1 {
                    break;
                }
                lambda.push(d.at(t)[0]);
            }
        });
        if let Err(c) = result {
            collision_tau = Some(c.tau);
        }
        on_progress(t_end / spec.span);
    }
    let omega: Vec<f64> = (0..lambda.len())
        .map(|j| chirp.omega_at(j as f64 * spec.dt))
        .collect();
    let per_window = ((spec.window / spec.dt).round() as usize).max(1);
    let envelope = lambda
        .chunks(per_window)
        .enumerate()
        .map(|(w, chunk)| {
            let (lo, hi) = chunk
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
                    (lo.min(x), hi.max(x))
                });
            let centre = (w * per_window) as f64 * spec.dt + 0.5 * chunk.len() as f64 * spec.dt;
            [centre, chirp.omega_at(centre), hi - lo]
        })
        .collect();
    Ok(ChirpSweep {
        dt: spec.dt,
        lambda,
        omega,
        envelope,
        window_samples: per_window,
        collision_tau,
    })
}
