//! The paper's global claims (MODEL.md §5) at E_a = 0.2², λ_p = 1.02, c̃ = 0.04, as the
//! analyses compute them, plus the properties of the job machinery: determinism whatever the
//! thread count, cancellation, progress.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use isola::analysis::global::basin::{Basin, BasinSpec, basin};
use isola::analysis::global::frequency_response::{
    FrequencyResponse, FrequencyResponseSpec, frequency_response,
};
use isola::analysis::grid::Axis;
use isola::analysis::orbit::chirp_sweep::{ChirpSpec, chirp_sweep};
use isola::analysis::orbit::scalogram::{ScalogramSpec, scalogram};
use isola::analysis::{Class, Progress};
use isola::jobs::{Job, JobError};
use isola::model::{DriveSpec, ParamSpec, Params};

fn on_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

fn response(adr: f64, omega: Axis) -> FrequencyResponse {
    let spec = FrequencyResponseSpec {
        omega,
        ..FrequencyResponseSpec::default()
    };
    frequency_response(&Params::paper(adr, 1.0).unwrap(), &spec, &Progress::new(0)).unwrap()
}

fn periodic_at(
    fr: &FrequencyResponse,
    omega: f64,
) -> Vec<&isola::analysis::global::frequency_response::Response> {
    let i = fr
        .omegas
        .iter()
        .position(|w| (w - omega).abs() < 1e-9)
        .unwrap();
    fr.at(i)
        .filter(|r| r.steady.class == Class::Periodic)
        .collect()
}

/// Fig 4 (ADR 0.6, ω_e 0.2–6 by 0.05, 15 × 15 initial states): two coexisting responses at the
/// super-harmonic and at the primary resonance; a 1:2 branch through ω_e = 3.7 that no sweep
/// reaches (hidden), more than ten times the 1:1 amplitude beside it.
#[test]
fn fig4_adr_0_6_has_a_hidden_subharmonic_isola() {
    let fr = response(0.6, Axis::new(0.2, 6.0, 117));
    // super-harmonic resonance: a 2:1 response coexisting with another near ω_e 1.2
    let coexisting_2_1 = fr
        .omegas
        .iter()
        .filter(|&&w| (1.1..1.45).contains(&w))
        .any(|&w| {
            let rs = periodic_at(&fr, w);
            rs.len() >= 2
                && rs
                    .iter()
                    .any(|r| r.steady.ratio.unwrap().to_string() == "2:1")
        });
    assert!(coexisting_2_1, "no coexisting super-harmonic responses");
    // primary resonance: a high and a low 1:1 response at ω_e 1.8
    let rs = periodic_at(&fr, 1.8);
    let amps: Vec<f64> = rs.iter().map(|r| r.steady.amplitude.unwrap()).collect();
    assert!(
        amps.iter().any(|&a| a > 0.4) && amps.iter().any(|&a| a < 0.05),
        "{amps:?}"
    );
    // the 1:2 isola
    let at_3_7 = periodic_at(&fr, 3.7);
    let sub = at_3_7
        .iter()
        .find(|r| r.steady.period == Some(2))
        .expect("1:2 at ω_e 3.7");
    let one = at_3_7
        .iter()
        .find(|r| r.steady.period == Some(1))
        .expect("1:1 at ω_e 3.7");
    assert!(sub.steady.amplitude.unwrap() > 10.0 * one.steady.amplitude.unwrap());
    assert_eq!(sub.hidden, Some(true));
    let branch = &fr.branches[sub.branch.unwrap()];
    assert!(
        branch.hidden,
        "every point of the isola is hidden: {branch:?}"
    );
    assert!(branch.omega_min <= 3.7 && branch.omega_max >= 3.7 && branch.points >= 10);
    assert_eq!(branch.ratio.to_string(), "1:2");
}

