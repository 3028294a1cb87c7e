//! A compiled list of instructions that evaluates chosen nodes of a [`Graph`] at one time and
//! state: only the nodes that vary with time or state, in dependency order, each once. Nodes
//! fixed by the parameters are evaluated once per parameter set ([`Registers::set_params`]).

use std::sync::Arc;

use super::graph::{Func, Graph, Node, NodeId, Op2};
use super::time_table::TimeTable;
use crate::model::system::{MAX_DIM, Mode, Vector};

/// What an instruction does: one flat list, so that the loop dispatches once.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Op {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    /// r[a]^n for the instruction's integer n.
    Powi,
    Un(Func),
    /// r[d] = mode bit k ? r[a] : r[b]
    Select,
    /// Records mode bit k from the switching value r[a] (on where ≥ 0); in a free
    /// evaluation the kinks after it follow that bit.
    Sign,
    /// The same, on only where > 0.
    SignStrict,
}

/// One instruction; registers are node ids.
#[derive(Debug, Clone, Copy)]
pub(super) struct Ins {
    pub op: Op,
    /// The switch of a `Select` or `Sign`.
    pub k: u8,
    /// The exponent of a `Powi`.
    pub n: i32,
    /// Destination and arguments: registers, always valid ones (an unused `b` is `a`).
    pub d: u32,
    pub a: u32,
    pub b: u32,
}

/// The instructions that evaluate some roots of a graph.
#[derive(Debug, Clone)]
pub struct Tape {
    ins: Vec<Ins>,
    /// Registers the tape addresses (every index is below this).
    registers: usize,
    /// Which switches this tape's roots depend on (a bit each).
    pub switch_mask: u64,
    /// The registers its users read: the roots it computes. The interpreter writes every
    /// register it computes, the machine code only these.
    pub roots: Vec<NodeId>,
    /// The tape as machine code, compiled at its first run (shared by clones).
    native: std::sync::Arc<Natives>,
}

/// Lanes a tape is compiled for besides one (the written model's batches); other lane
/// counts than these three are interpreted.
pub const NATIVE_LANES: usize = 16;
/// Lanes of the written model's small batches (a response's seeds and sweeps: up to this
/// many starts), compiled too.
pub const FEW_LANES: usize = 4;

/// Where `lanes`' machine code is kept among the lane counts compiled for: one,
/// [`FEW_LANES`] and [`NATIVE_LANES`].
#[cfg(target_arch = "x86_64")]
pub(super) fn lane_slot(lanes: usize) -> Option<usize> {
    match lanes {
        1 => Some(0),
        FEW_LANES => Some(1),
        NATIVE_LANES => Some(2),
        _ => None,
    }
}

/// A tape's machine code, per lane count ([`lane_slot`]) and use ([`HELD_USE`],
/// [`FREE_USE`], [`FIELD_USE`], [`SWITCHING_USE`]).
#[derive(Debug, Default)]
struct Natives {
    #[cfg(target_arch = "x86_64")]
    compiled: [[std::sync::OnceLock<Option<super::native::Native>>; 4]; 3],
}

/// The uses a tape is compiled for: each kink held on the lane's mode, or free (on its
/// switching value's sign), or held with the field's states and derivatives read and
/// written by the code itself.
#[cfg(target_arch = "x86_64")]
const HELD_USE: usize = 0;
#[cfg(target_arch = "x86_64")]
const FREE_USE: usize = 1;
#[cfg(target_arch = "x86_64")]
const FIELD_USE: usize = 2;
/// Held, one lane, reading the states and writing the switching values (a [`FieldIo`] whose
/// `derivatives` are the switches' registers).
#[cfg(target_arch = "x86_64")]
const SWITCHING_USE: usize = 3;

/// Where a field tape's states go and its derivatives come from: (state, register) pairs,
/// and the register of each state's derivative in state order. (The same for the switching
/// values a split reads, [`IoUse::Switching`]: then `derivatives` are the switches'
/// registers, in switch order.)
#[derive(Debug, Clone)]
pub struct FieldIo {
    pub states: Vec<(u8, u32)>,
    pub derivatives: Vec<u32>,
}

impl FieldIo {
    /// The states' registers in `graph`, and `derivatives`.
    pub fn new(graph: &Graph, derivatives: Vec<NodeId>) -> FieldIo {
        FieldIo {
            states: graph.states(),
            derivatives,
        }
    }
}

