//! Pseudo-arclength continuation of periodic responses in ω_e or a model parameter.
//!
//! Unknowns y = (x, μ) at τ = 0 (x = (λ_I, v) for the built-in model, the n states of a
//! written one); equations P^k(x; μ) − x = 0 plus the arclength condition t·(y − y_pred) = 0.
//! The state columns of the Jacobian are M − I from the variational equations; the μ column
//! is a central difference of the map. At each point the
//! Floquet multipliers give stability and the test functions of [`TestFunctions`]; a sign
//! change between two points is located by false position along the arclength (each trial a
//! corrected point). A subharmonic branch that shrinks onto a response of a divisor period
//! (its Poincaré points merge: a period doubling of the parent) ends there; one that comes
//! back to its seed is closed, an isola when it is a subharmonic.

use nalgebra::{DMatrix, DVector, Vector3};
use serde::{Deserialize, Serialize};

use crate::analysis::AnalysisError;
use crate::analysis::continuation::model::{Continuable, ModelBase};
use crate::analysis::orbit::floquet::{Multipliers, TestFunctions};
use crate::analysis::orbit::shooting::{
    PeriodFlow, PeriodicOrbit, ShootingError, ShootingSpec, shoot,
};
use crate::analysis::parameter::ContinuationParameter;
use crate::analysis::progress::Progress;
use crate::model::error::{ParamError, check};
use crate::model::system::StateVec;
use crate::solver::Collision;

/// How a branch is continued.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ContinuationSpec {
    pub parameter: ContinuationParameter,
    /// The branch stops where the parameter leaves [min, max].
    pub min: f64,
    pub max: f64,
    /// First arclength step, and its bounds (arclength in (λ_I, v, μ)).
    pub step: f64,
    pub step_min: f64,
    pub step_max: f64,
    /// Points per direction at most.
    pub max_points: usize,
    pub shooting: ShootingSpec,
}

impl Default for ContinuationSpec {
    fn default() -> Self {
        ContinuationSpec {
            parameter: ContinuationParameter::Omega,
            min: 0.2,
            max: 6.0,
            step: 0.01,
            step_min: 1e-7,
            step_max: 0.04,
            max_points: 3000,
            shooting: ShootingSpec::default(),
        }
    }
}

impl ContinuationSpec {
    /// Checks every field; `base` must have the parameter and be valid at both ends of the
    /// range.
    pub fn validate<M: Continuable>(&self, base: &M) -> Result<(), ParamError> {
        let parameter = base.resolve(self.parameter)?;
        check(
            "min",
            self.min,
            |m| m < self.max,
            format!("< max = {}", self.max),
        )?;
        for (field, v) in [("min", self.min), ("max", self.max)] {
            base.with(parameter, v).map_err(|e| e.as_value_of(field))?;
        }
        check_steps([self.step, self.step_min, self.step_max], self.max_points)?;
        self.shooting.validate().map_err(|e| e.within("shooting"))
    }

    /// [`Self::validate`] for a branch that starts at `base` itself: its parameter's value
    /// there must lie in [min, max], or the branch never enters its range.
    pub fn validate_from<M: Continuable>(&self, base: &M) -> Result<(), ParamError> {
        self.validate(base)?;
        let start = base.value_of(base.resolve(self.parameter)?);
        let name = self.parameter.name();
        check(
            "min",
            self.min,
            |m| m <= start,
            format!("<= {start}, the {name} the branch starts from"),
        )?;
        check(
            "max",
            self.max,
            |m| m >= start,
            format!(">= {start}, the {name} the branch starts from"),
        )?;
        Ok(())
    }
}

/// The smallest arclength step a continuation may take: below it a step moves the parameter
/// by rounding alone (a branch of 1e-14 steps stood still and was called closed).
const MIN_STEP: f64 = 1e-12;

/// Checks a continuation's arclength steps [step, step_min, step_max] and its point limit.
pub(crate) fn check_steps(
    [step, step_min, step_max]: [f64; 3],
    max_points: usize,
) -> Result<(), ParamError> {
    check("step_max", step_max, |s| s > 0.0 && s <= 1.0, "(0, 1]")?;
    check(
        "step_min",
        step_min,
        |s| s >= MIN_STEP && s < step_max,
        format!("[{MIN_STEP:e}, step_max = {step_max})"),
    )?;
    check(
        "step",
        step,
        |s| s >= step_min && s <= step_max,
        format!("[step_min, step_max] = [{step_min}, {step_max}]"),
    )?;
    check(
        "max_points",
        max_points as f64,
        |n| (2.0..=1e6).contains(&n),
        "[2, 1000000]",
    )?;
    Ok(())
}

/// One point of a continued branch: what a plot needs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BranchPoint {
    /// Value of the continuation parameter.
    pub parameter: f64,
    /// Forcing frequency ω_e (the parameter itself when continuing in ω_e).
    pub omega: f64,
    /// The stroboscopic state at τ = 0 ([λ_I, v] for the built-in model).
    pub x: StateVec,
    /// max − min of the amplitude's output (λ_I) over the response period.
    pub amplitude: f64,
    pub lambda_min: f64,
    pub lambda_max: f64,
    pub multipliers: Multipliers,
    pub stable: bool,
    pub tests: TestFunctions,
    /// det(monodromy) − exp(∫ tr A dτ): the Liouville check of the variational integration.
    pub liouville_error: f64,
}

