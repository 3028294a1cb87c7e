//! Engine benchmarks: RK4 steps per second per core, and the time to classify an orbit
//! from basin-grid initial states. `cargo bench --features bench --bench engine`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::sync::atomic::AtomicBool;

use isola::analysis::global::batch::steady_states;
use isola::analysis::{SteadyStateSpec, steady_state};
use isola::model::equations::lanes::EquationLanes;
use isola::model::equations::tape::NATIVE_LANES;
use isola::model::equations::{EquationModel, ModelDefinition};
use isola::model::{DriveSpec, ParamSpec, Params};
use isola::solver::general::GeneralRk4;
use isola::solver::general_lanes::Lanes;
use isola::solver::isa::{self, Isa};
use isola::solver::{Resolution, Rk4};

const PERIODS: usize = 200;

/// `L` lanes started near `dx` around λ_p, advanced `PERIODS` forcing periods in the code
/// compiled for `isa`.
fn run_lanes<const L: usize>(rk: &Rk4, isa: Isa, dx: f64) -> f64 {
    let p = rk.params();
    let x: [f64; L] = std::array::from_fn(|i| p.lambda_p() + dx * (i as f64 / L as f64 - 0.5));
    let v: [f64; L] = std::array::from_fn(|i| 0.01 * i as f64 / L as f64);
    let mut lanes = rk.start(x, v);
    for _ in 0..PERIODS {
        rk.advance_period_in(isa, &mut lanes, None);
    }
    lanes.x.iter().sum()
}

fn rk4_steps(c: &mut Criterion) {
    // taut: both membranes stay in tension (ADR 0.1, ω_e 1, small motion)
    let taut = ParamSpec {
        drive: DriveSpec::EaAdr {
            e_a: 0.04,
            adr: 0.1,
        },
        omega: 1.0,
        ..ParamSpec::default()
    }
    .build()
    .unwrap();
    // slack: the baseline at ω_e 3.7, where membrane I loses tension twice every period
    let slack = Params::baseline();
    let mut g = c.benchmark_group("rk4_steps");
    g.measurement_time(Duration::from_secs(4)).sample_size(20);
    for (name, p) in [("taut", &taut), ("slack", &slack)] {
        let rk = Rk4::new(p, &Resolution::default());
        let steps = (PERIODS * rk.steps_per_period()) as u64;
        // every instruction set this CPU has, side by side (the release build chooses the
        // widest)
        for isa in Isa::ALL.into_iter().filter(|isa| isa.available()) {
            let isa_name = isa.name();
            g.throughput(Throughput::Elements(steps));
            g.bench_function(format!("{name}/1_lane/{isa_name}"), |b| {
                b.iter(|| run_lanes::<1>(&rk, isa, black_box(0.01)))
            });
            g.throughput(Throughput::Elements(16 * steps));
            g.bench_function(format!("{name}/16_lanes/{isa_name}"), |b| {
                b.iter(|| run_lanes::<16>(&rk, isa, black_box(0.01)))
            });
        }
    }
    g.finish();
}

/// The paper's model written as equations (`sessions/user_model_paper.toml`) on the general
/// engine, against the built-in on one lane, at the same steps per period.
fn written_model_steps(c: &mut Criterion) {
    let text = include_str!("../sessions/user_model_paper.toml");
    let def = ModelDefinition::from_text(text).unwrap();
    let model = EquationModel::new(&def, text).unwrap();
    let mut values = model.defaults();
    values[model.parameter("omega").unwrap()] = 3.7;
    let mut sys = model.system(&values).unwrap();
    let p = Params::baseline();
    let rk = Rk4::new(&p, &Resolution::default());
    let general = GeneralRk4::new(&sys, &Resolution::default());
    let steps = (PERIODS * rk.steps_per_period()) as u64;
    let mut g = c.benchmark_group("written_model_steps");
    g.measurement_time(Duration::from_secs(4)).sample_size(20);
    g.throughput(Throughput::Elements(steps));
    g.bench_function("slack/built_in_1_lane", |b| {
        b.iter(|| run_lanes::<1>(&rk, isa::chosen(), black_box(0.01)))
    });
    g.bench_function("slack/written", |b| {
        b.iter(|| {
            let mut traj = general.start(&mut sys, &[black_box(p.lambda_p() - 0.005), 0.0]);
            for _ in 0..PERIODS {
                general.advance_period(&mut sys, &mut traj, |_, _, _| {});
            }
            traj.x[0]
        })
    });
    const L: usize = NATIVE_LANES;
    g.throughput(Throughput::Elements(L as u64 * steps));
    g.bench_function(format!("slack/written_{L}_lanes"), |b| {
        b.iter(|| {
            let mut eval = EquationLanes::<L>::new(&sys);
            let mut lanes = Lanes::<L>::idle(sys.origin());
            for l in 0..L {
                let mut x0 = *sys.origin();
                x0[0] = black_box(p.lambda_p() + 0.01 * (l as f64 / L as f64 - 0.5));
                x0[1] = 0.01 * l as f64 / L as f64;
                general.restart_lane(&mut sys, &mut lanes, l, &x0);
            }
            for _ in 0..PERIODS * general.steps_per_period() {
                general.advance_lanes(&mut sys, &mut eval, &mut lanes);
            }
            lanes.x[0][0]
        })
    });
    let built_in_16 = steps * 16;
    g.throughput(Throughput::Elements(built_in_16));
    g.bench_function("slack/built_in_16_lanes", |b| {
        b.iter(|| run_lanes::<16>(&rk, isa::chosen(), black_box(0.01)))
    });
    g.finish();
}

fn classify(c: &mut Criterion) {
    let p = Params::baseline();
    let spec = SteadyStateSpec::default();
    let mut g = c.benchmark_group("classify_orbit");
    g.measurement_time(Duration::from_secs(4)).sample_size(20);
    // two cells of the Fig 6A basin grid (ADR 0.6, ω_e 3.7): one goes to the 1:1 response,
    // one to the 1:2 isola
    g.bench_function("fig6a_cell_to_1_1", |b| {
        b.iter(|| steady_state(&p, black_box(p.lambda_p()), 0.0, &spec))
    });
    g.bench_function("fig6a_cell_to_1_2", |b| {
        b.iter(|| steady_state(&p, black_box(p.lambda_p() + 0.3), 0.0, &spec))
    });
    // the mean over a coarse 8 × 8 sample of the grid Δλ ∈ [−0.8, 0.8], v ∈ [−1, 1]
    let cells: Vec<(f64, f64)> = (0..64)
        .map(|i| {
            (
                -0.8 + 1.6 * (i / 8) as f64 / 7.0,
                -1.0 + 2.0 * (i % 8) as f64 / 7.0,
            )
        })
        .collect();
    g.throughput(Throughput::Elements(cells.len() as u64));
    g.bench_function("fig6a_grid_8x8", |b| {
        b.iter(|| {
            cells
                .iter()
                .map(|&(dx, v)| steady_state(&p, p.lambda_p() + dx, v, &spec).transient_periods)
                .sum::<usize>()
        })
    });
    // the same 64 cells in SIMD lanes (one core), integrated to full convergence
    let ics: Vec<[f64; 2]> = cells
        .iter()
        .map(|&(dx, v)| [p.lambda_p() + dx, v])
        .collect();
    let never = AtomicBool::new(false);
    g.bench_function("fig6a_grid_8x8_lanes", |b| {
        b.iter(|| steady_states(&p, &ics, &spec, None, &never, &mut |_| {}).unwrap())
    });
    g.finish();
}

criterion_group!(benches, rk4_steps, written_model_steps, classify);
criterion_main!(benches);