impl Tape {
    /// The tape computing `roots` (and what they need) in `graph`, taking the nodes marked
    /// `given` as already computed (the time-only values [`Registers::load`] refreshes).
    pub fn new(graph: &Graph, roots: &[NodeId], given: &[bool]) -> Tape {
        let n = graph.len();
        let varying = graph.varying();
        let mut needed = vec![false; n];
        let mut stack: Vec<NodeId> = roots.to_vec();
        // the switches whose branch can change along a trajectory
        let mut switch_mask = 0u64;
        while let Some(id) = stack.pop() {
            if needed[id as usize] || given[id as usize] {
                continue;
            }
            needed[id as usize] = true;
            match graph.node(id) {
                Node::Un(_, a) | Node::Powi(a, _) => stack.push(a),
                Node::Bin(_, a, b) => stack.extend([a, b]),
                Node::Select(k, a, b) => {
                    if varying[id as usize] {
                        switch_mask |= 1 << k;
                    }
                    stack.extend([a, b, graph.switches[k as usize].value]);
                }
                _ => {}
            }
        }
        let mut ins = Vec::new();
        let mut signed = 0u64;
        for id in 0..n as u32 {
            if !needed[id as usize] || !varying[id as usize] {
                continue;
            }
            let op = |op, a, b| Ins {
                op,
                k: 0,
                n: 0,
                d: id,
                a,
                b,
            };
            match graph.node(id) {
                Node::Un(f, a) => ins.push(op(Op::Un(f), a, a)),
                Node::Bin(o, a, b) => ins.push(op(
                    match o {
                        Op2::Add => Op::Add,
                        Op2::Sub => Op::Sub,
                        Op2::Mul => Op::Mul,
                        Op2::Div => Op::Div,
                        Op2::Pow => Op::Pow,
                    },
                    a,
                    b,
                )),
                Node::Powi(a, n) => ins.push(Ins {
                    n,
                    ..op(Op::Powi, a, a)
                }),
                Node::Select(k, a, b) => {
                    if signed & (1 << k) == 0 {
                        let s = graph.switches[k as usize];
                        let sign = if s.strict { Op::SignStrict } else { Op::Sign };
                        ins.push(Ins {
                            k,
                            ..op(sign, s.value, s.value)
                        });
                        signed |= 1 << k;
                    }
                    ins.push(Ins {
                        k,
                        ..op(Op::Select, a, b)
                    });
                }
                Node::Const(_) | Node::Time | Node::State(_) | Node::Param(_) => {}
            }
        }
        let mut computed = vec![false; n];
        for i in &ins {
            computed[i.d as usize] = !matches!(i.op, Op::Sign | Op::SignStrict);
        }
        let mut roots: Vec<NodeId> = roots
            .iter()
            .copied()
            .filter(|&r| computed[r as usize])
            .collect();
        roots.sort_unstable();
        roots.dedup();
        Tape {
            ins,
            registers: n,
            switch_mask,
            roots,
            native: Default::default(),
        }
    }

    /// Whether tapes run as machine code: on x86-64 unless `ISOLA_INTERPRET` is set (to
    /// compare the two, or if the code generator fails the host).
    pub fn native_enabled() -> bool {
        static ENABLED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
        *ENABLED.get_or_init(|| {
            cfg!(target_arch = "x86_64") && std::env::var_os("ISOLA_INTERPRET").is_none()
        })
    }

    /// The compiled tape for `lanes` (1, [`FEW_LANES`] or [`NATIVE_LANES`]) lanes, held or
    /// `free`, compiled now if it is the first call.
    #[cfg(target_arch = "x86_64")]
    pub fn native(&self, lanes: usize, free: bool) -> Option<super::native::Entry> {
        let usage = if free { FREE_USE } else { HELD_USE };
        self.compiled([lane_slot(lanes)?, usage], lanes, free, None)
    }

    /// The compiled tape for `lanes` lanes, held, reading the states and writing the
    /// derivatives `io` names (always the same `io` for one tape).
    #[cfg(target_arch = "x86_64")]
    pub fn native_field(&self, lanes: usize, io: &FieldIo) -> Option<super::native::Entry> {
        self.compiled([lane_slot(lanes)?, FIELD_USE], lanes, false, Some(io))
    }

