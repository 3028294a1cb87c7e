//! Where an isola begins and ends across a model parameter (ADR, E_a, ...).
//!
//! - **Birth** and **vanishing**: the isola shrinks to a point where its two folds meet. Its
//!   fold curve in (ω_e, parameter) passes through both folds and turns there: a minimum of
//!   the parameter along that curve (a birth as the parameter rises) or a maximum (the isola
//!   vanishes), located to the continuation's accuracy.
//! - **Merging**: the isola touches the branch attached to the main response's period
//!   doublings and the two become one. Between a value where the branch through an isola
//!   orbit closes on itself and one where it ends on period doublings, the value is bisected;
//!   at each trial the isola's orbit is followed in the parameter at fixed ω_e and its branch
//!   continued in ω_e. Then, as the bracket depends on the continuation's steps, the value is
//!   located exactly as the turning point of the fold curve the attached branch gains there.

use serde::{Deserialize, Serialize};

use crate::analysis::continuation::bifurcation_curve::{
    CurvePoint, CurveSpec, Turning, continue_bifurcation, turning_point,
};
use crate::analysis::continuation::branch::{
    BifurcationKind, ContinuationError, ContinuationSpec, ContinuedBranch, continue_branch,
    continue_from_orbit,
};
use crate::analysis::continuation::hunt::Verdict;
use crate::analysis::continuation::hunt_family::{
    HuntFamilySpec, HuntMember, Transition, transitions,
};
use crate::analysis::continuation::model::Continuable;
use crate::analysis::parameter::ContinuationParameter;
use crate::analysis::parameter::FamilyParameter;
use crate::analysis::progress::Progress;

/// A located limit of an isola.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct IsolaLimit {
    /// The parameter's value there.
    pub value: f64,
    /// ± on `value`.
    pub precision: f64,
    pub omega: f64,
    pub amplitude: f64,
}

/// Where the closed branch `isola` (continued in ω_e about `params`) is born in `parameter`:
/// its lowest fold continued in (ω_e, `parameter`) down to where the two folds meet. `curve`
/// bounds the continuation (its `second` is replaced by `parameter`; its upper bound by the
/// current value, so the curve ends at the isola's other fold). `None` if the curve does not
/// turn within the bounds.
pub fn isola_birth<M: Continuable>(
    params: &M,
    isola: &ContinuedBranch,
    parameter: FamilyParameter,
    curve: &CurveSpec,
    progress: &Progress,
) -> Result<Option<IsolaLimit>, ContinuationError> {
    isola_shrinks(params, isola, parameter, curve, Towards::Below, progress)
}

/// Where the closed branch `isola` vanishes as `parameter` rises: its lowest fold continued
/// in (ω_e, `parameter`) up to where the two folds meet, the curve's maximum in `parameter`.
/// `curve` bounds the continuation as for [`isola_birth`], its lower bound replaced by the
/// current value. `None` if the curve does not turn within the bounds.
pub fn isola_vanishing<M: Continuable>(
    params: &M,
    isola: &ContinuedBranch,
    parameter: FamilyParameter,
    curve: &CurveSpec,
    progress: &Progress,
) -> Result<Option<IsolaLimit>, ContinuationError> {
    isola_shrinks(params, isola, parameter, curve, Towards::Above, progress)
}

/// On which side of the current value an isola shrinks to a point.
#[derive(Clone, Copy, PartialEq)]
enum Towards {
    Below,
    Above,
}