/// What happens at a special point of a branch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BifurcationKind {
    /// A real multiplier through +1: the branch turns back in the parameter.
    Fold,
    /// A real multiplier through −1: a branch of twice the period is born.
    PeriodDoubling,
    /// A complex pair through the unit circle.
    NeimarkSacker,
    /// A real multiplier through +1 where the branch goes on in the parameter (a
    /// symmetry-breaking pitchfork or a transcritical point): another branch crosses it.
    BranchPoint,
    /// The branch shrinks onto a response of a divisor period (a period doubling of that
    /// parent branch) and ends there.
    ParentPeriodDoubling,
}

impl BifurcationKind {
    pub fn as_str(&self) -> &'static str {
        match self {
            BifurcationKind::Fold => "fold",
            BifurcationKind::PeriodDoubling => "period-doubling",
            BifurcationKind::NeimarkSacker => "neimark-sacker",
            BifurcationKind::BranchPoint => "branch-point",
            BifurcationKind::ParentPeriodDoubling => "parent-period-doubling",
        }
    }
}

/// A located bifurcation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Bifurcation {
    pub kind: BifurcationKind,
    pub parameter: f64,
    pub omega: f64,
    pub x: StateVec,
    pub amplitude: f64,
    /// Multipliers there (of the parent's map for a parent period doubling).
    pub multipliers: Multipliers,
    /// Width of the final bracket in the parameter: how precisely it was located.
    pub precision: f64,
    /// Period of the response that bifurcates (the parent's for a parent period doubling).
    pub period: usize,
}

/// Why one direction of a branch stopped.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "end")]
pub enum BranchEnd {
    /// Came back to the seed: the branch is a closed curve.
    Closed,
    /// The parameter reached the end of its range.
    Bound {
        value: f64,
    },
    /// The orbit reaches a frame or the Gent limit (a written model's collision; `lambda_i`
    /// is then its first state).
    Collision {
        tau: f64,
        lambda_i: f64,
    },
    /// Merged into the parent response of this period at its period doubling.
    Parent {
        period: usize,
    },
    /// The corrector failed even at the smallest step.
    StepTooSmall,
    /// A curve of bifurcations made no headway over many points (a corner where its orbit
    /// starts to graze a switch).
    Stalled,
    MaxPoints,
}

impl std::fmt::Display for BranchEnd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BranchEnd::Closed => write!(f, "closed"),
            BranchEnd::Bound { value } => write!(f, "range end {value}"),
            BranchEnd::Collision { tau, lambda_i } => {
                write!(f, "collision (τ {tau:.3}, λ_I {lambda_i:.4})")
            }
            BranchEnd::Parent { period } => {
                write!(f, "period doubling of a period-{period} response")
            }
            BranchEnd::StepTooSmall => write!(f, "corrector failed"),
            BranchEnd::Stalled => write!(f, "stalled at a corner"),
            BranchEnd::MaxPoints => write!(f, "point limit"),
        }
    }
}

/// A continued branch: its points in order along the curve, located bifurcations and the
/// reason each end stopped.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ContinuedBranch {
    pub period: usize,
    pub parameter: ContinuationParameter,
    /// The model at the seed.
    pub base: ModelBase,
    pub points: Vec<BranchPoint>,
    pub bifurcations: Vec<Bifurcation>,
    /// How the first and the last point of `points` ended the branch.
    pub ends: [BranchEnd; 2],
}

impl ContinuedBranch {
    /// The branch closes on itself.
    pub fn closed(&self) -> bool {
        self.ends.contains(&BranchEnd::Closed)
    }

    /// The located bifurcations of one kind.
    pub fn of_kind(&self, kind: BifurcationKind) -> impl Iterator<Item = &Bifurcation> {
        self.bifurcations.iter().filter(move |b| b.kind == kind)
    }

