//! Folds and period doublings continued in two parameters: the curves that bound where
//! responses exist, and their turning points, where an isola is born (its two folds meet at a
//! minimum of the second parameter) or merges with another branch (two facing folds meet at
//! a maximum).
//!
//! Unknowns y = (x, μ₁, μ₂) at τ = 0 (x = (λ_I, v) for the built-in model); equations P^k(x) − x = 0 and the test function
//! det(M − I) = 0 (fold) or det(M + I) = 0 (period doubling), M the monodromy of the k-fold
//! map; pseudo-arclength with the condition t·(y − y_pred) = 0. The state columns of the first
//! two rows are M − I from the variational equations; every other entry of the Jacobian is a
//! central difference (relative step 1e-6; the test function is a smooth function of M away
//! from collisions, and the integration tolerance 1e-11 leaves it good to about 1e-5, which
//! only slows Newton, not the point it converges to).

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::analysis::continuation::branch::{
    Bifurcation, BifurcationKind, BranchEnd, ContinuationError, Failure, bordered, check_steps,
    dot, norm, null_vector,
};
use crate::analysis::continuation::model::{Continuable, ModelBase};
use crate::analysis::orbit::floquet::{Multipliers, TestFunctions};
use crate::analysis::orbit::shooting::{PeriodFlow, ShootingError, ShootingSpec};
use crate::analysis::parameter::ContinuationParameter;
use crate::analysis::progress::Progress;
use crate::model::error::{ParamError, check};
use crate::model::system::StateVec;

/// A curve whose newest point lies closer than [`STALL_SPAN`] × its longest step to the point
/// this many before it, in its two parameters, has stalled (see [`stalled`]).
const STALL_POINTS: usize = 40;
/// See [`STALL_POINTS`].
const STALL_SPAN: f64 = 0.02;

/// The curve is crawling into a corner: over its last [`STALL_POINTS`] steps it moved less
/// than [`STALL_SPAN`] × `step_max` in its two parameters. Where the bifurcating orbit starts to
/// graze a switch, a curve can turn at a corner that a smooth predictor does not pass; each
/// step there is then cut to about 1e-5 and takes 8 or 9 Newton iterations, until the point
/// limit (260 such steps on the map's 1:2 fold curve near ω_e 5.45, ADR 0.656).
fn stalled(points: &[CurvePoint], step_max: f64) -> bool {
    let n = points.len();
    n > STALL_POINTS && {
        let (a, b) = (&points[n - 1 - STALL_POINTS], &points[n - 1]);
        (a.first - b.first).hypot(a.second - b.second) < STALL_SPAN * step_max
    }
}

/// Relative step of the finite differences in the Jacobian.
const DIFFERENCE_STEP: f64 = 1e-6;
/// The test function converges to this times the Newton tolerance: it carries the
/// integration's error amplified by the monodromy (1e-8 puts the critical multiplier within
/// about 1e-7 of ±1).
const TEST_TOL_FACTOR: f64 = 100.0;

/// How a bifurcation is continued in a second parameter.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CurveSpec {
    /// The second parameter (the first is the branch's own).
    pub second: ContinuationParameter,
    /// The curve stops where the second parameter leaves [min, max]...
    pub min: f64,
    pub max: f64,
    /// ... or the first leaves [first_min, first_max].
    pub first_min: f64,
    pub first_max: f64,
    /// First arclength step and its bounds (arclength in (λ_I, v, μ₁, μ₂)).
    pub step: f64,
    pub step_min: f64,
    pub step_max: f64,
    /// Points per direction at most.
    pub max_points: usize,
    pub shooting: ShootingSpec,
}

impl Default for CurveSpec {
    /// ADR over [0.05, 1.5], the first parameter (ω_e) over [0.2, 6].
    fn default() -> Self {
        CurveSpec {
            second: ContinuationParameter::Model(crate::analysis::parameter::FamilyParameter::Adr),
            min: 0.05,
            max: 1.5,
            first_min: 0.2,
            first_max: 6.0,
            step: 0.01,
            step_min: 1e-6,
            step_max: 0.03,
            max_points: 2000,
            shooting: ShootingSpec::default(),
        }
    }
}