/// Fig 5 (ADR 1.0): the 1:2 branch is attached (a sweep reaches part of it), and a period-3
/// response (the paper's 1:3) appears near ω_e 3.6.
#[test]
fn fig5_adr_1_0_subharmonic_is_attached_and_a_period_3_response_appears() {
    let fr = response(1.0, Axis::new(3.0, 6.0, 61));
    let subs: Vec<_> = fr.branches.iter().filter(|b| b.period == 2).collect();
    assert!(!subs.is_empty());
    assert!(
        subs.iter().any(|b| !b.hidden),
        "some 1:2 response is reached by a sweep: {subs:?}"
    );
    let p3 = fr
        .responses
        .iter()
        .find(|r| r.steady.period == Some(3))
        .expect("a period-3 response");
    assert!((3.5..=3.75).contains(&p3.omega), "{}", p3.omega);
    assert_eq!(p3.steady.response_type(), "1:3 subharmonic");
}

/// Fig 12: at λ_p = 1.2, E_a = 0.3² no subharmonic response exists.
#[test]
fn fig12_no_subharmonic_at_higher_prestretch() {
    let p = ParamSpec {
        lambda_p: 1.2,
        drive: DriveSpec::EaAdr {
            e_a: 0.09,
            adr: 0.6,
        },
        ..ParamSpec::default()
    }
    .build()
    .unwrap();
    let spec = FrequencyResponseSpec {
        dx: Axis::new(-0.8, 0.8, 9),
        v: Axis::new(-1.0, 1.0, 9),
        ..FrequencyResponseSpec::default()
    };
    let fr = frequency_response(&p, &spec, &Progress::new(0)).unwrap();
    assert!(
        fr.responses
            .iter()
            .all(|r| r.steady.period.unwrap_or(1) == 1)
    );
}

fn small_basin(early_stop: bool, threads: usize) -> Basin {
    let spec = BasinSpec {
        dx: Axis::new(-0.8, 0.8, 41),
        v: Axis::new(-1.0, 1.0, 51),
        early_stop,
        ..BasinSpec::default()
    };
    on_pool(threads, || {
        basin(
            &Params::paper(0.6, 3.7).unwrap(),
            &spec,
            &Progress::new(0),
            &|_| {},
        )
        .unwrap()
    })
}

/// Fig 6A (ADR 0.6, ω_e 3.7) on a 41 × 51 grid: the 1:1 basin is the largest, the 1:2 basin
/// sizeable, and it spirals: along the line v = 0 the label changes many times.
#[test]
fn fig6a_basin_1_1_largest_1_2_spiral() {
    let b = small_basin(true, 2);
    let find = |k: usize| {
        b.table
            .attractors
            .iter()
            .find(|a| a.response.period == Some(k))
            .unwrap()
    };
    let (one, two) = (find(1), find(2));
    assert!(b.fraction(one.id) > 0.6, "{}", b.fraction(one.id));
    assert!(b.fraction(two.id) > 0.1, "{}", b.fraction(two.id));
    // the spiral: count label changes along v = 0 (middle column)
    let nv = b.v.len();
    let along: Vec<usize> = (0..b.dx.len()).map(|i| b.labels[i * nv + nv / 2]).collect();
    let changes = along.windows(2).filter(|w| w[0] != w[1]).count();
    assert!(changes >= 4, "{along:?}");
}

/// The early stop gives the plain method's classes and amplitudes (1e-4), and the labels do
/// not depend on the number of threads.
#[test]
fn basin_early_stop_and_threads_do_not_change_results() {
    let plain = small_basin(false, 2);
    let fast = small_basin(true, 2);
    let fast_1 = small_basin(true, 1);
    assert_eq!(fast.labels, fast_1.labels);
    assert_eq!(fast.table, fast_1.table);
    for (c, (&a, &b)) in plain.labels.iter().zip(&fast.labels).enumerate() {
        let (ra, rb) = (
            &plain.table.attractors[a].response,
            &fast.table.attractors[b].response,
        );
        assert_eq!(
            (ra.class, ra.period, ra.ratio),
            (rb.class, rb.period, rb.ratio),
            "cell {c}"
        );
        match (ra.amplitude, rb.amplitude) {
            (Some(x), Some(y)) => assert!((x - y).abs() < 1e-4, "cell {c}: {x} vs {y}"),
            (x, y) => assert_eq!(x.is_some(), y.is_some(), "cell {c}"),
        }
    }
}

