//! A model written from the input (three expressions: a named value `s` and the derivatives
//! of x and v) → parsed, compiled and run: any input must end in a value or an error, never
//! a panic, an abort or a hang, and wherever the host compiles to machine code, that code
//! must give the interpreter's values bit for bit (every tape, one lane and `NATIVE_LANES`,
//! each kink held or free), and the plain step compiled for `NATIVE_LANES` lanes (AVX2 code
//! where the processor has it) each lane's own compiled step; a few periods in lanes, each
//! lane's trajectory alone; a short chirp sweep.

#![no_main]

use std::sync::atomic::AtomicBool;

use libfuzzer_sys::fuzz_target;

use isola::analysis::global::oscillator::chirp::written_chirp_sweep;
use isola::analysis::orbit::chirp_sweep::ChirpSpec;
use isola::solver::Tolerance;

use isola::model::equations::lanes::{EquationLanes, LaneTimes};
use isola::model::equations::tape::{NATIVE_LANES, Tape};
use isola::model::equations::{EquationModel, EquationSystem, ModelDefinition};
use isola::model::system::{END_SWITCHES, MAX_DIM, System};
use isola::solver::general::GeneralRk4;
use isola::solver::general_lanes::Lanes;

/// The model around the three expressions.
fn session(s: &str, dx: &str, dv: &str) -> String {
    format!(
        r#"
[model]
states = ["x", "v"]
frequency = "w"
amplitude = "x"
collision = ["x > 1e6"]
[model.parameters]
w = 1.3
a = {{ value = 0.7, min = -10, max = 10 }}
[model.let]
s = {s:?}
[model.derivatives]
x = {dx:?}
v = {dv:?}
"#
    )
}

/// A pseudo-random sequence in [0, 1) from the input's bytes and `seed`.
fn uniform_from(data: &[u8], seed: u64) -> impl FnMut() -> f64 {
    let mut seed = data.iter().fold(seed, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
    });
    move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A state within `scale` of the origin, drawn from `uniform`.