    /// Smallest and largest parameter value along the branch, located folds included.
    pub fn parameter_range(&self) -> (f64, f64) {
        let values = self.points.iter().map(|p| p.parameter);
        let located = self.bifurcations.iter().map(|b| b.parameter);
        values
            .chain(located)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            })
    }

    /// The responses of the branch at parameter `value`: one per crossing of `value` along
    /// the branch, each converged by shooting from the interpolated point. `base` is the
    /// model the branch was continued about.
    pub fn orbits_at<M: Continuable>(
        &self,
        base: &M,
        value: f64,
        shooting: &ShootingSpec,
    ) -> Result<Vec<PeriodicOrbit>, ContinuationError> {
        let model = base.with(base.resolve(self.parameter)?, value)?;
        let mut out = Vec::new();
        for w in self.points.windows(2) {
            let (a, b) = (w[0].parameter - value, w[1].parameter - value);
            if a == 0.0 || (a < 0.0) != (b < 0.0) {
                let f = a / (a - b);
                let mut x = w[0].x;
                for (c, xc) in x.iter_mut().enumerate() {
                    *xc += f * (w[1].x[c] - w[0].x[c]);
                }
                out.push(shoot(&model, self.period, &x, shooting)?);
            }
        }
        Ok(out)
    }

    /// True if one of the branch's orbits at parameter `value` has every state of `points`
    /// among its Poincaré states, within `tol` (max-norm).
    pub fn passes_through<M: Continuable>(
        &self,
        base: &M,
        value: f64,
        points: &[StateVec],
        tol: f64,
        shooting: &ShootingSpec,
    ) -> bool {
        let near = |p: &StateVec, q: &StateVec| max_distance(p, q) < tol;
        self.orbits_at(base, value, shooting)
            .unwrap_or_default()
            .iter()
            .any(|o| points.iter().all(|p| o.poincare.iter().any(|q| near(p, q))))
    }

    /// Maximal runs of points of equal stability, as (first, last, stable) index ranges.
    pub fn arcs(&self) -> Vec<(usize, usize, bool)> {
        let mut arcs: Vec<(usize, usize, bool)> = Vec::new();
        for (i, p) in self.points.iter().enumerate() {
            match arcs.last_mut() {
                Some(a) if a.2 == p.stable => a.1 = i,
                _ => arcs.push((i, i, p.stable)),
            }
        }
        arcs
    }

    /// The arcs in order along the branch with where each starts and ends; on a closed
    /// branch the last arc runs on through the seed into the first, and the two are one.
    pub fn arc_ends(&self) -> Vec<ArcEnds> {
        let mut arcs: Vec<ArcEnds> = self
            .arcs()
            .into_iter()
            .map(|(i, j, stable)| ArcEnds {
                stable,
                parameter_start: self.points[i].parameter,
                parameter_end: self.points[j].parameter,
                amplitude_start: self.points[i].amplitude,
                amplitude_end: self.points[j].amplitude,
            })
            .collect();
        if self.closed() && arcs.len() > 1 && arcs[0].stable == arcs[arcs.len() - 1].stable {
            let last = arcs.pop().expect("more than one arc");
            arcs[0].parameter_start = last.parameter_start;
            arcs[0].amplitude_start = last.amplitude_start;
        }
        arcs
    }
}

/// A maximal run of points of equal stability, from its first point to its last.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ArcEnds {
    pub stable: bool,
    pub parameter_start: f64,
    pub parameter_end: f64,
    pub amplitude_start: f64,
    pub amplitude_end: f64,
}