/// A grid of at most 12 × 12 cells is every cell of the early stop's seed sub-grid: it is
/// integrated in full, so early stop or not it is the same basin, bit for bit, with each
/// class the grid holds (1:1, 1:2 and a collision at Fig 6A's point).
#[test]
fn a_basin_as_small_as_its_seed_grid_is_integrated_in_full() {
    let at = |early_stop: bool, points: (usize, usize)| {
        let spec = BasinSpec {
            dx: Axis::new(-0.8, 0.8, points.0),
            v: Axis::new(-1.0, 1.0, points.1),
            early_stop,
            ..BasinSpec::default()
        };
        let p = Params::paper(0.6, 3.7).unwrap();
        basin(&p, &spec, &Progress::new(0), &|_| {}).unwrap()
    };
    for points in [(3, 3), (12, 5)] {
        let (plain, fast) = (at(false, points), at(true, points));
        assert_eq!(plain, fast, "{points:?}");
        let types: std::collections::BTreeSet<String> = plain
            .table
            .attractors
            .iter()
            .map(|a| a.response.response_type())
            .collect();
        assert_eq!(types.len(), 3, "{points:?}: {types:?}");
    }
}

/// Offline check of the full Fig 6A basin (201 × 251, about 30 s of CPU: run with
/// `cargo test --test it global_analyses:: -- --ignored`): the early stop gives every cell
/// the plain method's class, period and ratio, and its amplitude within 1e-4.
#[test]
#[ignore]
fn fig6a_full_basin_early_stop_equals_plain() {
    full_basin_early_stop_equals_plain(0.6, 3.7);
}

/// The same for Fig 6B (ADR 1.0, ω 3.6: 1:1, 1:2 and a period-3 response, whose saddle's
/// stable manifold runs close to its node).
#[test]
#[ignore]
fn fig6b_full_basin_early_stop_equals_plain() {
    full_basin_early_stop_equals_plain(1.0, 3.6);
}

fn full_basin_early_stop_equals_plain(adr: f64, omega: f64) {
    use isola::analysis::global::basin::BasinPlan;
    use rayon::prelude::*;
    let p = Params::paper(adr, omega).unwrap();
    let outcomes = |early_stop: bool| {
        let spec = BasinSpec {
            early_stop,
            ..BasinSpec::default()
        };
        let progress = Progress::new(0);
        let plan = BasinPlan::new(&p, &spec, &progress).unwrap();
        (0..plan.chunks())
            .into_par_iter()
            .map(|n| plan.chunk(n, &progress).unwrap())
            .collect::<Vec<_>>()
            .concat()
    };
    let (plain, fast) = (outcomes(false), outcomes(true));
    assert_eq!(plain.len(), 201 * 251);
    let mut worst = 0.0f64;
    let differing: Vec<usize> = plain
        .iter()
        .zip(&fast)
        .enumerate()
        .filter(|(_, (a, b))| (a.class, a.period, a.ratio) != (b.class, b.period, b.ratio))
        .map(|(c, _)| c)
        .collect();
    for (a, b) in plain.iter().zip(&fast) {
        if let (Some(x), Some(y)) = (a.amplitude, b.amplitude) {
            worst = worst.max((x - y).abs());
        }
    }
    eprintln!(
        "{} cells differ in class, period or ratio; largest amplitude difference {worst:e}",
        differing.len()
    );
    assert!(
        differing.is_empty(),
        "first differing cells: {:?}",
        &differing[..differing.len().min(10)]
    );
    assert!(worst < 1e-4, "{worst}");
}

/// The frequency response over `omega` at `adr` from `dx` × `v` starts without sweeps, with
/// the early stop and with every start integrated to full convergence (fast, plain).
fn response_fast_and_plain(
    adr: f64,
    omega: Axis,
    grid: usize,
) -> (FrequencyResponse, FrequencyResponse) {
    let spec = FrequencyResponseSpec {
        omega,
        dx: Axis::new(-0.8, 0.8, grid),
        v: Axis::new(-1.0, 1.0, grid),
        sweeps: false,
        ..FrequencyResponseSpec::default()
    };
    let plain_spec = FrequencyResponseSpec {
        early_stop: false,
        ..spec.clone()
    };
    let p = Params::paper(adr, 1.0).unwrap();
    let fast = frequency_response(&p, &spec, &Progress::new(0)).unwrap();
    let plain = frequency_response(&p, &plain_spec, &Progress::new(0)).unwrap();
    (fast, plain)
}