fn state(uniform: &mut impl FnMut() -> f64, scale: f64) -> [f64; 2] {
    [
        scale * (2.0 * uniform() - 1.0),
        scale * (2.0 * uniform() - 1.0),
    ]
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let mut lines = text.splitn(3, '\n');
    let (s, dx) = (lines.next().unwrap_or("0"), lines.next().unwrap_or("v"));
    let dv = lines.next().unwrap_or("-x");
    let doc = session(s, dx, dv);
    let Ok(def) = ModelDefinition::from_text(&doc) else {
        return;
    };
    let Ok(model) = EquationModel::new(&def, &doc) else {
        return;
    };
    let Ok(mut sys) = model.system(&model.defaults()) else {
        return;
    };
    let c = &*model.inner;
    if Tape::native_enabled() {
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        // states and times from the input's bytes
        let mut uniform = uniform_from(data, 0x9e37_79b9_7f4a_7c15);
        for tape in c.tapes() {
            for round in 0..4 {
                let scale = if round == 3 { 1e3 } else { 3.0 };
                let mut regs = sys.registers().clone();
                let x = state(&mut uniform, scale);
                regs.load(&c.time_tape, 20.0 * uniform(), &x);
                let mode = (uniform() * u32::MAX as f64) as u64;
                let (mut native, mut interpreted) = (regs.values.clone(), regs.values.clone());
                assert_eq!(
                    tape.run_in(&mut native, mode),
                    tape.interpret::<false>(&mut interpreted, mode)
                );
                assert_eq!(
                    tape.run_free(&mut native),
                    tape.interpret::<true>(&mut interpreted, 0)
                );
                for &r in &tape.roots {
                    let (a, b) = (native[r as usize], interpreted[r as usize]);
                    assert!(same(a, b), "register {r}: {a:e} native, {b:e} interpreted");
                }
                let mut lanes = vec![[0.0; NATIVE_LANES]; regs.values.len()];
                for l in 0..NATIVE_LANES {
                    let x = state(&mut uniform, scale);
                    regs.load(&c.time_tape, 20.0 * uniform(), &x);
                    for (lane, &v) in lanes.iter_mut().zip(&regs.values) {
                        lane[l] = v;
                    }
                }
                let modes: [u64; NATIVE_LANES] =
                    std::array::from_fn(|l| mode.rotate_left(l as u32));
                let mut by_lane = lanes.clone();
                assert_eq!(
                    tape.run_lanes(&mut lanes, &modes),
                    tape.interpret_lanes::<NATIVE_LANES, false>(&mut by_lane, &modes)
                );
                assert_eq!(
                    tape.run_lanes_free(&mut lanes),
                    tape.interpret_lanes::<NATIVE_LANES, true>(&mut by_lane, &[0; NATIVE_LANES])
                );
                for &r in &tape.roots {
                    for (a, b) in lanes[r as usize].iter().zip(&by_lane[r as usize]) {
                        assert!(same(*a, *b), "lanes: {a:e} native, {b:e} interpreted");
                    }
                }
            }
        }
        // the system's own field and switching values (the one-lane codes it keeps)
        let mut own = sys.clone();
        for round in 0..4 {
            let scale = if round == 3 { 1e3 } else { 3.0 };
            let (xy, t) = (state(&mut uniform, scale), 20.0 * uniform());
            let mode = (uniform() * u32::MAX as f64) as u64;
            let mut regs = sys.registers().clone();
            regs.load(&c.time_tape, t, &xy);
            let want = c.field_tape.interpret::<false>(&mut regs.values, mode);
            let mut x = [0.0; MAX_DIM];
            x[..2].copy_from_slice(&xy);
            let mut dx = [0.0; MAX_DIM];
            assert_eq!(own.field(t, &x, mode, &mut dx), want);
            for (d, &id) in dx.iter().zip(&c.field_io.derivatives) {
                assert!(same(*d, regs.get(id)), "field: {d:e}");
            }
            let mut s = [0.0; 64];
            assert_eq!(own.switching(t, &x, mode, &mut s), want);
            for (got, switch) in s.iter().zip(&c.graph.switches) {
                assert!(same(*got, regs.get(switch.value)), "switching: {got:e}");
            }
        }
    }
    if Tape::native_enabled() {
        step_in_lanes(&mut sys, data);
    }
    // a short chirp (the model's frequency swept, its time read as the sweep's phase) where
    // the model's time is periodic: a record or an error, never a panic or a hang
    let chirp = ChirpSpec {
        omega_start: 0.5,
        omega_end: 2.0,
        span: 20.0,
        dt: 0.5,
        window: 5.0,
        tolerance: Tolerance {
            rtol: 1e-4,
            atol: 1e-6,
        },
        ..ChirpSpec::default()
    };
    let _ = written_chirp_sweep(&sys, &chirp, &AtomicBool::new(false), |_| {});
    // a few periods from a few starts: a value or a stop, never a panic or a hang; in lanes,
    // each lane's the trajectory's alone, bit for bit
    let rk = GeneralRk4::with_steps(&sys, 16);
    let starts = [[0.5, 0.0], [-2.0, 1.0], [30.0, -7.0], [0.05, 0.3]];
    let mut alone = Vec::new();
    for x0 in starts {
        let mut traj = rk.start(&mut sys, &x0);
        for _ in 0..3 {
            rk.advance_period(&mut sys, &mut traj, |_, _, _| {});
        }
        alone.push(traj);
    }
    let mut eval = EquationLanes::<NATIVE_LANES>::new(&sys);
    let mut lanes = Lanes::<NATIVE_LANES>::idle(&[0.0; MAX_DIM]);
    for (l, x0) in starts.iter().enumerate() {
        let mut x = [0.0; MAX_DIM];
        x[..2].copy_from_slice(x0);
        rk.restart_lane(&mut sys, &mut lanes, l, &x);
    }
    for _ in 0..3 * rk.steps_per_period() {
        rk.advance_lanes(&mut sys, &mut eval, &mut lanes);
    }
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
    for (l, traj) in alone.iter().enumerate() {
        assert_eq!(lanes.stop(l).is_some(), traj.stop.is_some(), "lane {l}");
        if traj.stop.is_none() {
            assert_eq!(lanes.mode[l], traj.mode, "lane {l}");
            for i in 0..2 {
                assert!(same(lanes.x[i][l], traj.x[i]), "lane {l}, state {i}");
            }
        }
    }
});

