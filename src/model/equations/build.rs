//! From a [`ModelDefinition`] to a compiled [`EquationModel`]: names resolved, definitions
//! checked for cycles, kinks registered as switching functions, the Jacobian and the output's
//! rate derived symbolically, and the tapes compiled.

use std::collections::{BTreeMap, HashMap};
use std::sync::Arc;

use toml::Spanned;

use super::EquationError;
use super::definition::{ModelDefinition, expression_start, line_column};
use super::graph::{Func, Graph, MAX_SWITCHES, NodeId, Op2, Wrt};
use super::parse::{Ast, BinOp, CmpOp, Span, parse};
use super::tape::{FieldIo, Tape};
use crate::model::system::MAX_DIM;

/// A condition: true where a switching-like value is positive (or zero when not strict).
#[derive(Debug, Clone)]
pub enum Cond {
    Positive { value: NodeId, strict: bool },
    And(Box<Cond>, Box<Cond>),
    Or(Box<Cond>, Box<Cond>),
}

impl Cond {
    /// Whether the condition stops a trajectory in each of `L` lanes, reading each node's
    /// lanes with `value` (one lane for a single state): where it holds, and where it has no
    /// truth value (a comparison of NaN that decides it; `a && b` with `a` false needs no
    /// `b`). [`EquationSystem`](super::EquationSystem) tells the two apart.
    #[inline(always)]
    pub(crate) fn stops<const L: usize>(&self, value: &impl Fn(NodeId) -> [f64; L]) -> [bool; L] {
        self.decide(value).1
    }

    /// Where it has no truth value in each lane (it stops, yet does not hold).
    pub(crate) fn undefined<const L: usize>(
        &self,
        value: &impl Fn(NodeId) -> [f64; L],
    ) -> [bool; L] {
        let (holds, stops) = self.decide(value);
        std::array::from_fn(|l| stops[l] && !holds[l])
    }

    /// Whether it holds in each lane, and whether it holds or has no truth value. A
    /// comparison, the common condition, is inlined; `&&` and `||` recurse.
    #[inline(always)]
    fn decide<const L: usize>(
        &self,
        value: &impl Fn(NodeId) -> [f64; L],
    ) -> ([bool; L], [bool; L]) {
        match self {
            Cond::Positive { value: id, strict } => {
                let s = value(*id);
                if *strict {
                    (s.map(|s| s > 0.0), s.map(|s| s > 0.0 || s.is_nan()))
                } else {
                    (s.map(|s| s >= 0.0), s.map(|s| s >= 0.0 || s.is_nan()))
                }
            }
            Cond::And(a, b) => Cond::both(a, b, value, true),
            Cond::Or(a, b) => Cond::both(a, b, value, false),
        }
    }

    /// `a && b` (`and`) or `a || b` decided lane by lane (out of line: the recursion).
    #[inline(never)]
    fn both<const L: usize>(
        a: &Cond,
        b: &Cond,
        value: &impl Fn(NodeId) -> [f64; L],
        and: bool,
    ) -> ([bool; L], [bool; L]) {
        let ((a_holds, a_stops), (b_holds, b_stops)) = (a.decide(value), b.decide(value));
        if and {
            // a without a value stops; a true leaves it to b; a false does not stop
            (
                std::array::from_fn(|l| a_holds[l] && b_holds[l]),
                std::array::from_fn(|l| a_stops[l] && (!a_holds[l] || b_stops[l])),
            )
        } else {
            (
                std::array::from_fn(|l| a_holds[l] || b_holds[l]),
                std::array::from_fn(|l| a_stops[l] || b_stops[l]),
            )
        }
    }

    fn values(&self, out: &mut Vec<NodeId>) {
        match self {
            Cond::Positive { value, .. } => out.push(*value),
            Cond::And(a, b) | Cond::Or(a, b) => {
                a.values(out);
                b.values(out);
            }
        }
    }
}

/// A parameter of a written model.
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    pub name: String,
    pub default: f64,
    pub min: f64,
    pub max: f64,
    pub unit: Option<String>,
    pub about: Option<String>,
}

/// A written model, compiled. Cheap to share; [`EquationModel::system`] makes an integrable
/// instance for one set of parameter values.
#[derive(Debug, Clone)]
pub struct EquationModel {
    /// What the session's text compiled to, shared by every instance.
    pub inner: Arc<Compiled>,
}

