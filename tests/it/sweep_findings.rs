//! What a sweep found: the jumps of a chirp's envelope located against the envelope itself,
//! the jumps of a stepped sweep at the steps where its response changes, and their tables.

use std::sync::atomic::AtomicBool;

use isola::analysis::Progress;
use isola::analysis::SteadyStateSpec;
use isola::analysis::global::stepped_sweep::{SweepFindings, stepped_sweep};
use isola::analysis::orbit::chirp_sweep::{ChirpSpec, ChirpSweep, Direction, chirp_sweep};
use isola::model::Params;
use isola::session::Session;
use isola::session::run::{Shard, run_analysis};

/// The envelope recomputed from the recorded λ_I: max − min over each window of samples.
fn envelope_of(s: &ChirpSweep) -> Vec<f64> {
    s.lambda
        .chunks(s.window_samples)
        .map(|c| {
            let hi = c.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let lo = c.iter().copied().fold(f64::INFINITY, f64::min);
            hi - lo
        })
        .collect()
}

/// The window at which the envelope, in the sweep's order, first crosses halfway between its
/// largest and least values over the windows whose ω_e lies in `band`, going `direction`.
fn halfway_crossing(s: &ChirpSweep, band: (f64, f64), direction: Direction) -> usize {
    let envelope = envelope_of(s);
    let inside: Vec<usize> = (0..envelope.len() - 1)
        .filter(|&k| (band.0..band.1).contains(&s.envelope[k][1]))
        .collect();
    let hi = inside.iter().map(|&k| envelope[k]).fold(0.0, f64::max);
    let lo = inside
        .iter()
        .map(|&k| envelope[k])
        .fold(f64::INFINITY, f64::min);
    let half = 0.5 * (hi + lo);
    inside
        .windows(2)
        .find(|p| match direction {
            Direction::Up => envelope[p[0]] < half && envelope[p[1]] >= half,
            Direction::Down => envelope[p[0]] > half && envelope[p[1]] <= half,
        })
        .map(|p| p[1])
        .expect("the envelope crosses halfway in the band")
}

/// Fig 3's four chirps (ω_e 0 ↔ 6 over τ = 12000 at ADR 0.6 and 1.0): every jump the sweep
/// reports lies within one envelope window of where the envelope, recomputed from λ_I,
/// crosses halfway between its levels before and after, and no other jump is reported. The
/// jumps are the paper's: up onto the super-harmonic and primary peaks (and at ADR 1.0 onto
/// the 1:2 subharmonic near ω_e 5.1, off it near 5.5) going up; off the primary (ω_e ≈ 1.67,
/// 1.57), the super-harmonic and, at ADR 1.0, the 1:2 branch (≈ 3.36) going down.
#[test]
fn fig3_chirp_jumps_are_where_the_envelope_jumps() {
    let never = AtomicBool::new(false);
    type Expected = &'static [(f64, f64, Direction)];
    let cases: [(f64, bool, Expected); 4] = [
        (
            0.6,
            true,
            &[(1.2, 1.45, Direction::Up), (2.1, 2.5, Direction::Up)],
        ),
        (
            0.6,
            false,
            &[(1.0, 1.25, Direction::Down), (1.5, 1.9, Direction::Down)],
        ),
        (
            1.0,
            true,
            &[
                (1.1, 1.35, Direction::Up),
                (2.0, 2.4, Direction::Up),
                (4.9, 5.3, Direction::Up),
                (5.35, 5.7, Direction::Down),
            ],
        ),
        (
            1.0,
            false,
            &[
                (0.85, 1.1, Direction::Down),
                (1.4, 1.8, Direction::Down),
                (3.2, 3.6, Direction::Down),
            ],
        ),
    ];
    for (adr, forward, expected) in cases {
        let (omega_start, omega_end) = if forward { (0.0, 6.0) } else { (6.0, 0.0) };
        let spec = ChirpSpec {
            omega_start,
            omega_end,
            ..ChirpSpec::default()
        };
        let s = chirp_sweep(&Params::paper(adr, 1.0).unwrap(), &spec, &never, |_| {}).unwrap();
        let jumps = &s.findings.jumps;
        let label = format!("ADR {adr} {}", if forward { "up" } else { "down" });
        assert_eq!(jumps.len(), expected.len(), "{label}: {jumps:?}");
        for &(lo, hi, direction) in expected {
            let j = jumps
                .iter()
                .find(|j| (lo..hi).contains(&j.omega))
                .unwrap_or_else(|| panic!("{label}: no jump in {lo}–{hi}: {jumps:?}"));
            assert_eq!(j.direction, direction, "{label}: {j:?}");
            let crossing = halfway_crossing(&s, (lo, hi), direction);
            assert!(
                j.window.abs_diff(crossing) <= 1,
                "{label}: jump at window {} (ω_e {:.3}), envelope halfway at {crossing}",
                j.window,
                j.omega
            );
            // τ is the window's start, ω_e the chirp's there; the levels change twofold
            let per_window = s.window_samples as f64 * s.dt;
            assert!((j.tau - j.window as f64 * per_window).abs() < 1e-9);
            let (w0, w1) = (spec.omega_start, spec.omega_end);
            assert!((j.omega - (w0 + (w1 - w0) * j.tau / spec.span)).abs() < 1e-12);
            let (a, b) = (j.amplitude_before, j.amplitude_after);
            assert!(a.max(b) >= 2.0 * a.min(b), "{label}: {j:?}");
            assert_eq!(b > a, direction == Direction::Up, "{label}: {j:?}");
        }
        // the peak and the range of λ_I are the record's
        let envelope = envelope_of(&s);
        let peak = envelope.iter().copied().fold(0.0, f64::max);
        assert_eq!(s.findings.peak_amplitude, peak, "{label}");
        let lambda_max = s.lambda.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(s.findings.lambda_max, lambda_max, "{label}");
        assert_eq!(s.findings.collision, None, "{label}");
    }
}

