//! A [`Tape`](super::tape::Tape) compiled to machine code with Cranelift: the same
//! instructions in the same order, with the same library calls for the transcendental
//! functions and the same multiplications for integer powers, so that a native run gives
//! bit for bit the interpreter's values (tests hold this). Only on x86-64; elsewhere, or if
//! the host cannot be compiled for, the tape is interpreted.

use cranelift_codegen::control::ControlPlane;
use cranelift_codegen::ir::condcodes::{FloatCC, IntCC};
use cranelift_codegen::ir::{
    AbiParam, Endianness, Function, InstBuilder, MemFlagsData, SigRef, Signature, Type,
    UserFuncName, Value, types,
};
use cranelift_codegen::isa::OwnedTargetIsa;
use cranelift_codegen::settings::{self, Configurable};
use cranelift_codegen::{Context, isa::TargetIsa};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use std::sync::OnceLock;

use super::lane_code::{Arg, Arith, Compare, LaneCode, tape};
use super::tape::{FieldIo, Ins};

/// Runs a tape on registers: `(registers, modes, observed, states, derivatives)`, one
/// `Mode` of each per lane; lane l's register r is at `registers[r·L + l]`, its state i at
/// `states[i·L + l]`, its derivative i at `derivatives[i·L + l]`. Only code compiled with a
/// [`FieldIo`] reads the states and writes the derivatives (others may be given null).
pub type Entry = unsafe extern "C" fn(*mut f64, *const u64, *mut u64, *const f64, *mut f64);

/// Tapes longer than this are interpreted: compiling straight-line code grows faster than
/// its length, and a model this large is rare.
pub(super) const MAX_INSTRUCTIONS: usize = 20_000;

/// The host's code generator, made once per process (`None` where there is none).
fn host() -> Option<&'static dyn TargetIsa> {
    static HOST: OnceLock<Option<OwnedTargetIsa>> = OnceLock::new();
    HOST.get_or_init(|| {
        let mut flags = settings::builder();
        flags.set("opt_level", "speed").ok()?;
        let builder = cranelift_native::builder().ok()?;
        builder.finish(settings::Flags::new(flags)).ok()
    })
    .as_deref()
}

/// Machine code in pages of its own, executable and never written again.
#[derive(Debug)]
struct Code {
    ptr: *mut libc::c_void,
    len: usize,
}

// SAFETY: the pages are immutable once made executable, and only freed on drop
unsafe impl Send for Code {}
unsafe impl Sync for Code {}

impl Code {
    /// Copies `bytes` into fresh pages and makes them executable.
    fn new(bytes: &[u8]) -> Option<Code> {
        let len = bytes.len().max(1);
        // SAFETY: an anonymous private mapping of `len` bytes, checked before use; the copy
        // stays inside it; the protection change covers exactly the mapping
        unsafe {
            let ptr = libc::mmap(
                std::ptr::null_mut(),
                len,
                libc::PROT_READ | libc::PROT_WRITE,
                libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
                -1,
                0,
            );
            if ptr == libc::MAP_FAILED {
                return None;
            }
            let code = Code { ptr, len };
            std::ptr::copy_nonoverlapping(bytes.as_ptr(), ptr.cast::<u8>(), bytes.len());
            if libc::mprotect(ptr, len, libc::PROT_READ | libc::PROT_EXEC) != 0 {
                return None;
            }
            Some(code)
        }
    }
}

impl Drop for Code {
    fn drop(&mut self) {
        // SAFETY: the mapping made in `new`, unmapped once
        unsafe {
            libc::munmap(self.ptr, self.len);
        }
    }
}

/// One tape compiled for `lanes` lanes, held (`free`) or choosing each kink by its sign.
#[derive(Debug)]
pub struct Native {
    code: Code,
}

impl Native {
    /// `bytes` of machine code in pages of their own.
    pub(super) fn new(bytes: &[u8]) -> Option<Native> {
        Some(Native {
            code: Code::new(bytes)?,
        })
    }

    /// Where the code starts.
    pub(super) fn address(&self) -> *const libc::c_void {
        self.code.ptr
    }

    /// The compiled function.
    pub fn entry(&self) -> Entry {
        // SAFETY: the code is a function of exactly this signature (built in `compile`)
        unsafe { std::mem::transmute::<*mut libc::c_void, Entry>(self.code.ptr) }
    }
}