    /// The field tape's one-lane machine code reading the states and writing what `io`
    /// names, looked up once by its caller: `io` is the field's own ([`IoUse::Field`], the
    /// derivatives) or the switches' ([`IoUse::Switching`], always the same `io` for each).
    #[cfg(target_arch = "x86_64")]
    pub fn io_code(&self, usage: IoUse, io: &FieldIo) -> Option<IoCode> {
        let slot = match usage {
            IoUse::Field => FIELD_USE,
            IoUse::Switching => SWITCHING_USE,
        };
        let entry = self.compiled([0, slot], 1, false, Some(io))?;
        Some(IoCode {
            entry,
            registers: self.registers,
            outputs: io.derivatives.len(),
        })
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn compiled(
        &self,
        [slot, usage]: [usize; 2],
        lanes: usize,
        free: bool,
        io: Option<&FieldIo>,
    ) -> Option<super::native::Entry> {
        self.native.compiled[slot][usage]
            .get_or_init(|| {
                let (ins, roots) = (&self.ins, &self.roots);
                Tape::native_enabled()
                    .then(|| super::native::compile(ins, roots, self.registers, lanes, free, io))
                    .flatten()
            })
            .as_ref()
            .map(|n| n.entry())
    }

    /// The nodes that vary with time alone and that `roots` need: computed once per time by
    /// [`Registers::load`], so that the forcing's `cos(omega*t)` is not computed again at a
    /// stage of the same time (RK4's second and third stages share one, its fourth and the
    /// step's end another). Kinks and what follows them are left to each tape (they record
    /// modes).
    pub fn time_only(graph: &Graph, roots: &[NodeId]) -> Vec<bool> {
        let n = graph.len();
        // varying with the state, or through a kink
        let mut excluded = vec![false; n];
        for id in 0..n {
            excluded[id] = match graph.node(id as NodeId) {
                Node::State(_) | Node::Select(..) => true,
                Node::Un(_, a) | Node::Powi(a, _) => excluded[a as usize],
                Node::Bin(_, a, b) => excluded[a as usize] || excluded[b as usize],
                Node::Const(_) | Node::Param(_) | Node::Time => false,
            };
        }
        let varying = graph.varying();
        let mut time_only = vec![false; n];
        let mut stack: Vec<NodeId> = roots.to_vec();
        let mut seen = vec![false; n];
        while let Some(id) = stack.pop() {
            if std::mem::replace(&mut seen[id as usize], true) {
                continue;
            }
            let node = graph.node(id);
            let computed = matches!(node, Node::Un(..) | Node::Powi(..) | Node::Bin(..));
            time_only[id as usize] = computed && varying[id as usize] && !excluded[id as usize];
            match node {
                Node::Un(_, a) | Node::Powi(a, _) => stack.push(a),
                Node::Bin(_, a, b) => stack.extend([a, b]),
                Node::Select(k, a, b) => stack.extend([a, b, graph.switches[k as usize].value]),
                _ => {}
            }
        }
        time_only
    }

    /// The instructions, in order.
    pub(super) fn instructions(&self) -> &[Ins] {
        &self.ins
    }

    /// Number of instructions (a measure of the work per evaluation).
    pub fn len(&self) -> usize {
        self.ins.len()
    }

    pub fn is_empty(&self) -> bool {
        self.ins.is_empty()
    }

    /// Runs the tape on `regs` with each kink held on the branch `mode` says, and returns
    /// the mode the switching functions' signs select (bits of switches this tape does not
    /// use are 0).
    #[inline]
    pub fn run_in(&self, regs: &mut [f64], mode: Mode) -> Mode {
        self.run::<false>(regs, mode)
    }

    /// Runs the tape choosing each kink's branch by the sign of its switching function, and
    /// returns the mode that chose.
    #[inline]
    pub fn run_free(&self, regs: &mut [f64]) -> Mode {
        self.run::<true>(regs, 0)
    }

    #[inline(always)]
    fn run<const FREE: bool>(&self, r: &mut [f64], mode: Mode) -> Mode {
        assert!(
            r.len() >= self.registers,
            "a register file of another graph"
        );
        #[cfg(target_arch = "x86_64")]
        if let Some(entry) = self.native(1, FREE) {
            // SAFETY: the code reads and writes registers below `registers` ≤ r.len()
            // (asserted above) and one mode each way
            return unsafe { call(entry, r, [mode], std::ptr::null(), std::ptr::null_mut()) }[0];
        }
        self.interpret::<FREE>(r, mode)
    }

    /// [`Tape::run_in`] of a field tape reading the states from `x` and writing the
    /// derivatives into `dx`, instruction by instruction (the states' registers written):
    /// what its [`IoCode`] does where the tape is compiled.
    pub fn interpret_field(
        &self,
        r: &mut [f64],
        mode: Mode,
        io: &FieldIo,
        x: &Vector,
        dx: &mut Vector,
    ) -> Mode {
        assert!(
            r.len() >= self.registers,
            "a register file of another graph"
        );
        for &(i, slot) in &io.states {
            r[slot as usize] = x[i as usize];
        }
        let observed = self.interpret::<false>(r, mode);
        for (d, &id) in dx.iter_mut().zip(&io.derivatives) {
            *d = r[id as usize];
        }
        observed
    }

    /// The tape run instruction by instruction.
    pub fn interpret<const FREE: bool>(&self, r: &mut [f64], mut mode: Mode) -> Mode {
        let mut observed = 0;
        for ins in &self.ins {
            // SAFETY: every index is a node id below `registers` (built so in `new`), and
            // `r` has at least that many registers (asserted above)
            unsafe {
                let get = |i: u32| *r.get_unchecked(i as usize);
                let (x, y) = (get(ins.a), get(ins.b));
                let value = match ins.op {
                    Op::Add => x + y,
                    Op::Sub => x - y,
                    Op::Mul => x * y,
                    Op::Div => x / y,
                    Op::Pow => x.powf(y),
                    Op::Powi => x.powi(ins.n),
                    Op::Un(f) => f.apply(x),
                    Op::Select => {
                        if mode & (1 << ins.k) != 0 {
                            x
                        } else {
                            y
                        }
                    }
                    Op::Sign | Op::SignStrict => {
                        let on = if ins.op == Op::SignStrict {
                            x > 0.0
                        } else {
                            x >= 0.0
                        };
                        let bit = 1u64 << ins.k;
                        if on {
                            observed |= bit;
                        }
                        if FREE {
                            mode = (mode & !bit) | (observed & bit);
                        }
                        continue;
                    }
                };
                *r.get_unchecked_mut(ins.d as usize) = value;
            }
        }
        observed
    }
}

impl Tape {
    /// Runs the tape on `L` lanes of registers at once, lane l held on `modes[l]`; returns
    /// each lane's observed mode (as [`Tape::run_in`] does for one).
    #[inline]
    pub fn run_lanes<const L: usize>(&self, r: &mut [[f64; L]], modes: &[Mode; L]) -> [Mode; L] {
        self.lanes::<L, false>(r, modes)
    }

