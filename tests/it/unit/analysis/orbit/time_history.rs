//! Unit tests of `analysis::orbit::time_history` (`src/analysis/orbit/time_history.rs`).

use isola::analysis::orbit::time_history::*;
use isola::model::Params;

/// The summary read off the samples agrees with the steady-state analysis of the same
/// orbit: its period, its amplitude (samples miss the extremes by O(dt²)). At λ_p = 1.02
/// the peak voltage alone outweighs membrane I's tension at rest (φ_I² λ_p = 0.088 >
/// g(λ_p) = 0.078), so even the small 1:1 orbit slackens it part of the time, and the 1:2
/// isola orbit longer; membrane II is never driven and stays taut on the small orbit.
#[test]
fn the_summary_agrees_with_the_steady_state() {
    let p = Params::baseline();
    let mut slack = Vec::new();
    for (dx0, period) in [(0.3, 2), (0.0, 1)] {
        let spec = TimeHistorySpec {
            dx0,
            ..TimeHistorySpec::default()
        };
        let h = time_history(&p, &spec).unwrap();
        assert_eq!(h.steady_state.period, Some(period));
        let col = |f: fn(&Sample) -> f64| h.samples.iter().map(f).collect::<Vec<_>>();
        let steady: Vec<bool> = h.samples.iter().map(|s| s.steady).collect();
        let s = steady_summary(
            &p,
            &col(|s| s.tau),
            &col(|s| s.lambda),
            &col(|s| s.v),
            &steady,
        )
        .unwrap();
        assert_eq!(s.period_forcing_periods, Some(period));
        assert!((s.amplitude - h.steady_state.amplitude.unwrap()).abs() < 2e-3);
        let [slack_i, slack_ii] = s.slack.unwrap();
        assert!((0.0..1.0).contains(&slack_i) && (0.0..1.0).contains(&slack_ii));
        slack.push((slack_i, slack_ii));
    }
    let (isola, small) = (slack[0], slack[1]);
    assert!(isola.0 > small.0 && small.0 > 0.0, "{slack:?}");
    assert_eq!(small.1, 0.0);
}

/// The 1:2 isola orbit at the baseline (ADR 0.6, ω_e 3.7, from Δλ = 0.3, v = 0), sampled
/// `samples_per_period` times per forcing period.
fn isola_history(samples_per_period: usize) -> (Params, TimeHistory) {
    let p = Params::paper(0.6, 3.7).unwrap();
    let spec = TimeHistorySpec {
        dx0: 0.3,
        samples_per_period,
        ..TimeHistorySpec::default()
    };
    let h = time_history(&p, &spec).unwrap();
    (p, h)
}

/// The CSV's tension columns are MODEL.md §1's force law, written out here, at each
/// sample's λ_I, v and φ_I (φ_II = 0); a membrane is flagged slack exactly where its
/// tension is 0, and on the isola orbit each membrane is slack part of the time and taut
/// the rest.
#[test]
fn history_csv_tensions_are_the_force_law() {
    let (p, h) = isola_history(64);
    assert_eq!(h.steady_state.period, Some(2));
    let bytes =
        isola::session::export::history_bytes(&h, &isola::model::Device::silicone()).unwrap();
    let mut reader = csv::Reader::from_reader(bytes.as_slice());
    let header = reader.headers().unwrap().clone();
    assert_eq!(
        header.iter().collect::<Vec<_>>(),
        [
            "tau",
            "time_s",
            "lambda_stretch",
            "v_per_tau",
            "phi_i",
            "steady",
            "tension_i_nondim",
            "tension_ii_nondim",
            "slack_i",
            "slack_ii"
        ]
    );
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    // MODEL.md §1 at the baseline: J = 16, c̃ = 0.04, λ_p = 1.02, φ_DC = 0.2/√1.18,
    // φ_AC = 0.6 φ_DC (E_a = φ_DC² + φ_AC²/2 = 0.04)
    let (j, c, lambda_p, omega) = (16.0, 0.04, 1.02, 3.7);
    let phi_dc = (0.04f64 / (1.0 + 0.6 * 0.6 / 2.0)).sqrt();
    let phi_ac = 0.6 * phi_dc;
    assert_eq!((p.j(), p.c_tilde(), p.lambda_p()), (j, c, lambda_p));
    let lower_pole = 5f64.sqrt() - 2.0;
    let g = |l: f64| (l - l.powi(-3)) / (1.0 - (l * l + l.powi(-2) - 2.0) / j);
    // the force and the size of its terms (what "relative" is relative to)
    let force = |l: f64, phi_sq: f64, rate: f64| {
        let scale = g(l).abs().max(phi_sq * l).max((c * rate).abs());
        match l <= lower_pole {
            true => (0.0, scale),
            false => ((g(l) - phi_sq * l + c * rate).max(0.0), scale),
        }
    };
    let (mut slack_i, mut slack_ii) = ([false; 2], [false; 2]);
    let mut rows = 0;
    for row in reader.records() {
        let row = row.unwrap();
        let num = |name: &str| row[col(name)].parse::<f64>().unwrap();
        let flag = |name: &str| match &row[col(name)] {
            "true" => true,
            "false" => false,
            other => panic!("{name} = {other}"),
        };
        let (tau, lambda, v) = (num("tau"), num("lambda_stretch"), num("v_per_tau"));
        let phi_i = phi_dc + phi_ac * (omega * tau).cos();
        assert!((num("phi_i") - phi_i).abs() < 1e-15, "τ {tau}");
        let expected = [
            force(lambda, phi_i * phi_i, v),
            force(2.0 * lambda_p - lambda, 0.0, -v),
        ];
        for (m, (tension, slack)) in [
            ("tension_i_nondim", "slack_i"),
            ("tension_ii_nondim", "slack_ii"),
        ]
        .into_iter()
        .enumerate()
        {
            let (f, scale) = expected[m];
            let written = num(tension);
            assert!(
                (written - f).abs() <= 1e-12 * scale,
                "τ {tau}: {tension} {written} against {f}"
            );
            assert_eq!(flag(slack), written == 0.0, "τ {tau}: {slack}");
            let seen = if m == 0 { &mut slack_i } else { &mut slack_ii };
            seen[usize::from(flag(slack))] = true;
        }
        rows += 1;
    }
    assert_eq!(rows, h.samples.len());
    assert_eq!(slack_i, [true, true], "membrane I both taut and slack");
    assert_eq!(slack_ii, [true, true], "membrane II both taut and slack");
}

