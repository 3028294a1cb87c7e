//! Unit tests of `solver::rk4` (`src/solver/rk4.rs`).

use isola::model::Params;
use isola::solver::field::Mode;
use isola::solver::isa::Isa;
use isola::solver::resolution::Resolution;
use isola::solver::rk4::*;

/// Batching never changes a trajectory: each lane of a batch ends bit for bit where the
/// same state run alone ends, including next to a lane that collides and is frozen.
#[test]
fn lanes_are_independent_and_bitwise_reproducible() {
    let p = Params::baseline();
    let rk = Rk4::new(&p, &Resolution::default());
    let x0 = [1.02, 1.32, 1.02 + 0.8, 0.7];
    let v0 = [0.0, 0.0, 3.0, -0.5];
    let mut batch = rk.start(x0, v0);
    for _ in 0..50 {
        rk.advance_period(&mut batch, None);
    }
    assert!(
        batch.collision[2].is_some(),
        "lane 2 is thrown into the frame"
    );
    for i in [0, 1, 3] {
        let mut one = rk.start([x0[i]], [v0[i]]);
        for _ in 0..50 {
            rk.advance_period(&mut one, None);
        }
        assert!(one.collision[0].is_none());
        assert_eq!(one.x[0].to_bits(), batch.x[i].to_bits(), "lane {i}");
        assert_eq!(one.v[0].to_bits(), batch.v[i].to_bits(), "lane {i}");
    }
}

/// Lanes that switch in the same step are split side by side: each still ends bit for bit
/// where it ends alone (64 lanes over the Fig 6A window, slack twice a period).
#[test]
fn lanes_split_side_by_side_end_as_alone() {
    let p = Params::baseline();
    let rk = Rk4::new(&p, &Resolution::default());
    let x0: [f64; 64] = std::array::from_fn(|i| 1.02 - 0.8 + 1.6 * (i % 8) as f64 / 7.0);
    let v0: [f64; 64] = std::array::from_fn(|i| -1.0 + 2.0 * (i / 8) as f64 / 7.0);
    let mut lanes = rk.start(x0, v0);
    let mut mode = [Mode::default(); 64];
    let mut steps_with_several = 0;
    for _ in 0..30 {
        rk.advance_period(
            &mut lanes,
            Some(&mut |k, _, end| {
                let (phi_i, phi_ii) = rk.table().at(2 * k + 2);
                let mut switched = 0;
                for (i, mode) in mode.iter_mut().enumerate() {
                    let (_, m) = rk.field().accel(end.x[i], end.v[i], phi_i, phi_ii);
                    switched += usize::from(m != *mode);
                    *mode = m;
                }
                steps_with_several += usize::from(switched >= 2);
            }),
        );
    }
    assert!(
        steps_with_several > 300,
        "several lanes switch in the same step ({steps_with_several} steps)"
    );
    for i in 0..64 {
        let mut one = rk.start([x0[i]], [v0[i]]);
        for _ in 0..30 {
            rk.advance_period(&mut one, None);
        }
        assert_eq!(one.collision[0].is_some(), lanes.collision[i].is_some());
        assert_eq!(one.x[0].to_bits(), lanes.x[i].to_bits(), "lane {i}");
        assert_eq!(one.v[0].to_bits(), lanes.v[i].to_bits(), "lane {i}");
    }
}

/// Lanes moved to narrower lanes go on bit for bit as they would have.
#[test]
fn narrowed_lanes_go_on_as_before() {
    let p = Params::baseline();
    let rk = Rk4::new(&p, &Resolution::default());
    let x0: [f64; 32] = std::array::from_fn(|i| 0.5 + 1.2 * i as f64 / 31.0);
    let v0: [f64; 32] = std::array::from_fn(|i| 0.3 - 0.02 * i as f64);
    let mut wide = rk.start(x0, v0);
    for _ in 0..10 {
        rk.advance_period(&mut wide, None);
    }
    let picks = [3, 17, 30];
    let mut narrow = rk.narrowed::<32, 16>(&wide, &picks);
    for _ in 0..10 {
        rk.advance_period(&mut wide, None);
        rk.advance_period(&mut narrow, None);
    }
    assert_eq!(narrow.period, wide.period);
    for (j, &i) in picks.iter().enumerate() {
        assert_eq!(narrow.x[j].to_bits(), wide.x[i].to_bits(), "lane {i}");
        assert_eq!(narrow.v[j].to_bits(), wide.v[i].to_bits(), "lane {i}");
        assert_eq!(narrow.collision[j], wide.collision[i], "lane {i}");
    }
    assert!(
        narrow.collision[3..].iter().all(Option::is_some),
        "the rest parked"
    );
}

/// Every instruction set computes the same bits, on orbits that switch between taut and
/// slack (split steps) and in a lane that collides.
#[test]
fn every_instruction_set_computes_the_same_bits() {
    let p = Params::baseline();
    let rk = Rk4::new(&p, &Resolution::default());
    let x0 = [1.02, 1.32, 1.02 + 0.8, 0.7, 1.1, 1.5, 0.9, 1.25];
    let v0 = [0.0, 0.0, 3.0, -0.5, 0.2, -0.1, 0.05, 0.0];
    let run = |isa: Isa| {
        let mut lanes = rk.start(x0, v0);
        let (mut switches, mut mode) = (0, [Mode::default(); 8]);
        for _ in 0..60 {
            rk.advance_period_in(
                isa,
                &mut lanes,
                Some(&mut |k, _, end| {
                    let (phi_i, phi_ii) = rk.table().at(2 * k + 2);
                    for (i, mode) in mode.iter_mut().enumerate() {
                        let (_, m) = rk.field().accel(end.x[i], end.v[i], phi_i, phi_ii);
                        switches += usize::from(m != *mode);
                        *mode = m;
                    }
                }),
            );
        }
        (lanes, switches)
    };
    let (reference, switches) = run(Isa::Baseline);
    assert!(switches > 200, "the orbits switch ({switches} switches)");
    assert!(reference.collision[2].is_some());
    let available: Vec<Isa> = Isa::ALL.into_iter().filter(|isa| isa.available()).collect();
    for isa in &available[1..] {
        let (lanes, _) = run(*isa);
        for i in 0..8 {
            assert_eq!(
                lanes.x[i].to_bits(),
                reference.x[i].to_bits(),
                "{isa:?} lane {i}"
            );
            assert_eq!(
                lanes.v[i].to_bits(),
                reference.v[i].to_bits(),
                "{isa:?} lane {i}"
            );
            assert_eq!(
                lanes.collision[i], reference.collision[i],
                "{isa:?} lane {i}"
            );
        }
    }
    eprintln!("compared {available:?}");
}

/// A start outside the model is a collision at τ = 0, not a NaN.
#[test]
fn start_outside_the_model_is_a_collision() {
    let rk = Rk4::new(&Params::baseline(), &Resolution::default());
    let lanes = rk.start([-0.1, f64::NAN], [0.0, 0.0]);
    assert_eq!(lanes.collision[0].unwrap().tau, 0.0);
    assert!(lanes.collision[1].is_some());
    assert!(!lanes.any_alive());
}