/// The turning point of the fold curve through the isola's lowest fold, on the `side` of
/// the current value of `parameter` (a minimum below, a maximum above).
fn isola_shrinks<M: Continuable>(
    params: &M,
    isola: &ContinuedBranch,
    parameter: FamilyParameter,
    curve: &CurveSpec,
    side: Towards,
    progress: &Progress,
) -> Result<Option<IsolaLimit>, ContinuationError> {
    let second = ContinuationParameter::Model(parameter);
    let now = params.value_of(params.resolve(second)?);
    let Some(low) = isola
        .of_kind(BifurcationKind::Fold)
        .min_by(|a, b| a.omega.total_cmp(&b.omega))
    else {
        return Ok(None);
    };
    // a little past the current value, so that the curve ends beyond the isola's other fold
    let past = 1e-3 * now.abs().max(1e-3);
    let spec = match side {
        Towards::Below => CurveSpec {
            second,
            max: now + past,
            ..*curve
        },
        Towards::Above => CurveSpec {
            second,
            min: now - past,
            ..*curve
        },
    };
    let minimum = side == Towards::Below;
    let turning = turning_point(params, isola.parameter, low, &spec, minimum, progress)?;
    Ok(turning.map(|e| limit(&e.point, e.precision)))
}

fn limit(p: &CurvePoint, precision: f64) -> IsolaLimit {
    IsolaLimit {
        value: p.second,
        // the orbits are integrated to 1e-11: below 1e-9 the estimate says nothing
        precision: precision.max(1e-9),
        omega: p.omega,
        amplitude: p.amplitude,
    }
}

/// Where the isola `isola` (closed, continued in ω_e about `params`) merges with an attached
/// branch as `parameter` moves from its value in `params` to `towards` (where the branch is
/// attached).
///
/// First bisected to `tolerance` between closed and attached. Near the merging the gap
/// between the isola and the branch is narrow, and whether a continuation crosses it depends
/// on its steps and on the orbit it starts from (brackets from other seeds differ by up to
/// about 1e-4 in ADR at the paper's point, much more than their widths). So the value is
/// then located exactly: where the two touch, the attached branch gains a fold (the facing
/// folds of isola and branch lie on one fold curve, which turns at the merging value), and
/// the turning point of that fold curve nearest the bracket, within a margin of the
/// dependence, is the merging, to the curve's precision. If no fold curve turns there, the
/// bisection is repeated with half the continuation steps, and the value is the middle of
/// the two brackets' union, its half-width the precision. `None` if at `towards` the branch
/// is still closed, or a bisection meets a picture that is not a simple merging.
pub fn isola_merge<M: Continuable>(
    params: &M,
    isola: &ContinuedBranch,
    parameter: FamilyParameter,
    towards: f64,
    spec: &ContinuationSpec,
    tolerance: f64,
    progress: &Progress,
) -> Result<Option<IsolaLimit>, ContinuationError> {
    let Some(first) = bisect_merge(params, isola, parameter, towards, spec, tolerance, progress)?
    else {
        return Ok(None);
    };
    let from = params.value_of(params.resolve(ContinuationParameter::Model(parameter))?);
    let margin = (10.0 * tolerance).max(1e-3 * (towards - from).abs());
    if let Some(exact) =
        merge_on_fold_curve(&first, parameter, towards > from, margin, spec, progress)?
    {
        return Ok(Some(exact));
    }
    let finer = ContinuationSpec {
        step: 0.5 * spec.step,
        step_max: 0.5 * spec.step_max,
        ..*spec
    };
    let Some(second) = bisect_merge(
        params, isola, parameter, towards, &finer, tolerance, progress,
    )?
    else {
        return Ok(None);
    };
    let lo = first.bracket[0].min(second.bracket[0]);
    let hi = first.bracket[1].max(second.bracket[1]);
    Ok(Some(IsolaLimit {
        value: 0.5 * (lo + hi),
        precision: 0.5 * (hi - lo),
        omega: second.omega,
        amplitude: second.amplitude,
    }))
}

/// One bisection of a merging: the final bracket in the parameter (increasing), where the
/// isola's fold touches the attached branch, and the attached branch at the bracket's end
/// (with the model there).
struct Merging<M> {
    bracket: [f64; 2],
    omega: f64,
    amplitude: f64,
    attached: ContinuedBranch,
    attached_at: M,
}