/// 16 samples per period are 2π/(16 ω_e) apart and are every fourth of the 64: the
/// integrator's steps do not depend on the sampling (samples are read off its dense
/// output), and k·(T/16) = 4k·(T/64) exactly in floating point, so the shared samples are
/// equal to the last bit.
#[test]
fn a_coarser_sampling_reads_the_same_trajectory() {
    let (p, h16) = isola_history(16);
    let (_, h64) = isola_history(64);
    let dt = 2.0 * std::f64::consts::PI / (16.0 * p.omega());
    assert_eq!(h16.samples.len() - 1, (h64.samples.len() - 1) / 4);
    for (k, pair) in h16.samples.windows(2).enumerate() {
        assert!((pair[1].tau - pair[0].tau - dt).abs() < 1e-12, "sample {k}");
    }
    for (k, s) in h16.samples.iter().enumerate() {
        assert_eq!(*s, h64.samples[4 * k], "sample {k}");
    }
    assert_eq!(h16.steady_from, h64.steady_from);
}

/// The sampling is a whole number in [4, 4096]; anything else is an error naming the
/// setting, the value and the range.
#[test]
fn samples_per_period_outside_its_range_is_refused() {
    for n in [4, 64, 4096] {
        let spec = TimeHistorySpec {
            samples_per_period: n,
            ..TimeHistorySpec::default()
        };
        assert!(spec.validate().is_ok(), "{n}");
    }
    for n in [0, 3, 4097, 5000] {
        let spec = TimeHistorySpec {
            samples_per_period: n,
            ..TimeHistorySpec::default()
        };
        let e = spec.validate().unwrap_err();
        assert_eq!(
            e.to_string(),
            format!("samples_per_period = {n} is out of range: allowed [4, 4096]")
        );
    }
    let table: toml::Table = toml::from_str("samples_per_period = 1.5").unwrap();
    let e = isola::session::Settings::read("time_history", Some(table)).unwrap_err();
    assert_eq!(e.path.as_deref(), Some("samples_per_period"));
    assert!(
        e.message.contains("1.5") && e.message.contains("whole number"),
        "{}",
        e.message
    );
}

/// The steady part repeats with the response period, and it spans the reported amplitude.
#[test]
fn steady_part_repeats_and_spans_the_amplitude() {
    let p = Params::baseline();
    let spec = TimeHistorySpec {
        dx0: 0.3,
        ..TimeHistorySpec::default()
    };
    let h = time_history(&p, &spec).unwrap();
    assert_eq!(h.steady_state.period, Some(2));
    let steady: Vec<&Sample> = h.samples.iter().filter(|s| s.steady).collect();
    let per = 2 * spec.samples_per_period;
    assert!(steady.len() > per);
    for i in 0..steady.len() - per {
        assert!((steady[i].lambda - steady[i + per].lambda).abs() < 1e-6);
    }
    let (lo, hi) = steady
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
            (lo.min(s.lambda), hi.max(s.lambda))
        });
    // samples miss the exact extremes by at most O(dt²)
    assert!((hi - lo - h.steady_state.amplitude.unwrap()).abs() < 2e-3);
    assert!(h.samples.iter().any(|s| !s.steady));
}
