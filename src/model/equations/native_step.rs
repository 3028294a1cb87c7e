//! A written model's plain RK4 step as one piece of machine code: the general engine's step
//! (`solver::general`'s `rk4`, the same operations in the same order) with the field's
//! instructions emitted at each of its four evaluations, the forcing read from the rows of
//! the period's table, and the collision conditions at its end. One call per step instead of
//! a call per stage and the engine's bookkeeping around each: the step's values are those of
//! the stage-by-stage path bit for bit (tests hold this). A step in which a switch is seen
//! is still split by the engine, stage by stage.

use super::build::{Compiled, Cond};
use super::graph::{Node, NodeId};
use super::lane_code::{Arg, Arith, Compare, LaneCode, tape};
use super::lanes::LaneTimes;
use super::native::{MAX_INSTRUCTIONS, Native, lane_loop};
use super::time_table::{GridTime, TimeTable};
use crate::model::system::{END_SWITCHES, MAX_DIM, Mode};

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
    /// The model's first [`END_SWITCHES`] switching values at the end (row k of lane l at
    /// k·L + l; rows past its last switch are not written), and the mode bits the end alone
    /// saw (not or-ed with the stages').
    pub switching: *mut f64,
    pub end_seen: *mut u64,
}

/// Runs a compiled step.
pub type StepEntry = unsafe extern "C" fn(*const StepArgs);

/// `c`'s plain RK4 step of `L` lanes, every lane at step `phase` of a period of
/// `steps_per_period` (`times` each lane's), from states `x` with first stages `k1` (lane-major,
/// [`MAX_DIM`] rows of `L`) on `modes`, by its compiled code: the ends and their derivatives
/// into `end` and `dx`, the switching values at the ends into `switching` ([`END_SWITCHES`]
/// rows of `L`); returns each lane's mode bits seen to differ from its mode, whether it
/// collided, and the mode bits its end alone saw. `registers`: the lanes' register file,
/// `table` the forcing's. `None` where the model has no compiled step or the step's forcing
/// is not in `table`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn run<const L: usize>(
    c: &Compiled,
    registers: &[f64],
    table: Option<&TimeTable>,
    [phase, steps_per_period]: [usize; 2],
    times: &LaneTimes<L>,
    [x, k1]: [&[f64]; 2],
    modes: &[Mode; L],
    [end, dx]: [&mut [f64]; 2],
    switching: &mut [f64],
) -> Option<([Mode; L], [bool; L], [Mode; L])> {
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
            && [x.len(), k1.len(), end.len(), dx.len()] == [vectors; 4]
            && switching.len() == END_SWITCHES * L,
        "a compiled step given arrays of another shape"
    );
    let (mut seen, mut hit, mut end_seen) = ([0u64; L], [0u64; L], [0u64; L]);
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
        switching: switching.as_mut_ptr(),
        end_seen: end_seen.as_mut_ptr(),
    };
    // SAFETY: the code was compiled for `L` lanes of this model: it reads registers below
    // the graph's length (L each), L values of each lane array, the model's states (fewer
    // than MAX_DIM rows) of x, k1, end and dx, at most END_SWITCHES rows of switching
    // (asserted above), and columns of this model's table's rows (none where there is no
    // table and no time-only value)
    unsafe { entry(&args) };
    Some((seen, hit.map(|h| h != 0), end_seen))
}

/// The compiled step in `code`.
pub(super) fn entry(code: &Native) -> StepEntry {
    // SAFETY: code from `compile_step`, a function of exactly this signature
    unsafe { std::mem::transmute::<*const libc::c_void, StepEntry>(code.address()) }
}

/// The pointers of [`StepArgs`], in its order.
const REGISTERS: Arg = 0;
const MODES: Arg = 1;
const X: Arg = 2;
const K1: Arg = 3;
const H: Arg = 4;
const T_HALF: Arg = 5;
const T_END: Arg = 6;
const ROW_HALF: Arg = 7;
const ROW_END: Arg = 8;
const END: Arg = 9;
const DX: Arg = 10;
const SEEN: Arg = 11;
const HIT: Arg = 12;
const SWITCHING: Arg = 13;
const END_SEEN: Arg = 14;
/// How many.
const STEP_POINTERS: usize = 15;
const _: () = assert!(std::mem::size_of::<StepArgs>() == 8 * STEP_POINTERS);

/// Whether `c`'s step can be compiled for `lanes` lanes: a model not too large.
fn compilable(c: &Compiled, lanes: usize) -> bool {
    4 * c.field_tape.len() + c.collision_tape.len() <= MAX_INSTRUCTIONS
        && c.graph.len() * lanes * 8 < i32::MAX as usize
}

