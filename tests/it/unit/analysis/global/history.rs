//! Unit tests of `analysis::global::oscillator::history` (a written model's time history),
//! against the exact solution of a linear oscillator.

use std::sync::atomic::AtomicBool;

use isola::analysis::global::oscillator::history::{StateHistory, state_history};
use isola::analysis::orbit::time_history::TimeHistorySpec;
use isola::solver::Tolerance;

/// x'' + c x' + x = F cos(ωt), as a session writes it, with a collision condition.
fn linear(c: f64, omega: f64, collision: &str) -> isola::model::equations::EquationSystem {
    linear_with(c, omega, collision, "0")
}

/// The same with `zero`, an expression that is 0 wherever it is defined, added to the force.
pub fn linear_with(
    c: f64,
    omega: f64,
    collision: &str,
    zero: &str,
) -> isola::model::equations::EquationSystem {
    crate::common::written(&format!(
        r#"[model]
states = ["x", "v"]
frequency = "omega"
amplitude = "x"
collision = [{collision}]
[model.parameters]
omega = {{ value = {omega}, min = 0.01, max = 100.0 }}
[model.derivatives]
x = "v"
v = "0.5*cos(omega*t) - {c}*v - x + {zero}""#
    ))
}

/// The exact x(τ) of x'' + c x' + x = F cos(ωt) from (x0, v0) (c < 2).
pub fn exact(c: f64, f: f64, omega: f64, x0: f64, v0: f64) -> impl Fn(f64) -> [f64; 2] {
    let d = (1.0 - omega * omega).powi(2) + (c * omega).powi(2);
    let (a, b) = (f * (1.0 - omega * omega) / d, f * c * omega / d);
    let (zeta, wd) = (c / 2.0, (1.0 - c * c / 4.0).sqrt());
    let c1 = x0 - a;
    let c2 = (v0 - b * omega + zeta * c1) / wd;
    move |t| {
        let (e, (s, co)) = ((-zeta * t).exp(), (wd * t).sin_cos());
        let (sp, cp) = (omega * t).sin_cos();
        let x = e * (c1 * co + c2 * s) + a * cp + b * sp;
        let v = e * (-zeta * (c1 * co + c2 * s) + wd * (c2 * co - c1 * s)) - a * omega * sp
            + b * omega * cp;
        [x, v]
    }
}

/// The first τ at which `exact`'s x reaches `wall` from below: scanned in steps of 1e-3,
/// then bisected to round-off.
fn first_crossing(exact: &impl Fn(f64) -> [f64; 2], wall: f64) -> f64 {
    let dt = 1e-3;
    let mut lo = 0.0;
    while exact(lo + dt)[0] < wall {
        lo += dt;
    }
    let mut hi = lo + dt;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if exact(mid)[0] < wall {
            lo = mid
        } else {
            hi = mid
        }
    }
    hi
}

/// The largest error of a history's samples against `exact`.
fn largest_error(h: &StateHistory, exact: &impl Fn(f64) -> [f64; 2]) -> f64 {
    h.samples
        .iter()
        .flat_map(|s| {
            let e = exact(s.tau);
            [(s.state[0] - e[0]).abs(), (s.state[1] - e[1]).abs()]
        })
        .fold(0.0, f64::max)
}

/// The recorded orbit meets its tolerance: at the default (rtol 1e-10, atol 1e-12) and at
/// rtol 1e-12 (as `resolution = "rtol=1e-12"` sets it), against the exact solution over the
/// whole transient and steady part: 3.8e-12 and 1.0e-13 off. Before the tolerance was used, a
/// written model's history was RK4 at 256 steps per period whatever it said: 1.4e-9 off here,
/// at either setting.
#[test]
fn a_written_history_meets_its_tolerance_against_the_exact_solution() {
    let (c, omega) = (0.1, 1.4);
    let sys = linear(c, omega, "");
    let spec = TimeHistorySpec {
        dx0: 0.3,
        v0: -0.2,
        ..TimeHistorySpec::default()
    };
    let x = exact(c, 0.5, omega, 0.3, -0.2);
    let at_default = largest_error(
        &state_history(&sys, &spec, &AtomicBool::new(false)).unwrap(),
        &x,
    );
    let fine = TimeHistorySpec {
        tolerance: Tolerance {
            rtol: 1e-12,
            atol: 1e-14,
        },
        ..spec.clone()
    };
    let h = state_history(&sys, &fine, &AtomicBool::new(false)).unwrap();
    let at_fine = largest_error(&h, &x);
    // the orbit's size is about 0.5: a tolerance of 1e-10 relative is 5e-11 a period, and
    // the error carried over the decaying transient stays within it
    assert!(at_default < 5e-11, "{at_default:e}");
    assert!(at_fine < 1e-12, "{at_fine:e}");
    assert!(at_fine < at_default / 10.0, "{at_fine:e} {at_default:e}");
    // the whole transient and the steady periods, every sample
    let t_end = h.samples.last().unwrap().tau;
    assert!(t_end > 50.0 * 2.0 * std::f64::consts::PI / omega, "{t_end}");
    assert!(h.collision.is_none());
}

