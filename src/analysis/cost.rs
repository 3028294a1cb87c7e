//! What an analysis will cost before it starts: integration steps in the worst case (every
//! trajectory runs to its `max_forcing_periods`) and the memory its result needs at its
//! largest, with the settings that make them up, so that a run can be refused with the
//! setting to change rather than abort, hang or fill the disk.

use std::f64::consts::PI;

use super::continuation::branch::ContinuationSpec;
use super::continuation::hunt::HuntSpec;
use super::continuation::map::MapSpec;
use super::global::basin::BasinSpec;
use super::global::family::FamilySpec;
use super::global::frequency_response::FrequencyResponseSpec;
use super::grid::Axis;
use super::orbit::chirp_sweep::ChirpSpec;
use super::orbit::force_curve::ForceCurveSpec;
use super::orbit::steady_state::SteadyStateSpec;
use super::orbit::time_history::TimeHistorySpec;
use crate::model::ParamError;

/// Steps of the fixed-step integrator in one forcing period at most: beyond this a drive
/// table alone takes tens of megabytes per thread.
pub const MAX_STEPS_PER_PERIOD: usize = 1_000_000;

/// The worst-case cost of an analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct Cost {
    /// Integration steps if every trajectory runs to its limit.
    pub steps: f64,
    /// Bytes of memory at the largest: the result in memory, its CSV, its chunks on disk.
    pub bytes: f64,
    /// What the steps are made of, in the settings' own names.
    pub factors: Vec<String>,
    /// What the bytes are made of.
    pub memory: Vec<String>,
    /// Bytes of chunks written beside the result while it is computed.
    pub disk: f64,
    /// Steps of the largest chunk, the work a kill can lose (`None`: the analysis is one).
    pub chunk: Option<f64>,
}

impl Cost {
    /// Steps of the largest unit of work saved at once.
    pub fn chunk_steps(&self) -> f64 {
        self.chunk.unwrap_or(self.steps)
    }
}

impl Cost {
    fn new(trajectories: f64, what: &str, steady: &Steady) -> Cost {
        Cost {
            steps: trajectories * steady.steps,
            bytes: 0.0,
            factors: vec![format!("{} {what}", count(trajectories))],
            memory: Vec::new(),
            disk: 0.0,
            chunk: None,
        }
        .with_steady(steady)
    }

    fn with_steady(mut self, steady: &Steady) -> Cost {
        self.factors.extend(steady.factors.iter().cloned());
        self
    }

    fn plus(mut self, other: Cost) -> Cost {
        self.steps += other.steps;
        self.bytes += other.bytes;
        for f in other.factors {
            if !self.factors.contains(&f) {
                self.factors.push(f);
            }
        }
        self.memory.extend(other.memory);
        self.disk += other.disk;
        self
    }

    fn times(mut self, n: f64, what: String) -> Cost {
        self.steps *= n;
        self.bytes *= n;
        self.disk *= n;
        self.memory.insert(0, what.clone());
        self.factors.insert(0, what);
        self
    }

    fn bytes(mut self, bytes: f64, what: String) -> Cost {
        self.bytes += bytes;
        self.memory.push(what);
        self
    }
}

/// A count for people: `49152`, `1.2e9`.
fn count(n: f64) -> String {
    if n < 1e6 {
        format!("{n:.0}")
    } else {
        format!("{n:.2e}")
    }
}

/// One trajectory's worst case under a steady-state spec at the smallest ω_e it meets.
struct Steady {
    steps: f64,
    factors: Vec<String>,
}