/// Compiles `ins` (registers below `registers`) for `lanes` lanes, storing the registers
/// `roots`, and with `io` reading the states and writing the derivatives itself; `None` if
/// the host has no code generator or the tape is too long.
pub fn compile(
    ins: &[Ins],
    roots: &[u32],
    registers: usize,
    lanes: usize,
    free: bool,
    io: Option<&FieldIo>,
) -> Option<Native> {
    if ins.len() > MAX_INSTRUCTIONS || registers * lanes * 8 >= i32::MAX as usize {
        return None;
    }
    // the entry's pointers
    const REGS: Arg = 0;
    const MODES: Arg = 1;
    const OBSERVED: Arg = 2;
    const STATES: Arg = 3;
    const DERIVATIVES: Arg = 4;
    lane_loop(5, lanes, |e| {
        let stride = (lanes * 8) as i32;
        let mode = e.load_int(MODES, 0);
        let mut known = vec![None; registers];
        if let Some(io) = io {
            // the states from the caller's vectors (not stored in the registers: every other
            // use loads them itself)
            for &(i, slot) in &io.states {
                known[slot as usize] = Some(e.load(STATES, i32::from(i) * stride));
            }
        }
        let observed = tape(e, ins, free, mode, &mut known, &mut |e, r| {
            e.load(REGS, r as i32 * stride)
        });
        // what the caller reads; the rest stays in the machine's registers
        for &r in roots {
            let value = known[r as usize].expect("a root the tape computes");
            e.store(REGS, r as i32 * stride, value);
        }
        if let Some(io) = io {
            for (i, &r) in io.derivatives.iter().enumerate() {
                let value = known[r as usize].unwrap_or_else(|| e.load(REGS, r as i32 * stride));
                e.store(DERIVATIVES, i as i32 * stride, value);
            }
        }
        e.store_int(OBSERVED, 0, observed);
    })
}

/// Compiles a function of `params` pointers that runs `body(emitter)` over `lanes` lanes,
/// `emitter.width` at a time (the emitter's loads and stores address the group's lanes of
/// lane-major arrays: lane l of row r at byte (r·lanes + l)·8). `None` if the host has no
/// code generator or the code cannot be compiled.
pub(super) fn lane_loop(
    params: usize,
    lanes: usize,
    body: impl FnOnce(&mut Emitter),
) -> Option<Native> {
    let isa = host()?;
    let pointer = isa.pointer_type();
    let mut sig = Signature::new(isa.default_call_conv());
    sig.params
        .extend(std::iter::repeat_n(AbiParam::new(pointer), params));
    let mut func = Function::with_name_signature(UserFuncName::default(), sig);
    let mut fctx = FunctionBuilderContext::new();
    let mut b = FunctionBuilder::new(&mut func, &mut fctx);

    let entry = b.create_block();
    let block = b.create_block();
    let exit = b.create_block();
    b.append_block_params_for_function_params(entry);
    b.append_block_param(block, pointer);
    b.switch_to_block(entry);
    let args = b.block_params(entry).to_vec();
    let zero = b.ins().iconst(pointer, 0);
    b.ins().jump(block, &[zero.into()]);

    b.switch_to_block(block);
    let lane = b.block_params(block)[0];
    let mut e = Emitter::new(&mut b, isa, lanes, args, lane);
    body(&mut e);
    let width = e.width;
    let next = b.ins().iadd_imm_u(lane, 8 * width as i64);
    let more = b
        .ins()
        .icmp_imm_u(IntCC::UnsignedLessThan, next, (lanes * 8) as i64);
    b.ins().brif(more, block, &[next.into()], exit, &[]);
    b.switch_to_block(exit);
    b.ins().return_(&[]);
    b.seal_all_blocks();
    b.finalize(isa.frontend_config());

    let mut ctx = Context::for_function(func);
    let compiled = match ctx.compile(isa, &mut ControlPlane::default()) {
        Ok(compiled) => compiled,
        Err(e) => {
            tracing::warn!("a written model's code is interpreted: {:?}", e.inner);
            return None;
        }
    };
    // calls go through addresses held as constants: nothing to relocate
    if !compiled.buffer.relocs().is_empty() {
        return None;
    }
    Native::new(compiled.code_buffer())
}

