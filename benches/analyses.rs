//! The paper's global workloads, on all cores: `cargo bench --features bench --bench analyses`.
//! - Fig 6A basin: 201 × 251 initial states at ADR 0.6, ω_e 3.7.
//! - Fig 4 frequency response: ω_e 0.2–6 by 0.05, 15 × 15 initial states each, ADR 0.6,
//!   with neighbour seeding and the two stepped sweeps.
//! - Fig 3C scalogram: 157 frequencies × 600 columns of the forward chirp sweep at ADR 0.6
//!   (240 001 samples; the sweep itself is made once, outside the measurement).

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use isola::analysis::Progress;
use isola::analysis::global::basin::{BasinSpec, basin};
use isola::analysis::global::frequency_response::{FrequencyResponseSpec, frequency_response};
use isola::analysis::orbit::chirp_sweep::{ChirpSpec, chirp_sweep};
use isola::analysis::orbit::scalogram::{ScalogramSpec, scalogram};
use isola::model::Params;

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

criterion_group!(benches, workloads);
criterion_main!(benches);