    /// Runs the tape on `L` lanes, each kink on the branch its switching function's sign
    /// selects in that lane.
    pub fn run_lanes_free<const L: usize>(&self, r: &mut [[f64; L]]) -> [Mode; L] {
        self.lanes::<L, true>(r, &[0; L])
    }

    #[inline(always)]
    fn lanes<const L: usize, const FREE: bool>(
        &self,
        r: &mut [[f64; L]],
        modes: &[Mode; L],
    ) -> [Mode; L] {
        assert!(
            r.len() >= self.registers,
            "a register file of another graph"
        );
        #[cfg(target_arch = "x86_64")]
        if let Some(entry) = self.native(L, FREE) {
            // SAFETY: as in `run`, with `L` lanes of registers, modes and observed modes
            let r = r.as_flattened_mut();
            return unsafe { call(entry, r, *modes, std::ptr::null(), std::ptr::null_mut()) };
        }
        self.interpret_lanes::<L, FREE>(r, modes)
    }

    /// [`Tape::run_lanes`] of a field tape with every lane's states loaded first and its
    /// derivatives copied out after, as [`Tape::interpret_field`] for one.
    #[inline]
    pub fn run_field_lanes<const L: usize>(
        &self,
        r: &mut [[f64; L]],
        modes: &[Mode; L],
        io: &FieldIo,
        x: &[[f64; L]; MAX_DIM],
        dx: &mut [[f64; L]; MAX_DIM],
    ) -> [Mode; L] {
        assert!(
            r.len() >= self.registers && io.derivatives.len() <= MAX_DIM,
            "a register file of another graph"
        );
        #[cfg(target_arch = "x86_64")]
        if let Some(entry) = self.native_field(L, io) {
            // SAFETY: as in `IoCode::run`, with `L` lanes of each (state i of lane l at
            // i·L + l, as the code reads it)
            let (x, dx) = (
                x.as_flattened().as_ptr(),
                dx.as_flattened_mut().as_mut_ptr(),
            );
            return unsafe { call(entry, r.as_flattened_mut(), *modes, x, dx) };
        }
        for &(i, slot) in &io.states {
            r[slot as usize] = x[i as usize];
        }
        let observed = self.interpret_lanes::<L, false>(r, modes);
        for (d, &id) in dx.iter_mut().zip(&io.derivatives) {
            *d = r[id as usize];
        }
        observed
    }

