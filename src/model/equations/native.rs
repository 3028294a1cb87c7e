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

use super::graph::Func;
use super::tape::{FieldIo, Ins, Op};

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
    lane_loop(5, lanes, |e, lane, params| {
        let [regs, modes, observed_out, states, derivatives] =
            params.try_into().expect("five pointers");
        let stride = (lanes * 8) as i32;
        let (float, flags) = (e.float, e.flags);
        let base = e.b.ins().iadd(regs, lane);
        let mode = e.load_lanes(e.int, modes, lane, 0);
        let mut known: Vec<Option<Value>> = vec![None; registers];
        if let Some(io) = io {
            // the states from the caller's vectors (not stored in the registers: every other
            // use loads them itself)
            for &(i, slot) in &io.states {
                known[slot as usize] =
                    Some(e.load_lanes(float, states, lane, i32::from(i) * stride));
            }
        }
        let observed = e.tape(ins, free, mode, &mut known, &mut |b, r| {
            b.ins().load(float, flags, base, r as i32 * stride)
        });
        // what the caller reads; the rest stays in the machine's registers
        for &r in roots {
            let value = known[r as usize].expect("a root the tape computes");
            e.b.ins().store(flags, value, base, r as i32 * stride);
        }
        if let Some(io) = io {
            let at = e.b.ins().iadd(derivatives, lane);
            for (i, &r) in io.derivatives.iter().enumerate() {
                let value = known[r as usize]
                    .unwrap_or_else(|| e.b.ins().load(float, flags, base, r as i32 * stride));
                e.b.ins().store(flags, value, at, i as i32 * stride);
            }
        }
        e.store_lanes(observed, observed_out, lane, 0);
    })
}

/// Compiles a function of `params` pointers that runs `body(emitter, lane, params)` over
/// `lanes` lanes, `emitter.width` at a time, `lane` being the group's byte offset into a
/// lane-major array (lane l of row r at byte (r·lanes + l)·8). `None` if the host has no
/// code generator or the code cannot be compiled.
pub(super) fn lane_loop(
    params: usize,
    lanes: usize,
    body: impl FnOnce(&mut Emitter, Value, &[Value]),
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
    let mut e = Emitter::new(&mut b, isa, lanes);
    body(&mut e, lane, &args);
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
    Some(Native {
        code: Code::new(compiled.code_buffer())?,
    })
}

/// Emits tapes into one lane group of a [`lane_loop`]: `width` lanes at a time (two in one
/// SSE register where there are pairs).
pub(super) struct Emitter<'a, 'f> {
    pub b: &'a mut FunctionBuilder<'f>,
    pub width: usize,
    /// A group's float and integer (mode) values.
    pub float: Type,
    pub int: Type,
    /// Loads and stores (registers of lanes are f64-aligned, pairs of them not always
    /// 16-byte aligned).
    pub flags: MemFlagsData,
    lanes_of: MemFlagsData,
    unary: SigRef,
    binary: SigRef,
    int_zero: Value,
    float_zero: Value,
    pub float_one: Value,
}

impl<'a, 'f> Emitter<'a, 'f> {
    fn new(b: &'a mut FunctionBuilder<'f>, isa: &dyn TargetIsa, lanes: usize) -> Self {
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
        let splat = |b: &mut FunctionBuilder, ty: Type, v: Value| match width {
            2 => b.ins().splat(ty, v),
            _ => v,
        };
        let zero = b.ins().iconst(types::I64, 0);
        let int_zero = splat(b, int, zero);
        let zero = b.ins().f64const(0.0);
        let float_zero = splat(b, float, zero);
        let one = b.ins().f64const(1.0);
        let float_one = splat(b, float, one);
        Emitter {
            b,
            width,
            float,
            int,
            flags: MemFlagsData::new().with_notrap(),
            lanes_of: MemFlagsData::new().with_endianness(Endianness::Little),
            unary,
            binary,
            int_zero,
            float_zero,
            float_one,
        }
    }

    /// `v` in every lane of the group.
    pub fn splat(&mut self, ty: Type, v: Value) -> Value {
        match self.width {
            2 => self.b.ins().splat(ty, v),
            _ => v,
        }
    }

    pub fn int_const(&mut self, v: u64) -> Value {
        let v = self.b.ins().iconst(types::I64, v as i64);
        self.splat(self.int, v)
    }

    pub fn float_const(&mut self, v: f64) -> Value {
        let v = self.b.ins().f64const(v);
        self.splat(self.float, v)
    }

    /// The group's lanes of the lane-major array at `array`, row at byte `offset`.
    pub fn load_lanes(&mut self, ty: Type, array: Value, lane: Value, offset: i32) -> Value {
        let at = self.b.ins().iadd(array, lane);
        self.b.ins().load(ty, self.flags, at, offset)
    }