/// The steps per period at `omega` (erring on `steady.resolution` if too many) and a
/// trajectory's worst case; `prefix` is where the steady settings live (`steady.`).
fn steady_cost(steady: &SteadyStateSpec, omega: f64, prefix: &str) -> Result<Steady, ParamError> {
    // the ω_e itself: a written model's frequency may lie below the built-in's range, and
    // its periods are as long as it says (a period of no positive length: no bound at all)
    let per_period = if omega > 0.0 {
        steady.resolution.steps_for(2.0 * PI / omega)
    } else {
        usize::MAX
    };
    if per_period > MAX_STEPS_PER_PERIOD {
        return Err(ParamError {
            field: format!("{prefix}resolution.max_step"),
            value: steady.resolution.max_step,
            allowed: format!(
                "a step that cuts a forcing period (ω_e {omega}) into at most \
                 {MAX_STEPS_PER_PERIOD} steps, not {per_period}"
            ),
        });
    }
    Ok(Steady {
        steps: steady.max_forcing_periods as f64 * per_period as f64,
        factors: vec![
            format!(
                "{} forcing periods each at most ({prefix}max_forcing_periods)",
                steady.max_forcing_periods
            ),
            format!("{per_period} steps per period ({prefix}resolution, ω_e {omega})"),
        ],
    })
}

/// The smallest ω_e of an axis of ω_e values.
fn lowest(axis: &Axis) -> f64 {
    axis.min.min(axis.max)
}

/// Bytes of one steady state in memory, and about as many as JSON in a chunk (its Poincaré
/// points up to `max_period`; measured, 275 B a cell in a basin's chunks).
fn steady_bytes(steady: &SteadyStateSpec) -> f64 {
    160.0 + 16.0 * steady.max_period as f64
}

/// A frequency response over `omega` values (ω_e, or another parameter's values at `at_omega`).
pub fn response(spec: &FrequencyResponseSpec, at_omega: Option<f64>) -> Result<Cost, ParamError> {
    let omega = at_omega.unwrap_or(lowest(&spec.omega));
    let steady = steady_cost(&spec.steady, omega, "steady.")?;
    let (points, starts) = (
        spec.omega.points as f64,
        (spec.dx.points * spec.v.points) as f64,
    );
    let grid = Cost::new(
        points * starts,
        "trajectories (omega.points × dx.points × v.points)",
        &steady,
    );
    // both stepped sweeps, and the neighbour seeding (a few orbits per ω_e and round)
    let sweeps = Cost::new(2.0 * points, "sweep steps", &steady);
    let seeding = Cost::new(8.0 * points, "seeded orbits", &steady);
    let bytes = points * 16.0 * steady_bytes(&spec.steady);
    let what = format!("{} ω_e values (omega.points)", spec.omega.points);
    let mut cost = grid.plus(sweeps).plus(seeding).bytes(bytes, what);
    cost.disk = bytes;
    let per_chunk = super::global::frequency_response::omegas_per_chunk(spec.omega.points);
    cost.chunk = Some(per_chunk as f64 * starts * steady.steps);
    Ok(cost)
}

pub fn basin(spec: &BasinSpec, omega: f64) -> Result<Cost, ParamError> {
    let steady = steady_cost(&spec.steady, omega, "steady.")?;
    let cells = (spec.dx.points * spec.v.points) as f64;
    // a label and the CSV's row per cell in memory while assembling (the chunks are read one
    // at a time: a 1001 × 1001 basin peaks at 56 MB); the chunks on disk
    let what = format!("{} cells (dx.points × v.points)", count(cells));
    let mut cost =
        Cost::new(cells, "cells (dx.points × v.points)", &steady).bytes(cells * 64.0, what);
    cost.disk = cells * steady_bytes(&spec.steady);
    let per_chunk = super::global::basin::cells_per_chunk(spec.dx.points * spec.v.points);
    cost.chunk = Some(cells.min(per_chunk as f64) * steady.steps);
    Ok(cost)
}

pub fn family(spec: &FamilySpec) -> Result<Cost, ParamError> {
    let n = spec.values.len() as f64;
    let member = response(&spec.response, None)?;
    let mut cost = member
        .clone()
        .times(n, format!("{} members (values)", count(n)));
    cost.chunk = Some(member.steps);
    Ok(cost)
}

/// A map about a model whose forcing frequency is `omega`.
pub fn map(spec: &MapSpec, omega: f64) -> Result<Cost, ParamError> {
    let rows = spec.values.points as f64;
    let at = (spec.x != super::parameter::ContinuationParameter::Omega).then_some(omega);
    let mut cost =
        response(&spec.response, at)?.times(rows, format!("{} rows (values.points)", count(rows)));
    if spec.curves {
        let curve = continuation(&ContinuationSpec::default(), &spec.response.steady, omega)?;
        cost = cost.plus(curve.times(4.0, "curves (up to 4)".into()));
    }
    Ok(cost)
}