    /// The lanes run instruction by instruction.
    pub fn interpret_lanes<const L: usize, const FREE: bool>(
        &self,
        r: &mut [[f64; L]],
        modes: &[Mode; L],
    ) -> [Mode; L] {
        let mut observed = [0u64; L];
        for ins in &self.ins {
            // SAFETY: as in `run`: every index is below `registers` ≤ r.len()
            let (x, y) = unsafe {
                (
                    *r.get_unchecked(ins.a as usize),
                    *r.get_unchecked(ins.b as usize),
                )
            };
            let bit = 1u64 << ins.k;
            let mut out = [0.0; L];
            match ins.op {
                Op::Add => (0..L).for_each(|l| out[l] = x[l] + y[l]),
                Op::Sub => (0..L).for_each(|l| out[l] = x[l] - y[l]),
                Op::Mul => (0..L).for_each(|l| out[l] = x[l] * y[l]),
                Op::Div => (0..L).for_each(|l| out[l] = x[l] / y[l]),
                Op::Pow => (0..L).for_each(|l| out[l] = x[l].powf(y[l])),
                Op::Powi => (0..L).for_each(|l| out[l] = x[l].powi(ins.n)),
                Op::Un(f) => (0..L).for_each(|l| out[l] = f.apply(x[l])),
                Op::Select => (0..L).for_each(|l| {
                    let m = if FREE { observed[l] } else { modes[l] };
                    out[l] = if m & bit != 0 { x[l] } else { y[l] };
                }),
                Op::Sign => {
                    (0..L).for_each(|l| observed[l] |= if x[l] >= 0.0 { bit } else { 0 });
                    continue;
                }
                Op::SignStrict => {
                    (0..L).for_each(|l| observed[l] |= if x[l] > 0.0 { bit } else { 0 });
                    continue;
                }
            }
            // SAFETY: as above
            unsafe { *r.get_unchecked_mut(ins.d as usize) = out };
        }
        observed
    }
}

/// Runs machine code `entry` on registers `r` with one mode per lane, and the state and
/// derivative vectors of a field entry (null for others); returns the observed modes.
///
/// # Safety
/// `entry` must address only registers below `r.len()`, `L` lanes of them, and, if it is a
/// field entry, states and derivatives within `x` and `dx`.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn call<const L: usize>(
    entry: super::native::Entry,
    r: &mut [f64],
    modes: [Mode; L],
    x: *const f64,
    dx: *mut f64,
) -> [Mode; L] {
    let mut observed = [0u64; L];
    // SAFETY: the caller's promise
    unsafe { entry(r.as_mut_ptr(), modes.as_ptr(), observed.as_mut_ptr(), x, dx) };
    observed
}

/// What a tape's [`IoCode`] writes out: the field's derivatives or the switching values.
#[cfg(target_arch = "x86_64")]
#[derive(Debug, Clone, Copy)]
pub enum IoUse {
    Field,
    Switching,
}

/// A tape's one-lane machine code that reads the states and writes its outputs itself
/// ([`Tape::io_code`]), kept by its caller so that a call passes no lock.
#[cfg(target_arch = "x86_64")]
#[derive(Debug, Clone, Copy)]
pub struct IoCode {
    entry: super::native::Entry,
    registers: usize,
    outputs: usize,
}

#[cfg(target_arch = "x86_64")]
impl IoCode {
    /// Runs the code on registers `r` held on `mode`, the states from `x`, its outputs into
    /// `out`; the observed mode (as [`Tape::run_in`]).
    #[inline(always)]
    pub fn run(&self, r: &mut [f64], mode: Mode, x: &Vector, out: &mut [f64]) -> Mode {
        assert!(
            r.len() >= self.registers && out.len() >= self.outputs,
            "a register file of another graph"
        );
        // SAFETY: registers as in `Tape::run`; the code reads states i < MAX_DIM from x and
        // writes `outputs` values into out, both long enough (x by its type, out asserted)
        let observed = unsafe { call(self.entry, r, [mode], x.as_ptr(), out.as_mut_ptr()) };
        observed[0]
    }
}

