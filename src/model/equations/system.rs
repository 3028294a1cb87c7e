//! A compiled written model at one set of parameter values: the [`System`] the general
//! engine integrates.

use std::sync::Arc;

use super::build::{Cond, EquationModel};
use super::graph::NodeId;
#[cfg(target_arch = "x86_64")]
use super::lanes::LaneTimes;
#[cfg(target_arch = "x86_64")]
use super::native_step;
#[cfg(target_arch = "x86_64")]
use super::tape::{IoCode, IoUse};
use super::time_table::TimeTable;
use crate::model::ParamError;
use crate::model::equations::tape::Registers;
use crate::model::system::{Differentiable, MAX_DIM, Mode, System, Vector};
#[cfg(target_arch = "x86_64")]
use crate::model::system::{END_SWITCHES, EndSwitching, GridStep};

/// A written model ready to integrate: its parameters set and its own registers.
#[derive(Debug, Clone)]
pub struct EquationSystem {
    model: EquationModel,
    regs: Registers,
    values: Vec<f64>,
    period: f64,
    origin: Vector,
    /// The field tape's one-lane machine code, looked up at first use.
    #[cfg(target_arch = "x86_64")]
    code: OwnCode,
}

/// A system's machine code for one trajectory: `None` until looked up, then the code or
/// `Some(None)` where the tape is interpreted.
#[cfg(target_arch = "x86_64")]
#[derive(Debug, Clone, Copy, Default)]
struct OwnCode {
    field: Option<Option<IoCode>>,
    switching: Option<Option<IoCode>>,
}

impl EquationModel {
    /// The model at parameter `values` (in [`EquationModel::parameters`] order), each checked
    /// against its range, the frequency against > 0.
    pub fn system(&self, values: &[f64]) -> Result<EquationSystem, ParamError> {
        let c = &self.inner;
        for (p, &v) in c.parameters.iter().zip(values) {
            crate::model::error::check(
                &p.name,
                v,
                |v| (p.min..=p.max).contains(&v),
                range_words(p.min, p.max),
            )?;
        }
        let omega = values[c.frequency];
        let omega = crate::model::error::check(
            &c.parameters[c.frequency].name,
            omega,
            |w| w > 0.0,
            "> 0 (the forcing frequency)",
        )?;
        let mut regs = Registers::new(&c.graph);
        regs.set_params(&c.graph, values);
        let mut origin = [0.0; MAX_DIM];
        for (o, &id) in origin.iter_mut().zip(&c.origin) {
            *o = regs.get(id);
        }
        Ok(EquationSystem {
            model: self.clone(),
            regs,
            values: values.to_vec(),
            period: std::f64::consts::TAU / omega,
            origin,
            #[cfg(target_arch = "x86_64")]
            code: OwnCode::default(),
        })
    }
}

/// `[a, b]`, `≥ a`, `≤ b` or `any finite value`.
fn range_words(min: f64, max: f64) -> String {
    match (min.is_finite(), max.is_finite()) {
        (true, true) => format!("[{min}, {max}]"),
        (true, false) => format!(">= {min}"),
        (false, true) => format!("<= {max}"),
        (false, false) => "any finite value".into(),
    }
}

impl EquationSystem {
    pub fn model(&self) -> &EquationModel {
        &self.model
    }

    /// The parameter values this system was made with.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Its registers (constants and parameter-fixed values filled in, and the table of its
    /// forcing once [`System::tabulate`]d).
    pub fn registers(&self) -> &Registers {
        &self.regs
    }

    /// The forcing frequency ω (the value of the model's frequency parameter).
    pub fn omega(&self) -> f64 {
        self.values[self.model.frequency()]
    }

    /// Its frequency parameter set to `omega` (> 0), unchecked: a chirp moves it through the
    /// values between its checked ends.
    pub(super) fn set_frequency(&mut self, omega: f64) {
        let c = &*self.model.inner;
        self.values[c.frequency] = omega;
        self.regs.set_params(&c.graph, &self.values);
        self.period = std::f64::consts::TAU / omega;
    }

    /// The state the grids are laid out around.
    pub fn origin(&self) -> &Vector {
        &self.origin
    }

    /// The collision condition (τ, x) meets, as `model.collision[i] = \`text\``; `None`
    /// where it meets none.
    pub fn collision_met(&mut self, tau: f64, x: &Vector) -> Option<String> {
        self.first_collision(tau, x, |cond, value| cond.stops(&value)[0])
    }