/// Emits a [`lane_loop`]'s body for one lane group with Cranelift: `width` lanes at a time
/// (two in one SSE register where there are pairs).
pub(super) struct Emitter<'a, 'f> {
    b: &'a mut FunctionBuilder<'f>,
    width: usize,
    /// A group's float and integer (mode) values.
    float: Type,
    int: Type,
    /// Loads and stores (registers of lanes are f64-aligned, pairs of them not always
    /// 16-byte aligned).
    flags: MemFlagsData,
    lanes_of: MemFlagsData,
    unary: SigRef,
    binary: SigRef,
    /// The function's pointers, and each offset to the group's lanes (made at first use).
    pointers: Vec<Value>,
    at_group: Vec<Option<Value>>,
    /// The group's byte offset into a lane-major array.
    lane: Value,
}

impl<'a, 'f> Emitter<'a, 'f> {
    fn new(
        b: &'a mut FunctionBuilder<'f>,
        isa: &dyn TargetIsa,
        lanes: usize,
        pointers: Vec<Value>,
        lane: Value,
    ) -> Self {
        let mut unary = Signature::new(isa.default_call_conv());
        unary.params.push(AbiParam::new(types::F64));
        unary.returns.push(AbiParam::new(types::F64));
        let mut binary = unary.clone();
        binary.params.push(AbiParam::new(types::F64));
        let unary = b.import_signature(unary);
        let binary = b.import_signature(binary);
        let width = if lanes.is_multiple_of(2) { 2 } else { 1 };
        let (float, int) = match width {
            2 => (types::F64X2, types::I64X2),
            _ => (types::F64, types::I64),
        };
        Emitter {
            b,
            width,
            float,
            int,
            flags: MemFlagsData::new().with_notrap(),
            lanes_of: MemFlagsData::new().with_endianness(Endianness::Little),
            unary,
            binary,
            at_group: vec![None; pointers.len()],
            pointers,
            lane,
        }
    }

    /// Takes the function's pointers from the `count` stored at its pointer `arg` (a
    /// `#[repr(C)]` struct of pointers).
    pub fn pointers_at(&mut self, arg: Arg, count: usize) {
        let base = self.pointers[arg];
        self.pointers = (0..count)
            .map(|k| {
                self.b
                    .ins()
                    .load(types::I64, self.flags, base, 8 * k as i32)
            })
            .collect();
        self.at_group = vec![None; count];
    }

    /// `v` in every lane of the group.
    fn splat(&mut self, ty: Type, v: Value) -> Value {
        match self.width {
            2 => self.b.ins().splat(ty, v),
            _ => v,
        }
    }

    /// Pointer `arg` moved to the lane group's first lane.
    fn at_group(&mut self, arg: Arg) -> Value {
        match self.at_group[arg] {
            Some(at) => at,
            None => {
                let at = self.b.ins().iadd(self.pointers[arg], self.lane);
                *self.at_group[arg].insert(at)
            }
        }
    }

    /// A library call per lane.
    fn call_each(&mut self, sig: SigRef, address: usize, args: &[Value]) -> Value {
        if self.width == 1 {
            return call(self.b, sig, address, args);
        }
        let mut out = None;
        for l in 0..2u8 {
            let lane_args: Vec<Value> = args
                .iter()
                .map(|&a| self.b.ins().extractlane(a, l))
                .collect();
            let r = call(self.b, sig, address, &lane_args);
            out = Some(match out {
                None => self.b.ins().scalar_to_vector(self.float, r),
                Some(v) => self.b.ins().insertlane(v, r, l),
            });
        }
        out.expect("two lanes")
    }
}

impl LaneCode for Emitter<'_, '_> {
    type F = Value;
    type M = Value;

    fn float_const(&mut self, v: f64) -> Value {
        let v = self.b.ins().f64const(v);
        self.splat(self.float, v)
    }

    fn int_const(&mut self, v: u64) -> Value {
        let v = self.b.ins().iconst(types::I64, v as i64);
        self.splat(self.int, v)
    }