/// The merging as the turning point (a minimum of the parameter if it `rises` towards the
/// attached side, else a maximum) of the fold curve through one of the attached branch's
/// folds, within `margin` of the bisection's bracket: the one nearest the bracket's middle.
fn merge_on_fold_curve<M: Continuable>(
    m: &Merging<M>,
    parameter: FamilyParameter,
    rises: bool,
    margin: f64,
    spec: &ContinuationSpec,
    progress: &Progress,
) -> Result<Option<IsolaLimit>, ContinuationError> {
    let [lo, hi] = [m.bracket[0] - margin, m.bracket[1] + margin];
    let curve = CurveSpec {
        second: ContinuationParameter::Model(parameter),
        min: lo,
        max: hi,
        first_min: spec.min,
        first_max: spec.max,
        ..CurveSpec::default()
    };
    let middle = 0.5 * (m.bracket[0] + m.bracket[1]);
    let mut nearest: Option<IsolaLimit> = None;
    for fold in m.attached.of_kind(BifurcationKind::Fold) {
        let c = continue_bifurcation(&m.attached_at, m.attached.parameter, fold, &curve, progress)?;
        for e in c.extrema_of(Turning::Second) {
            let value = e.point.second;
            let closer = nearest
                .as_ref()
                .is_none_or(|n| (value - middle).abs() < (n.value - middle).abs());
            if e.minimum == rises && (lo..=hi).contains(&value) && closer {
                nearest = Some(limit(&e.point, e.precision));
            }
        }
    }
    Ok(nearest)
}

/// [`isola_merge`]'s bisection with the continuation steps of `spec`.
fn bisect_merge<M: Continuable>(
    params: &M,
    isola: &ContinuedBranch,
    parameter: FamilyParameter,
    towards: f64,
    spec: &ContinuationSpec,
    tolerance: f64,
    progress: &Progress,
) -> Result<Option<Merging<M>>, ContinuationError> {
    let model = ContinuationParameter::Model(parameter);
    let resolved = params.resolve(model)?;
    let from = params.value_of(resolved);
    // follow a mid-range stable orbit of the isola in the parameter at fixed ω_e
    let (w_lo, w_hi) = isola.parameter_range();
    let middle = 0.5 * (w_lo + w_hi);
    let Some(seed) = isola.points.iter().filter(|p| p.stable).min_by(|a, b| {
        (a.omega - middle)
            .abs()
            .total_cmp(&(b.omega - middle).abs())
    }) else {
        return Ok(None);
    };
    let at_seed = params.with(params.frequency(), seed.omega)?;
    // a little past both ends, so that both are crossed, not just reached
    let margin = 0.01 * (towards - from).abs();
    let in_parameter = ContinuationSpec {
        parameter: model,
        min: from.min(towards) - margin,
        max: from.max(towards) + margin,
        ..*spec
    };
    let along = continue_branch(&at_seed, isola.period, &seed.x, &in_parameter, progress)?;
    type Trial = Option<(Verdict, ContinuedBranch)>;
    let verdict_at = |value: f64| -> Result<Trial, ContinuationError> {
        let orbits = along.orbits_at(&at_seed, value, &spec.shooting)?;
        let Some(orbit) = orbits
            .into_iter()
            .max_by(|a, b| a.amplitude.total_cmp(&b.amplitude))
        else {
            return Ok(None);
        };
        let p = at_seed.with(resolved, value)?;
        let branch = continue_from_orbit(&p, &orbit, spec, progress)?;
        Ok(Some((Verdict::of(&branch), branch)))
    };
    let attached = |v: Verdict| matches!(v, Verdict::Attached | Verdict::HalfAttached);
    // the branches at both ends of the bracket, kept as it narrows
    let mut after = match verdict_at(towards)? {
        Some((v, b)) if attached(v) => b,
        _ => return Ok(None),
    };
    let mut before = isola.clone();
    let (mut closed, mut merged) = (from, towards);
    while (merged - closed).abs() > tolerance {
        let mid = 0.5 * (closed + merged);
        match verdict_at(mid)? {
            Some((Verdict::Isola, b)) => (closed, before) = (mid, b),
            Some((v, b)) if attached(v) => (merged, after) = (mid, b),
            // no orbit there, or a branch that ends elsewhere: the picture is not simple
            _ => return Ok(None),
        }
    }
    // where the two touch: the isola's fold (just before) nearest a parent doubling of the
    // attached branch (just after)
    let doublings: Vec<f64> = after
        .of_kind(BifurcationKind::ParentPeriodDoubling)
        .map(|b| b.omega)
        .collect();
    let distance = |w: f64| {
        doublings
            .iter()
            .map(|d| (d - w).abs())
            .fold(f64::INFINITY, f64::min)
    };
    let Some(fold) = before
        .of_kind(BifurcationKind::Fold)
        .min_by(|a, b| distance(a.omega).total_cmp(&distance(b.omega)))
    else {
        return Ok(None);
    };
    Ok(Some(Merging {
        bracket: [closed.min(merged), closed.max(merged)],
        omega: fold.omega,
        amplitude: fold.amplitude,
        attached_at: at_seed.with(resolved, merged)?,
        attached: after,
    }))
}