/// Why a branch could not be started.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ContinuationError {
    #[error(transparent)]
    Param(#[from] ParamError),
    #[error("no periodic response at the seed: {0}")]
    Seed(#[from] ShootingError),
    #[error("cancelled")]
    Cancelled,
}

impl From<ContinuationError> for AnalysisError {
    fn from(e: ContinuationError) -> Self {
        match e {
            ContinuationError::Param(p) => AnalysisError::Param(p),
            ContinuationError::Cancelled => AnalysisError::Cancelled,
            ContinuationError::Seed(s) => AnalysisError::Shooting(s),
        }
    }
}

/// Poincaré points of one orbit closer than this (max-norm) are one point: far above the
/// Newton tolerance, far below the gap of a subharmonic even 1e-10 away from its period
/// doubling (the gap grows as the square root of the distance).
const PARENT_GAP: f64 = 1e-7;

/// A branch is taken to end on a parent only after a step at most this long (arclength)
/// confirms it.
const PARENT_CONFIRM_STEP: f64 = 1e-3;

/// Reads one test function (`None` where it does not apply).
type TestOf = fn(&TestFunctions) -> Option<f64>;

/// max_i |p_i − q_i|.
pub(crate) fn max_distance(p: &[f64], q: &[f64]) -> f64 {
    p.iter()
        .zip(q)
        .fold(0.0, |m: f64, (a, b)| m.max((a - b).abs()))
}

/// a · b, summed as nalgebra sums a fixed-size vector of that length (a 4-vector pairwise),
/// so that the built-in model's branches (3 unknowns) and curves (4) keep the bits they had
/// with fixed-size vectors.
pub(crate) fn dot(a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    if a.len() == 4 {
        let v = |x: &DVector<f64>| nalgebra::Vector4::from_column_slice(x.as_slice());
        v(a).dot(&v(b))
    } else {
        a.dot(b)
    }
}

/// |a|, summed as [`dot`].
pub(crate) fn norm(a: &DVector<f64>) -> f64 {
    dot(a, a).sqrt()
}

/// The unit null vector of an m × (m + 1) matrix `jac` of rank m, oriented along `prev`:
/// the cross product of the rows where m = 2, else the solution of the bordered system
/// [jac; prevᵀ] t = e_{m+1}.
pub(crate) fn null_vector(jac: &DMatrix<f64>, prev: &DVector<f64>) -> Option<DVector<f64>> {
    let m = jac.nrows();
    let t = if m == 2 {
        let r0 = Vector3::new(jac[(0, 0)], jac[(0, 1)], jac[(0, 2)]);
        let r1 = Vector3::new(jac[(1, 0)], jac[(1, 1)], jac[(1, 2)]);
        let t = r0.cross(&r1).normalize();
        DVector::from_column_slice(t.as_slice())
    } else {
        let mut e = DVector::zeros(m + 1);
        e[m] = 1.0;
        let t = bordered(jac, prev).lu().solve(&e)?;
        &t / norm(&t)
    };
    t.iter()
        .all(|v| v.is_finite())
        .then(|| if dot(&t, prev) < 0.0 { -t } else { t })
}

/// `jac` (n × (n + 1)) with `t` as its last row.
pub(crate) fn bordered(jac: &DMatrix<f64>, t: &DVector<f64>) -> DMatrix<f64> {
    let n = jac.nrows();
    DMatrix::from_fn(n + 1, n + 1, |r, c| if r < n { jac[(r, c)] } else { t[c] })
}

/// A corrected point with everything computed there.
#[derive(Debug, Clone)]
struct Solved {
    /// (x, μ).
    y: DVector<f64>,
    flow: PeriodFlow,
    /// [M − I | ∂P/∂μ].
    jac: DMatrix<f64>,
    iterations: usize,
}

/// Where a monodromy's multipliers lie against the unit circle: what tells a complex pair
/// crossing it (Neimark–Sacker) from complex pairs meeting on the real axis, which also
/// changes the sign of the product of |μ|² − 1 over the pairs where n > 2.
#[derive(Debug, Clone, Copy, PartialEq)]
struct UnitCircle {
    /// Complex pairs (counted once).
    pairs: usize,
    /// Multipliers of modulus above 1, and those of them complex.
    outside: usize,
    complex_outside: usize,
}

impl UnitCircle {
    fn of(mu: &Multipliers) -> UnitCircle {
        let outside = |z: &&crate::analysis::orbit::floquet::Multiplier| z.modulus() > 1.0;
        UnitCircle {
            pairs: mu.0.iter().filter(|z| z.im > 0.0).count(),
            outside: mu.0.iter().filter(outside).count(),
            complex_outside: mu.0.iter().filter(|z| z.im != 0.0).filter(outside).count(),
        }
    }

    /// Whether a complex pair crossed the circle between `self` and `other`: as many pairs
    /// on both, and the complex ones outside changed as all outside did (no real crossing
    /// or pair meeting on the real axis in between).
    fn torus_between(&self, other: &UnitCircle) -> bool {
        let change = |a: usize, b: usize| b as isize - a as isize;
        self.pairs == other.pairs
            && change(self.complex_outside, other.complex_outside) != 0
            && change(self.complex_outside, other.complex_outside)
                == change(self.outside, other.outside)
    }
}

/// Why a corrector failed: the orbit collides, or Newton gets nowhere (any other failure
/// of the flow included).
pub(crate) enum Failure {
    Collision(Collision),
    Diverged,
}

impl From<ShootingError> for Failure {
    fn from(e: ShootingError) -> Failure {
        match e {
            ShootingError::Collision(c) => Failure::Collision(c),
            _ => Failure::Diverged,
        }
    }
}

impl Failure {
    /// The failure as a seed's.
    pub(crate) fn into_shooting(self) -> ShootingError {
        match self {
            Failure::Collision(c) => ShootingError::Collision(c),
            Failure::Diverged => ShootingError::Singular,
        }
    }
}

/// The continuation problem for period `k` about the model `base`.
struct Problem<'a, M: Continuable> {
    base: M,
    parameter: M::Parameter,
    /// Number of states n: y has n + 1 entries, μ last.
    n: usize,
    k: usize,
    spec: &'a ContinuationSpec,
}

impl<'a, M: Continuable> Problem<'a, M> {
    fn new(base: &M, k: usize, spec: &'a ContinuationSpec) -> Result<Self, ParamError> {
        Ok(Problem {
            parameter: base.resolve(spec.parameter)?,
            n: base.dim(),
            base: base.clone(),
            k,
            spec,
        })
    }

    fn params_at(&self, mu: f64) -> Option<M> {
        self.base.with(self.parameter, mu).ok()
    }

    /// (x, μ) as one vector.
    fn join(&self, x: &[f64], mu: f64) -> DVector<f64> {
        DVector::from_fn(self.n + 1, |i, _| if i < self.n { x[i] } else { mu })
    }

    /// P^k, its monodromy and the μ column at y.
    fn evaluate(&self, y: &DVector<f64>) -> Result<Solved, Failure> {
        let n = self.n;
        let mu = y[n];
        let p = self.params_at(mu).ok_or(Failure::Diverged)?;
        let x = &y.as_slice()[..n];
        let tol = self.spec.shooting.tol;
        let d = 1e-6 * mu.abs().max(1.0);
        let side = |mu: f64| {
            let q = self.params_at(mu)?;
            q.period_flow(x, self.k, tol).ok().map(|f| f.end)
        };
        // the three orbits side by side (each exactly as alone)
        let (flow, (up, down)) = rayon::join(
            || p.period_flow(x, self.k, tol),
            || rayon::join(|| side(mu + d), || side(mu - d)),
        );
        let flow = flow?;
        let dp: Vec<f64> = match (up, down) {
            (Some(a), Some(b)) => (0..n).map(|i| (a[i] - b[i]) / (2.0 * d)).collect(),
            (Some(a), None) => (0..n).map(|i| (a[i] - flow.end[i]) / d).collect(),
            (None, Some(b)) => (0..n).map(|i| (flow.end[i] - b[i]) / d).collect(),
            (None, None) => return Err(Failure::Diverged),
        };
        let m = &flow.monodromy;
        let jac = DMatrix::from_fn(n, n + 1, |r, c| match c {
            c if c == n => dp[r],
            c if c == r => m[(r, c)] - 1.0,
            c => m[(r, c)],
        });
        Ok(Solved {
            y: y.clone(),
            flow,
            jac,
            iterations: 0,
        })
    }

