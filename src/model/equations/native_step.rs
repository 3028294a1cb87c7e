//! A written model's plain RK4 step as one piece of machine code: the general engine's step
//! (`solver::general`'s `rk4`, the same operations in the same order) with the field's
//! instructions emitted at each of its four evaluations, the forcing read from the rows of
//! the period's table, and the collision conditions at its end. One call per step instead of
//! a call per stage and the engine's bookkeeping around each: the step's values are those of
//! the stage-by-stage path bit for bit (tests hold this). A step in which a switch is seen
//! is still split by the engine, stage by stage.

use cranelift_codegen::ir::condcodes::FloatCC;
use cranelift_codegen::ir::{InstBuilder, MemFlagsData, Type, Value, types};
use cranelift_frontend::FunctionBuilder;

use super::build::{Compiled, Cond};
use super::graph::{Node, NodeId};
use super::lanes::LaneTimes;
use super::native::{Emitter, MAX_INSTRUCTIONS, Native, lane_loop};
use super::tape::Ins;
use super::time_table::{GridTime, TimeTable};
use crate::model::system::{MAX_DIM, Mode};

/// What a compiled step reads and writes. Per-lane arrays are lane-major (row i of lane l at
/// i·L + l, for the L lanes the step was compiled for).
#[repr(C)]
pub struct StepArgs {
    /// The lanes' register file (parameters and what they fix).
    pub registers: *const f64,
    /// Each lane's mode, held through the step.
    pub modes: *const u64,
    /// States at the step's start, and their derivative there (the first stage).
    pub x: *const f64,
    pub k1: *const f64,
    /// Each lane's step length, and the times of its middle and end.
    pub h: *const f64,
    pub t_half: *const f64,
    pub t_end: *const f64,
    /// The time-only values at the step's middle and end: a row of the period's table each,
    /// shared by every lane (null where the model has none).
    pub row_half: *const f64,
    pub row_end: *const f64,
    /// The states at the step's end, and their derivative there.
    pub end: *mut f64,
    pub dx: *mut f64,
    /// Mode bits that a stage or the end saw differ from the lane's mode.
    pub seen: *mut u64,
    /// Nonzero where a collision condition holds at the end.
    pub hit: *mut u64,
}

/// Runs a compiled step.
pub type StepEntry = unsafe extern "C" fn(*const StepArgs);

/// `c`'s plain RK4 step of `L` lanes, every lane at step `phase` of a period of
/// `steps_per_period` (`times` each lane's), from states `x` with first stages `k1` (lane-major,
/// [`MAX_DIM`] rows of `L`) on `modes`, by its compiled code: the ends and their derivatives
/// into `end` and `dx`; returns each lane's mode bits seen to differ from its mode and
/// whether it collided. `registers`: the lanes' register file, `table` the forcing's. `None`
/// where the model has no compiled step or the step's forcing is not in `table`.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn run<const L: usize>(
    c: &Compiled,
    registers: &[f64],
    table: Option<&TimeTable>,
    [phase, steps_per_period]: [usize; 2],
    times: &LaneTimes<L>,
    [x, k1]: [&[f64]; 2],
    modes: &[Mode; L],
    [end, dx]: [&mut [f64]; 2],
) -> Option<([Mode; L], [bool; L])> {
    let entry = c.step_entry(L)?;
    let [row_half, row_end] = match table {
        Some(table) => [1, 2].map(|s| {
            let at = GridTime::in_step(phase, s, steps_per_period);
            table.row_at(at).map(<[f64]>::as_ptr)
        }),
        // the code reads no row where the model has no time-only value
        None if c.time_tape.is_empty() => [Some(std::ptr::null()); 2],
        None => [None; 2],
    };
    let vectors = MAX_DIM * L;
    assert!(
        registers.len() >= c.graph.len() * L
            && [x.len(), k1.len(), end.len(), dx.len()] == [vectors; 4],
        "a compiled step given arrays of another shape"
    );
    let (mut seen, mut hit) = ([0u64; L], [0u64; L]);
    let args = StepArgs {
        registers: registers.as_ptr(),
        modes: modes.as_ptr(),
        x: x.as_ptr(),
        k1: k1.as_ptr(),
        h: times.h.as_ptr(),
        t_half: times.t_half.as_ptr(),
        t_end: times.t_end.as_ptr(),
        row_half: row_half?,
        row_end: row_end?,
        end: end.as_mut_ptr(),
        dx: dx.as_mut_ptr(),
        seen: seen.as_mut_ptr(),
        hit: hit.as_mut_ptr(),
    };
    // SAFETY: the code was compiled for `L` lanes of this model: it reads registers below
    // the graph's length (L each), L values of each lane array, the model's states (fewer
    // than MAX_DIM rows) of x, k1, end and dx (asserted above), and columns of this
    // model's table's rows (none where there is no table and no time-only value)
    unsafe { entry(&args) };
    Some((seen, hit.map(|h| h != 0)))
}

