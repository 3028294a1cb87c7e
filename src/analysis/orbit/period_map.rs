//! The stroboscopic (Poincaré) map: advance one trajectory by whole forcing periods, with
//! either integrator, optionally recording the orbit on the way.

use crate::model::Params;
use crate::solver::{Collision, DenseStep, Dopri5, Lanes, Resolution, Rk4, State, Tolerance};

/// What is recorded of an orbit while it is followed: extremes of λ_I refined between
/// samples, its time integral, and uniform samples for the harmonic analysis.
#[derive(Debug, Clone, Default)]
pub struct OrbitRecord {
    pub lambda_min: f64,
    pub lambda_max: f64,
    integral: f64,
    duration: f64,
    /// λ_I at uniformly spaced times, `samples_per_period` per forcing period.
    pub samples: Vec<f64>,
    pub samples_per_period: usize,
}

impl OrbitRecord {
    pub fn new(samples_per_period: usize) -> Self {
        OrbitRecord {
            lambda_min: f64::INFINITY,
            lambda_max: f64::NEG_INFINITY,
            samples_per_period,
            ..Default::default()
        }
    }

    /// Adds one fixed step of length `h` from (x0, v0) to (x1, v1): the end sample, an
    /// extremum inside the step from its cubic Hermite interpolant, and the exact integral of
    /// that interpolant.
    pub fn add_step(&mut self, x0: f64, v0: f64, x1: f64, v1: f64, h: f64) {
        self.include(x1);
        if let Some((_, peak)) = crate::solver::hermite::interior_extremum(x0, v0, x1, v1, h) {
            self.include(peak);
        }
        self.integral += h * 0.5 * (x0 + x1) + h * h * (v0 - v1) / 12.0;
        self.duration += h;
        self.samples.push(x1);
    }

    fn include(&mut self, lambda: f64) {
        self.lambda_min = self.lambda_min.min(lambda);
        self.lambda_max = self.lambda_max.max(lambda);
    }

    /// Time average of λ_I over the recorded span.
    pub fn lambda_mean(&self) -> f64 {
        self.integral / self.duration
    }

    /// max − min of λ_I over the recorded span.
    pub fn amplitude(&self) -> f64 {
        self.lambda_max - self.lambda_min
    }
}

/// A stroboscopic map τ → τ + T for one trajectory.
pub trait PeriodMap {
    /// Advances one forcing period and returns the stroboscopic point [λ_I, v].
    fn advance(&mut self) -> Result<[f64; 2], Collision>;
    /// The same, recording the orbit into `record`.
    fn advance_recording(&mut self, record: &mut OrbitRecord) -> Result<[f64; 2], Collision>;
    /// Samples per period this map records.
    fn samples_per_period(&self) -> usize;
}

/// The fast map: fixed-step RK4 on one lane.
pub struct Rk4PeriodMap {
    rk4: Rk4,
    lanes: Lanes<1>,
}

impl Rk4PeriodMap {
    pub fn new(params: &Params, resolution: &Resolution, x0: f64, v0: f64) -> Self {
        let rk4 = Rk4::new(params, resolution);
        let lanes = rk4.start([x0], [v0]);
        Rk4PeriodMap { rk4, lanes }
    }

    fn point(&self) -> Result<[f64; 2], Collision> {
        match self.lanes.collision[0] {
            Some(c) => Err(c),
            None => Ok([self.lanes.x[0], self.lanes.v[0]]),
        }
    }
}

impl PeriodMap for Rk4PeriodMap {
    fn advance(&mut self) -> Result<[f64; 2], Collision> {
        self.point()?;
        self.rk4.advance_period(&mut self.lanes, None);
        self.point()
    }

    fn advance_recording(&mut self, rec: &mut OrbitRecord) -> Result<[f64; 2], Collision> {
        self.point()?;
        let h = self.rk4.step();
        self.rk4.advance_period(
            &mut self.lanes,
            Some(&mut |_, b, e| {
                rec.add_step(b.x[0], b.v[0], e.x[0], e.v[0], h);
            }),
        );
        self.point()
    }

    fn samples_per_period(&self) -> usize {
        self.rk4.steps_per_period()
    }
}

/// The accurate map: adaptive Dormand–Prince with located switches.
pub struct DopriPeriodMap {
    dopri: Dopri5,
    state: State,
    period: f64,
    periods_done: u64,
    samples_per_period: usize,
}

impl DopriPeriodMap {
    pub fn new(params: &Params, tol: Tolerance, x0: f64, v0: f64) -> Self {
        let dopri = Dopri5::new(params, tol);
        let state = dopri.state(0.0, x0, v0);
        DopriPeriodMap {
            dopri,
            state,
            period: params.period(),
            periods_done: 0,
            samples_per_period: 256,
        }
    }

    fn end_of_period(&self) -> f64 {
        (self.periods_done + 1) as f64 * self.period
    }
}

impl PeriodMap for DopriPeriodMap {
    fn advance(&mut self) -> Result<[f64; 2], Collision> {
        let end = self.end_of_period();
        self.dopri.integrate(&mut self.state, end, |_| {})?;
        self.periods_done += 1;
        Ok([self.state.x, self.state.v])
    }

    fn advance_recording(&mut self, rec: &mut OrbitRecord) -> Result<[f64; 2], Collision> {
        let start = self.periods_done as f64 * self.period;
        let end = self.end_of_period();
        let n = self.samples_per_period;
        let dt = self.period / n as f64;
        let mut next_sample = 1;
        self.dopri
            .integrate(&mut self.state, end, |d: &DenseStep| {
                let [x0, v0] = d.at(d.t0);
                let [x1, v1] = d.at(d.t1);
                rec.include(x1);
                if v0 * v1 <= 0.0 {
                    let t = crate::solver::dopri::root_of(|t| d.at(t)[1], d.t0, d.t1, v0);
                    rec.include(d.at(t)[0]);
                }
                // Simpson on the step is exact to its 4th-order dense output's accuracy
                let xm = d.at(0.5 * (d.t0 + d.t1))[0];
                rec.integral += (d.t1 - d.t0) * (x0 + 4.0 * xm + x1) / 6.0;
                rec.duration += d.t1 - d.t0;
                while next_sample <= n && start + next_sample as f64 * dt <= d.t1 + 1e-12 {
                    let t = (start + next_sample as f64 * dt).min(d.t1);
                    rec.samples.push(d.at(t)[0]);
                    next_sample += 1;
                }
            })?;
        self.periods_done += 1;
        Ok([self.state.x, self.state.v])
    }

    fn samples_per_period(&self) -> usize {
        self.samples_per_period
    }
}