    fn residual(&self, s: &Solved) -> DVector<f64> {
        DVector::from_fn(self.n, |i, _| s.flow.end[i] - s.y[i])
    }

    /// Newton on [P^k(x) − x; t·(y − pred)] = 0 from the predictor.
    fn correct(&self, pred: DVector<f64>, t: &DVector<f64>) -> Result<Solved, Failure> {
        let n = self.n;
        let tol = self.spec.shooting.newton_tol;
        let mut y = pred.clone();
        for it in 0..self.spec.shooting.max_iterations {
            let mut s = self.evaluate(&y)?;
            let r = self.residual(&s);
            if it > 0 && r.amax() < tol {
                s.iterations = it;
                return Ok(s);
            }
            let a = bordered(&s.jac, t);
            let along = -t.dot(&(&y - &pred));
            let rhs = DVector::from_fn(n + 1, |i, _| if i < n { -r[i] } else { along });
            let dy = a.lu().solve(&rhs).ok_or(Failure::Diverged)?;
            if !dy.iter().all(|v| v.is_finite()) || dy.amax() > 0.5 {
                return Err(Failure::Diverged);
            }
            y += dy;
        }
        Err(Failure::Diverged)
    }

    /// The unit tangent at `s` (null vector of the Jacobian), oriented along `prev`.
    fn tangent(s: &Solved, prev: &DVector<f64>) -> Option<DVector<f64>> {
        null_vector(&s.jac, prev)
    }

    /// Whether the branch turns back in its parameter between the point of tangent `t` and
    /// `b` (their tangents' parameter parts of opposite signs; a fold if unknown).
    fn turns(b: &Solved, t: &DVector<f64>) -> bool {
        let n = t.len() - 1;
        Self::tangent(b, t).is_none_or(|tb| tb[n] * t[n] < 0.0)
    }

    fn omega_at(&self, mu: f64) -> f64 {
        if self.parameter == self.base.frequency() {
            mu
        } else {
            self.base.omega()
        }
    }

    fn point(&self, s: &Solved) -> BranchPoint {
        let n = self.n;
        let m = &s.flow.monodromy;
        let multipliers = Multipliers::of_matrix(m);
        BranchPoint {
            parameter: s.y[n],
            omega: self.omega_at(s.y[n]),
            x: StateVec::from_slice(&s.y.as_slice()[..n]),
            amplitude: s.flow.lambda_max - s.flow.lambda_min,
            lambda_min: s.flow.lambda_min,
            lambda_max: s.flow.lambda_max,
            stable: multipliers.stable(),
            multipliers,
            tests: TestFunctions::of_matrix(m),
            liouville_error: m.determinant() - s.flow.trace_integral.exp(),
        }
    }

    /// Difference vectors P^j(x) − x for each proper divisor j of k.
    fn divisor_gaps(&self, s: &Solved) -> Vec<(usize, StateVec)> {
        let x = s.flow.poincare[0];
        (1..self.k)
            .filter(|j| self.k.is_multiple_of(*j))
            .map(|j| {
                let mut d = s.flow.poincare[j];
                for (dc, xc) in d.iter_mut().zip(x.iter()) {
                    *dc -= xc;
                }
                (j, d)
            })
            .collect()
    }

    /// The root of `g` (g(0) and g(h) of opposite sign) along the secant from `from`, by
    /// false position on corrected points. Returns the point nearest the root and the last
    /// bracket's width in the parameter.
    fn locate(
        &self,
        from: &Solved,
        t: &DVector<f64>,
        (g0, g1, h, end): (f64, f64, f64, &Solved),
        g: impl Fn(&Solved) -> f64,
    ) -> (Solved, f64) {
        let n = self.n;
        let (mut lo, mut hi, mut g_lo, mut g_hi) = (0.0, h, g0, g1);
        let (mut s_lo, mut s_hi) = (from.clone(), end.clone());
        // the corrected point of the smallest test met: near a branch point the corrector
        // may land on the crossing branch, whose points then bracket nothing on this one
        let mut best = if g0.abs() <= g1.abs() {
            (g0.abs(), from.clone())
        } else {
            (g1.abs(), end.clone())
        };
        let mut side = 0;
        for _ in 0..40 {
            if (s_hi.y[n] - s_lo.y[n]).abs() < 1e-11 && (&s_hi.y - &s_lo.y).amax() < 1e-9 {
                break;
            }
            let mut sigma = lo + (hi - lo) * g_lo / (g_lo - g_hi);
            if !(sigma > lo && sigma < hi) {
                sigma = 0.5 * (lo + hi);
            }
            let Ok(trial) = self.correct(&from.y + t * sigma, t) else {
                break;
            };
            let gt = g(&trial);
            if gt.abs() < best.0 {
                best = (gt.abs(), trial.clone());
            }
            if gt == 0.0 {
                return (trial, 0.0);
            }
            if (gt < 0.0) == (g_lo < 0.0) {
                (lo, g_lo, s_lo) = (sigma, gt, trial);
                if side == 1 {
                    g_hi *= 0.5;
                }
                side = 1;
            } else {
                (hi, g_hi, s_hi) = (sigma, gt, trial);
                if side == -1 {
                    g_lo *= 0.5;
                }
                side = -1;
            }
        }
        let precision = (s_hi.y[n] - s_lo.y[n]).abs();
        (best.1, precision)
    }