    /// The first collision condition for which `which` is true at (τ, x), as
    /// `model.collision[i] = \`text\``.
    fn first_collision(
        &mut self,
        tau: f64,
        x: &Vector,
        which: impl Fn(&Cond, &dyn Fn(NodeId) -> [f64; 1]) -> bool,
    ) -> Option<String> {
        if !self.load_collisions(tau, x) {
            return None;
        }
        let (c, regs) = (&*self.model.inner, &self.regs);
        let i = c
            .collisions
            .iter()
            .position(|cond| which(cond, &|id| [regs.get(id)]))?;
        Some(format!("model.collision[{i}] = `{}`", c.collision_text[i]))
    }

    /// The field tape's one-lane machine code for `usage`, looked up (compiled if it is the
    /// first) and kept.
    #[cfg(target_arch = "x86_64")]
    #[cold]
    fn look_up(&mut self, usage: IoUse) -> Option<IoCode> {
        let c = &*self.model.inner;
        let (io, kept) = match usage {
            IoUse::Field => (&c.field_io, &mut self.code.field),
            IoUse::Switching => (&c.switch_io, &mut self.code.switching),
        };
        *kept.insert(c.field_tape.io_code(usage, io))
    }

    /// The collision conditions' values at (τ, x) into the registers; false if the model
    /// has none.
    fn load_collisions(&mut self, tau: f64, x: &Vector) -> bool {
        let c = &*self.model.inner;
        if c.collisions.is_empty() {
            return false;
        }
        self.regs.load(&c.time_tape, tau, x);
        c.collision_tape.run_free(&mut self.regs.values);
        true
    }
}

impl System for EquationSystem {
    fn dim(&self) -> usize {
        self.model.inner.states.len()
    }

    fn state_names(&self) -> &[String] {
        &self.model.inner.states
    }

    fn period(&self) -> f64 {
        self.period
    }

    fn switch_mask(&self) -> Mode {
        self.model.inner.field_tape.switch_mask
    }

    fn continuous_switches(&self) -> Mode {
        self.model.inner.continuous_switches
    }

    fn mode_at(&mut self, tau: f64, x: &Vector) -> Mode {
        let c = &*self.model.inner;
        self.regs.load(&c.time_tape, tau, x);
        c.field_tape.run_free(&mut self.regs.values)
    }

    #[inline]
    fn field(&mut self, tau: f64, x: &Vector, mode: Mode, dx: &mut Vector) -> Mode {
        #[cfg(target_arch = "x86_64")]
        let code = match self.code.field {
            Some(code) => code,
            None => self.look_up(IoUse::Field),
        };
        let c = &*self.model.inner;
        self.regs.load_time(&c.time_tape, tau);
        #[cfg(target_arch = "x86_64")]
        if let Some(code) = code {
            return code.run(&mut self.regs.values, mode, x, dx);
        }
        // no machine code: the interpreter
        c.field_tape
            .interpret_field(&mut self.regs.values, mode, &c.field_io, x, dx)
    }

    fn switching(&mut self, tau: f64, x: &Vector, mode: Mode, s: &mut [f64]) -> Mode {
        #[cfg(target_arch = "x86_64")]
        let code = match self.code.switching {
            Some(code) => code,
            None => self.look_up(IoUse::Switching),
        };
        let c = &*self.model.inner;
        // (the code writes every switch's value: where `s` has room for them all)
        #[cfg(target_arch = "x86_64")]
        if let Some(code) = code
            && s.len() >= c.switch_io.derivatives.len()
        {
            self.regs.load_time(&c.time_tape, tau);
            return code.run(&mut self.regs.values, mode, x, s);
        }
        self.regs.load(&c.time_tape, tau, x);
        let observed = c.field_tape.run_in(&mut self.regs.values, mode);
        for (out, sw) in s.iter_mut().zip(&c.graph.switches) {
            *out = self.regs.get(sw.value);
        }
        observed
    }

