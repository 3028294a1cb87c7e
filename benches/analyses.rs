//! The paper's global workloads, on all cores: `cargo bench --features bench --bench analyses`.
//! - Fig 6A basin: 201 × 251 initial states at ADR 0.6, ω_e 3.7.
//! - Fig 4 frequency response: ω_e 0.2–6 by 0.05, 15 × 15 initial states each, ADR 0.6,
//!   with neighbour seeding and the two stepped sweeps.
//! - Fig 6B basin: the same grid at ADR 1.0, ω_e 3.6.
//! - Fig 3C scalogram: 157 frequencies × 600 columns of the forward chirp sweep at ADR 0.6
//!   (240 001 samples; the sweep itself is made once, outside the measurement).
//! - Through sessions, as `isola run` and the workbench compute them, with the results store
//!   (claims, chunk files, assembly): Fig 4's response (`sessions/fig04_response_adr06.toml`)
//!   and the map (`sessions/map_adr_omega.toml`: 51 × 23 cells, 7 × 7 starts, with curves).
//!   Each iteration starts from an empty results folder.

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use isola::analysis::Progress;
use isola::analysis::global::basin::{BasinSpec, basin};
use isola::analysis::global::frequency_response::{FrequencyResponseSpec, frequency_response};
use isola::analysis::orbit::chirp_sweep::{ChirpSpec, chirp_sweep};
use isola::analysis::orbit::scalogram::{ScalogramSpec, scalogram};
use isola::model::Params;
use isola::session::Session;
use isola::session::run::{Outcome, Shard, run_analysis};

fn workloads(c: &mut Criterion) {
    let p = Params::baseline();
    let mut g = c.benchmark_group("paper_workloads");
    g.sample_size(10)
        .measurement_time(Duration::from_secs(20))
        .warm_up_time(Duration::from_secs(1));
    g.bench_function("fig6a_basin_201x251", |b| {
        b.iter(|| basin(&p, &BasinSpec::default(), &Progress::new(0), &|_| {}).unwrap())
    });
    g.bench_function("fig4_response_117x225", |b| {
        b.iter(|| {
            frequency_response(&p, &FrequencyResponseSpec::default(), &Progress::new(0)).unwrap()
        })
    });
    g.bench_function("fig6b_basin_201x251", |b| {
        let fig6b = Params::paper(1.0, 3.6).unwrap();
        b.iter(|| basin(&fig6b, &BasinSpec::default(), &Progress::new(0), &|_| {}).unwrap())
    });
    g.bench_function("fig6a_basin_201x251_no_early_stop", |b| {
        let spec = BasinSpec {
            early_stop: false,
            ..BasinSpec::default()
        };
        b.iter(|| basin(&p, &spec, &Progress::new(0), &|_| {}).unwrap())
    });
    let never = std::sync::atomic::AtomicBool::new(false);
    let sweep = chirp_sweep(&p, &ChirpSpec::default(), &never, |_| {}).unwrap();
    g.bench_function("fig3_scalogram_157x600", |b| {
        b.iter(|| scalogram(&sweep.lambda, sweep.dt, &ScalogramSpec::default()).unwrap())
    });
    g.finish();
}

/// One analysis of an example session run through the results store, from an empty results
/// folder each time (in a temporary copy of the session).
fn through_session(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    id: &str,
    file: &str,
    analysis: &str,
) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(file);
    std::fs::copy(std::path::Path::new("sessions").join(file), &path).unwrap();
    let session = Session::load(&path).unwrap();
    let entry = session.analysis(analysis).unwrap();
    let results = path.with_extension("results");
    g.bench_function(id, |b| {
        b.iter(|| {
            let _ = std::fs::remove_dir_all(&results);
            let outcome = run_analysis(&session, entry, Shard::ALL, &Progress::new(0)).unwrap();
            assert!(matches!(outcome, Outcome::Completed { .. }), "{outcome:?}");
        })
    });
}

fn sessions(c: &mut Criterion) {
    let mut g = c.benchmark_group("sessions");
    g.sample_size(10)
        .measurement_time(Duration::from_secs(20))
        .warm_up_time(Duration::from_secs(1));
    through_session(
        &mut g,
        "fig4_response",
        "fig04_response_adr06.toml",
        "response",
    );
    through_session(&mut g, "fig6a_basin", "fig06a_basin_adr06.toml", "basin");
    through_session(&mut g, "map_adr_omega", "map_adr_omega.toml", "adr_omega");
    g.finish();
}

criterion_group!(benches, workloads, sessions);
criterion_main!(benches);