/// A written model compiled: its names, graph and tapes, for every set of parameter values.
#[derive(Debug)]
pub struct Compiled {
    pub name: Option<String>,
    pub states: Vec<String>,
    pub parameters: Vec<Parameter>,
    pub frequency: usize,
    pub grid: [usize; 2],
    /// The origin of each state (fixed by the parameters).
    pub origin: Vec<NodeId>,
    pub graph: Graph,
    /// ∂f_i/∂x_j, row-major.
    pub jacobian: Vec<NodeId>,
    /// The amplitude's output and its rate.
    pub output: [NodeId; 2],
    /// The amplitude's expression as written.
    pub amplitude: String,
    pub collisions: Vec<Cond>,
    /// Each collision condition as written.
    pub collision_text: Vec<String>,
    /// Every named value (intermediates, then derivatives) in dependency order, to say which
    /// is the first that is not finite.
    pub named: Vec<(String, NodeId)>,
    /// The nodes that vary with time alone (the forcing), run by [`Registers::load`] once
    /// per time.
    pub time_tape: Tape,
    /// Whether every value read repeats with the forcing period, so that the time tape
    /// can be tabulated over one ([`super::time_table::TimeTable`]).
    pub periodic: bool,
    pub field_tape: Tape,
    /// The states' registers and their derivatives' (in state order), which the field's
    /// machine code reads and writes.
    pub field_io: FieldIo,
    /// The states' registers and the switching values' (in switch order), which the field
    /// tape's machine code for locating a switch reads and writes.
    pub switch_io: FieldIo,
    /// The derivatives and the Jacobian together.
    pub jacobian_tape: Tape,
    pub output_tape: Tape,
    pub collision_tape: Tape,
    pub named_tape: Tape,
    /// Per switching function h: ∂h/∂x_j for each state, then ∂h/∂τ.
    pub switch_gradients: Vec<Vec<NodeId>>,
    pub switch_gradient_tapes: Vec<Tape>,
    /// Bits of the switching functions across which the field is continuous
    /// ([`super::graph::Switch::continuous`]).
    pub continuous_switches: u64,
    /// The plain RK4 step as machine code, per lane count compiled for (one,
    /// [`super::tape::FEW_LANES`] and [`super::tape::NATIVE_LANES`]), compiled at its first
    /// use ([`Compiled::step_entry`]).
    #[cfg(target_arch = "x86_64")]
    step_code: [std::sync::OnceLock<Option<super::native::Native>>; 3],
}

impl Compiled {
    /// Every tape of the model: time, field, Jacobian, output, collision, named values, then
    /// each switching function's gradient.
    pub fn tapes(&self) -> Vec<&Tape> {
        let mut tapes = vec![
            &self.time_tape,
            &self.field_tape,
            &self.jacobian_tape,
            &self.output_tape,
            &self.collision_tape,
            &self.named_tape,
        ];
        tapes.extend(&self.switch_gradient_tapes);
        tapes
    }

    /// The plain RK4 step compiled for `lanes` (1, [`super::tape::FEW_LANES`] or
    /// [`super::tape::NATIVE_LANES`]) lanes, compiled now if it is the first call; `None`
    /// where tapes are interpreted.
    #[cfg(target_arch = "x86_64")]
    pub fn step_entry(&self, lanes: usize) -> Option<super::native_step::StepEntry> {
        self.step_code[super::tape::lane_slot(lanes)?]
            .get_or_init(|| {
                Tape::native_enabled()
                    .then(|| super::native_step::compile_step(self, lanes))
                    .flatten()
            })
            .as_ref()
            .map(super::native_step::entry)
    }
}

/// Stack of the compiler's thread (virtual: only what it uses is committed).
const BUILD_STACK: usize = 1 << 30;
/// Expressions built at most (each call of a function builds its body again): a model that
/// expands beyond this is refused rather than compiled for ever.
const MAX_WORK: usize = 5_000_000;

/// Names a written model may not take.
const RESERVED: [&str; 3] = ["t", "pi", "if"];

impl EquationModel {
    /// Compiles `def`, read from `doc` (the session's text, for lines and columns in errors;
    /// empty if there is none).
    pub fn new(def: &ModelDefinition, doc: &str) -> Result<EquationModel, EquationError> {
        // the builder recurses as deep as the expressions nest: on a stack of its own, so
        // that no model, however deep, can overflow the caller's
        std::thread::scope(|scope| {
            std::thread::Builder::new()
                .stack_size(BUILD_STACK)
                .spawn_scoped(scope, || Builder::new(def, doc)?.finish())
                .map_err(|e| EquationError {
                    place: "model".into(),
                    message: format!("cannot start the compiler: {e}"),
                })?
                .join()
                .unwrap_or_else(|_| {
                    Err(EquationError {
                        place: "model".into(),
                        message: "the compiler failed".into(),
                    })
                })
        })
        .map(|inner| EquationModel {
            inner: Arc::new(inner),
        })
    }

