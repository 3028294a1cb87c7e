//! Unit tests of `analysis::orbit::scalogram` (`src/analysis/orbit/scalogram.rs`).

use isola::analysis::grid::Axis;
use isola::analysis::orbit::scalogram::*;

/// A sinusoid of amplitude 0.3 at ω = 2 shows |W| ≈ 0.3 at ω = 2 and its ridge there.
#[test]
fn a_sinusoid_shows_its_frequency_and_amplitude() {
    let dt = 0.05;
    let signal: Vec<f64> = (0..20000)
        .map(|j| 1.0 + 0.3 * (2.0 * j as f64 * dt).cos())
        .collect();
    let spec = ScalogramSpec {
        frequencies: Axis::new(0.5, 4.0, 71),
        columns: 50,
    };
    let s = scalogram(&signal, dt, &spec).unwrap();
    // away from the edges
    for c in 10..40 {
        assert!((s.ridge[c] - 2.0).abs() < 0.051, "{}", s.ridge[c]);
        let f2 = s
            .frequencies
            .iter()
            .position(|&f| (f - 2.0).abs() < 1e-9)
            .unwrap();
        assert!(
            (s.magnitude[f2][c] - 0.3).abs() < 0.01,
            "{}",
            s.magnitude[f2][c]
        );
    }
}

/// Morlet's gain at ω for the analysis frequency ω_r: 2·exp(−(a·ω − ω₀)²/2), a = ω₀/ω_r.
fn gain(omega_r: f64, omega: f64) -> f64 {
    let a = MORLET_OMEGA0 / omega_r;
    2.0 * (-0.5 * (a * omega - MORLET_OMEGA0).powi(2)).exp()
}

/// Away from the ends, a sum of sinusoids A_q·cos(ω_q·τ) shows exactly
/// |Σ_q (A_q/2)·(G(ω_q)·e^{iω_q·τ} + G(−ω_q)·e^{−iω_q·τ})| (G the gain), to 1e-12: checked
/// for few columns (summed over the wavelet's taps) and for every sample as a column (so
/// many that the rows are computed by transforms).
#[test]
fn sinusoids_show_the_morlet_gain_exactly() {
    let dt = 0.05;
    let waves = [(0.3, 2.0), (0.1, 3.1), (0.05, 0.7)];
    let len = 12_000;
    let signal: Vec<f64> = (0..len)
        .map(|j| {
            let t = j as f64 * dt;
            waves.iter().map(|(a, w)| a * (w * t).cos()).sum::<f64>()
        })
        .collect();
    // the signal's mean is not zero over the record; remove it as the scalogram does
    let mean = signal.iter().sum::<f64>() / len as f64;
    let expected = |omega_r: f64, t: f64| {
        let (mut re, mut im) = (0.0, 0.0);
        for (a, w) in waves {
            let (plus, minus) = (gain(omega_r, w), gain(omega_r, -w));
            re += 0.5 * a * (plus + minus) * (w * t).cos();
            im += 0.5 * a * (plus - minus) * (w * t).sin();
        }
        // the removed mean, at ω = 0
        re -= mean * gain(omega_r, 0.0);
        re.hypot(im)
    };
    for columns in [40, len] {
        let spec = ScalogramSpec {
            frequencies: Axis::new(1.0, 4.0, 31),
            columns,
        };
        let s = scalogram(&signal, dt, &spec).unwrap();
        // the widest wavelet (ω_r 1) reaches 8.6·6 = 51.6 τ
        let inside = |c: usize| {
            let t = s.times[c];
            t > 52.0 && t < (len - 1) as f64 * dt - 52.0
        };
        let want = |omega_r: f64, c: usize| expected(omega_r, s.times[c]);
        let checked = assert_cells(&s, inside, want, 1e-12, columns);
        assert!(checked > 30 * columns / 2, "{checked}");
    }
}

/// Near the ends and where the wavelet is wider than the record, each column is the sum
/// over the samples there are, W_j = Σ_l x_l·κ(τ_j − τ_l) (computed here term by term), by
/// taps and by transforms alike: to 1e-12 of the largest |W|.
#[test]
fn every_column_is_the_wavelets_sum_over_the_record() {
    let dt = 0.1;
    let len = 600;
    // a chirp with a step, so no closed form helps
    let signal: Vec<f64> = (0..len)
        .map(|j| {
            let t = j as f64 * dt;
            (0.5 * t + 0.02 * t * t).sin() + if t > 31.0 { 0.4 } else { 0.0 }
        })
        .collect();
    let mean = signal.iter().sum::<f64>() / len as f64;
    let reference = |omega_r: f64, j: usize| {
        let a = MORLET_OMEGA0 / omega_r;
        let (mut re, mut im) = (0.0, 0.0);
        for (l, x) in signal.iter().enumerate() {
            let s = (j as f64 - l as f64) * dt;
            let w = dt * (2.0 / std::f64::consts::PI).sqrt() / a * (-0.5 * (s / a).powi(2)).exp();
            re += (x - mean) * w * (omega_r * s).cos();
            im += (x - mean) * w * (omega_r * s).sin();
        }
        re.hypot(im)
    };
    // 0.05: a wavelet reaching 8.6·120 = 1032 τ over a record of 60 τ
    for columns in [7, len] {
        let spec = ScalogramSpec {
            frequencies: Axis::new(0.05, 6.05, 13),
            columns,
        };
        let s = scalogram(&signal, dt, &spec).unwrap();
        let largest = s
            .magnitude
            .iter()
            .flatten()
            .fold(0.0, |m: f64, &w| m.max(w));
        assert!(largest > 0.1, "{largest}");
        let want = |omega_r: f64, c: usize| reference(omega_r, s.samples[c]);
        assert_cells(&s, |_| true, want, 1e-12 * largest, columns);
    }
}

/// Asserts that every cell of `s` in a column `keep` accepts is `want(ω_r, column)` to
/// within `tol`; returns how many were checked. `columns`: what was asked, for the message.
fn assert_cells(
    s: &Scalogram,
    keep: impl Fn(usize) -> bool,
    want: impl Fn(f64, usize) -> f64,
    tol: f64,
    columns: usize,
) -> usize {
    let mut checked = 0;
    for (f, &omega_r) in s.frequencies.iter().enumerate() {
        for c in (0..s.times.len()).filter(|&c| keep(c)) {
            let (got, want) = (s.magnitude[f][c], want(omega_r, c));
            assert!(
                (got - want).abs() < tol,
                "{columns} columns, ω_r {omega_r}, τ {}, sample {}: {got} against {want}",
                s.times[c],
                s.samples[c]
            );
            checked += 1;
        }
    }
    checked
}