impl CurveSpec {
    /// Checks every field for a curve whose first parameter is `first`, about `base`.
    pub fn validate<M: Continuable>(
        &self,
        base: &M,
        first: ContinuationParameter,
    ) -> Result<(), ParamError> {
        let second = base.resolve(self.second).map_err(|e| e.within("second"))?;
        let first_p = base.resolve(first)?;
        if second == first_p {
            return Err(ParamError {
                field: "second".into(),
                value: ParamError::NOT_NUMERIC,
                allowed: format!("a parameter other than the branch's own ({})", first.name()),
            });
        }
        check(
            "min",
            self.min,
            |m| m < self.max,
            format!("< max = {}", self.max),
        )?;
        check(
            "first_min",
            self.first_min,
            |m| m < self.first_max,
            format!("< first_max = {}", self.first_max),
        )?;
        for (field, v) in [("min", self.min), ("max", self.max)] {
            base.with(second, v).map_err(|e| e.as_value_of(field))?;
        }
        for (field, v) in [("first_min", self.first_min), ("first_max", self.first_max)] {
            base.with(first_p, v).map_err(|e| e.as_value_of(field))?;
        }
        check_steps([self.step, self.step_min, self.step_max], self.max_points)?;
        self.shooting.validate().map_err(|e| e.within("shooting"))
    }
}

/// One point of a bifurcation curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CurvePoint {
    /// The first parameter's value (the branch's own).
    pub first: f64,
    pub second: f64,
    pub omega: f64,
    /// The orbit's state at τ = 0 ([λ_I, v] for the built-in model).
    pub x: StateVec,
    pub amplitude: f64,
    pub multipliers: Multipliers,
}

/// Which parameter turns at an extremum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Turning {
    First,
    Second,
}

/// A located extremum of one parameter along the curve: where two bifurcations of the same
/// kind meet (the curve folds back in that parameter).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Extremum {
    pub of: Turning,
    /// A minimum of that parameter (else a maximum).
    pub minimum: bool,
    pub point: CurvePoint,
    /// ± on the point's value of that parameter: the last bracket's width, plus how far the
    /// point may lie from the curve with its equations solved to the Newton tolerance.
    pub precision: f64,
}

/// A fold or period-doubling curve in two parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BifurcationCurve {
    /// `Fold` or `PeriodDoubling` (a parent's period doubling is continued as the parent's).
    pub kind: BifurcationKind,
    /// Period of the response that bifurcates.
    pub period: usize,
    pub first: ContinuationParameter,
    pub second: ContinuationParameter,
    /// The model the curve started from.
    pub base: ModelBase,
    /// In order along the curve.
    pub points: Vec<CurvePoint>,
    pub extrema: Vec<Extremum>,
    /// How the first and the last point of `points` ended the curve.
    pub ends: [BranchEnd; 2],
}

impl BifurcationCurve {
    /// The extrema of one parameter.
    pub fn extrema_of(&self, of: Turning) -> impl Iterator<Item = &Extremum> {
        self.extrema.iter().filter(move |e| e.of == of)
    }
}

/// Continues `bif`, located on a branch of `base` continued in `first`, in `first` and
/// `spec.second` both ways from where it was found.
pub fn continue_bifurcation<M: Continuable>(
    base: &M,
    first: ContinuationParameter,
    bif: &Bifurcation,
    spec: &CurveSpec,
    progress: &Progress,
) -> Result<BifurcationCurve, ContinuationError> {
    let (problem, start, t0) = Curve::through(base, first, bif, spec, None)?;
    let flip = problem.flip;
    let (fwd, mut extrema, end_fwd) = problem.run(&start, t0.clone(), progress)?;
    let mut points = vec![problem.point(&start)];
    let end_back = if end_fwd == BranchEnd::Closed {
        BranchEnd::Closed
    } else {
        let (back, e2, end) = problem.run(&start, -t0, progress)?;
        extrema.extend(e2);
        points = back.into_iter().rev().chain(points).collect();
        end
    };
    points.extend(fwd);
    Ok(BifurcationCurve {
        kind: if flip {
            BifurcationKind::PeriodDoubling
        } else {
            BifurcationKind::Fold
        },
        period: bif.period,
        first,
        second: spec.second,
        base: base.base(),
        points,
        extrema,
        ends: [end_back, end_fwd],
    })
}