    /// Stores the group's lanes of `value` into the lane-major array at `array`.
    pub fn store_lanes(&mut self, value: Value, array: Value, lane: Value, offset: i32) {
        let at = self.b.ins().iadd(array, lane);
        self.b.ins().store(self.flags, value, at, offset);
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

    /// Emits `ins` with each kink held on `mode`'s branch (or, `free`, on its switching
    /// value's sign), and returns the mode the switching values' signs select. `known`
    /// holds the registers' values so far (given or computed); a register not in it is
    /// `read` once.
    pub fn tape(
        &mut self,
        ins: &[Ins],
        free: bool,
        mode: Value,
        known: &mut [Option<Value>],
        read: &mut dyn FnMut(&mut FunctionBuilder, u32) -> Value,
    ) -> Value {
        let (int_zero, float_zero, float_one) = (self.int_zero, self.float_zero, self.float_one);
        let mut observed = int_zero;
        for i in ins {
            let x = *known[i.a as usize].get_or_insert_with(|| read(self.b, i.a));
            let y = *known[i.b as usize].get_or_insert_with(|| read(self.b, i.b));
            let value = match i.op {
                Op::Add => self.b.ins().fadd(x, y),
                Op::Sub => self.b.ins().fsub(x, y),
                Op::Mul => self.b.ins().fmul(x, y),
                Op::Div => self.b.ins().fdiv(x, y),
                Op::Pow => self.call_each(self.binary, powf as *const () as usize, &[x, y]),
                Op::Powi => powi(self.b, x, i.n, float_one),
                Op::Un(Func::Neg) => self.b.ins().fneg(x),
                Op::Un(Func::Sqrt) => self.b.ins().sqrt(x),
                Op::Un(Func::Undefined) => self.b.ins().fsub(x, x),
                Op::Un(f) => self.call_each(self.unary, library(f), &[x]),
                Op::Select => {
                    let m = if free { observed } else { mode };
                    let bit = self.int_const(1u64 << i.k);
                    let bit = self.b.ins().band(m, bit);
                    let on = self.b.ins().icmp(IntCC::NotEqual, bit, int_zero);
                    if self.width == 1 {
                        self.b.ins().select(on, x, y)
                    } else {
                        let on = self.b.ins().bitcast(self.float, self.lanes_of, on);
                        self.b.ins().bitselect(on, x, y)
                    }
                }
                Op::Sign | Op::SignStrict => {
                    let cc = if i.op == Op::Sign {
                        FloatCC::GreaterThanOrEqual
                    } else {
                        FloatCC::GreaterThan
                    };
                    let on = self.b.ins().fcmp(cc, x, float_zero);
                    let bits = if self.width == 1 {
                        let on = self.b.ins().uextend(types::I64, on);
                        self.b.ins().ishl_imm_u(on, i64::from(i.k))
                    } else {
                        // a lane's comparison is all ones where it holds
                        let bit = self.int_const(1u64 << i.k);
                        self.b.ins().band(on, bit)
                    };
                    observed = self.b.ins().bor(observed, bits);
                    continue;
                }
            };
            known[i.d as usize] = Some(value);
        }
        observed
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

/// x^n by the multiplications of the runtime's `__powidf2`, which the interpreter's
/// `f64::powi` calls: bit for bit its value (`one` is 1 in x's type).
fn powi(b: &mut FunctionBuilder, x: Value, n: i32, one: Value) -> Value {
    let mut a = x;
    let mut left = n.unsigned_abs();
    let mut product: Option<Value> = None;
    loop {
        if left & 1 != 0 {
            // 1 · a is a exactly
            product = Some(match product {
                None => a,
                Some(p) => b.ins().fmul(p, a),
            });
        }
        left >>= 1;
        if left == 0 {
            break;
        }
        a = b.ins().fmul(a, a);
    }
    let product = product.unwrap_or(one);
    if n < 0 {
        b.ins().fdiv(one, product)
    } else {
        product
    }
}

extern "C" fn powf(x: f64, y: f64) -> f64 {
    x.powf(y)
}

/// The address of the function computing `f` as [`Func::apply`] does.
fn library(f: Func) -> usize {
    macro_rules! via {
        ($($name:ident),*) => {
            match f {
                $(Func::$name => {
                    extern "C" fn apply(x: f64) -> f64 {
                        Func::$name.apply(x)
                    }
                    apply as *const () as usize
                })*
            }
        };
    }
    via!(
        Neg, Sin, Cos, Tan, Exp, Ln, Sqrt, Sinh, Cosh, Tanh, Asin, Acos, Atan, Undefined
    )
}