    fn bifurcation(&self, kind: BifurcationKind, s: &Solved, precision: f64) -> Bifurcation {
        let p = self.point(s);
        Bifurcation {
            kind,
            parameter: p.parameter,
            omega: p.omega,
            x: p.x,
            amplitude: p.amplitude,
            multipliers: p.multipliers,
            precision,
            period: self.k,
        }
    }

    /// The bifurcations whose test functions change sign between `a` and `b`, located.
    fn crossings(&self, a: &Solved, b: &Solved, t: &DVector<f64>, h: f64) -> Vec<Bifurcation> {
        let (ta, tb) = (
            TestFunctions::of_matrix(&a.flow.monodromy),
            TestFunctions::of_matrix(&b.flow.monodromy),
        );
        let mut found = Vec::new();
        let tests: [(BifurcationKind, TestOf); 3] = [
            (BifurcationKind::Fold, |t| Some(t.fold)),
            (BifurcationKind::PeriodDoubling, |t| Some(t.flip)),
            (BifurcationKind::NeimarkSacker, |t| t.torus),
        ];
        let circle = |s: &Solved| UnitCircle::of(&Multipliers::of_matrix(&s.flow.monodromy));
        for (kind, f) in tests {
            let (Some(ga), Some(gb)) = (f(&ta), f(&tb)) else {
                continue;
            };
            // (the multipliers again only where the torus test changed sign)
            if (ga < 0.0) != (gb < 0.0)
                && (kind != BifurcationKind::NeimarkSacker
                    // pairs meeting on the real axis change the product's sign too
                    || circle(a).torus_between(&circle(b)))
            {
                let g = |s: &Solved| f(&TestFunctions::of_matrix(&s.flow.monodromy)).unwrap_or(ga);
                let (at, precision) = self.locate(a, t, (ga, gb, h, b), g);
                // a multiplier through +1 is a fold only where the branch turns back
                let kind = match kind {
                    BifurcationKind::Fold if !Self::turns(b, t) => BifurcationKind::BranchPoint,
                    kind => kind,
                };
                found.push(self.bifurcation(kind, &at, precision));
            }
        }
        found
    }

    /// The divisor period j whose Poincaré points of `s` coincide within
    /// [`PARENT_GAP`]: `s` is a period-j response counted k/j times.
    fn on_parent(&self, s: &Solved) -> Option<usize> {
        self.divisor_gaps(s)
            .into_iter()
            .find(|(_, d)| d.iter().fold(0.0f64, |m, v| m.max(v.abs())) < PARENT_GAP)
            .map(|(j, _)| j)
    }

    /// The divisor period j whose gap P^j(x) − x reversed between `a` and `b`: its Poincaré
    /// points merged in between, at the parent's period doubling.
    fn reversed_gap(&self, a: &Solved, b: &Solved) -> Option<usize> {
        let (ga, gb) = (self.divisor_gaps(a), self.divisor_gaps(b));
        let norm = |v: &StateVec| v.iter().fold(0.0f64, |m, c| m.hypot(*c));
        ga.into_iter().zip(gb).find_map(|((j, da), (_, db))| {
            let dot = da.iter().zip(db.iter()).fold(0.0, |s, (a, b)| s + a * b);
            let norms = norm(&da) * norm(&db);
            (dot < -0.5 * norms).then_some(j)
        })
    }

