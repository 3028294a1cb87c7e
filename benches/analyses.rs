//! The paper's global workloads, on all cores: `cargo bench --features bench --bench analyses`.
//! - Fig 6A basin: 201 × 251 initial states at ADR 0.6, ω_e 3.7.
//! - Fig 4 frequency response: ω_e 0.2–6 by 0.05, 15 × 15 initial states each, ADR 0.6,
//!   with neighbour seeding and the two stepped sweeps.

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use isola::analysis::Progress;
use isola::analysis::global::basin::{BasinSpec, basin};
use isola::analysis::global::frequency_response::{FrequencyResponseSpec, frequency_response};
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
    g.finish();
}

criterion_group!(benches, workloads);
criterion_main!(benches);