/// The plain step of `NATIVE_LANES` lanes from states and modes drawn from `data`, against
/// each lane's own compiled step, bit for bit.
fn step_in_lanes(sys: &mut EquationSystem, data: &[u8]) {
    const L: usize = NATIVE_LANES;
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
    let mut uniform = uniform_from(data, 0x2545_f491_4f6c_dd1d);
    let rk = GeneralRk4::with_steps(sys, 16);
    let n = rk.steps_per_period();
    sys.tabulate(n);
    let mut eval = EquationLanes::<L>::new(sys);
    for round in 0..2 {
        let scale = if round == 1 { 1e3 } else { 3.0 };
        let steps = (uniform() * n as f64) as u64;
        let (step, t) = (rk.grid_step(steps, steps as usize), rk.tau(steps));
        let (phase, times) = (step.phase, LaneTimes::<L>::of(&step));
        let (mut x, mut k1) = ([[0.0; L]; MAX_DIM], [[0.0; L]; MAX_DIM]);
        let mut modes = [0; L];
        for l in 0..L {
            let mut xl = [0.0; MAX_DIM];
            xl[..2].copy_from_slice(&state(&mut uniform, scale));
            modes[l] = (uniform() * u32::MAX as f64) as u64;
            let mut k = [0.0; MAX_DIM];
            sys.field(t, &xl, modes[l], &mut k);
            for i in 0..2 {
                (x[i][l], k1[i][l]) = (xl[i], k[i]);
            }
        }
        let (mut end, mut dx) = ([[0.0; L]; MAX_DIM], [[0.0; L]; MAX_DIM]);
        let mut switching = [[0.0; L]; END_SWITCHES];
        let Some((seen, hit, end_seen)) = eval.compiled_step(
            phase,
            n,
            &times,
            &x,
            &k1,
            &modes,
            &mut end,
            &mut dx,
            &mut switching,
        ) else {
            return;
        };
        for l in 0..L {
            let (xl, kl) = (
                std::array::from_fn(|i| x[i][l]),
                std::array::from_fn(|i| k1[i][l]),
            );
            let (mut end_l, mut dx_l) = ([0.0; MAX_DIM], [0.0; MAX_DIM]);
            let (seen_l, hit_l, at_end) = sys
                .compiled_step(&step, &xl, &kl, modes[l], &mut end_l, &mut dx_l)
                .expect("a compiled step");
            assert_eq!(
                (seen[l], hit[l], end_seen[l]),
                (seen_l, hit_l, at_end.seen),
                "lane {l}"
            );
            for i in 0..2 {
                assert!(
                    same(end[i][l], end_l[i]) && same(dx[i][l], dx_l[i]),
                    "lane {l}"
                );
            }
            let mut s = [0.0; END_SWITCHES];
            let seen_there = sys.switching(step.t_end, &end_l, modes[l], &mut s);
            assert_eq!(seen_there, at_end.seen, "lane {l}: seen at the end");
            for k in 0..END_SWITCHES {
                assert!(
                    same(switching[k][l], at_end.s[k]) && same(s[k], at_end.s[k]),
                    "lane {l}, switch {k}"
                );
            }
        }
    }
}