/// A register file for one graph: constants filled in, parameters and the nodes they fix
/// evaluated by [`Registers::set_params`].
#[derive(Debug, Clone)]
pub struct Registers {
    pub values: Vec<f64>,
    pub(super) state_slots: Vec<(u8, u32)>,
    pub(super) time_slot: Option<u32>,
    param_slots: Vec<(u16, u32)>,
    /// The parameter-fixed nodes, in dependency order.
    fixed: Vec<NodeId>,
    /// The register holding the time the time-only nodes were computed at (NaN: not yet).
    pub stamp: u32,
    /// A period of the time-only values, for a periodic model (see [`TimeTable`]).
    pub table: Option<Arc<TimeTable>>,
}

impl Registers {
    pub fn new(graph: &Graph) -> Registers {
        let varying = graph.varying();
        let mut values = vec![0.0; graph.len() + 1];
        let stamp = graph.len() as u32;
        values[stamp as usize] = f64::NAN;
        let (mut time_slot, mut param_slots, mut fixed) = (None, Vec::new(), Vec::new());
        for id in 0..graph.len() as u32 {
            match graph.node(id) {
                Node::Const(v) => values[id as usize] = v,
                Node::Time => time_slot = Some(id),
                Node::State(_) => {}
                Node::Param(i) => param_slots.push((i, id)),
                _ if !varying[id as usize] => fixed.push(id),
                _ => {}
            }
        }
        Registers {
            values,
            state_slots: graph.states(),
            time_slot,
            param_slots,
            fixed,
            stamp,
            table: None,
        }
    }

    /// Loads parameter values and evaluates every node they alone fix. A kink between fixed
    /// values takes its branch by its switching value's sign.
    pub fn set_params(&mut self, graph: &Graph, params: &[f64]) {
        self.values[self.stamp as usize] = f64::NAN;
        self.table = None;
        for &(i, slot) in &self.param_slots {
            self.values[slot as usize] = params[i as usize];
        }
        let r = &mut self.values;
        for &id in &self.fixed {
            r[id as usize] = match graph.node(id) {
                Node::Un(f, a) => f.apply(r[a as usize]),
                Node::Bin(op, a, b) => op.apply(r[a as usize], r[b as usize]),
                Node::Powi(a, k) => r[a as usize].powi(k),
                Node::Select(k, a, b) => {
                    let s = graph.switches[k as usize];
                    if s.on(r[s.value as usize]) {
                        r[a as usize]
                    } else {
                        r[b as usize]
                    }
                }
                _ => unreachable!("only computed nodes are fixed"),
            };
        }
    }

    /// Loads the time and state, and the time-only nodes (the model's `time_tape`) unless
    /// they were last computed at this very time (see [`Registers::load_time`]).
    #[inline(always)]
    pub fn load(&mut self, time_tape: &Tape, t: f64, x: &[f64]) {
        self.load_time(time_tape, t);
        for &(i, slot) in &self.state_slots {
            self.values[slot as usize] = x[i as usize];
        }
    }

    /// Loads the time, and the time-only nodes unless they were last computed at this very
    /// time: from the table where it has the time, else by running `time_tape`.
    #[inline(always)]
    pub fn load_time(&mut self, time_tape: &Tape, t: f64) {
        if let Some(slot) = self.time_slot {
            let values = &mut self.values;
            values[slot as usize] = t;
            let stamp = &mut values[self.stamp as usize];
            if stamp.to_bits() != t.to_bits() {
                *stamp = t;
                match self
                    .table
                    .as_deref()
                    .and_then(|table| Some((table, table.row(t)?)))
                {
                    Some((table, row)) => {
                        for (&s, &v) in table.slots().iter().zip(row) {
                            values[s as usize] = v;
                        }
                    }
                    None => {
                        time_tape.run_in(values, 0);
                    }
                }
            }
        }
    }

    #[inline(always)]
    pub fn get(&self, id: NodeId) -> f64 {
        self.values[id as usize]
    }
}
