//! Fig 3A/B: a frequency sweep as in the lab: ω_e moves linearly over a span of time while the
//! response is recorded; its envelope is the amplitude per window against the instantaneous
//! frequency.

use std::sync::atomic::{AtomicBool, Ordering};

use serde::{Deserialize, Serialize};

use crate::analysis::AnalysisError;
use crate::analysis::orbit::scalogram::ScalogramSpec;
use crate::model::error::{check, check_in};
use crate::model::{Chirp, Params, Sweep};
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
    /// The factor by which the envelope must change across a jump (see [`EnvelopeJump`]).
    pub jump_ratio: f64,
    /// The Morlet scalogram of the recorded response (Fig 3C/D), written beside the sweep
    /// when given (`scalogram = {}` for the default frequencies and columns).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scalogram: Option<ScalogramSpec>,
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
            jump_ratio: DEFAULT_JUMP_RATIO,
            scalogram: None,
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
    /// What the sweep found: its jumps, its peak, the range of λ_I, its collision.
    pub findings: ChirpFindings,
}

/// The factor by which the envelope changes across a jump by default: it at least doubles or
/// halves.
pub const DEFAULT_JUMP_RATIO: f64 = 2.0;
/// The factor by which the envelope changes at least between each two neighbouring windows
/// of a jump: a response leaving a branch settles onto the other at the damping's rate, over
/// several windows (at c̃ = 0.04 and a window of 20 τ, by a factor of about 0.6 per window),
/// while passing through a resonance peak changes it by a few per cent per window.
pub const JUMP_STEP_RATIO: f64 = 1.25;
/// A jump changes the envelope by at least this share of the sweep's largest envelope: less
/// would not show on the envelope's plot (the start-up transient, for one, stays below it).
pub const JUMP_FLOOR: f64 = 0.05;

/// Up or down.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    Up,
    Down,
}

impl Direction {
    /// `up` or `down`, as the tables write it.
    pub fn as_str(self) -> &'static str {
        match self {
            Direction::Up => "up",
            Direction::Down => "down",
        }
    }
}

/// A jump of a chirp's envelope: a run of neighbouring windows over which the envelope rises
/// (or falls) by at least [`JUMP_STEP_RATIO`] from each window to the next, by the spec's
/// `jump_ratio` in all, and by at least [`JUMP_FLOOR`] of the largest envelope. Only windows
/// spanning a whole forcing period count (a shorter window does not hold the response's
/// swing). The jump is located at the steepest step of its run: the boundary between the two
/// windows whose envelopes differ most.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EnvelopeJump {
    pub direction: Direction,
    /// The window after the steepest step (numbered from 0 as [`ChirpSweep::envelope`]).
    pub window: usize,
    /// τ at the boundary between that window and the one before it.
    pub tau: f64,
    /// ω_e there.
    pub omega: f64,
    /// The envelope at the run's first window, and at its last.
    pub amplitude_before: f64,
    pub amplitude_after: f64,
}

/// Where the mass met a frame: τ and ω_e.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Collision {
    pub tau: f64,
    pub omega: f64,
}

/// What a chirp found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChirpFindings {
    /// In the order of the sweep.
    pub jumps: Vec<EnvelopeJump>,
    /// The largest envelope, and τ and ω_e at the centre of its window.
    pub peak_amplitude: f64,
    pub peak_tau: f64,
    pub peak_omega: f64,
    /// The extremes of λ_I over the record.
    pub lambda_min: f64,
    pub lambda_max: f64,
    pub collision: Option<Collision>,
}

impl ChirpSpec {
    /// Checks every setting for the built-in model; the error names the first bad one.
    pub fn validate(&self) -> Result<(), crate::model::ParamError> {
        let omega_max = crate::model::limits::OMEGA.1;
        check_in("omega_start", self.omega_start, 0.0, omega_max)?;
        check_in("omega_end", self.omega_end, 0.0, omega_max)?;
        self.validate_settings()
    }

    /// Checks every setting but the frequencies, which a written model checks against its
    /// frequency parameter's range.
    pub fn validate_settings(&self) -> Result<(), crate::model::ParamError> {
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
        if let Some(scalogram) = &self.scalogram {
            scalogram
                .validate(self.dt)
                .map_err(|e| e.within("scalogram"))?;
        }
        check_jump_ratio(self.jump_ratio)
    }
}

/// Checks a sweep's `jump_ratio`: a change by a factor in (1, 1e6].
pub fn check_jump_ratio(jump_ratio: f64) -> Result<(), crate::model::ParamError> {
    check(
        "jump_ratio",
        jump_ratio,
        |r| r > 1.0 && r <= 1e6,
        "(1, 1e6]",
    )
    .map(drop)
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
        sweep: spec.sweep(),
    };
    let dopri = Dopri5::with_forcing(params, chirp, spec.tolerance, 0.05);
    let mut state = dopri.state(0.0, params.lambda_p() + spec.dx0, spec.v0);
    let n = spec.samples();
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
    Ok(spec.recorded(lambda, collision_tau))
}