/// `fast` has `plain`'s responses in the same order (ω_e, class, period, ratio, starts
/// reaching it, seeded or not), with a subharmonic among them, and amplitudes within `tol`.
fn assert_same_responses(plain: &FrequencyResponse, fast: &FrequencyResponse, tol: f64) {
    let key = |r: &isola::analysis::global::frequency_response::Response| {
        let s = &r.steady;
        (r.omega_index, s.class, s.period, s.ratio, r.count, r.seeded)
    };
    let keys = |fr: &FrequencyResponse| fr.responses.iter().map(key).collect::<Vec<_>>();
    assert_eq!(keys(plain), keys(fast));
    assert!(
        plain.responses.iter().any(|r| r.steady.period == Some(2)),
        "a subharmonic in the range"
    );
    for (a, b) in plain.responses.iter().zip(&fast.responses) {
        match (a.steady.amplitude, b.steady.amplitude) {
            (Some(x), Some(y)) => assert!((x - y).abs() < tol, "ω {}: {x} vs {y}", a.omega),
            (x, y) => assert_eq!(x.is_some(), y.is_some(), "ω {}", a.omega),
        }
    }
}

/// The early stop changes no result of a frequency response either: across the 1:2 isola at
/// ADR 0.6 (ω_e 3.5–3.9, 9 × 9 starts, neighbour seeding), every ω_e has the same responses in
/// the same order (class, period, ratio, starts reaching it, seeded or not) as integrating
/// every start to full convergence, with amplitudes within 1e-4.
#[test]
fn response_early_stop_keeps_every_response() {
    let (fast, plain) = response_fast_and_plain(0.6, Axis::new(3.5, 3.9, 5), 9);
    assert_same_responses(&plain, &fast, 1e-4);
}

/// The map's grids (7 × 7 starts, ω_e 1–6) are where the early stop learns most responses
/// from the cycles Newton's method finds ahead of a settling trajectory: over ADR 0.3 and 1.0
/// every ω_e still has the same responses in the same order (class, period, ratio, starts,
/// seeded or not) as integrating every start to full convergence, amplitudes within 1e-6
/// (the cycle's point is the fixed point of the same integrator's map; a trajectory stops
/// within 1e-9 of it).
#[test]
fn map_grids_early_stop_keeps_every_response() {
    for adr in [0.3, 1.0] {
        let (fast, plain) = response_fast_and_plain(adr, Axis::new(1.0, 6.0, 21), 7);
        assert_same_responses(&plain, &fast, 1e-6);
    }
}

/// Newton's method on the integrator's k-period map, from a point 0.02 off a response's
/// Poincaré point, finds the point the trajectory itself converges to (within 1e-8: the
/// trajectory stops once it repeats to 1e-9), which the map fixes to 1e-11: the 1:1 and the
/// 1:2 responses of Fig 6A. A start that meets the frame finds nothing.
#[test]
fn the_cycle_found_ahead_is_the_one_a_trajectory_converges_to() {
    use isola::analysis::global::cycle::attracting_cycle_near;
    use isola::analysis::global::flow::Flow;
    use isola::analysis::orbit::steady_state::{SteadyStateSpec, steady_state};
    use isola::solver::{Resolution, Rk4};
    let p = Params::paper(0.6, 3.7).unwrap();
    let spec = SteadyStateSpec::default();
    let flow = Flow::BuiltIn(Box::new(Rk4::new(&p, &Resolution::default())));
    for (dx, period) in [(0.0, 1), (0.3, 2)] {
        let s = steady_state(&p, p.lambda_p() + dx, 0.0, &spec);
        assert_eq!(s.period, Some(period));
        let q = s.poincare[0];
        let found = attracting_cycle_near(&flow, [q[0] + 0.02, q[1] - 0.02], period)
            .expect("an attracting cycle");
        let off = (found[0] - q[0]).abs().max((found[1] - q[1]).abs());
        assert!(
            off < 1e-8,
            "period {period}: {off:e} from the trajectory's point"
        );
        let image = flow.iterate(&[Some(found)], period)[0].unwrap();
        let moved = (image[0] - found[0]).abs().max((image[1] - found[1]).abs());
        assert!(moved < 1e-11, "period {period}: the map moves it {moved:e}");
    }
    assert_eq!(attracting_cycle_near(&flow, [0.05, -3.0], 1), None);
}