    /// The expression whose max − min is the amplitude, as written.
    pub fn amplitude_text(&self) -> &str {
        &self.inner.amplitude
    }

    pub fn name(&self) -> Option<&str> {
        self.inner.name.as_deref()
    }

    /// State names, in order.
    pub fn states(&self) -> &[String] {
        &self.inner.states
    }

    pub fn parameters(&self) -> &[Parameter] {
        &self.inner.parameters
    }

    /// Index of the forcing-frequency parameter.
    pub fn frequency(&self) -> usize {
        self.inner.frequency
    }

    /// The forcing-frequency parameter's name, as written.
    pub fn frequency_name(&self) -> &str {
        &self.inner.parameters[self.inner.frequency].name
    }

    /// Whether its time enters only as k·ω·t plus a fixed phase inside `sin`, `cos` or `tan`
    /// ([`super::graph::Graph::periodic_in_time`]): so it repeats with the forcing period,
    /// and a chirp can read ω·t as its phase.
    pub fn periodic_in_time(&self) -> bool {
        self.inner.periodic
    }

    /// Indices of the two states the grids span.
    pub fn grid(&self) -> [usize; 2] {
        self.inner.grid
    }

    /// Index of the parameter named `name`.
    pub fn parameter(&self, name: &str) -> Option<usize> {
        self.inner.parameters.iter().position(|p| p.name == name)
    }

    /// The default parameter values.
    pub fn defaults(&self) -> Vec<f64> {
        self.inner.parameters.iter().map(|p| p.default).collect()
    }
}

/// An expression's key and text, for errors.
#[derive(Debug, Clone)]
struct Place {
    key: String,
    /// Where the expression's text starts in the document, if known.
    start: Option<usize>,
    /// The line its value starts on, where its characters are not the document's (a
    /// string with escapes).
    line: Option<usize>,
}

struct Builder<'d> {
    def: &'d ModelDefinition,
    doc: &'d str,
    graph: Graph,
    states: HashMap<String, usize>,
    params: HashMap<String, usize>,
    lets: HashMap<String, (Ast, Place)>,
    functions: HashMap<String, (Vec<String>, Ast, Place)>,
    built: HashMap<String, NodeId>,
    /// Definitions being built, innermost last: a name met again is a cycle.
    building: Vec<String>,
    named: Vec<(String, NodeId)>,
    /// Expressions built so far (see [`MAX_WORK`]).
    work: usize,
}

fn at(place: &Place, message: impl Into<String>) -> EquationError {
    EquationError {
        place: place.key.clone(),
        message: message.into(),
    }
}