/// The compiled step in `code`.
pub(super) fn entry(code: &Native) -> StepEntry {
    // SAFETY: code from `compile_step`, a function of exactly this signature
    unsafe { std::mem::transmute::<*const libc::c_void, StepEntry>(code.address()) }
}

/// Compiles `c`'s plain RK4 step for `lanes` lanes; `None` if the host has no code
/// generator or the model is too large.
pub fn compile_step(c: &Compiled, lanes: usize) -> Option<Native> {
    let (field, collision) = (&c.field_tape, &c.collision_tape);
    let registers = c.graph.len();
    if 4 * field.len() + collision.len() > MAX_INSTRUCTIONS
        || registers * lanes * 8 >= i32::MAX as usize
    {
        return None;
    }
    let dim = c.states.len();
    let time_slot = (0..registers as NodeId).find(|&id| matches!(c.graph.node(id), Node::Time));
    // each time-only value's column in a row of the table
    let mut column = vec![None; registers];
    for (j, &slot) in c.time_tape.roots.iter().enumerate() {
        column[slot as usize] = Some(j as i32);
    }
    let io = &c.field_io;
    lane_loop(1, lanes, |e, lane, params| {
        let (float, int, flags) = (e.float, e.int, e.flags);
        let stride = (lanes * 8) as i32;
        let args: [Value; 13] =
            std::array::from_fn(|k| e.b.ins().load(types::I64, flags, params[0], 8 * k as i32));
        let [
            regs,
            modes,
            x,
            k1,
            h,
            t_half,
            t_end,
            row_half,
            row_end,
            end_out,
            dx_out,
            seen_out,
            hit_out,
        ] = args;
        let mode = e.load_lanes(int, modes, lane, 0);
        let h = e.load_lanes(float, h, lane, 0);
        let row = |e: &mut Emitter, array: Value| -> Vec<Value> {
            (0..dim)
                .map(|i| e.load_lanes(float, array, lane, i as i32 * stride))
                .collect()
        };
        let (x, k1) = (row(e, x), row(e, k1));
        let mut reads = Reads {
            float,
            flags,
            base: e.b.ins().iadd(regs, lane),
            stride,
            time_slot,
            column: &column,
            loaded: vec![None; registers],
        };
        let mut half = Time {
            t: e.load_lanes(float, t_half, lane, 0),
            row: row_half,
            cache: vec![None; c.time_tape.roots.len()],
        };
        let mut at_end = Time {
            t: e.load_lanes(float, t_end, lane, 0),
            row: row_end,
            cache: vec![None; c.time_tape.roots.len()],
        };
        // the field at one stage: its derivatives and the mode bits it saw differ
        let mut stage = |e: &mut Emitter, y: &[Value], time: &mut Time, seen: Value| {
            let mut known = vec![None; registers];
            for &(i, slot) in &io.states {
                known[slot as usize] = Some(y[i as usize]);
            }
            let observed = evaluate(
                e,
                field.instructions(),
                false,
                mode,
                &mut known,
                time,
                &mut reads,
            );
            let k: Vec<Value> = io
                .derivatives
                .iter()
                .map(|&r| value(e, &mut known, time, &mut reads, r))
                .collect();
            let differs = e.b.ins().bxor(observed, mode);
            (k, e.b.ins().bor(seen, differs))
        };
        // y = x + c·k, as the engine's `x[i] + c * k[i]`
        let ahead = |e: &mut Emitter, c: Value, k: &[Value]| -> Vec<Value> {
            (0..dim)
                .map(|i| {
                    let step = e.b.ins().fmul(c, k[i]);
                    e.b.ins().fadd(x[i], step)
                })
                .collect()
        };
        let half_h = {
            let c = e.float_const(0.5);
            e.b.ins().fmul(c, h)
        };
        let seen = e.int_const(0);
        let y = ahead(e, half_h, &k1);
        let (k2, seen) = stage(e, &y, &mut half, seen);
        let y = ahead(e, half_h, &k2);
        let (k3, seen) = stage(e, &y, &mut half, seen);
        let y = ahead(e, h, &k3);
        let (k4, seen) = stage(e, &y, &mut at_end, seen);
        // x + h/6·(k1 + 2·(k2 + k3) + k4)
        let (two, six) = (e.float_const(2.0), e.float_const(6.0));
        let sixth = e.b.ins().fdiv(h, six);
        let end: Vec<Value> = (0..dim)
            .map(|i| {
                let inner = e.b.ins().fadd(k2[i], k3[i]);
                let inner = e.b.ins().fmul(two, inner);
                let sum = e.b.ins().fadd(k1[i], inner);
                let sum = e.b.ins().fadd(sum, k4[i]);
                let step = e.b.ins().fmul(sixth, sum);
                e.b.ins().fadd(x[i], step)
            })
            .collect();
        let (dx, seen) = stage(e, &end, &mut at_end, seen);
        for i in 0..dim {
            e.store_lanes(end[i], end_out, lane, i as i32 * stride);
            e.store_lanes(dx[i], dx_out, lane, i as i32 * stride);
        }
        e.store_lanes(seen, seen_out, lane, 0);
        let hit = if c.collisions.is_empty() {
            e.int_const(0)
        } else {
            let mut known = vec![None; registers];
            for &(i, slot) in &io.states {
                known[slot as usize] = Some(end[i as usize]);
            }
            evaluate(
                e,
                collision.instructions(),
                true,
                mode,
                &mut known,
                &mut at_end,
                &mut reads,
            );
            let mut hit = None;
            for cond in &c.collisions {
                let (_, stops) = decide(e, cond, &mut known, &mut at_end, &mut reads);
                hit = Some(match hit {
                    None => stops,
                    Some(h) => e.b.ins().bor(h, stops),
                });
            }
            let hit = hit.expect("a collision condition");
            if e.width == 1 {
                e.b.ins().uextend(types::I64, hit)
            } else {
                hit
            }
        };
        e.store_lanes(hit, hit_out, lane, 0);
    })
}