/// A collision is reported with both its τ and the chirp's ω_e there.
#[test]
fn a_chirp_that_hits_a_frame_says_where_in_omega() {
    let never = AtomicBool::new(false);
    let p = Params::paper(0.6, 1.0).unwrap();
    let spec = ChirpSpec {
        omega_start: 3.0,
        omega_end: 4.0,
        span: 400.0,
        dx0: 0.6,
        v0: 2.0,
        ..ChirpSpec::default()
    };
    let s = chirp_sweep(&p, &spec, &never, |_| {}).unwrap();
    let c = s
        .findings
        .collision
        .expect("a start this far out hits a frame");
    assert_eq!(Some(c.tau), s.collision_tau);
    assert!((c.omega - (3.0 + c.tau / 400.0)).abs() < 1e-12, "{c:?}");
}

/// Fig 3's stepped sweep up at ADR 0.6 (ω_e 0.2 to 6 by 0.05): a jump is reported exactly
/// at each step whose response type differs from the step before's, or whose amplitude is
/// twice (or half) the one before; the peaks are each type's largest amplitude.
#[test]
fn stepped_jumps_are_the_steps_where_the_response_changes() {
    let never = AtomicBool::new(false);
    let p = Params::paper(0.6, 1.0).unwrap();
    let omegas: Vec<f64> = (0..=116).map(|i| 0.2 + 0.05 * i as f64).collect();
    let steps = stepped_sweep(
        &p,
        &omegas,
        [p.lambda_p(), 0.0],
        &SteadyStateSpec::default(),
        &never,
        |_| {},
    )
    .unwrap();
    let found = SweepFindings::of(&steps, 2.0);
    let changed: Vec<usize> = (1..steps.len())
        .filter(|&i| {
            let (a, b) = (&steps[i - 1].steady, &steps[i].steady);
            let (x, y) = (a.amplitude.unwrap(), b.amplitude.unwrap());
            a.response_type() != b.response_type() || x.max(y) >= 2.0 * x.min(y)
        })
        .collect();
    let at: Vec<usize> = found.jumps.iter().map(|j| j.step).collect();
    assert_eq!(at, changed);
    // onto the super-harmonic at 1.30 and off it at 1.45, up onto the primary peak at 2.30
    let omegas_at: Vec<(f64, f64)> = found
        .jumps
        .iter()
        .map(|j| (j.omega_before, j.omega_after))
        .collect();
    let near = |a: f64, b: f64| (a - b).abs() < 1e-9;
    let expected = [(1.25, 1.3), (1.4, 1.45), (2.25, 2.3)];
    assert_eq!(omegas_at.len(), expected.len(), "{:?}", found.jumps);
    for ((a, b), (x, y)) in omegas_at.iter().zip(expected) {
        assert!(near(*a, x) && near(*b, y), "{:?}", found.jumps);
    }
    assert!(
        found.jumps[0].type_after.starts_with("2:1"),
        "{:?}",
        found.jumps[0]
    );
    for peak in &found.peaks {
        let mine = steps
            .iter()
            .filter(|s| s.steady.response_type() == peak.response_type);
        let (count, largest) = mine.fold((0, 0.0f64), |(n, m), s| {
            (n + 1, m.max(s.steady.amplitude.unwrap()))
        });
        assert_eq!((peak.steps, peak.peak_amplitude), (count, largest));
    }
    assert_eq!(
        found.peaks.iter().map(|p| p.steps).sum::<usize>(),
        steps.len()
    );
}