    fn arith(&mut self, op: Arith, x: Value, y: Value) -> Value {
        let ins = self.b.ins();
        match op {
            Arith::Add => ins.fadd(x, y),
            Arith::Sub => ins.fsub(x, y),
            Arith::Mul => ins.fmul(x, y),
            Arith::Div => ins.fdiv(x, y),
        }
    }

    fn sqrt(&mut self, x: Value) -> Value {
        self.b.ins().sqrt(x)
    }

    fn neg(&mut self, x: Value) -> Value {
        self.b.ins().fneg(x)
    }

    fn call(&mut self, address: usize, args: &[Value]) -> Value {
        let sig = if args.len() == 1 {
            self.unary
        } else {
            self.binary
        };
        self.call_each(sig, address, args)
    }

    fn compare(&mut self, cc: Compare, x: Value, y: Value) -> Value {
        let cc = match cc {
            Compare::Ge => FloatCC::GreaterThanOrEqual,
            Compare::Gt => FloatCC::GreaterThan,
            Compare::UnorderedOrGe => FloatCC::UnorderedOrGreaterThanOrEqual,
            Compare::UnorderedOrGt => FloatCC::UnorderedOrGreaterThan,
        };
        self.b.ins().fcmp(cc, x, y)
    }

    fn sign_bit(&mut self, truth: Value, k: u8) -> Value {
        if self.width == 1 {
            let on = self.b.ins().uextend(types::I64, truth);
            self.b.ins().ishl_imm_u(on, i64::from(k))
        } else {
            // a lane's comparison is all ones where it holds
            let bit = self.int_const(1u64 << k);
            self.b.ins().band(truth, bit)
        }
    }

    fn and(&mut self, a: Value, b: Value) -> Value {
        self.b.ins().band(a, b)
    }

    fn or(&mut self, a: Value, b: Value) -> Value {
        self.b.ins().bor(a, b)
    }

    fn xor(&mut self, a: Value, b: Value) -> Value {
        self.b.ins().bxor(a, b)
    }

    fn not(&mut self, a: Value) -> Value {
        if self.width == 1 {
            self.b.ins().bxor_imm_u(a, 1)
        } else {
            self.b.ins().bnot(a)
        }
    }

    fn select_on_bit(&mut self, m: Value, k: u8, x: Value, y: Value) -> Value {
        let bit = self.int_const(1u64 << k);
        let zero = self.int_const(0);
        let bit = self.b.ins().band(m, bit);
        let on = self.b.ins().icmp(IntCC::NotEqual, bit, zero);
        if self.width == 1 {
            // the comparison's truth picks (no mask made of it)
            self.b.ins().select(on, x, y)
        } else {
            // two lanes' comparison is a mask (all ones where it holds)
            let on = self.b.ins().bitcast(self.float, self.lanes_of, on);
            self.b.ins().bitselect(on, x, y)
        }
    }

    fn load(&mut self, arg: Arg, offset: i32) -> Value {
        let at = self.at_group(arg);
        self.b.ins().load(self.float, self.flags, at, offset)
    }

    fn load_int(&mut self, arg: Arg, offset: i32) -> Value {
        let at = self.at_group(arg);
        self.b.ins().load(self.int, self.flags, at, offset)
    }

    fn load_splat(&mut self, arg: Arg, offset: i32) -> Value {
        let v = self
            .b
            .ins()
            .load(types::F64, self.flags, self.pointers[arg], offset);
        self.splat(self.float, v)
    }

    fn store(&mut self, arg: Arg, offset: i32, v: Value) {
        let at = self.at_group(arg);
        self.b.ins().store(self.flags, v, at, offset);
    }

    fn store_int(&mut self, arg: Arg, offset: i32, v: Value) {
        // one lane's truth is a byte
        let v = if self.b.func.dfg.value_type(v) == types::I8 {
            self.b.ins().uextend(types::I64, v)
        } else {
            v
        };
        self.store(arg, offset, v);
    }
}

/// Calls the function at `address` (of signature `sig`) on `args`.
fn call(
    b: &mut FunctionBuilder,
    sig: cranelift_codegen::ir::SigRef,
    address: usize,
    args: &[Value],
) -> Value {
    let callee = b.ins().iconst(types::I64, address as i64);
    let call = b.ins().call_indirect(sig, callee, args);
    b.inst_results(call)[0]
}