/// The first turning point of `spec.second` that is a minimum (`minimum`) or a maximum along
/// the curve through `bif` (as [`continue_bifurcation`] continues it), one way and then, if
/// not found, the other: where an isola is born or vanishes, without the other fold's curve
/// beyond. `None` if neither way turns within the bounds.
pub fn turning_point<M: Continuable>(
    base: &M,
    first: ContinuationParameter,
    bif: &Bifurcation,
    spec: &CurveSpec,
    minimum: bool,
    progress: &Progress,
) -> Result<Option<Extremum>, ContinuationError> {
    let (problem, start, t0) = Curve::through(base, first, bif, spec, Some(minimum))?;
    let wanted = |e: &Extremum| e.of == Turning::Second && e.minimum == minimum;
    for t in [t0.clone(), -t0] {
        let (_, extrema, _) = problem.run(&start, t, progress)?;
        if let Some(e) = extrema.into_iter().find(wanted) {
            return Ok(Some(e));
        }
    }
    Ok(None)
}

/// A corrected curve point with its Jacobian.
#[derive(Debug, Clone)]
struct Solved {
    /// (x, μ₁, μ₂).
    y: DVector<f64>,
    flow: PeriodFlow,
    /// Rows: P^k(x) − x (n) and the test function; columns: x, μ₁, μ₂.
    jac: DMatrix<f64>,
    iterations: usize,
}

/// The curve problem for period `k` about the model `base`.
struct Curve<'a, M: Continuable> {
    base: M,
    /// Number of states n: y has n + 2 entries, μ₁ and μ₂ last.
    n: usize,
    k: usize,
    first: M::Parameter,
    second: M::Parameter,
    /// Period doubling (det(M + I)) rather than fold (det(M − I)).
    flip: bool,
    spec: &'a CurveSpec,
    /// Stop at the first turning point of the second parameter that is a minimum
    /// (`Some(true)`) or a maximum (`Some(false)`).
    stop: Option<bool>,
}

impl<'a, M: Continuable> Curve<'a, M> {
    /// The curve problem through `bif`, its first point polished on the curve and the
    /// tangent there.
    fn through(
        base: &M,
        first: ContinuationParameter,
        bif: &Bifurcation,
        spec: &'a CurveSpec,
        stop: Option<bool>,
    ) -> Result<(Self, Solved, DVector<f64>), ContinuationError> {
        spec.validate(base, first)?;
        let flip = match bif.kind {
            BifurcationKind::Fold => false,
            BifurcationKind::PeriodDoubling | BifurcationKind::ParentPeriodDoubling => true,
            BifurcationKind::NeimarkSacker | BifurcationKind::BranchPoint => {
                return Err(ContinuationError::Param(ParamError {
                    field: "kind".into(),
                    value: ParamError::NOT_NUMERIC,
                    allowed: "a fold or a period doubling".into(),
                }));
            }
        };
        let problem = Curve {
            base: base.clone(),
            n: base.dim(),
            k: bif.period,
            first: base.resolve(first)?,
            second: base.resolve(spec.second)?,
            flip,
            spec,
            stop,
        };
        let n = problem.n;
        let second = base.value_of(problem.second);
        let guess = DVector::from_fn(n + 2, |i, _| match i {
            i if i < n => bif.x[i],
            i if i == n => bif.parameter,
            _ => second,
        });
        // the located point is good to the locator's precision: polish it on the curve, the
        // arclength condition fixing the second parameter
        let mut along_second = DVector::zeros(n + 2);
        along_second[n + 1] = 1.0;
        let start = problem
            .correct(guess, &along_second, None)
            .map_err(|f| ContinuationError::Seed(f.into_shooting()))?;
        let t0 = problem
            .tangent(&start, &along_second)
            .ok_or(ContinuationError::Seed(ShootingError::Singular))?;
        Ok((problem, start, t0))
    }
}

