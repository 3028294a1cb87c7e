//! Where an isola begins and ends across a model parameter (ADR, E_a, ...).
//!
//! - **Birth**: the isola shrinks to a point where its two folds meet. Its fold curve in
//!   (ω_e, parameter) passes through both folds and turns at the birth value: the minimum
//!   (or maximum) of the parameter along that curve, located to the continuation's accuracy.
//! - **Merging**: the isola touches the branch attached to the main response's period
//!   doublings and the two become one. Between a value where the branch through an isola
//!   orbit closes on itself and one where it ends on period doublings, the value is bisected;
//!   at each trial the isola's orbit is followed in the parameter at fixed ω_e and its branch
//!   continued in ω_e. The precision is the final bracket's width.

use serde::{Deserialize, Serialize};

use crate::analysis::continuation::bifurcation_curve::{
    CurvePoint, CurveSpec, Turning, continue_bifurcation,
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
    let second = ContinuationParameter::Model(parameter);
    let now = params.value_of(params.resolve(second)?);
    let Some(low) = isola
        .of_kind(BifurcationKind::Fold)
        .min_by(|a, b| a.omega.total_cmp(&b.omega))
    else {
        return Ok(None);
    };
    let spec = CurveSpec {
        second,
        max: now + 1e-3 * now.abs().max(1e-3),
        ..*curve
    };
    let c = continue_bifurcation(params, isola.parameter, low, &spec, progress)?;
    Ok(c.extrema_of(Turning::Second)
        .filter(|e| e.minimum)
        .min_by(|a, b| a.point.second.total_cmp(&b.point.second))
        .map(|e| limit(&e.point, e.precision)))
}

fn limit(p: &CurvePoint, precision: f64) -> IsolaLimit {
    IsolaLimit {
        value: p.second,
        // the curve's points solve their equations to the Newton tolerance with orbits
        // integrated at 1e-11: below 1e-9 the bracket says nothing
        precision: precision.max(1e-9),
        omega: p.omega,
        amplitude: p.amplitude,
    }
}

/// Where the isola `isola` (closed, continued in ω_e about `params`) merges with an attached
/// branch as `parameter` moves from its value in `params` to `towards` (where the branch is
/// attached): bisected to `tolerance`. `None` if at `towards` the branch is still closed.
pub fn isola_merge<M: Continuable>(
    params: &M,
    isola: &ContinuedBranch,
    parameter: FamilyParameter,
    towards: f64,
    spec: &ContinuationSpec,
    tolerance: f64,
    progress: &Progress,
) -> Result<Option<IsolaLimit>, ContinuationError> {
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
    Ok(Some(IsolaLimit {
        value: 0.5 * (closed + merged),
        precision: 0.5 * (merged - closed).abs(),
        omega: fold.omega,
        amplitude: fold.amplitude,
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
    let hi = spec.values.iter().fold(f64::NEG_INFINITY, |a, &v| a.max(v));
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
                let at = if t.after.is_some() { t.to } else { t.from };
                match isola_at(at, t.period) {
                    Some(h) => {
                        let p = params.with(model, at)?;
                        let p = p.with(p.frequency(), h.peak_omega)?;
                        // a birth bracketed by these values turns above the lower one, a
                        // valid model of the family
                        let curve = CurveSpec {
                            first_min: c.min,
                            first_max: c.max,
                            min: t.from.min(t.to),
                            max: hi,
                            ..CurveSpec::default()
                        };
                        let found = isola_birth(&p, &h.branch, spec.parameter, &curve, progress)?;
                        // a birth bracketed by these two values
                        found.filter(|l| l.value >= t.from.min(t.to) && l.value <= t.to.max(t.from))
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