/// A running basin stops within 0.5 s of a cancel; a finished one reports done = total once.
#[test]
fn basin_job_cancels_quickly_and_counts_to_total() {
    let p = Params::paper(0.6, 3.7).unwrap();
    let job = Job::<Basin>::spawn(2, move |ctx| {
        basin(&p, &BasinSpec::default(), &ctx.progress, &|_| {})
            .map_err(|e| JobError::Failed(e.to_string()))
    })
    .unwrap();
    let progress = Arc::clone(&job.progress);
    while progress.get().0 < 100 {
        std::thread::sleep(Duration::from_millis(5));
    }
    let asked = Instant::now();
    job.cancel();
    let result = job.join();
    assert!(
        asked.elapsed() < Duration::from_millis(500),
        "{:?}",
        asked.elapsed()
    );
    assert!(result.is_err());

    let spec = BasinSpec {
        dx: Axis::new(-0.8, 0.8, 11),
        v: Axis::new(-1.0, 1.0, 13),
        ..BasinSpec::default()
    };
    let progress = Progress::new(0);
    basin(&p, &spec, &progress, &|_| {}).unwrap();
    assert_eq!(progress.get(), (143, 143));
}

/// Fig 3: the backward chirp rides the high primary branch where the forward one stays low;
/// at ADR 0.6 the forward sweep's scalogram never shows the 1:2 line (the isola is hidden),
/// at ADR 1.0 it does (ω_r/ω_e = 1/2 above ω_e ≈ 5).
#[test]
fn fig3_sweeps_and_scalograms() {
    let never = AtomicBool::new(false);
    let p = Params::paper(0.6, 1.0).unwrap();
    let forward = chirp_sweep(&p, &ChirpSpec::default(), &never, |_| {}).unwrap();
    let back_spec = ChirpSpec {
        omega_start: 6.0,
        omega_end: 0.0,
        ..ChirpSpec::default()
    };
    let backward = chirp_sweep(&p, &back_spec, &never, |_| {}).unwrap();
    let peak_near = |s: &isola::analysis::orbit::chirp_sweep::ChirpSweep, lo: f64, hi: f64| {
        s.envelope
            .iter()
            .filter(|e| e[1] > lo && e[1] < hi)
            .map(|e| e[2])
            .fold(0.0, f64::max)
    };
    assert!(
        peak_near(&backward, 1.8, 1.9) > 0.4,
        "{}",
        peak_near(&backward, 1.8, 1.9)
    );
    assert!(peak_near(&forward, 1.8, 1.9) < 0.05);
    // ω_r/ω_e at the columns where the sweep's ω_e, as it recorded it, is within [lo, hi)
    let ratio_range = |s: &isola::analysis::orbit::chirp_sweep::ChirpSweep, lo: f64, hi: f64| {
        let sc = scalogram(&s.lambda, s.dt, &ScalogramSpec::default()).unwrap();
        sc.forcing(&s.omega)
            .into_iter()
            .zip(&sc.ridge)
            .filter(|(w, _)| (lo..hi).contains(w))
            .map(|(w, r)| r / w)
            .collect::<Vec<f64>>()
    };
    let ratios = ratio_range(&forward, 3.0, 5.0);
    assert!(ratios.len() > 100, "{}", ratios.len());
    assert!(ratios.iter().all(|r| (r - 1.0).abs() < 0.1), "{ratios:?}");
    let forward_1 = chirp_sweep(
        &Params::paper(1.0, 1.0).unwrap(),
        &ChirpSpec::default(),
        &never,
        |_| {},
    )
    .unwrap();
    assert!(
        ratio_range(&forward_1, 5.1, 5.4)
            .iter()
            .any(|r| (r - 0.5).abs() < 0.05)
    );
}

/// The frequency response does not depend on the number of threads either.
#[test]
fn frequency_response_is_the_same_on_one_or_two_threads() {
    let spec = FrequencyResponseSpec {
        omega: Axis::new(3.4, 3.9, 6),
        dx: Axis::new(-0.8, 0.8, 7),
        v: Axis::new(-1.0, 1.0, 7),
        ..FrequencyResponseSpec::default()
    };
    let p = Params::paper(0.6, 1.0).unwrap();
    let one = on_pool(1, || {
        frequency_response(&p, &spec, &Progress::new(0)).unwrap()
    });
    let two = on_pool(2, || {
        frequency_response(&p, &spec, &Progress::new(0)).unwrap()
    });
    assert_eq!(one, two);
}