/// A collision ends the orbit and says so: the last sample is where the orbit meets the wall,
/// the exact crossing of x = 3 (resonance from rest, c = 0.1, ω = 1: x grows towards 5), the
/// condition is named, and the CSV's `collision` column is true on that row only.
#[test]
fn a_collision_ends_the_history_where_the_exact_orbit_crosses() {
    let sys = linear(0.1, 1.0, r#""x >= 3""#);
    let h = state_history(&sys, &TimeHistorySpec::default(), &AtomicBool::new(false)).unwrap();
    let collision = h.collision.as_ref().expect("a collision");
    assert_eq!(collision.condition, "model.collision[0] = `x >= 3`");
    let x = exact(0.1, 0.5, 1.0, 0.0, 0.0);
    let hi = first_crossing(&x, 3.0);
    // located within the step that met it (on its interpolant, whose error is about h⁴): at
    // the exact crossing to 1e-9 (4.7e-12 here; the step's end was 0.0029 past)
    let last = h.samples.last().unwrap();
    assert_eq!(last.tau, collision.tau);
    assert!(last.state[0] >= 3.0, "{last:?}");
    assert!(
        (collision.tau - hi).abs() < 1e-9 && (last.state[0] - 3.0).abs() < 1e-9,
        "met at {} against {hi}, x = {}",
        collision.tau,
        last.state[0]
    );
    // every earlier sample is on the exact orbit and short of the wall
    let before = &h.samples[..h.samples.len() - 1];
    assert!(before.iter().all(|s| s.state[0] < 3.0));
    assert!(
        largest_error(
            &StateHistory {
                samples: before.to_vec(),
                ..h.clone()
            },
            &x
        ) < 1e-9
    );
    let csv = isola::session::export::state_history_bytes(&h, [0, 1]).unwrap();
    let csv = String::from_utf8(csv).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert!(rows[0].ends_with(",steady,collision"), "{}", rows[0]);
    assert!(rows.last().unwrap().ends_with(",true"));
    assert!(
        rows[1..rows.len() - 1]
            .iter()
            .all(|r| r.ends_with(",false"))
    );
    // from a start already past the wall: one sample, the collision at τ = 0
    let past = TimeHistorySpec {
        dx0: 3.5,
        ..TimeHistorySpec::default()
    };
    let h = state_history(&sys, &past, &AtomicBool::new(false)).unwrap();
    assert_eq!(h.samples.len(), 1);
    assert_eq!(h.collision.map(|c| c.tau), Some(0.0));
}

/// A branch not taken is never taken, even by a stage that strays past its switch: the
/// orbit (resonance from rest, x growing to 5) crosses x = 2, where `sqrt(2 - x)` and
/// `ln(2 - x)` stop being defined on the branch before it; their terms are 0 wherever they
/// are, so the orbit is the linear oscillator's. Before a stage took the piece it is on, such
/// stages stopped the time history ("not finite at a stage of the step") once the steps were
/// fine enough to land one there.
#[test]
fn a_branch_not_taken_past_its_switch_leaves_the_orbit_exact() {
    for zero in [
        "if(x < 2, sqrt(2 - x) - sqrt(2 - x), 0)",
        "if(x >= 2 || ln(2 - x) > 0, x - x, 0)",
    ] {
        let sys = linear_with(0.1, 1.0, "", zero);
        // from rest, and from just short of the switch at speed: the first step's stages
        // land past it
        for (dx0, v0) in [(0.0, 0.0), (1.999, 5.0)] {
            let spec = TimeHistorySpec {
                dx0,
                v0,
                ..TimeHistorySpec::default()
            };
            let h = state_history(&sys, &spec, &AtomicBool::new(false)).unwrap();
            assert!(h.samples.iter().any(|s| s.state[0] > 4.0), "{zero}");
            let error = largest_error(&h, &exact(0.1, 0.5, 1.0, dx0, v0));
            assert!(error < 2e-10, "{zero} from ({dx0}, {v0}): {error:e}");
        }
    }
}

/// The same where the branch not taken matters: `- 0.01·if(x < 2, sqrt(2 - x), 0)` in the
/// force, F = 1, ω = 1.2, from the 3 × 3 starts of a response's grid. Each orbit crosses x = 2
/// and settles; before a stage took the piece it is on, one of them stopped in its
/// classification ("not finite at a stage of the step", from x = 1.99997). The classification
/// (RK4 at 64 steps a period) and the recording (within its tolerance) agree on the
/// amplitude to RK4's error at 64 steps.
#[test]
fn orbits_through_a_branch_not_taken_settle_from_every_start() {
    let sys = crate::common::written(
        r#"[model]
states = ["x", "v"]
frequency = "omega"
amplitude = "x"
[model.parameters]
omega = { value = 1.2, min = 0.01, max = 100.0 }
[model.let]
s = "if(x < 2, sqrt(2 - x), 0)"
[model.derivatives]
x = "v"
v = "cos(omega*t) - 0.1*v - x - 0.01*s""#,
    );
    for dx0 in [-1.0, 0.0, 1.0] {
        for v0 in [-1.0, 0.0, 1.0] {
            let spec = TimeHistorySpec {
                dx0,
                v0,
                ..TimeHistorySpec::default()
            };
            let h = state_history(&sys, &spec, &AtomicBool::new(false)).unwrap();
            let amplitude = h.steady_state.amplitude.expect("a periodic orbit");
            // the amplitude is the output's range, max − min
            let steady = || h.samples.iter().filter(|s| s.steady).map(|s| s.state[0]);
            let (min, max) = (
                steady().fold(f64::MAX, f64::min),
                steady().fold(f64::MIN, f64::max),
            );
            let recorded = max - min;
            assert!(max > 2.0, "({dx0}, {v0}): {max}");
            // the samples miss the extremes by O(dt²): 64 a period
            assert!(
                (recorded - amplitude).abs() < 2e-3 * amplitude,
                "({dx0}, {v0}): {recorded} against {amplitude}"
            );
        }
    }
}

/// Lanes and a lone trajectory of the same written model meet a wall where the exact orbit
/// does, located within the step (64 a period here, 0.098 long): τ within 3e-5 of the exact
/// crossing of x = 3 from four starts (RK4's own error after 20 time units at this step is
/// 9e-6 in τ; the step's end was up to 0.098 late), in each lane and in the scalar engine.
#[test]
fn a_collision_is_located_within_its_step_in_lanes_and_alone() {
    use isola::model::equations::lanes::EquationLanes;
    use isola::solver::general::{GeneralRk4, Stop};
    use isola::solver::general_lanes::Lanes;
    let mut sys = linear(0.1, 1.0, r#""x >= 3""#);
    let rk = GeneralRk4::with_steps(&sys, 64);
    let starts = [[0.0, 0.0], [0.5, 0.0], [0.0, 0.7], [-1.0, 0.3]];
    let crossing = |x0: [f64; 2]| first_crossing(&exact(0.1, 0.5, 1.0, x0[0], x0[1]), 3.0);
    let met = |stop: Option<&Stop>| match stop {
        Some(Stop::Collision { tau, state }) => (*tau, state[0]),
        other => panic!("no collision: {other:?}"),
    };
    let mut eval = EquationLanes::<4>::new(&sys);
    let mut lanes = Lanes::<4>::idle(sys.origin());
    for (l, x0) in starts.iter().enumerate() {
        let mut x = *sys.origin();
        x[..2].copy_from_slice(x0);
        rk.restart_lane(&mut sys, &mut lanes, l, &x);
    }
    for _ in 0..200 * 64 {
        rk.advance_lanes(&mut sys, &mut eval, &mut lanes);
    }
    for (l, x0) in starts.iter().enumerate() {
        let exact = crossing(*x0);
        let (tau, x) = met(lanes.stop(l));
        assert!(
            (tau - exact).abs() < 3e-5,
            "lane {l}: {tau} against {exact}"
        );
        assert!((x - 3.0).abs() < 1e-9 && x >= 3.0, "lane {l}: x = {x}");
        let mut traj = rk.start(&mut sys, x0);
        while traj.stop.is_none() {
            rk.advance_step(&mut sys, &mut traj);
        }
        let (alone, _) = met(traj.stop.as_ref());
        assert_eq!(alone, tau, "alone {l}");
    }
}

/// A recording stops when cancelled (seen at every sample), with no record.
#[test]
fn a_cancelled_recording_stops() {
    let sys = linear(0.1, 1.0, "");
    let cancel = AtomicBool::new(true);
    let h = state_history(&sys, &TimeHistorySpec::default(), &cancel);
    assert_eq!(h, Err(isola::analysis::AnalysisError::Cancelled));
}