impl<'d> Builder<'d> {
    fn new(def: &'d ModelDefinition, doc: &'d str) -> Result<Builder<'d>, EquationError> {
        let mut b = Builder {
            def,
            doc,
            graph: Graph::default(),
            states: HashMap::new(),
            params: HashMap::new(),
            lets: HashMap::new(),
            functions: HashMap::new(),
            built: HashMap::new(),
            building: Vec::new(),
            named: Vec::new(),
            work: 0,
        };
        b.declare()?;
        Ok(b)
    }

    fn place(&self, key: String, value: &Spanned<String>) -> Place {
        Place {
            key,
            start: expression_start(self.doc, value),
            line: (value.span().start <= self.doc.len())
                .then(|| line_column(self.doc, value.span().start).0),
        }
    }

    /// The error at `span` of the expression at `place`: key, line and column, token.
    fn error_at(&self, place: &Place, span: Span, message: String) -> EquationError {
        let key = match place.start {
            Some(start) => {
                let (line, column) = line_column(self.doc, start + span.start);
                format!("{}, line {line}, column {column}", place.key)
            }
            None => match place.line {
                Some(line) => format!(
                    "{}, line {line}, character {} of its text",
                    place.key,
                    span.start + 1
                ),
                None => format!("{}, character {}", place.key, span.start + 1),
            },
        };
        EquationError {
            place: key,
            message,
        }
    }

    fn parse(&self, place: &Place, text: &str) -> Result<Ast, EquationError> {
        parse(text).map_err(|e| {
            let token = if e.token.is_empty() {
                "the end".to_string()
            } else {
                format!("`{}`", e.token)
            };
            self.error_at(place, e.span, format!("{} at {token}", e.message))
        })
    }

    /// Registers every name, checking they are valid and distinct.
    fn declare(&mut self) -> Result<(), EquationError> {
        let def = self.def;
        let mut taken: BTreeMap<String, &str> = BTreeMap::new();
        let mut claim = |name: &str, what: &'static str, key: String| {
            let place = Place {
                key,
                start: None,
                line: None,
            };
            let valid = name
                .chars()
                .next()
                .is_some_and(|c| c.is_alphabetic() || c == '_')
                && name.chars().all(|c| c.is_alphanumeric() || c == '_');
            if !valid {
                return Err(at(
                    &place,
                    format!("`{name}` is not a name (letters, digits, _)"),
                ));
            }
            if RESERVED.contains(&name) || Func::named(name).is_some() || is_kink(name) {
                return Err(at(&place, format!("`{name}` is a built-in name")));
            }
            if let Some(other) = taken.insert(name.to_string(), what) {
                return Err(at(&place, format!("`{name}` is already a {other}")));
            }
            Ok(())
        };
        if def.states.is_empty() || def.states.len() > MAX_DIM {
            return Err(at(
                &Place {
                    key: "model.states".into(),
                    start: None,
                    line: None,
                },
                format!("{} states: allowed 1 to {MAX_DIM}", def.states.len()),
            ));
        }
        for (i, s) in def.states.iter().enumerate() {
            claim(s, "state", "model.states".into())?;
            self.states.insert(s.clone(), i);
        }
        for (i, (name, p)) in def.parameters.iter().enumerate() {
            let key = format!("model.parameters.{name}");
            claim(name, "parameter", key.clone())?;
            let (lo, hi) = p.range();
            let place = Place {
                key,
                start: None,
                line: None,
            };
            // the range itself first: a NaN bound, or min above max, is the mistake to name
            if lo.is_nan() || hi.is_nan() || lo > hi {
                return Err(at(
                    &place,
                    format!("min = {lo} and max = {hi}: give min ≤ max, both numbers"),
                ));
            }
            if !p.value().is_finite() {
                return Err(at(
                    &place,
                    format!("value = {}: give a finite number", p.value()),
                ));
            }
            if !(lo..=hi).contains(&p.value()) {
                return Err(at(
                    &place,
                    format!("value {} is outside its range [{lo}, {hi}]", p.value()),
                ));
            }
            self.params.insert(name.clone(), i);
        }
        for (name, text) in &def.lets {
            let place = self.place(format!("model.let.{name}"), text);
            claim(name, "named value", place.key.clone())?;
            let ast = self.parse(&place, text.get_ref())?;
            self.lets.insert(name.clone(), (ast, place));
        }
        for (head, text) in &def.functions {
            let key = format!("model.functions.\"{head}\"");
            let place = self.place(key.clone(), text);
            let (name, args) = function_head(head).ok_or_else(|| {
                at(
                    &place,
                    "a function is written `name(arg, ...)`, e.g. \"g(lam)\"".to_string(),
                )
            })?;
            claim(&name, "function", key)?;
            if let Some(twice) =
                (args.iter().enumerate()).find_map(|(i, a)| args[..i].contains(a).then_some(a))
            {
                return Err(at(
                    &place,
                    format!(
                        "the argument `{twice}` is named twice in `{head}`: give each its own name"
                    ),
                ));
            }
            let ast = self.parse(&place, text.get_ref())?;
            self.functions.insert(name, (args, ast, place));
        }
        Ok(())
    }

    fn finish(mut self) -> Result<Compiled, EquationError> {
        let def = self.def;
        for name in def.derivatives.keys() {
            if !self.states.contains_key(name) {
                return Err(at(
                    &Place {
                        key: format!("model.derivatives.{name}"),
                        start: None,
                        line: None,
                    },
                    format!(
                        "`{name}` is not a state (states: {})",
                        def.states.join(", ")
                    ),
                ));
            }
        }
        let mut derivatives = Vec::new();
        for s in &def.states {
            let text = def.derivatives.get(s).ok_or_else(|| {
                at(
                    &Place {
                        key: "model.derivatives".into(),
                        start: None,
                        line: None,
                    },
                    format!("the state `{s}` has no derivative"),
                )
            })?;
            let place = self.place(format!("model.derivatives.{s}"), text);
            let ast = self.parse(&place, text.get_ref())?;
            let node = self.expr(&ast, &place, &HashMap::new())?;
            derivatives.push(node);
        }
        // every named value is built, used or not, so that each is checked
        let mut names: Vec<String> = self.lets.keys().cloned().collect();
        names.sort();
        for name in &names {
            self.named_value(name, None)?;
        }
        let amplitude_place = self.place("model.amplitude".into(), &def.amplitude);
        let amplitude_ast = self.parse(&amplitude_place, def.amplitude.get_ref())?;
        let y = self.expr(&amplitude_ast, &amplitude_place, &HashMap::new())?;
        let mut collisions = Vec::new();
        for (i, text) in def.collision.iter().enumerate() {
            let place = self.place(format!("model.collision[{i}]"), text);
            let ast = self.parse(&place, text.get_ref())?;
            collisions.push(self.cond(&ast, &place, &HashMap::new())?);
        }
        let grid = self.grid()?;
        let frequency = *self.params.get(&def.frequency).ok_or_else(|| {
            at(
                &Place {
                    key: "model.frequency".into(),
                    start: None,
                    line: None,
                },
                format!("`{}` is not a parameter", def.frequency),
            )
        })?;
        let zero = self.graph.num(0.0);
        let mut origin = vec![zero; def.states.len()];
        for (name, text) in &def.origin {
            let place = self.place(format!("model.origin.{name}"), text);
            let i = *self
                .states
                .get(name)
                .ok_or_else(|| at(&place, format!("`{name}` is not a state")))?;
            let ast = self.parse(&place, text.get_ref())?;
            let node = self.expr(&ast, &place, &HashMap::new())?;
            if self.graph.varying()[node as usize] {
                return Err(at(
                    &place,
                    "an origin depends on the parameters alone, not on t or a state",
                ));
            }
            origin[i] = node;
        }
        let g = &mut self.graph;
        let n = def.states.len();
        let mut jacobian = Vec::with_capacity(n * n);
        for &f in &derivatives {
            for j in 0..n {
                jacobian.push(g.derivative(f, Wrt::State(j as u8)));
            }
        }
        // dy/dτ = Σ ∂y/∂x_j f_j + ∂y/∂τ
        let mut rate = g.derivative(y, Wrt::Time);
        for (j, &f) in derivatives.iter().enumerate() {
            let dy = g.derivative(y, Wrt::State(j as u8));
            let term = g.mul(dy, f);
            rate = g.add(rate, term);
        }
        // ∇h and ∂h/∂τ of each switching function h, for the saltation of the monodromy
        // where a switch makes the field jump
        let switch_values: Vec<NodeId> = g.switches.iter().map(|s| s.value).collect();
        let switch_gradients: Vec<Vec<NodeId>> = switch_values
            .iter()
            .map(|&h| {
                let mut grad: Vec<NodeId> = (0..n)
                    .map(|j| g.derivative(h, Wrt::State(j as u8)))
                    .collect();
                grad.push(g.derivative(h, Wrt::Time));
                grad
            })
            .collect();
        let mut field_roots = derivatives.clone();
        field_roots.extend(g.switches.iter().map(|s| s.value));
        let mut collision_roots = Vec::new();
        for c in &collisions {
            c.values(&mut collision_roots);
        }
        self.named.sort_by_key(|(_, id)| *id);
        self.named.extend(
            def.states
                .iter()
                .zip(&derivatives)
                .map(|(s, &d)| (format!("model.derivatives.{s}"), d)),
        );
        let named_roots: Vec<NodeId> = self.named.iter().map(|(_, id)| *id).collect();
        let g = &self.graph;
        // what the integration evaluates at every stage: its time-only part once per time
        let hot = [field_roots.as_slice(), &collision_roots, &[y, rate]].concat();
        let time_only = Tape::time_only(g, &hot);
        let time_roots: Vec<NodeId> = (0..g.len() as NodeId)
            .filter(|&id| time_only[id as usize])
            .collect();
        let tape = |roots: &[NodeId]| Tape::new(g, roots, &time_only);
        let read = [hot.as_slice(), &jacobian, &switch_gradients.concat()].concat();
        let periodic = g.periodic_in_time(frequency as u16, &read);
        Ok(Compiled {
            name: def.name.clone(),
            states: def.states.clone(),
            parameters: def
                .parameters
                .iter()
                .map(|(name, p)| {
                    let (min, max) = p.range();
                    Parameter {
                        name: name.clone(),
                        default: p.value(),
                        min,
                        max,
                        unit: p.unit().map(str::to_string),
                        about: p.about().map(str::to_string),
                    }
                })
                .collect(),
            frequency,
            grid,
            origin,
            time_tape: Tape::new(g, &time_roots, &vec![false; g.len()]),
            periodic,
            field_tape: tape(&field_roots),
            jacobian_tape: tape(&[derivatives.as_slice(), &jacobian].concat()),
            field_io: FieldIo::new(g, derivatives),
            switch_io: FieldIo::new(g, g.switches.iter().map(|s| s.value).collect()),
            output_tape: tape(&[y, rate]),
            collision_tape: tape(&collision_roots),
            named_tape: tape(&named_roots),
            switch_gradient_tapes: switch_gradients.iter().map(|r| tape(r)).collect(),
            continuous_switches: (g.switches.iter().enumerate())
                .filter(|(_, s)| s.continuous)
                .fold(0, |mask, (k, _)| mask | 1 << k),
            switch_gradients,
            jacobian,
            output: [y, rate],
            amplitude: def.amplitude.get_ref().trim().to_string(),
            collisions,
            collision_text: def
                .collision
                .iter()
                .map(|c| c.get_ref().trim().to_string())
                .collect(),
            named: self.named,
            graph: self.graph,
            #[cfg(target_arch = "x86_64")]
            step_code: Default::default(),
        })
    }

    fn grid(&self) -> Result<[usize; 2], EquationError> {
        let place = Place {
            key: "model.grid".into(),
            start: None,
            line: None,
        };
        let names: Vec<String> = match &self.def.grid {
            Some(g) => g.clone(),
            None => self.def.states.iter().take(2).cloned().collect(),
        };
        if names.len() == 1 && self.def.grid.is_none() {
            // a one-state model: its grid is that state alone, twice (its time history and
            // continuation start from it; grids of starts are refused)
            return Ok([0, 0]);
        }
        if names.len() != 2 || names[0] == names[1] {
            return Err(at(&place, "name two different states"));
        }
        let index = |n: &String| {
            self.states
                .get(n)
                .copied()
                .ok_or_else(|| at(&place, format!("`{n}` is not a state")))
        };
        Ok([index(&names[0])?, index(&names[1])?])
    }

    /// The node of the named value `name`, built on first use.
    fn named_value(
        &mut self,
        name: &str,
        used: Option<(&Place, Span)>,
    ) -> Result<NodeId, EquationError> {
        if let Some(&id) = self.built.get(name) {
            return Ok(id);
        }
        if self.building.iter().any(|n| n == name) {
            let mut cycle = self.building.clone();
            let first = cycle.iter().position(|n| n == name).unwrap_or(0);
            cycle.drain(..first);
            cycle.push(name.to_string());
            let message = format!("a cyclic definition: {}", cycle.join(" → "));
            return Err(match used {
                Some((place, span)) => self.error_at(place, span, message),
                None => at(
                    &Place {
                        key: format!("model.let.{name}"),
                        start: None,
                        line: None,
                    },
                    message,
                ),
            });
        }
        let (ast, place) = self.lets[name].clone();
        self.building.push(name.to_string());
        let node = self.expr(&ast, &place, &HashMap::new());
        self.building.pop();
        let node = node?;
        self.built.insert(name.to_string(), node);
        self.named.push((place.key, node));
        Ok(node)
    }

    fn expr(
        &mut self,
        ast: &Ast,
        place: &Place,
        local: &HashMap<String, NodeId>,
    ) -> Result<NodeId, EquationError> {
        self.work += 1;
        if self.work > MAX_WORK {
            return Err(at(
                place,
                format!(
                    "the model expands to more than {MAX_WORK} operations (functions calling functions)"
                ),
            ));
        }
        Ok(match ast {
            Ast::Num(v) => self.graph.num(*v),
            Ast::Name(name, span) => self.name(name, *span, place, local)?,
            Ast::Neg(a) => {
                let a = self.expr(a, place, local)?;
                self.graph.neg(a)
            }
            Ast::Bin(op, a, b) => {
                let (a, b) = (self.expr(a, place, local)?, self.expr(b, place, local)?);
                let op = match op {
                    BinOp::Add => Op2::Add,
                    BinOp::Sub => Op2::Sub,
                    BinOp::Mul => Op2::Mul,
                    BinOp::Div => Op2::Div,
                    BinOp::Pow => Op2::Pow,
                };
                self.graph.bin(op, a, b)
            }
            Ast::Call(name, span, args) => self.call(name, *span, args, place, local)?,
            Ast::Cmp(..) | Ast::And(..) | Ast::Or(..) => {
                let span = first_span(ast).unwrap_or(Span { start: 0, end: 0 });
                return Err(self.error_at(
                    place,
                    span,
                    "a comparison is a condition: use it as the first argument of if(…)".into(),
                ));
            }
        })
    }

    fn name(
        &mut self,
        name: &str,
        span: Span,
        place: &Place,
        local: &HashMap<String, NodeId>,
    ) -> Result<NodeId, EquationError> {
        if let Some(&id) = local.get(name) {
            return Ok(id);
        }
        if let Some(&i) = self.states.get(name) {
            return Ok(self.graph.state(i));
        }
        if let Some(&i) = self.params.get(name) {
            return Ok(self.graph.param(i));
        }
        if self.lets.contains_key(name) {
            return self.named_value(name, Some((place, span)));
        }
        match name {
            "t" => Ok(self.graph.time()),
            "pi" => Ok(self.graph.num(std::f64::consts::PI)),
            _ if self.functions.contains_key(name)
                || Func::named(name).is_some()
                || is_kink(name) =>
            {
                Err(self.error_at(
                    place,
                    span,
                    format!("`{name}` is a function: call it as {name}(…)"),
                ))
            }
            _ => Err(self.error_at(
                place,
                span,
                format!("unknown name `{name}`{}", self.suggestion(name)),
            )),
        }
    }

    /// ", did you mean `x`?" for a known name one edit away, else nothing.
    fn suggestion(&self, name: &str) -> String {
        let known = self
            .states
            .keys()
            .chain(self.params.keys())
            .chain(self.lets.keys());
        known
            .filter(|k| edit_distance(k, name) <= 2)
            .min_by_key(|k| edit_distance(k, name))
            .map(|k| format!("; did you mean `{k}`?"))
            .unwrap_or_default()
    }

    fn call(
        &mut self,
        name: &str,
        span: Span,
        args: &[Ast],
        place: &Place,
        local: &HashMap<String, NodeId>,
    ) -> Result<NodeId, EquationError> {
        let arity = |want: &str, ok: bool| -> Result<(), EquationError> {
            if ok {
                Ok(())
            } else {
                Err(self.error_at(
                    place,
                    span,
                    format!("{name}(…) takes {want}, not {}", args.len()),
                ))
            }
        };
        if name == "if" {
            arity("3 arguments (condition, then, else)", args.len() == 3)?;
            let cond = self.cond(&args[0], place, local)?;
            let on = self.expr(&args[1], place, local)?;
            let off = self.expr(&args[2], place, local)?;
            return self.branch(&cond, on, off, place, span);
        }
        if let Some(f) = Func::named(name) {
            arity("1 argument", args.len() == 1)?;
            let a = self.expr(&args[0], place, local)?;
            return Ok(self.graph.un(f, a));
        }
        match name {
            "max" | "min" => {
                arity("2 or more arguments", args.len() >= 2)?;
                let mut acc = self.expr(&args[0], place, local)?;
                for arg in &args[1..] {
                    let b = self.expr(arg, place, local)?;
                    // max: a where a − b ≥ 0; min: a where b − a ≥ 0
                    let s = if name == "max" {
                        self.graph.sub(acc, b)
                    } else {
                        self.graph.sub(b, acc)
                    };
                    acc = self.kink(s, false, true, acc, b, place, span)?;
                }
                Ok(acc)
            }
            "abs" => {
                arity("1 argument", args.len() == 1)?;
                let a = self.expr(&args[0], place, local)?;
                let minus = self.graph.neg(a);
                self.kink(a, false, true, a, minus, place, span)
            }
            "pow" => {
                arity("2 arguments", args.len() == 2)?;
                let a = self.expr(&args[0], place, local)?;
                let b = self.expr(&args[1], place, local)?;
                Ok(self.graph.bin(Op2::Pow, a, b))
            }
            _ => {
                let Some((params, body, fplace)) = self.functions.get(name).cloned() else {
                    return Err(self.error_at(place, span, format!("unknown function `{name}`")));
                };
                arity(
                    &format!(
                        "{} argument{}",
                        params.len(),
                        if params.len() == 1 { "" } else { "s" }
                    ),
                    args.len() == params.len(),
                )?;
                if self.building.iter().any(|n| n == name) {
                    return Err(self.error_at(
                        place,
                        span,
                        format!("`{name}` calls itself: functions cannot recurse"),
                    ));
                }
                let mut scope = HashMap::new();
                for (p, a) in params.iter().zip(args) {
                    scope.insert(p.clone(), self.expr(a, place, local)?);
                }
                self.building.push(name.to_string());
                let node = self.expr(&body, &fplace, &scope);
                self.building.pop();
                node
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn kink(
        &mut self,
        value: NodeId,
        strict: bool,
        continuous: bool,
        on: NodeId,
        off: NodeId,
        place: &Place,
        span: Span,
    ) -> Result<NodeId, EquationError> {
        self.graph
            .kink(value, strict, continuous, on, off)
            .map_err(|_| {
                self.error_at(
                    place,
                    span,
                    format!("more than {MAX_SWITCHES} kinks (max, min, abs, if) in the model"),
                )
            })
    }

    /// `on` where `cond` holds, else `off`: a kink per comparison.
    fn branch(
        &mut self,
        cond: &Cond,
        on: NodeId,
        off: NodeId,
        place: &Place,
        span: Span,
    ) -> Result<NodeId, EquationError> {
        match cond {
            Cond::Positive { value, strict } => {
                self.kink(*value, *strict, false, on, off, place, span)
            }
            Cond::And(a, b) => {
                let inner = self.branch(b, on, off, place, span)?;
                self.branch(a, inner, off, place, span)
            }
            Cond::Or(a, b) => {
                let inner = self.branch(b, on, off, place, span)?;
                self.branch(a, on, inner, place, span)
            }
        }
    }

    fn cond(
        &mut self,
        ast: &Ast,
        place: &Place,
        local: &HashMap<String, NodeId>,
    ) -> Result<Cond, EquationError> {
        match ast {
            Ast::Cmp(op, l, r) => {
                let (l, r) = (self.expr(l, place, local)?, self.expr(r, place, local)?);
                // l < r is r − l > 0; l > r is l − r > 0
                let (value, strict) = match op {
                    CmpOp::Lt => (self.graph.sub(r, l), true),
                    CmpOp::Le => (self.graph.sub(r, l), false),
                    CmpOp::Gt => (self.graph.sub(l, r), true),
                    CmpOp::Ge => (self.graph.sub(l, r), false),
                };
                Ok(Cond::Positive { value, strict })
            }
            Ast::And(a, b) => Ok(Cond::And(
                Box::new(self.cond(a, place, local)?),
                Box::new(self.cond(b, place, local)?),
            )),
            Ast::Or(a, b) => Ok(Cond::Or(
                Box::new(self.cond(a, place, local)?),
                Box::new(self.cond(b, place, local)?),
            )),
            _ => {
                let span = first_span(ast).unwrap_or(Span { start: 0, end: 0 });
                Err(self.error_at(
                    place,
                    span,
                    "expected a condition such as `x < 0` (with <, <=, >, >=, &&, ||)".into(),
                ))
            }
        }
    }
}

fn is_kink(name: &str) -> bool {
    matches!(name, "max" | "min" | "abs" | "if" | "pow")
}

/// `g(lam, phi)` → ("g", ["lam", "phi"]).
fn function_head(head: &str) -> Option<(String, Vec<String>)> {
    let (name, rest) = head.split_once('(')?;
    let args = rest.trim_end().strip_suffix(')')?;
    let args: Vec<String> = args
        .split(',')
        .map(|a| a.trim().to_string())
        .filter(|a| !a.is_empty())
        .collect();
    let name = name.trim().to_string();
    let valid = |n: &str| {
        n.chars()
            .next()
            .is_some_and(|c| c.is_alphabetic() || c == '_')
            && n.chars().all(|c| c.is_alphanumeric() || c == '_')
    };
    (valid(&name) && args.iter().all(|a| valid(a))).then_some((name, args))
}

/// The place of the first name or call in `ast`, for an error about all of it.
fn first_span(ast: &Ast) -> Option<Span> {
    match ast {
        Ast::Num(_) => None,
        Ast::Name(_, s) | Ast::Call(_, s, _) => Some(*s),
        Ast::Neg(a) => first_span(a),
        Ast::Bin(_, a, b) | Ast::Cmp(_, a, b) | Ast::And(a, b) | Ast::Or(a, b) => {
            first_span(a).or_else(|| first_span(b))
        }
    }
}

/// Levenshtein distance, for suggestions.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for j in 0..b.len() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != b[j]))
                .min(row[j] + 1)
                .min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}