/// Compiles `c`'s plain RK4 step for `lanes` lanes: with our AVX2 emitter where the lanes
/// come in fours and the processor has AVX2 (and the step's frame is not too large), else
/// with Cranelift; `None` if neither can, or the model is too large.
pub fn compile_step(c: &Compiled, lanes: usize) -> Option<Native> {
    if !compilable(c, lanes) {
        return None;
    }
    if lanes.is_multiple_of(super::avx2::WIDTH)
        && super::avx2::available()
        && let Some(code) = super::avx2::compile(lanes, |e| emit_step(e, c, lanes))
    {
        return Some(code);
    }
    lane_loop(1, lanes, |e| {
        e.pointers_at(0, STEP_POINTERS);
        emit_step(e, c, lanes);
    })
}

/// `c`'s plain RK4 step over one lane group of `lanes`, reading and writing through the
/// pointers of [`StepArgs`].
fn emit_step<E: LaneCode>(e: &mut E, c: &Compiled, lanes: usize) {
    let (field, collision) = (&c.field_tape, &c.collision_tape);
    let registers = c.graph.len();
    let dim = c.states.len();
    let time_slot = (0..registers as NodeId).find(|&id| matches!(c.graph.node(id), Node::Time));
    // each time-only value's column in a row of the table
    let mut column = vec![None; registers];
    for (j, &slot) in c.time_tape.roots.iter().enumerate() {
        column[slot as usize] = Some(j as i32);
    }
    let io = &c.field_io;
    let stride = (lanes * 8) as i32;
    let mode = e.load_int(MODES, 0);
    let h = e.load(H, 0);
    let x: Vec<E::F> = (0..dim).map(|i| e.load(X, i as i32 * stride)).collect();
    let k1: Vec<E::F> = (0..dim).map(|i| e.load(K1, i as i32 * stride)).collect();
    let mut reads = Reads {
        stride,
        time_slot,
        column: &column,
        loaded: vec![None; registers],
    };
    let mut half = Time {
        t: e.load(T_HALF, 0),
        row: ROW_HALF,
        cache: vec![None; c.time_tape.roots.len()],
    };
    let mut at_end = Time {
        t: e.load(T_END, 0),
        row: ROW_END,
        cache: vec![None; c.time_tape.roots.len()],
    };
    // the field at one stage: its derivatives, the mode bits it saw differ (or-ed into
    // `seen`), the mode bits it saw and its registers
    let mut stage = |e: &mut E, y: &[E::F], time: &mut Time<E::F>, seen: E::M| {
        let mut known = vec![None; registers];
        for &(i, slot) in &io.states {
            known[slot as usize] = Some(y[i as usize]);
        }
        let observed = tape(
            e,
            field.instructions(),
            false,
            mode,
            &mut known,
            &mut |e, r| reads.read(e, time, r),
        );
        let k: Vec<E::F> = io
            .derivatives
            .iter()
            .map(|&r| value(e, &mut known, time, &mut reads, r))
            .collect();
        let differs = e.xor(observed, mode);
        (k, e.or(seen, differs), observed, known)
    };
    // y = x + c·k, as the engine's `x[i] + c * k[i]`
    let ahead = |e: &mut E, c: E::F, k: &[E::F]| -> Vec<E::F> {
        (0..dim)
            .map(|i| {
                let step = e.arith(Arith::Mul, c, k[i]);
                e.arith(Arith::Add, x[i], step)
            })
            .collect()
    };
    let half_h = {
        let c = e.float_const(0.5);
        e.arith(Arith::Mul, c, h)
    };
    let seen = e.int_const(0);
    let y = ahead(e, half_h, &k1);
    let (k2, seen, ..) = stage(e, &y, &mut half, seen);
    let y = ahead(e, half_h, &k2);
    let (k3, seen, ..) = stage(e, &y, &mut half, seen);
    let y = ahead(e, h, &k3);
    let (k4, seen, ..) = stage(e, &y, &mut at_end, seen);
    // x + h/6·(k1 + 2·(k2 + k3) + k4)
    let (two, six) = (e.float_const(2.0), e.float_const(6.0));
    let sixth = e.arith(Arith::Div, h, six);
    let end: Vec<E::F> = (0..dim)
        .map(|i| {
            let inner = e.arith(Arith::Add, k2[i], k3[i]);
            let inner = e.arith(Arith::Mul, two, inner);
            let sum = e.arith(Arith::Add, k1[i], inner);
            let sum = e.arith(Arith::Add, sum, k4[i]);
            let step = e.arith(Arith::Mul, sixth, sum);
            e.arith(Arith::Add, x[i], step)
        })
        .collect();
    let (dx, seen, end_seen, mut at) = stage(e, &end, &mut at_end, seen);
    for i in 0..dim {
        e.store(END, i as i32 * stride, end[i]);
        e.store(DX, i as i32 * stride, dx[i]);
    }
    e.store_int(SEEN, 0, seen);
    e.store_int(END_SEEN, 0, end_seen);
    for (k, switch) in c.graph.switches.iter().take(END_SWITCHES).enumerate() {
        let s = value(e, &mut at, &mut at_end, &mut reads, switch.value);
        e.store(SWITCHING, k as i32 * stride, s);
    }
    let hit = if c.collisions.is_empty() {
        e.int_const(0)
    } else {
        let mut known = vec![None; registers];
        for &(i, slot) in &io.states {
            known[slot as usize] = Some(end[i as usize]);
        }
        tape(
            e,
            collision.instructions(),
            true,
            mode,
            &mut known,
            &mut |e, r| reads.read(e, &mut at_end, r),
        );
        let mut hit = None;
        for cond in &c.collisions {
            let (_, stops) = decide(e, cond, &mut known, &mut at_end, &mut reads);
            hit = Some(match hit {
                None => stops,
                Some(h) => e.or(h, stops),
            });
        }
        hit.expect("a collision condition")
    };
    e.store_int(HIT, 0, hit);
}