/// The 1:2 branches of a response over ω_e 3.4–5.6 by 0.05 at ADR 0.6 from `grid` × `grid`
/// starts, without seeding (so a coarse grid misses the response at some ω_e): each as
/// (ω_min, ω_max, points).
fn subharmonic_branches(adr: f64, grid: usize, omega: Axis) -> Vec<(f64, f64, usize)> {
    let spec = FrequencyResponseSpec {
        omega,
        dx: Axis::new(-0.8, 0.8, grid),
        v: Axis::new(-1.0, 1.0, grid),
        seed_neighbours: false,
        sweeps: false,
        ..FrequencyResponseSpec::default()
    };
    let fr =
        frequency_response(&Params::paper(adr, 1.0).unwrap(), &spec, &Progress::new(0)).unwrap();
    fr.branches
        .iter()
        .filter(|b| b.period == 2)
        .map(|b| (b.omega_min, b.omega_max, b.points))
        .collect()
}

/// A branch that a coarse grid of starts misses at one ω_e is one branch across the gap:
/// from 4 × 4 starts the 1:2 response at ADR 0.6 is missed at ω_e 3.65 only, and its two
/// pieces (3.60 alone, 3.70–5.40) are joined into the branch 3.60–5.40 that 5 × 5 starts
/// find whole (36 responses and the gap). From 3 × 3 starts it is missed at 3.65, 3.75,
/// 4.75 and 4.80: the one-step gaps are joined (3.60–4.70), the two-step gap is not.
#[test]
fn a_branch_missed_at_one_omega_is_joined_across_the_gap() {
    let omega = || Axis::new(3.4, 5.6, 45);
    let close = |got: &[(f64, f64, usize)], want: &[(f64, f64, usize)]| {
        got.len() == want.len()
            && got
                .iter()
                .zip(want)
                .all(|(g, w)| (g.0 - w.0).abs() < 1e-9 && (g.1 - w.1).abs() < 1e-9 && g.2 == w.2)
    };
    let whole = subharmonic_branches(0.6, 5, omega());
    assert!(close(&whole, &[(3.6, 5.4, 37)]), "{whole:?}");
    let four = subharmonic_branches(0.6, 4, omega());
    assert!(close(&four, &[(3.6, 5.4, 36)]), "{four:?}");
    let three = subharmonic_branches(0.6, 3, omega());
    assert!(
        close(&three, &[(3.6, 4.7, 21), (4.85, 5.4, 12)]),
        "{three:?}"
    );
}

/// Branches that coexist are never joined: at ADR 1.0 the 1:1 response loses stability near
/// ω_e 4.93 and a small 1:2 response (amplitude 0.014) lives beside the large 1:2 branch
/// (0.066) at ω_e 4.95 only; it stays a branch of its own, and the 1:1 branch ends at 4.90.
#[test]
fn coexisting_branches_of_one_type_are_not_joined() {
    let spec = FrequencyResponseSpec {
        omega: Axis::new(4.8, 5.1, 7),
        ..FrequencyResponseSpec::default()
    };
    let fr =
        frequency_response(&Params::paper(1.0, 1.0).unwrap(), &spec, &Progress::new(0)).unwrap();
    let subharmonic: Vec<(f64, f64, f64)> = fr
        .branches
        .iter()
        .filter(|b| b.period == 2)
        .map(|b| (b.omega_min, b.omega_max, b.peak_amplitude))
        .collect();
    assert_eq!(subharmonic.len(), 2, "{subharmonic:?}");
    let small = subharmonic.iter().find(|b| b.2 < 0.03).unwrap();
    assert!(
        (small.0 - 4.95).abs() < 1e-9 && (small.1 - 4.95).abs() < 1e-9,
        "{small:?}"
    );
    let large = subharmonic.iter().find(|b| b.2 > 0.03).unwrap();
    assert!(
        (large.0 - 4.8).abs() < 1e-9 && (large.1 - 5.1).abs() < 1e-9,
        "{large:?}"
    );
}
