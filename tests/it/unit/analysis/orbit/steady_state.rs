//! Unit tests of `analysis::orbit::steady_state` (`src/analysis/orbit/steady_state.rs`).

use isola::analysis::orbit::period_map::{OrbitRecord, PeriodMap};
use isola::analysis::orbit::steady_state::*;
use isola::solver::Collision;

/// A linear stroboscopic map P → P* + M(P − P*) (optionally cycling through several
/// fixed points), with a sine orbit recorded for the harmonic analysis.
struct LinearMap {
    centres: Vec<[f64; 2]>,
    m: [[f64; 2]; 2],
    dev: [f64; 2],
    n: usize,
}

impl PeriodMap for LinearMap {
    fn advance(&mut self) -> Result<[f64; 2], Collision> {
        let d = self.dev;
        self.dev = [
            self.m[0][0] * d[0] + self.m[0][1] * d[1],
            self.m[1][0] * d[0] + self.m[1][1] * d[1],
        ];
        self.n += 1;
        let c = self.centres[self.n % self.centres.len()];
        Ok([c[0] + self.dev[0], c[1] + self.dev[1]])
    }
    fn advance_recording(&mut self, rec: &mut OrbitRecord) -> Result<[f64; 2], Collision> {
        let k = self.centres.len() as f64;
        for j in 0..16 {
            let th = 2.0 * std::f64::consts::PI * (self.n as f64 + j as f64 / 16.0) / k;
            let x = 1.0 + 0.1 * th.cos();
            rec.samples.push(x);
            rec.lambda_min = rec.lambda_min.min(x);
            rec.lambda_max = rec.lambda_max.max(x);
        }
        self.advance()
    }
    fn samples_per_period(&self) -> usize {
        16
    }
}

fn spiral(mu: f64, angle: f64, centres: Vec<[f64; 2]>) -> LinearMap {
    let (s, c) = angle.sin_cos();
    LinearMap {
        centres,
        m: [[mu * c, -mu * s], [mu * s, mu * c]],
        dev: [0.3, 0.0],
        n: 0,
    }
}

/// A fixed point approached with multiplier −0.995: P_n and P_{n−2} agree long before
/// P_n and P_{n−1} do. The two-stage test must still call it period 1, not 1:2.
#[test]
fn slow_flip_transient_is_period_one() {
    let pi = std::f64::consts::PI;
    let s = steady_state_with(
        &mut spiral(0.995, pi, vec![[1.0, 0.0]]),
        &SteadyStateSpec::default(),
    );
    assert_eq!(s.class, Class::Periodic);
    assert_eq!(s.period, Some(1));
    // and a spiral with multipliers 0.995·e^{±2πi/3} is not a 1:3 response
    let s = steady_state_with(
        &mut spiral(0.995, 2.0 * pi / 3.0, vec![[1.0, 0.0]]),
        &SteadyStateSpec::default(),
    );
    assert_eq!(s.period, Some(1));
    // a one-stage test at the matching tolerance would have been fooled
    let naive = SteadyStateSpec {
        tol_converged: 0.99e-5,
        max_forcing_periods: 20_000,
        ..SteadyStateSpec::default()
    };
    let s = steady_state_with(&mut spiral(0.9995, pi, vec![[1.0, 0.0]]), &naive);
    assert_eq!(s.period, Some(2), "the pitfall this design avoids");
}

#[test]
fn true_cycles_get_their_period() {
    let cycle = vec![[1.0, 0.0], [1.2, 0.1], [0.9, -0.3]];
    let s = steady_state_with(&mut spiral(0.9, 0.3, cycle), &SteadyStateSpec::default());
    assert_eq!(s.period, Some(3));
    assert_eq!(s.poincare.len(), 3);
    assert_eq!(s.ratio.unwrap().to_string(), "1:3");
    assert_eq!(s.response_type(), "1:3 subharmonic");
    // period 9 > max_period 8: non-periodic
    let cycle: Vec<_> = (0..9).map(|i| [1.0 + 0.01 * i as f64, 0.0]).collect();
    let s = steady_state_with(&mut spiral(0.5, 0.0, cycle), &SteadyStateSpec::default());
    assert_eq!(s.class, Class::NonPeriodic);
    assert_eq!(s.period, None);
    assert_eq!(
        s.transient_periods,
        SteadyStateSpec::default().max_forcing_periods
    );
}

#[test]
fn bad_specs_name_the_field() {
    let bad = SteadyStateSpec {
        max_period: 0,
        ..SteadyStateSpec::default()
    };
    assert_eq!(bad.validate().unwrap_err().field, "max_period");
    let bad = SteadyStateSpec {
        tol_converged: 1e-3,
        ..SteadyStateSpec::default()
    };
    assert_eq!(bad.validate().unwrap_err().field, "tol_converged");
    assert!(SteadyStateSpec::default().validate().is_ok());
}
