//! Fig 3C/D: continuous wavelet transform (Morlet) of a recorded response, and its ridge:
//! the strongest response frequency ω_r over time, as a ratio to the forcing frequency.

use std::f64::consts::PI;

use rayon::prelude::*;
use rustfft::FftPlanner;
use rustfft::num_complex::Complex;
use serde::{Deserialize, Serialize};

use crate::analysis::AnalysisError;
use crate::analysis::grid::Axis;
use crate::model::ParamError;
use crate::model::error::check;

/// Most cells (frequencies × columns) of a scalogram: 80 MB of magnitudes.
const MAX_CELLS: usize = 10_000_000;

/// Morlet centre frequency ω₀ (the usual 6: the wavelet is admissible to ~1e-8).
pub const MORLET_OMEGA0: f64 = 6.0;

/// Which frequencies and how many time columns to keep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ScalogramSpec {
    /// Analysis frequencies (angular, non-dimensional like ω_e).
    pub frequencies: Axis,
    /// Time columns kept (evenly spaced).
    pub columns: usize,
}

impl Default for ScalogramSpec {
    fn default() -> Self {
        ScalogramSpec {
            frequencies: Axis::new(0.2, 8.0, 157),
            columns: 600,
        }
    }
}

impl ScalogramSpec {
    /// Checks the frequencies (at most 4096, above 0 and below the Nyquist frequency π/dt of
    /// a signal sampled every `dt`) and the columns ([1, 100000], and at most 10⁷ cells).
    pub fn validate(&self, dt: f64) -> Result<(), ParamError> {
        self.frequencies.validate("frequencies", 4096)?;
        check("frequencies.min", self.frequencies.min, |f| f > 0.0, "> 0")?;
        let nyquist = PI / dt;
        check(
            "frequencies.max",
            self.frequencies.max,
            |f| f < nyquist,
            format!("< {nyquist} (π/dt, the Nyquist frequency of samples every dt = {dt})"),
        )?;
        // |W| is held for every cell and written a row each: bounded like a basin's grid
        let points = self.frequencies.points;
        let most = (MAX_CELLS / points).min(100_000);
        let allowed = match most {
            100_000 => "[1, 100000]".to_string(),
            _ => format!(
                "[1, 100000], and at most {most} with frequencies.points = {points} (10^7 cells)"
            ),
        };
        check(
            "columns",
            self.columns as f64,
            |c| c >= 1.0 && c <= most as f64,
            allowed,
        )?;
        Ok(())
    }
}

/// |W| on a frequency × time grid, normalised so a sinusoid of amplitude A shows about A.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scalogram {
    pub frequencies: Vec<f64>,
    /// The sample of each kept column (its τ is `samples[c]`·dt).
    pub samples: Vec<usize>,
    /// τ of each kept column.
    pub times: Vec<f64>,
    /// `magnitude[f][c]`.
    pub magnitude: Vec<Vec<f64>>,
    /// Per column: the frequency of the largest magnitude.
    pub ridge: Vec<f64>,
}

impl Scalogram {
    /// ω_r/ω_e per column, given the forcing frequency at each column's time.
    pub fn ridge_ratio(&self, omega_e: impl Fn(f64) -> f64) -> Vec<f64> {
        self.times
            .iter()
            .zip(&self.ridge)
            .map(|(&t, &w)| w / omega_e(t))
            .collect()
    }

    /// The forcing frequency at each column, from `omega` at every sample of the signal.
    pub fn forcing(&self, omega: &[f64]) -> Vec<f64> {
        self.samples.iter().map(|&j| omega[j]).collect()
    }
}

/// The Morlet scalogram of `signal` sampled every `dt` (its mean removed first).
pub fn scalogram(
    signal: &[f64],
    dt: f64,
    spec: &ScalogramSpec,
) -> Result<Scalogram, AnalysisError> {
    check("dt", dt, |d| d > 0.0, "> 0")?;
    check("samples", signal.len() as f64, |n| n >= 8.0, ">= 8")?;
    spec.validate(dt)?;
    let len = signal.len();
    let mean = signal.iter().sum::<f64>() / len as f64;
    // zero-padded to a power of two: fast transforms, and no wrap-around between the ends
    let n = (2 * len).next_power_of_two();
    let mut planner = FftPlanner::new();
    let forward = planner.plan_fft_forward(n);
    let inverse = planner.plan_fft_inverse(n);
    let mut spectrum: Vec<Complex<f64>> = signal
        .iter()
        .map(|&x| Complex::new(x - mean, 0.0))
        .chain(std::iter::repeat(Complex::new(0.0, 0.0)))
        .take(n)
        .collect();
    forward.process(&mut spectrum);
    let columns = spec.columns.min(len);
    let picks: Vec<usize> = (0..columns)
        .map(|c| c * (len - 1) / (columns - 1).max(1))
        .collect();
    let frequencies = spec.frequencies.values();
    // angular frequency of FFT bin k
    let bin_omega = |k: usize| {
        let k = if k <= n / 2 {
            k as f64
        } else {
            k as f64 - n as f64
        };
        2.0 * PI * k / (n as f64 * dt)
    };
    let magnitude: Vec<Vec<f64>> = frequencies
        .par_iter()
        .map_init(
            || vec![Complex::new(0.0, 0.0); n],
            |buffer, &w| {
                let scale = MORLET_OMEGA0 / w;
                for (k, b) in buffer.iter_mut().enumerate() {
                    let om = bin_omega(k);
                    // analytic Morlet in frequency: positive frequencies only, peak gain 2
                    let gain = if om > 0.0 {
                        2.0 * (-0.5 * (scale * om - MORLET_OMEGA0).powi(2)).exp()
                    } else {
                        0.0
                    };
                    *b = spectrum[k] * gain;
                }
                inverse.process(buffer);
                picks.iter().map(|&j| buffer[j].norm() / n as f64).collect()
            },
        )
        .collect();
    let ridge = (0..columns)
        .map(|c| {
            let best = (0..frequencies.len())
                .max_by(|&a, &b| magnitude[a][c].total_cmp(&magnitude[b][c]))
                .unwrap_or(0);
            frequencies[best]
        })
        .collect();
    Ok(Scalogram {
        frequencies,
        times: picks.iter().map(|&j| j as f64 * dt).collect(),
        samples: picks,
        magnitude,
        ridge,
    })
}