/// Where a register that an evaluation has not computed comes from.
struct Reads<'c, F> {
    stride: i32,
    time_slot: Option<NodeId>,
    /// Each register's column in a row of the forcing's table, if it is time-only.
    column: &'c [Option<i32>],
    /// Registers loaded so far (parameters and what they fix: the same at every stage).
    loaded: Vec<Option<F>>,
}

/// One of the step's times: τ in each lane, and its row of time-only values (loaded once).
struct Time<F> {
    t: F,
    row: Arg,
    cache: Vec<Option<F>>,
}

impl<F: Copy> Reads<'_, F> {
    fn read<E: LaneCode<F = F>>(&mut self, e: &mut E, time: &mut Time<F>, r: NodeId) -> F {
        if self.time_slot == Some(r) {
            return time.t;
        }
        if let Some(j) = self.column[r as usize] {
            return match time.cache[j as usize] {
                Some(v) => v,
                None => *time.cache[j as usize].insert(e.load_splat(time.row, 8 * j)),
            };
        }
        match self.loaded[r as usize] {
            Some(v) => v,
            None => *self.loaded[r as usize].insert(e.load(REGISTERS, r as i32 * self.stride)),
        }
    }
}

/// Register `r`'s value: computed, given, or read.
fn value<E: LaneCode>(
    e: &mut E,
    known: &mut [Option<E::F>],
    time: &mut Time<E::F>,
    reads: &mut Reads<E::F>,
    r: NodeId,
) -> E::F {
    match known[r as usize] {
        Some(v) => v,
        None => *known[r as usize].insert(reads.read(e, time, r)),
    }
}

/// Whether `cond` holds in each lane, and whether it holds or has no truth value (it then
/// stops the trajectory too), as [`Cond::stops`] decides it: masks, all ones where true.
fn decide<E: LaneCode>(
    e: &mut E,
    cond: &Cond,
    known: &mut [Option<E::F>],
    time: &mut Time<E::F>,
    reads: &mut Reads<E::F>,
) -> (E::M, E::M) {
    match cond {
        Cond::Positive { value: id, strict } => {
            let s = value(e, known, time, reads, *id);
            let zero = e.float_const(0.0);
            let (holds, stops) = if *strict {
                (Compare::Gt, Compare::UnorderedOrGt)
            } else {
                (Compare::Ge, Compare::UnorderedOrGe)
            };
            (e.compare(holds, s, zero), e.compare(stops, s, zero))
        }
        Cond::And(a, b) => {
            let (a_holds, a_stops) = decide(e, a, known, time, reads);
            let (b_holds, b_stops) = decide(e, b, known, time, reads);
            // a without a value stops; a true leaves it to b; a false does not stop
            let a_fails = e.not(a_holds);
            let b_decides = e.or(a_fails, b_stops);
            (e.and(a_holds, b_holds), e.and(a_stops, b_decides))
        }
        Cond::Or(a, b) => {
            let (a_holds, a_stops) = decide(e, a, known, time, reads);
            let (b_holds, b_stops) = decide(e, b, known, time, reads);
            (e.or(a_holds, b_holds), e.or(a_stops, b_stops))
        }
    }
}