impl ChirpSpec {
    /// The sweep of the forcing frequency.
    pub fn sweep(&self) -> Sweep {
        Sweep {
            omega_start: self.omega_start,
            omega_end: self.omega_end,
            span: self.span,
        }
    }

    /// Samples in the whole record, τ = 0 and `span` included.
    pub(crate) fn samples(&self) -> usize {
        (self.span / self.dt).round() as usize + 1
    }

    /// The sweep of the output `lambda` sampled every `dt` (up to a collision at
    /// `collision_tau`): its envelope and findings.
    pub(crate) fn recorded(&self, lambda: Vec<f64>, collision_tau: Option<f64>) -> ChirpSweep {
        let (spec, sweep) = (self, self.sweep());
        let omega: Vec<f64> = (0..lambda.len())
            .map(|j| sweep.omega_at(j as f64 * spec.dt))
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
                [centre, sweep.omega_at(centre), hi - lo]
            })
            .collect::<Vec<_>>();
        let findings = ChirpFindings {
            jumps: envelope_jumps(&envelope, spec.dt * per_window as f64, spec.jump_ratio)
                .into_iter()
                .map(|(direction, window, before, after)| {
                    let tau = (window * per_window) as f64 * spec.dt;
                    EnvelopeJump {
                        direction,
                        window,
                        tau,
                        omega: sweep.omega_at(tau),
                        amplitude_before: before,
                        amplitude_after: after,
                    }
                })
                .collect(),
            ..peak_and_range(
                &envelope,
                &lambda,
                collision_tau.map(|tau| Collision {
                    tau,
                    omega: sweep.omega_at(tau),
                }),
            )
        };
        ChirpSweep {
            dt: spec.dt,
            lambda,
            omega,
            envelope,
            window_samples: per_window,
            collision_tau,
            findings,
        }
    }
}

/// The largest envelope, the range of λ_I and the collision; no jumps.
fn peak_and_range(
    envelope: &[[f64; 3]],
    lambda: &[f64],
    collision: Option<Collision>,
) -> ChirpFindings {
    let peak = envelope
        .iter()
        .fold([0.0; 3], |m, e| if e[2] > m[2] { *e } else { m });
    let (lambda_min, lambda_max) = lambda
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
    ChirpFindings {
        jumps: Vec::new(),
        peak_amplitude: peak[2],
        peak_tau: peak[0],
        peak_omega: peak[1],
        lambda_min,
        lambda_max,
        collision,
    }
}

/// The jumps of `envelope` (windows of `window` τ; see [`EnvelopeJump`]): each as its
/// direction, the window after its steepest step, and the envelope before and after.
fn envelope_jumps(
    envelope: &[[f64; 3]],
    window: f64,
    jump_ratio: f64,
) -> Vec<(Direction, usize, f64, f64)> {
    let largest = envelope.iter().map(|e| e[2]).fold(0.0, f64::max);
    let n = envelope.len();
    // a window counts if it is whole and spans a forcing period (the last may be cut short)
    let counts = |k: usize| k + 1 < n && envelope[k][1] * window >= std::f64::consts::TAU;
    let amplitude = |k: usize| envelope[k][2];
    let step = |k: usize| -> Option<Direction> {
        if !(counts(k) && counts(k + 1)) {
            return None;
        }
        let (a, b) = (amplitude(k), amplitude(k + 1));
        if b >= JUMP_STEP_RATIO * a && b > 0.0 {
            Some(Direction::Up)
        } else if a >= JUMP_STEP_RATIO * b && a > 0.0 {
            Some(Direction::Down)
        } else {
            None
        }
    };
    let mut jumps = Vec::new();
    let mut k = 0;
    while k + 1 < n {
        let Some(direction) = step(k) else {
            k += 1;
            continue;
        };
        let first = k;
        while k + 1 < n && step(k) == Some(direction) {
            k += 1;
        }
        let (before, after) = (amplitude(first), amplitude(k));
        let (low, high) = (before.min(after), before.max(after));
        if high >= jump_ratio * low && high - low >= JUMP_FLOOR * largest {
            let steepest = (first..k)
                .max_by(|&i, &j| {
                    let change = |i: usize| (amplitude(i + 1) - amplitude(i)).abs();
                    change(i).total_cmp(&change(j))
                })
                .unwrap_or(first);
            jumps.push((direction, steepest + 1, before, after));
        }
    }
    jumps
}