/// Where a register that an evaluation has not computed comes from.
struct Reads<'c> {
    float: Type,
    flags: MemFlagsData,
    /// The lane group's registers.
    base: Value,
    stride: i32,
    time_slot: Option<NodeId>,
    /// Each register's column in a row of the forcing's table, if it is time-only.
    column: &'c [Option<i32>],
    /// Registers loaded so far (parameters and what they fix: the same at every stage).
    loaded: Vec<Option<Value>>,
}

/// One of the step's times: τ in each lane, and its row of time-only values (loaded once).
struct Time {
    t: Value,
    row: Value,
    cache: Vec<Option<Value>>,
}

impl Reads<'_> {
    fn read(&mut self, b: &mut FunctionBuilder, time: &mut Time, r: NodeId) -> Value {
        let (float, flags) = (self.float, self.flags);
        if self.time_slot == Some(r) {
            return time.t;
        }
        if let Some(j) = self.column[r as usize] {
            return *time.cache[j as usize].get_or_insert_with(|| {
                let v = b.ins().load(types::F64, flags, time.row, 8 * j);
                if float.is_vector() {
                    b.ins().splat(float, v)
                } else {
                    v
                }
            });
        }
        let (base, stride) = (self.base, self.stride);
        *self.loaded[r as usize]
            .get_or_insert_with(|| b.ins().load(float, flags, base, r as i32 * stride))
    }
}

/// Emits `ins` at `time` over `known` (the states given).
fn evaluate(
    e: &mut Emitter,
    ins: &[Ins],
    free: bool,
    mode: Value,
    known: &mut [Option<Value>],
    time: &mut Time,
    reads: &mut Reads,
) -> Value {
    e.tape(ins, free, mode, known, &mut |b, r| reads.read(b, time, r))
}

/// Register `r`'s value: computed, given, or read.
fn value(
    e: &mut Emitter,
    known: &mut [Option<Value>],
    time: &mut Time,
    reads: &mut Reads,
    r: NodeId,
) -> Value {
    *known[r as usize].get_or_insert_with(|| reads.read(e.b, time, r))
}

/// Whether `cond` holds in each lane, and whether it holds or has no truth value (it then
/// stops the trajectory too), as [`Cond::stops`] decides it: masks, all ones where true.
fn decide(
    e: &mut Emitter,
    cond: &Cond,
    known: &mut [Option<Value>],
    time: &mut Time,
    reads: &mut Reads,
) -> (Value, Value) {
    match cond {
        Cond::Positive { value: id, strict } => {
            let s = value(e, known, time, reads, *id);
            let zero = e.float_const(0.0);
            let (holds, stops) = if *strict {
                (FloatCC::GreaterThan, FloatCC::UnorderedOrGreaterThan)
            } else {
                (
                    FloatCC::GreaterThanOrEqual,
                    FloatCC::UnorderedOrGreaterThanOrEqual,
                )
            };
            (
                e.b.ins().fcmp(holds, s, zero),
                e.b.ins().fcmp(stops, s, zero),
            )
        }
        Cond::And(a, b) => {
            let (a_holds, a_stops) = decide(e, a, known, time, reads);
            let (b_holds, b_stops) = decide(e, b, known, time, reads);
            // a without a value stops; a true leaves it to b; a false does not stop
            let a_fails = if e.width == 1 {
                e.b.ins().bxor_imm_u(a_holds, 1)
            } else {
                e.b.ins().bnot(a_holds)
            };
            let b_decides = e.b.ins().bor(a_fails, b_stops);
            (
                e.b.ins().band(a_holds, b_holds),
                e.b.ins().band(a_stops, b_decides),
            )
        }
        Cond::Or(a, b) => {
            let (a_holds, a_stops) = decide(e, a, known, time, reads);
            let (b_holds, b_stops) = decide(e, b, known, time, reads);
            (
                e.b.ins().bor(a_holds, b_holds),
                e.b.ins().bor(a_stops, b_stops),
            )
        }
    }
}
