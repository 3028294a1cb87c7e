//! An orbit picked off a plot: the model it runs on (the built-in DEA or the session's written
//! model, at the picked point's ω_e and parameter), where it starts, and its record.

use isola::analysis::Oscillator;
use isola::analysis::global::oscillator::history::{StateHistory, state_history_from};
use isola::analysis::orbit::steady_state::SteadyState;
use isola::analysis::orbit::time_history::{TimeHistory, TimeHistorySpec, time_history};
use isola::analysis::parameter::ContinuationParameter;
use isola::model::equations::EquationSystem;
use isola::model::system::{System, Vector, outside_grid};
use isola::model::{Device, ParamError, Params};
use isola::session::export;
use isola::session::results::HistoryView;
use isola::session::schema::Settings;
use isola::session::written::ModelPoint;

use super::plots::Start;

/// The model of a picked orbit and its start.
pub enum OrbitModel {
    /// The built-in model, from the spec's offsets (Δλ, v).
    BuiltIn(Box<Params>),
    /// A written model, from a whole state.
    Written(Box<EquationSystem>, Box<Vector>),
}

/// A picked orbit's record.
pub enum OrbitHistory {
    BuiltIn(TimeHistory),
    /// With the indices of the two states its grid spans.
    Written(StateHistory, [usize; 2]),
}

impl OrbitHistory {
    /// The response it settled on.
    pub fn steady_state(&self) -> &SteadyState {
        match self {
            OrbitHistory::BuiltIn(h) => &h.steady_state,
            OrbitHistory::Written(h, _) => &h.steady_state,
        }
    }

    /// Its CSV, as its model's time history analysis writes it.
    pub fn csv_bytes(&self, device: &Device) -> anyhow::Result<Vec<u8>> {
        match self {
            OrbitHistory::BuiltIn(h) => export::history_bytes(h, device),
            OrbitHistory::Written(h, grid) => export::state_history_bytes(h, *grid),
        }
    }
}

/// `model` at the picked point: `member` the value of a family's or a continuation's
/// parameter (as `settings` names it), `omega` the forcing frequency.
pub fn at_pick(
    model: ModelPoint,
    settings: &Settings,
    member: Option<f64>,
    omega: Option<f64>,
) -> Result<ModelPoint, ParamError> {
    Ok(match model {
        ModelPoint::BuiltIn(p) => ModelPoint::BuiltIn(moved(&p, settings, member, omega)?),
        ModelPoint::Written(s) => ModelPoint::Written(moved(&s, settings, member, omega)?),
    })
}

fn moved<O: Oscillator>(
    base: &O,
    settings: &Settings,
    member: Option<f64>,
    omega: Option<f64>,
) -> Result<O, ParamError> {
    let parameter = match settings {
        Settings::Family(spec) => Some(ContinuationParameter::Model(spec.parameter)),
        Settings::Continuation(spec) => Some(spec.continuation.parameter),
        _ => None,
    };
    let at_member = match (parameter, member) {
        (Some(parameter), Some(value)) => base.with(base.resolve(parameter)?, value)?,
        _ => base.clone(),
    };
    match omega {
        Some(w) => at_member.with(at_member.frequency(), w),
        None => Ok(at_member),
    }
}

/// The orbit of `model` from `start`, with the spec it is integrated by (the built-in
/// model's start is the spec's offset; a written model's, its whole state) and a label
/// naming where it starts.
pub fn orbit_from(model: ModelPoint, start: &Start) -> (OrbitModel, TimeHistorySpec, String) {
    match model {
        ModelPoint::BuiltIn(p) => {
            let [dx0, v0] = match start {
                Start::Absolute(x) => [x[0] - p.lambda_p(), x[1]],
                Start::Offset(s) => *s,
            };
            let spec = TimeHistorySpec {
                dx0,
                v0,
                ..TimeHistorySpec::default()
            };
            let from = format!("from Δλ {dx0:+.3}, v {v0:+.3}");
            (OrbitModel::BuiltIn(Box::new(p)), spec, from)
        }
        ModelPoint::Written(sys) => {
            let grid = sys.model().grid();
            let x = match start {
                Start::Absolute(values) => whole_state(&sys, values),
                Start::Offset(s) => sys.grid_start(*s),
            };
            let names = sys.model().states();
            let from = format!(
                "from {} {:.4}, {} {:.4}",
                names[grid[0]], x[grid[0]], names[grid[1]], x[grid[1]]
            );
            let model = OrbitModel::Written(Box::new(sys), Box::new(x));
            (model, TimeHistorySpec::default(), from)
        }
    }
}

/// The whole state of a response's start as a plot holds it: the grid's two states, then the
/// others in the model's order; where the others are missing (a result written before they
/// were kept), the model's origin.
fn whole_state(sys: &EquationSystem, values: &[f64]) -> Vector {
    let grid = sys.model().grid();
    let mut x = *sys.origin();
    let others: Vec<usize> = outside_grid(sys.dim(), grid).collect();
    if let [a, b, rest @ ..] = values {
        (x[grid[0]], x[grid[1]]) = (*a, *b);
        if rest.len() == others.len() {
            for (&i, &value) in others.iter().zip(rest) {
                x[i] = value;
            }
        }
    }
    x
}

/// Integrates a picked orbit: its record and its view (a written model's recording stops at
/// `cancel`).
pub fn integrate(
    model: &OrbitModel,
    spec: &TimeHistorySpec,
    cancel: &std::sync::atomic::AtomicBool,
) -> Result<(OrbitHistory, HistoryView), String> {
    match model {
        OrbitModel::BuiltIn(p) => {
            let h = time_history(p, spec).map_err(|e| e.to_string())?;
            let view = HistoryView::from(&h).summarised(p);
            Ok((OrbitHistory::BuiltIn(h), view))
        }
        OrbitModel::Written(sys, start) => {
            let h = state_history_from(sys, start, spec, cancel).map_err(|e| e.to_string())?;
            let grid = sys.model().grid();
            let view = HistoryView::of_states(&h, grid, sys.omega());
            Ok((OrbitHistory::Written(h, grid), view))
        }
    }
}