    /// The period doubling of the period-j parent between the branch points `a` and `b`:
    /// the parent is shot at fixed parameter from the mid-points of the merging Poincaré
    /// points, and its flip test det(M_j + I) is driven to zero by the secant method in μ
    /// (the doubling sits at the branch's turning point, outside [μ_a, μ_b] in general).
    fn parent_period_doubling(&self, j: usize, a: &Solved, b: &Solved) -> Bifurcation {
        let n = self.n;
        let shooting = &self.spec.shooting;
        let parent = |s: &Solved, mu: f64, seed: Option<StateVec>| {
            let x = s.flow.poincare[0];
            let pj = s.flow.poincare[j];
            let guess = seed.unwrap_or_else(|| {
                let mut mid = x;
                for (m, p) in mid.iter_mut().zip(pj.iter()) {
                    *m = 0.5 * (*m + p);
                }
                mid
            });
            let p = self.params_at(mu)?;
            shoot(&p, j, &guess, shooting).ok()
        };
        let flip = |o: &PeriodicOrbit| TestFunctions::of_matrix(&o.monodromy_matrix()).flip;
        let mut best = parent(b, b.y[n], None).map(|o| (b.y[n], o));
        let mut other = parent(a, a.y[n], None).map(|o| (a.y[n], o));
        let mut precision = (b.y[n] - a.y[n]).abs();
        for _ in 0..30 {
            let (Some((m1, o1)), Some((m0, o0))) = (&best, &other) else {
                break;
            };
            let (f1, f0) = (flip(o1), flip(o0));
            if f1 == f0 || precision < 1e-12 {
                break;
            }
            let step = (-f1 * (m1 - m0) / (f1 - f0)).clamp(-0.05, 0.05);
            let mu = m1 + step;
            let Some(o) = parent(b, mu, Some(o1.poincare[0])) else {
                break;
            };
            precision = step.abs();
            other = best.take();
            best = Some((mu, o));
        }
        let mut bif = self.bifurcation(BifurcationKind::ParentPeriodDoubling, b, precision);
        bif.period = j;
        if let Some((mu, o)) = best {
            bif.parameter = mu;
            bif.omega = self.omega_at(mu);
            bif.x = o.poincare[0];
            bif.amplitude = o.amplitude;
            bif.multipliers = o.multipliers.clone();
        }
        bif
    }

    /// Continues from `start` along `t0` until an end; returns the points after `start`.
    fn run(
        &self,
        start: &Solved,
        t0: DVector<f64>,
        seed: &[StateVec],
        progress: &Progress,
    ) -> Result<(Vec<BranchPoint>, Vec<Bifurcation>, BranchEnd), ContinuationError> {
        let spec = self.spec;
        let n = self.n;
        let (mut prev, mut t, mut h) = (start.clone(), t0, spec.step);
        let mut points = Vec::new();
        let mut bifs = Vec::new();
        let mu0 = start.y[n];
        loop {
            if progress.is_cancelled() {
                return Err(ContinuationError::Cancelled);
            }
            if points.len() >= spec.max_points {
                return Ok((points, bifs, BranchEnd::MaxPoints));
            }
            let next = match self.correct(&prev.y + &t * h, &t) {
                Ok(s) => Some(s),
                Err(Failure::Collision(c)) if h <= spec.step_min => {
                    return Ok((
                        points,
                        bifs,
                        BranchEnd::Collision {
                            tau: c.tau,
                            lambda_i: c.lambda_i,
                        },
                    ));
                }
                Err(_) => None,
            };
            let next = next.and_then(|s| {
                let tn = Self::tangent(&s, &t)?;
                // refuse a step whose corrector moved far from the predictor or that turns
                // the tangent sharply: it may have jumped to another part of the branch
                let moved = (&s.y - (&prev.y + &t * h)).norm();
                let smooth = tn.dot(&t) > 0.9 && moved < 0.3 * h;
                (smooth || h <= spec.step_min).then_some((s, tn))
            });
            let Some((next, t_next)) = next else {
                if h <= spec.step_min {
                    return Ok((points, bifs, BranchEnd::StepTooSmall));
                }
                h = (h * 0.5).max(spec.step_min);
                continue;
            };
            // a branch's length is not known ahead: each point is counted as it is done
            progress.step();
            // the end of the parameter range
            let mu = next.y[n];
            if mu < spec.min || mu > spec.max {
                let bound = if mu < spec.min { spec.min } else { spec.max };
                let g = |s: &Solved| s.y[n] - bound;
                let (at, _) = self.locate(&prev, &t, (g(&prev), g(&next), h, &next), g);
                bifs.extend(self.crossings(&prev, &at, &t, t.dot(&(&at.y - &prev.y))));
                points.push(self.point(&at));
                return Ok((points, bifs, BranchEnd::Bound { value: bound }));
            }
            // the branch reaches a parent of period j: `next` sits on it (its Poincaré
            // points coincide) or the gap P^j(x) − x reversed since `prev`. Confirm with a
            // short step first: a long one can jump across a hairpin near a fold.
            if let Some(j) = self
                .on_parent(&next)
                .or_else(|| self.reversed_gap(&prev, &next))
            {
                if h > PARENT_CONFIRM_STEP.max(spec.step_min) {
                    h = (h * 0.25).max(spec.step_min);
                    continue;
                }
                bifs.push(self.parent_period_doubling(j, &prev, &next));
                return Ok((points, bifs, BranchEnd::Parent { period: j }));
            }
            bifs.extend(self.crossings(&prev, &next, &t, h));
            // back at the seed (or at one of its shifts, for a subharmonic)
            let (a, b) = (prev.y[n] - mu0, next.y[n] - mu0);
            if points.len() >= 4 && (a < 0.0) != (b < 0.0) {
                let w = a / (a - b);
                let xi: Vec<f64> = (0..n)
                    .map(|c| prev.y[c] + w * (next.y[c] - prev.y[c]))
                    .collect();
                let step_x = max_distance(&next.y.as_slice()[..n], &prev.y.as_slice()[..n]);
                let near = seed
                    .iter()
                    .any(|q| max_distance(q, &xi) < 0.25 * step_x + 1e-7);
                if near {
                    points.push(self.point(&next));
                    return Ok((points, bifs, BranchEnd::Closed));
                }
            }
            points.push(self.point(&next));
            h = match next.iterations {
                0..=2 => h * 1.5,
                3 => h,
                _ => h * 0.6,
            }
            .clamp(spec.step_min, spec.step_max);
            (prev, t) = (next, t_next);
        }
    }
}