/// Each birth and merging a hunt family's verdicts bracket, located: a birth (no branch →
/// isola) from the isola's fold curve, a merging (isola → attached) by bisection to
/// `tolerance`.
pub fn locate_limits<M: Continuable>(
    params: &M,
    spec: &HuntFamilySpec,
    members: &[HuntMember],
    tolerance: f64,
    progress: &Progress,
) -> Result<Vec<(Transition, Option<IsolaLimit>)>, ContinuationError> {
    let model = params.resolve(ContinuationParameter::Model(spec.parameter))?;
    let isola_at = |value: f64, k: usize| {
        members
            .iter()
            .find(|m| m.value == value)?
            .branches
            .iter()
            .filter(|b| b.branch.period == k && b.verdict == Verdict::Isola)
            .max_by(|a, b| a.peak_amplitude.total_cmp(&b.peak_amplitude))
    };
    let mut out = Vec::new();
    for t in transitions(members) {
        let c = &spec.hunt.continuation;
        let limit = match (t.before, t.after) {
            (None, Some(Verdict::Isola)) | (Some(Verdict::Isola), None) => {
                let born = t.after.is_some();
                let at = if born { t.to } else { t.from };
                match isola_at(at, t.period) {
                    Some(h) => {
                        let p = params.with(model, at)?;
                        let p = p.with(p.frequency(), h.peak_omega)?;
                        // the curve stays within the bracket (both ends valid models of the
                        // family); the side towards the isola is set by the locator
                        let curve = CurveSpec {
                            first_min: c.min,
                            first_max: c.max,
                            min: t.from,
                            max: t.to,
                            ..CurveSpec::default()
                        };
                        let found = if born {
                            isola_birth(&p, &h.branch, spec.parameter, &curve, progress)?
                        } else {
                            isola_vanishing(&p, &h.branch, spec.parameter, &curve, progress)?
                        };
                        found.filter(|l| l.value >= t.from && l.value <= t.to)
                    }
                    None => None,
                }
            }
            (Some(Verdict::Isola), Some(Verdict::Attached | Verdict::HalfAttached)) => {
                match isola_at(t.from, t.period) {
                    Some(h) => {
                        let p = params.with(model, t.from)?;
                        let p = p.with(p.frequency(), h.peak_omega)?;
                        isola_merge(&p, &h.branch, spec.parameter, t.to, c, tolerance, progress)?
                    }
                    None => None,
                }
            }
            _ => None,
        };
        out.push((t, limit));
    }
    Ok(out)
}
