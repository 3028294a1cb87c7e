//! Fig 3C/D: continuous wavelet transform (Morlet) of a recorded response, and its ridge:
//! the strongest response frequency ω_r over time, as a ratio to the forcing frequency.

use std::f64::consts::PI;

use rayon::prelude::*;
use rustfft::algorithm::Radix4;
use rustfft::num_complex::Complex;
use rustfft::{Fft, FftDirection};
use serde::{Deserialize, Serialize};

use crate::analysis::AnalysisError;
use crate::analysis::grid::Axis;
use crate::model::ParamError;
use crate::model::error::check;

/// Most cells (frequencies × columns) of a scalogram: 80 MB of magnitudes.
const MAX_CELLS: usize = 10_000_000;

/// The version of the scalogram's numerics, part of the fingerprint of a chirp sweep that
/// writes one (beside [`crate::analysis::NUMERICS_VERSION`]): bump it with any change that
/// alters a number of a scalogram.
/// 2: each row summed over the wavelet's taps at the kept columns (or by transforms of the
/// same taps), the Morlet two-sided (1: the analytic wavelet, one transform per row): Fig 3's
/// magnitudes moved by at most 1.3e-10 (of 0.1), their ridges not at all.
pub const NUMERICS_VERSION: u32 = 2;

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
    /// The forcing frequency at each column, from `omega` at every sample of the signal.
    pub fn forcing(&self, omega: &[f64]) -> Vec<f64> {
        self.samples.iter().map(|&j| omega[j]).collect()
    }
}

/// A Gaussian is below 1e-16 of its peak beyond this many standard deviations
/// (exp(−8.6²/2) = 8.7e-17): the Morlet wavelet's reach either side of its centre, in scales.
const GAUSSIAN_REACH: f64 = 8.6;

/// A row of the scalogram is summed tap by tap at the kept columns while it has at most this
/// many times n·log₂n taps × columns (n the transform's size), else by transforms: measured,
/// a tap and column took 2 ns and a row by transforms of 2¹⁹ points 64 ms (6.4 ns·n·log₂n).
const DIRECT_PER_TRANSFORM: f64 = 3.0;

/// The Morlet scalogram of `signal` sampled every `dt` (its mean removed first, zero
/// beyond its ends).
///
/// Row ω_r is the convolution of the signal with the Morlet wavelet of scale a = ω₀/ω_r,
/// sampled every dt (taps κ_m = dt·√(2/π)/a · exp(−(m·dt)²/(2a²)) · e^{iω_r·m·dt}, out to
/// 8.6 a either side, where they fall below 1e-16): in frequency a gain
/// 2·exp(−(a·ω − ω₀)²/2), so a sinusoid of amplitude A at ω_r shows A. Only the kept columns
/// are computed: directly, as a sum over the taps, where that is cheaper than transforming
/// the whole record, else through FFTs of the signal and of the same taps; the two agree to
/// rounding.
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
    let centred: Vec<f64> = signal.iter().map(|&x| x - mean).collect();
    let columns = spec.columns.min(len);
    let picks: Vec<usize> = (0..columns)
        .map(|c| c * (len - 1) / (columns - 1).max(1))
        .collect();
    let frequencies = spec.frequencies.values();
    let wavelets: Vec<Morlet> = frequencies
        .iter()
        .map(|&w| Morlet::new(w, dt, len))
        .collect();
    // zero-padded to a power of two at least twice the record: no wrap-around between its ends
    let n = (2 * len).next_power_of_two();
    let transform_cost = DIRECT_PER_TRANSFORM * n as f64 * (n as f64).log2();
    let direct = |m: &Morlet| (columns * m.taps()) as f64 <= transform_cost;
    let transform = wavelets
        .iter()
        .any(|m| !direct(m))
        .then(|| Transform::new(&centred, n));
    let magnitude: Vec<Vec<f64>> = wavelets
        .par_iter()
        .map(|m| match &transform {
            Some(t) if !direct(m) => t.row(m, &picks),
            _ => m.row(&centred, &picks),
        })
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

/// The Morlet wavelet at one analysis frequency, as taps κ_m for |m| ≤ `reach` (its reach in
/// samples, at most the record's length less one: further taps meet no sample).
struct Morlet {
    omega_r: f64,
    scale: f64,
    dt: f64,
    reach: usize,
}