/// The branch of period-`k` responses through the state `seed` at τ = 0 ([λ_I, v] for the
/// built-in model; a point near the response in `model`), continued both ways in
/// `spec.parameter`. The seed is first converged by Newton at fixed parameter.
pub fn continue_branch<M: Continuable>(
    model: &M,
    k: usize,
    seed: &[f64],
    spec: &ContinuationSpec,
    progress: &Progress,
) -> Result<ContinuedBranch, ContinuationError> {
    spec.validate(model)?;
    let orbit = shoot(model, k, seed, &spec.shooting)?;
    continue_from_orbit(model, &orbit, spec, progress)
}

/// The branch through a converged periodic response of `model`.
pub fn continue_from_orbit<M: Continuable>(
    model: &M,
    orbit: &PeriodicOrbit,
    spec: &ContinuationSpec,
    progress: &Progress,
) -> Result<ContinuedBranch, ContinuationError> {
    let problem = Problem::new(model, orbit.period, spec)?;
    let n = problem.n;
    let mu0 = model.value_of(problem.parameter);
    let start = problem
        .evaluate(&problem.join(&orbit.poincare[0], mu0))
        .map_err(|_| ShootingError::Singular)?;
    let mut along_mu = DVector::zeros(n + 1);
    along_mu[n] = 1.0;
    let t0 = Problem::<M>::tangent(&start, &along_mu).ok_or(ShootingError::Singular)?;
    let (fwd, mut bifs, end_fwd) = problem.run(&start, t0.clone(), &orbit.poincare, progress)?;
    let mut points = vec![problem.point(&start)];
    let end_start = if end_fwd == BranchEnd::Closed {
        BranchEnd::Closed
    } else {
        let (back, b2, end_back) = problem.run(&start, -t0, &orbit.poincare, progress)?;
        bifs.extend(b2);
        points = back.into_iter().rev().chain(points).collect();
        end_back
    };
    points.extend(fwd);
    Ok(ContinuedBranch {
        period: orbit.period,
        parameter: spec.parameter,
        base: model.base(),
        points,
        bifurcations: bifs,
        ends: [end_start, end_fwd],
    })
}

/// The null vector of M + I (the eigenvector of the multiplier −1), unit length: from a row
/// where n = 2, else the right singular vector of the smallest singular value.
fn flip_eigenvector(m: &DMatrix<f64>) -> DVector<f64> {
    let n = m.nrows();
    let a = m + DMatrix::<f64>::identity(n, n);
    if n == 2 {
        let row = |r: usize| a[(r, 0)].abs().max(a[(r, 1)].abs());
        let e = if row(0) >= row(1) {
            nalgebra::Vector2::new(-a[(0, 1)], a[(0, 0)])
        } else {
            nalgebra::Vector2::new(-a[(1, 1)], a[(1, 0)])
        }
        .normalize();
        return DVector::from_column_slice(e.as_slice());
    }
    let svd = a.svd(false, true);
    let v_t = svd.v_t.expect("asked for V");
    let smallest = svd.singular_values.imin();
    v_t.row(smallest).transpose().normalize()
}

/// At a period doubling of a period-k branch continued about `base`, the branch of period
/// 2k born there: started along the critical eigenvector (multiplier −1) and continued both
/// ways.
pub fn switch_at_period_doubling<M: Continuable>(
    base: &M,
    branch: &ContinuedBranch,
    pd: &Bifurcation,
    spec: &ContinuationSpec,
    progress: &Progress,
) -> Result<ContinuedBranch, ContinuationError> {
    let model = base.with(base.resolve(spec.parameter)?, pd.parameter)?;
    let k = branch.period;
    let flow = model
        .period_flow(&pd.x, k, spec.shooting.tol)
        .map_err(ContinuationError::Seed)?;
    let e = flip_eigenvector(&flow.monodromy);
    let problem = Problem::new(&model, 2 * k, spec)?;
    let n = problem.n;
    let t = DVector::from_fn(n + 1, |i, _| if i < n { e[i] } else { 0.0 });
    let origin = problem.join(&pd.x, pd.parameter);
    let mut h = spec.step;
    let first = loop {
        match problem.correct(&origin + &t * h, &t) {
            Ok(s) if (&s.y - &origin).amax() > 0.1 * h => break s,
            _ if h > spec.step_min => h *= 0.5,
            _ => {
                return Err(ContinuationError::Seed(ShootingError::NoConvergence {
                    iterations: spec.shooting.max_iterations,
                    residual: f64::NAN,
                }));
            }
        }
    };
    let at = problem
        .params_at(first.y[n])
        .ok_or(ShootingError::Singular)?;
    let orbit = PeriodicOrbit::from_flow(problem.omega_at(first.y[n]), 2 * k, &first.flow, 0);
    continue_from_orbit(&at, &orbit, spec, progress)
}