pub fn hunt(spec: &HuntSpec) -> Result<Cost, ParamError> {
    let branches = continuation(
        &spec.continuation,
        &spec.response.steady,
        lowest(&spec.response.omega),
    )?;
    Ok(response(&spec.response, None)?
        .plus(branches.times(8.0, "branches continued (up to 8)".into())))
}

/// A continuation: up to `max_points` per direction, each a Newton solve of the monodromy
/// over `max_period` periods with the variational equations (three times the work of one).
pub fn continuation(
    spec: &ContinuationSpec,
    steady: &SteadyStateSpec,
    omega: f64,
) -> Result<Cost, ParamError> {
    let one = steady_cost(steady, omega, "steady.")?;
    let per_point = spec.shooting.max_iterations as f64 * steady.max_period as f64 * 3.0;
    let per_period = one.steps / steady.max_forcing_periods.max(1) as f64;
    let points = 2.0 * spec.max_points as f64;
    Ok(Cost {
        steps: one.steps + points * per_point * per_period,
        bytes: points * 400.0,
        disk: 0.0,
            chunk: None,
        memory: vec![format!("{} points (2 × continuation.max_points)", count(points))],
        factors: vec![format!(
            "{} points (2 × continuation.max_points) × {} Newton iterations (continuation.shooting.max_iterations)",
            count(points),
            spec.shooting.max_iterations
        )],
    }
    .with_steady(&one))
}

pub fn time_history(spec: &TimeHistorySpec, omega: f64) -> Result<Cost, ParamError> {
    let steady = steady_cost(&spec.steady, omega, "steady.")?;
    let periods = spec
        .max_transient_periods
        .min(spec.steady.max_forcing_periods) as f64
        + (spec.steady_periods * spec.steady.max_period) as f64;
    let samples = periods * spec.samples_per_period as f64;
    let what = format!(
        "{} samples (samples_per_period × (max_transient_periods + steady_periods × steady.max_period))",
        count(samples)
    );
    // the adaptive integrator's steps cost some ten of the fixed-step one's
    Ok(Cost::new(1.0, "orbit", &steady).plus(Cost {
        steps: 10.0 * samples,
        bytes: samples * (40.0 + 70.0),
        factors: vec![what.clone()],
        memory: vec![what],
        disk: 0.0,
        chunk: None,
    }))
}

pub fn chirp(spec: &ChirpSpec) -> Result<Cost, ParamError> {
    let samples = spec.span / spec.dt;
    // the adaptive integrator takes at least span/0.05 steps, and some 50 a forcing period
    let turns = spec.span * spec.omega_start.max(spec.omega_end) / (2.0 * PI);
    let what = format!("{} samples (span / dt)", count(samples));
    Ok(Cost {
        steps: 10.0 * (spec.span / 0.05 + 50.0 * turns),
        bytes: samples * (16.0 + 60.0),
        factors: vec![
            format!("span {}", spec.span),
            format!(
                "ω_e up to {} (omega_start, omega_end)",
                spec.omega_start.max(spec.omega_end)
            ),
        ],
        memory: vec![what],
        disk: 0.0,
        chunk: None,
    })
}

pub fn stepped(omega: &Axis, steady: &SteadyStateSpec) -> Result<Cost, ParamError> {
    let steady_c = steady_cost(steady, lowest(omega), "steady.")?;
    let what = format!("{} steps (omega.points)", omega.points);
    Ok(
        Cost::new(omega.points as f64, "steps (omega.points)", &steady_c)
            .bytes(omega.points as f64 * steady_bytes(steady), what),
    )
}

pub fn force(spec: &ForceCurveSpec) -> Cost {
    let points = (spec.lambda_p.len() * spec.phi_i.len() * spec.points) as f64;
    let what = format!("{} points (lambda_p × phi_i × points)", count(points));
    Cost {
        steps: points,
        bytes: points * 80.0,
        factors: vec![what.clone()],
        memory: vec![what],
        disk: 0.0,
        chunk: None,
    }
}