/// A session's chirp writes `time_s` = τ × the device's time unit (seconds per τ) in its
/// samples and its jumps, and lists its jumps and extremes tables in its manifest; a
/// stepped sweep lists its jumps and peaks.
#[test]
fn session_sweeps_write_their_findings_beside_their_results() {
    let dir = tempfile::Builder::new()
        .prefix("isola-test-sweep-findings-")
        .tempdir()
        .unwrap();
    let path = dir.path().join("s.toml");
    let text = "schema = 1\n[device]\nmu = 400e3\nj = 16.0\nl1 = 20e-3\nl2 = 200e-3\nl3 = 0.1e-3\nmass = 200e-3\nepsilon = 2.48e-11\n[model]\nadr = 0.6\ne_a = 0.04\n\n\
        [[analysis]]\nname = \"chirp\"\nkind = \"chirp_sweep\"\n[analysis.settings]\nomega_start = 2.6\nomega_end = 1.4\nspan = 1200.0\n\n\
        [[analysis]]\nname = \"stepped\"\nkind = \"stepped_sweep\"\n[analysis.settings]\nomega = { min = 2.1, max = 2.4, points = 7 }\n";
    std::fs::write(&path, text).unwrap();
    let session = Session::load(&path).unwrap();
    let unit = session.device().time_scale();
    for entry in &session.analyses {
        run_analysis(&session, entry, Shard::ALL, &Progress::new(0)).unwrap();
    }
    let results = session.results_dir();
    let rows = |file: &str| -> Vec<csv::StringRecord> {
        let mut r = csv::Reader::from_path(results.join(file)).unwrap();
        let headers = r.headers().unwrap().clone();
        let mut out = vec![headers];
        out.extend(r.records().map(|x| x.unwrap()));
        out
    };
    let column = |rows: &[csv::StringRecord], name: &str| -> Vec<f64> {
        let i = rows[0].iter().position(|h| h == name).unwrap();
        rows[1..].iter().map(|r| r[i].parse().unwrap()).collect()
    };
    for file in ["chirp.csv", "chirp.jumps.csv"] {
        let table = rows(file);
        let (tau, time_s) = (column(&table, "tau"), column(&table, "time_s"));
        assert!(!tau.is_empty(), "{file}");
        for (t, s) in tau.iter().zip(&time_s) {
            assert_eq!(*s, t * unit, "{file}: τ {t}");
        }
    }
    // sweeping the primary resonance down falls off its high branch once
    let jumps = rows("chirp.jumps.csv");
    assert_eq!(jumps.len(), 2, "{jumps:?}");
    assert_eq!(&jumps[1][1], "down");
    let manifest = |name: &str| -> Vec<String> {
        let m: serde_json::Value = serde_json::from_slice(
            &std::fs::read(results.join(format!("{name}.manifest.json"))).unwrap(),
        )
        .unwrap();
        m["files"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f["name"].as_str().unwrap().to_string())
            .collect()
    };
    assert_eq!(
        manifest("chirp"),
        ["chirp.csv", "chirp.jumps.csv", "chirp.extremes.csv"]
    );
    assert_eq!(
        manifest("stepped"),
        ["stepped.csv", "stepped.jumps.csv", "stepped.peaks.csv"]
    );
    // the stepped sweep up meets the primary peak's jump between ω_e 2.25 and 2.30
    let stepped = rows("stepped.jumps.csv");
    assert_eq!(stepped.len(), 2, "{stepped:?}");
    assert_eq!(&stepped[1][1], "4");
}

/// `isola sweep`: the chirp's jumps in `--json` as the text lists them, with `time_s`
/// = τ × the silicone device's seconds per τ and the collision-free record's ω_e range; the
/// CSV's jumps table beside it; `--jump-ratio` out of (1, 1e6] refused, naming the flag.
#[test]
fn the_cli_chirp_reports_its_jumps_and_refuses_a_bad_ratio() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("c.csv");
    let args = [
        "sweep",
        "--omega",
        "2.6:1.4",
        "--span",
        "1200",
        "--csv",
        csv.to_str().unwrap(),
    ];
    let isola = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_isola"))
            .args(args)
            .output()
            .unwrap()
    };
    let with_json: Vec<&str> = args.iter().copied().chain(["--json"]).collect();
    let v: serde_json::Value = serde_json::from_slice(&isola(&with_json).stdout).unwrap();
    let text = String::from_utf8(isola(&args).stdout).unwrap();
    let jumps = v["jumps"].as_array().unwrap();
    assert!(!jumps.is_empty(), "{v}");
    let unit = isola::model::Device::silicone().time_scale();
    for j in jumps {
        let (tau, omega) = (j["tau"].as_f64().unwrap(), j["omega"].as_f64().unwrap());
        assert_eq!(j["time_s"].as_f64().unwrap(), tau * unit);
        let line = format!("{:<4} at ω_e {omega:.3}", j["direction"].as_str().unwrap());
        assert!(text.contains(&line), "{line} in\n{text}");
    }
    assert_eq!(v["collision_omega"], serde_json::Value::Null);
    let table = std::fs::read_to_string(dir.path().join("c.jumps.csv")).unwrap();
    assert_eq!(table.lines().count(), jumps.len() + 1, "{table}");
    for bad in ["1", "0.5", "1e7", "nan"] {
        let out = isola(&["sweep", "--jump-ratio", bad]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains("--jump-ratio"),
            "{bad}: {err}"
        );
        assert!(
            err.contains("(1, 1e6]") || err.contains("not a finite number"),
            "{bad}: {err}"
        );
    }
}