impl<M: Continuable> Curve<'_, M> {
    fn params_at(&self, first: f64, second: f64) -> Option<M> {
        let p = self.base.with(self.second, second).ok()?;
        p.with(self.first, first).ok()
    }

    fn flow(&self, y: &DVector<f64>) -> Result<PeriodFlow, Failure> {
        let n = self.n;
        let p = self.params_at(y[n], y[n + 1]).ok_or(Failure::Diverged)?;
        Ok(p.period_flow(&y.as_slice()[..n], self.k, self.spec.shooting.tol)?)
    }

    fn test(&self, m: &DMatrix<f64>) -> f64 {
        let t = TestFunctions::of_matrix(m);
        if self.flip { t.flip } else { t.fold }
    }

    /// The residual [P^k(x) − x; test] of a flow from `y`.
    fn residual(&self, y: &DVector<f64>, flow: &PeriodFlow) -> DVector<f64> {
        let n = self.n;
        DVector::from_fn(n + 1, |i, _| {
            if i < n {
                flow.end[i] - y[i]
            } else {
                self.test(&flow.monodromy)
            }
        })
    }

    /// The flow at `y` and the Jacobian of the residual there; `flow`, if given, is the flow
    /// at `y` already computed.
    fn evaluate(&self, y: &DVector<f64>, flow: Option<PeriodFlow>) -> Result<Solved, Failure> {
        let n = self.n;
        // y (unless its flow is given), then each column's two sides: orbits computed side by
        // side (each exactly as alone), the first failure in this order returned
        let steps: Vec<f64> = (0..n + 2)
            .map(|c| DIFFERENCE_STEP * y[c].abs().max(1.0))
            .collect();
        let given = flow.is_some();
        let mut at = if given { vec![] } else { vec![y.clone()] };
        for (c, &d) in steps.iter().enumerate() {
            let (mut up, mut down) = (y.clone(), y.clone());
            up[c] += d;
            down[c] -= d;
            at.extend([up, down]);
        }
        let mut flows: Vec<PeriodFlow> = at
            .par_iter()
            .map(|y| self.flow(y))
            .collect::<Vec<_>>()
            .into_iter()
            .collect::<Result<_, _>>()?;
        if let Some(flow) = flow {
            at.insert(0, y.clone());
            flows.insert(0, flow);
        }
        let mut jac = DMatrix::zeros(n + 1, n + 2);
        for (c, &d) in steps.iter().enumerate() {
            let (up, down) = (1 + 2 * c, 2 + 2 * c);
            let ru = self.residual(&at[up], &flows[up]);
            let rd = self.residual(&at[down], &flows[down]);
            jac.set_column(c, &((ru - rd) / (2.0 * d)));
        }
        let flow = flows.swap_remove(0);
        // the state columns of P^k(x) − x exactly, from the variational equations
        let m = &flow.monodromy;
        for r in 0..n {
            for c in 0..n {
                jac[(r, c)] = m[(r, c)] - if r == c { 1.0 } else { 0.0 };
            }
        }
        Ok(Solved {
            y: y.clone(),
            flow,
            jac,
            iterations: 0,
        })
    }

    /// The point `y` with its orbit integrated and the Jacobian `jac` kept from elsewhere (a
    /// chord method's iterate).
    fn with_jacobian(&self, y: DVector<f64>, jac: DMatrix<f64>) -> Result<Solved, Failure> {
        Ok(Solved {
            flow: self.flow(&y)?,
            y,
            jac,
            iterations: 0,
        })
    }

    /// Newton's method on [residual; t·(y − pred)] = 0 from the predictor, as a chord method:
    /// the Jacobian (nine orbits) is kept from one iterate to the next, so that an iteration
    /// integrates one orbit, while its steps at least halve; where one does not, the Jacobian
    /// is evaluated afresh at that iterate. The first Jacobian is `near`'s, a solved point's
    /// close by (the one the predictor steps from), else the predictor's own. The Jacobian
    /// at the solution is evaluated in full, for the tangent there. `iterations` counts the
    /// steps taken.
    fn correct(
        &self,
        pred: DVector<f64>,
        t: &DVector<f64>,
        near: Option<&Solved>,
    ) -> Result<Solved, Failure> {
        let n = self.n;
        let tol = self.spec.shooting.newton_tol;
        let (mut s, mut fresh) = match near {
            Some(near) => (self.with_jacobian(pred.clone(), near.jac.clone())?, false),
            None => (self.evaluate(&pred, None)?, true),
        };
        let mut lu = bordered(&s.jac, t).lu();
        // the first step, from a neighbour's Jacobian, must be one Newton would take (at most
        // 0.5, as below); each later kept Jacobian's must at least halve the one before
        let mut last_step = 1.0f64;
        for it in 0..self.spec.shooting.max_iterations {
            let r = self.residual(&s.y, &s.flow);
            let state_residual = (0..n).fold(0.0f64, |m, i| m.max(r[i].abs()));
            if it > 0 && state_residual < tol && r[n].abs() < TEST_TOL_FACTOR * tol {
                if !fresh {
                    s = self.evaluate(&s.y, Some(s.flow.clone()))?;
                }
                s.iterations = it;
                return Ok(s);
            }
            let along = -dot(t, &(&s.y - &pred));
            let rhs = DVector::from_fn(n + 2, |i, _| if i <= n { -r[i] } else { along });
            let mut dy = lu.solve(&rhs);
            // a kept Jacobian's step that does not halve the last: the Jacobian here instead
            let halving = |dy: &DVector<f64>| {
                dy.iter().all(|v| v.is_finite()) && dy.amax() <= 0.5 * last_step
            };
            if !fresh && !dy.as_ref().is_some_and(halving) {
                s = self.evaluate(&s.y, Some(s.flow.clone()))?;
                lu = bordered(&s.jac, t).lu();
                dy = lu.solve(&rhs);
            }
            let dy = dy.ok_or(Failure::Diverged)?;
            if !dy.iter().all(|v| v.is_finite()) || dy.amax() > 0.5 {
                return Err(Failure::Diverged);
            }
            last_step = dy.amax();
            s = self.with_jacobian(&s.y + dy, s.jac)?;
            fresh = false;
        }
        Err(Failure::Diverged)
    }

    /// How far coordinate `c` of the corrected point `s` may lie from the curve's own: its
    /// equations hold to the Newton tolerance (the test function to [`TEST_TOL_FACTOR`] times
    /// it), and a residual in a row moves `c`, across the curve, by that row's entry of the
    /// inverse of the Jacobian bordered with the tangent (infinite, unknown, where that is
    /// singular).
    fn solved_to(&self, s: &Solved, prev: &DVector<f64>, c: usize) -> f64 {
        let n = self.n;
        let tol = self.spec.shooting.newton_tol;
        let inverse = self
            .tangent(s, prev)
            .and_then(|tangent| bordered(&s.jac, &tangent).try_inverse());
        let Some(inverse) = inverse else {
            return f64::INFINITY;
        };
        (0..=n)
            .map(|row| {
                let residual = if row < n { tol } else { TEST_TOL_FACTOR * tol };
                inverse[(c, row)].abs() * residual
            })
            .sum()
    }

    /// The unit tangent at `s` (null vector of the Jacobian), oriented along `prev`.
    fn tangent(&self, s: &Solved, prev: &DVector<f64>) -> Option<DVector<f64>> {
        null_vector(&s.jac, prev)
    }

    fn point(&self, s: &Solved) -> CurvePoint {
        let n = self.n;
        let frequency = self.base.frequency();
        let omega = if self.first == frequency {
            s.y[n]
        } else if self.second == frequency {
            s.y[n + 1]
        } else {
            self.base.omega()
        };
        CurvePoint {
            first: s.y[n],
            second: s.y[n + 1],
            omega,
            x: StateVec::from_slice(&s.y.as_slice()[..n]),
            amplitude: s.flow.lambda_max - s.flow.lambda_min,
            multipliers: Multipliers::of_matrix(&s.flow.monodromy),
        }
    }

    fn outside(&self, y: &DVector<f64>) -> bool {
        let (s, n) = (self.spec, self.n);
        y[n] < s.first_min || y[n] > s.first_max || y[n + 1] < s.min || y[n + 1] > s.max
    }

    /// Continues from `start` along `t0` until an end; returns the points after `start` and
    /// the extrema passed.
    fn run(
        &self,
        start: &Solved,
        t0: DVector<f64>,
        progress: &Progress,
    ) -> Result<(Vec<CurvePoint>, Vec<Extremum>, BranchEnd), ContinuationError> {
        let spec = self.spec;
        let n = self.n;
        let (mut prev, mut t, mut h) = (start.clone(), t0, spec.step);
        let mut points = Vec::new();
        let mut extrema = Vec::new();
        loop {
            if progress.is_cancelled() {
                return Err(ContinuationError::Cancelled);
            }
            if points.len() >= spec.max_points {
                return Ok((points, extrema, BranchEnd::MaxPoints));
            }
            let next = match self.correct(&prev.y + &t * h, &t, Some(&prev)) {
                Ok(s) => Some(s),
                Err(Failure::Collision(c)) if h <= spec.step_min => {
                    return Ok((
                        points,
                        extrema,
                        BranchEnd::Collision {
                            tau: c.tau,
                            lambda_i: c.lambda_i,
                        },
                    ));
                }
                Err(_) => None,
            };
            let next = next.and_then(|s| {
                let tn = self.tangent(&s, &t)?;
                let moved = norm(&(&s.y - (&prev.y + &t * h)));
                let smooth = dot(&tn, &t) > 0.9 && moved < 0.3 * h;
                (smooth || h <= spec.step_min).then_some((s, tn))
            });
            let Some((next, t_next)) = next else {
                if h <= spec.step_min {
                    return Ok((points, extrema, BranchEnd::StepTooSmall));
                }
                h = (h * 0.5).max(spec.step_min);
                continue;
            };
            progress.step();
            let mut turned = false;
            for (of, c) in [(Turning::First, n), (Turning::Second, n + 1)] {
                if (t[c] < 0.0) != (t_next[c] < 0.0) {
                    let e = self.extremum(&prev, &t, h, of, c);
                    turned |= of == Turning::Second && Some(e.minimum) == self.stop;
                    extrema.push(e);
                }
            }
            if turned {
                points.push(self.point(&next));
                let value = next.y[n + 1];
                return Ok((points, extrema, BranchEnd::Bound { value }));
            }
            if self.outside(&next.y) {
                points.push(self.point(&next));
                let value = if next.y[n + 1] < spec.min || next.y[n + 1] > spec.max {
                    next.y[n + 1]
                } else {
                    next.y[n]
                };
                return Ok((points, extrema, BranchEnd::Bound { value }));
            }
            let back_home = points.len() >= 8 && norm(&(&next.y - &start.y)) < 0.5 * h;
            points.push(self.point(&next));
            if back_home {
                return Ok((points, extrema, BranchEnd::Closed));
            }
            if stalled(&points, spec.step_max) {
                return Ok((points, extrema, BranchEnd::Stalled));
            }
            // the test function is only piecewise smooth where the orbit grazes a switch
            // (a membrane just going slack), and Newton on it then converges linearly: more
            // iterations than on a branch are normal
            h = match next.iterations {
                0..=4 => h * 1.5,
                5..=8 => h,
                _ => h * 0.6,
            }
            .clamp(spec.step_min, spec.step_max);
            (prev, t) = (next, t_next);
        }
    }

    /// The extremum of coordinate `c` between `from` and the point a step `h` along `t`: the
    /// tangent's component `c` driven to zero by false position on corrected points.
    fn extremum(&self, from: &Solved, t: &DVector<f64>, h: f64, of: Turning, c: usize) -> Extremum {
        let component = |sigma: f64| -> Option<(f64, Solved)> {
            let s = self.correct(&from.y + t * sigma, t, Some(from)).ok()?;
            let tn = self.tangent(&s, t)?;
            Some((tn[c], s))
        };
        let g_from = self.tangent(from, t).map_or(t[c], |tn| tn[c]);
        let (mut lo, mut hi, mut g_lo) = (0.0, h, g_from);
        let (mut s_lo, mut s_hi) = (from.clone(), None::<Solved>);
        let mut g_hi = match component(h) {
            Some((g, s)) => {
                s_hi = Some(s);
                g
            }
            None => -g_from,
        };
        // false position with the Illinois correction: the end kept twice has its value halved
        let mut side = 0;
        for _ in 0..40 {
            let mut sigma = lo + (hi - lo) * g_lo / (g_lo - g_hi);
            if !(sigma > lo && sigma < hi) {
                sigma = 0.5 * (lo + hi);
            }
            let Some((g, s)) = component(sigma) else {
                break;
            };
            if (g < 0.0) == (g_lo < 0.0) {
                (lo, g_lo, s_lo) = (sigma, g, s);
                if side == 1 {
                    g_hi *= 0.5;
                }
                side = 1;
            } else {
                (hi, g_hi, s_hi) = (sigma, g, Some(s));
                if side == -1 {
                    g_lo *= 0.5;
                }
                side = -1;
            }
            if hi - lo < 1e-9 * h.max(1e-3) {
                break;
            }
        }
        let bracket = s_hi
            .as_ref()
            .map_or(f64::NAN, |s| (s.y[c] - s_lo.y[c]).abs());
        let best = match s_hi {
            Some(s) if g_hi.abs() < g_lo.abs() => s,
            _ => s_lo,
        };
        let precision = bracket + self.solved_to(&best, t, c);
        // at a minimum the coordinate was decreasing before it
        let minimum = t[c] < 0.0;
        Extremum {
            of,
            minimum,
            point: self.point(&best),
            precision,
        }
    }
}