impl Morlet {
    fn new(omega_r: f64, dt: f64, len: usize) -> Self {
        let scale = MORLET_OMEGA0 / omega_r;
        let reach = (GAUSSIAN_REACH * scale / dt).ceil().min((len - 1) as f64) as usize;
        Morlet {
            omega_r,
            scale,
            dt,
            reach,
        }
    }

    fn taps(&self) -> usize {
        2 * self.reach + 1
    }

    /// κ_m, m = −reach..=reach, as (re, im).
    fn tap(&self, m: isize) -> (f64, f64) {
        let s = m as f64 * self.dt;
        let weight =
            self.dt * (2.0 / PI).sqrt() / self.scale * (-0.5 * (s / self.scale).powi(2)).exp();
        let (sin, cos) = (self.omega_r * s).sin_cos();
        (weight * cos, weight * sin)
    }

    /// |W| at each pick, summed over the taps: W_j = Σ_m x_{j−m} κ_m.
    fn row(&self, x: &[f64], picks: &[usize]) -> Vec<f64> {
        let reach = self.reach as isize;
        // reversed, so that tap i meets sample j − reach + i
        let (re, im): (Vec<f64>, Vec<f64>) = (-reach..=reach).rev().map(|m| self.tap(m)).unzip();
        picks
            .iter()
            .map(|&j| {
                let first = j.saturating_sub(self.reach);
                let last = (j + self.reach).min(x.len() - 1);
                let offset = first + self.reach - j;
                let samples = &x[first..=last];
                let taps = offset..offset + samples.len();
                let (w_re, w_im) = dot_complex(samples, &re[taps.clone()], &im[taps]);
                w_re.hypot(w_im)
            })
            .collect()
    }
}

/// (Σ x·re, Σ x·im), four partial sums each so that the loop vectorises.
fn dot_complex(x: &[f64], re: &[f64], im: &[f64]) -> (f64, f64) {
    let (mut sum_re, mut sum_im) = ([0.0; 4], [0.0; 4]);
    let (xs, res, ims) = (x.chunks_exact(4), re.chunks_exact(4), im.chunks_exact(4));
    let tail = (xs.remainder(), res.remainder(), ims.remainder());
    for ((x, re), im) in xs.zip(res).zip(ims) {
        for k in 0..4 {
            sum_re[k] += x[k] * re[k];
            sum_im[k] += x[k] * im[k];
        }
    }
    for ((x, re), im) in tail.0.iter().zip(tail.1).zip(tail.2) {
        sum_re[0] += x * re;
        sum_im[0] += x * im;
    }
    let total = |s: [f64; 4]| (s[0] + s[1]) + (s[2] + s[3]);
    (total(sum_re), total(sum_im))
}

/// The signal's transform, zero-padded to `n`, for rows computed as products of transforms
/// (radix 4: `n` is a power of two, and the rows that take this path are few).
struct Transform {
    spectrum: Vec<Complex<f64>>,
    forward: Radix4<f64>,
    inverse: Radix4<f64>,
}

impl Transform {
    fn new(x: &[f64], n: usize) -> Self {
        let forward = Radix4::new(n, FftDirection::Forward);
        let inverse = Radix4::new(n, FftDirection::Inverse);
        let mut spectrum: Vec<Complex<f64>> = x
            .iter()
            .map(|&x| Complex::new(x, 0.0))
            .chain(std::iter::repeat(Complex::new(0.0, 0.0)))
            .take(n)
            .collect();
        forward.process(&mut spectrum);
        Transform {
            spectrum,
            forward,
            inverse,
        }
    }

    /// |W| at each pick: the circular convolution with the same taps as [`Morlet::row`], by
    /// transforms (n at least twice the record, so no tap wraps onto a sample).
    fn row(&self, m: &Morlet, picks: &[usize]) -> Vec<f64> {
        let n = self.spectrum.len();
        let mut kernel = vec![Complex::new(0.0, 0.0); n];
        let reach = m.reach as isize;
        for k in -reach..=reach {
            let (re, im) = m.tap(k);
            kernel[k.rem_euclid(n as isize) as usize] = Complex::new(re, im);
        }
        self.forward.process(&mut kernel);
        for (k, x) in kernel.iter_mut().zip(&self.spectrum) {
            *k *= x;
        }
        self.inverse.process(&mut kernel);
        picks.iter().map(|&j| kernel[j].norm() / n as f64).collect()
    }
}