    fn output(&mut self, tau: f64, x: &Vector, mode: Mode) -> (f64, f64) {
        let c = &*self.model.inner;
        self.regs.load(&c.time_tape, tau, x);
        // the field's kinks on the trajectory's piece; the output's own (`abs(x)` as the
        // amplitude) by their signs here: the trajectory's mode does not follow them
        let own = c.output_tape.switch_mask & !c.field_tape.switch_mask;
        let mode = if own == 0 {
            mode
        } else {
            (mode & !own) | (c.output_tape.run_free(&mut self.regs.values) & own)
        };
        c.output_tape.run_in(&mut self.regs.values, mode);
        (self.regs.get(c.output[0]), self.regs.get(c.output[1]))
    }

    fn collided(&mut self, tau: f64, x: &Vector) -> bool {
        if !self.load_collisions(tau, x) {
            return false;
        }
        let (c, regs) = (&*self.model.inner, &self.regs);
        c.collisions
            .iter()
            .any(|cond| cond.stops(&|id| [regs.get(id)])[0])
    }

    fn undefined_collision(&mut self, tau: f64, x: &Vector) -> Option<String> {
        self.first_collision(tau, x, |cond, value| cond.undefined(&value)[0])
            .map(|named| format!("{named}, which compares a value that is not a number"))
    }

    fn explain_non_finite(&mut self, tau: f64, x: &Vector) -> Option<String> {
        let c = &*self.model.inner;
        self.regs.load(&c.time_tape, tau, x);
        // computed, not from a period's table: a name may hold a phase ω·t itself
        c.time_tape.run_in(&mut self.regs.values, 0);
        c.named_tape.run_free(&mut self.regs.values);
        c.named
            .iter()
            .find(|(_, id)| !self.regs.get(*id).is_finite())
            .map(|(key, id)| format!("{key} = {}", self.regs.get(*id)))
    }

    #[cfg(target_arch = "x86_64")]
    #[inline]
    fn compiled_step(
        &mut self,
        step: &GridStep,
        x: &Vector,
        k1: &Vector,
        mode: Mode,
        end: &mut Vector,
        dx: &mut Vector,
    ) -> Option<(Mode, bool, EndSwitching)> {
        let times = LaneTimes::of(step);
        let mut s = [0.0; END_SWITCHES];
        let ([seen_diff], [collided], [seen]) = native_step::run(
            &self.model.inner,
            &self.regs.values,
            self.regs.table.as_deref(),
            [step.phase, step.steps_per_period],
            &times,
            [x, k1],
            &[mode],
            [end, dx],
            &mut s,
        )?;
        Some((seen_diff, collided, EndSwitching { s, seen }))
    }

    fn tabulate(&mut self, n: usize) {
        let c = &*self.model.inner;
        let current = self.regs.table.as_ref().map(|t| t.steps_per_period());
        if c.periodic && !c.time_tape.is_empty() && n <= MAX_TABULATED_STEPS && current != Some(n) {
            let table = TimeTable::new(&c.time_tape, &self.regs, self.period, n);
            self.regs.table = Some(Arc::new(table));
        }
    }
}

impl Differentiable for EquationSystem {
    fn field_and_jacobian(
        &mut self,
        tau: f64,
        x: &Vector,
        mode: Mode,
        dx: &mut Vector,
        jac: &mut [Vector; MAX_DIM],
    ) {
        let c = &*self.model.inner;
        let n = c.states.len();
        self.regs.load(&c.time_tape, tau, x);
        c.jacobian_tape.run_in(&mut self.regs.values, mode);
        for (d, &id) in dx.iter_mut().zip(&c.field_io.derivatives) {
            *d = self.regs.get(id);
        }
        for (row, ids) in jac.iter_mut().zip(c.jacobian.chunks(n)) {
            for (entry, &id) in row.iter_mut().zip(ids) {
                *entry = self.regs.get(id);
            }
        }
    }

    fn switch_gradient(
        &mut self,
        tau: f64,
        x: &Vector,
        mode: Mode,
        k: usize,
        grad: &mut Vector,
    ) -> f64 {
        let c = &*self.model.inner;
        let ids = &c.switch_gradients[k];
        self.regs.load(&c.time_tape, tau, x);
        c.switch_gradient_tapes[k].run_in(&mut self.regs.values, mode);
        let (time, states) = ids.split_last().expect("a gradient has its ∂/∂τ");
        for (g, &id) in grad.iter_mut().zip(states) {
            *g = self.regs.get(id);
        }
        self.regs.get(*time)
    }
}

/// Most steps per period whose forcing is tabulated (2n rows of the time-only values).
const MAX_TABULATED_STEPS: usize = 1 << 16;
