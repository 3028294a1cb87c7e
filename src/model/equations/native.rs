//! A [`Tape`](super::tape::Tape) compiled to machine code with Cranelift: the same
//! instructions in the same order, with the same library calls for the transcendental
//! functions and the same multiplications for integer powers, so that a native run gives
//! bit for bit the interpreter's values (tests hold this). Only on x86-64; elsewhere, or if
//! the host cannot be compiled for, the tape is interpreted.

use cranelift_codegen::control::ControlPlane;
use cranelift_codegen::ir::condcodes::{FloatCC, IntCC};
use cranelift_codegen::ir::{
    AbiParam, Endianness, Function, InstBuilder, MemFlagsData, Signature, UserFuncName, Value,
    types,
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
const MAX_INSTRUCTIONS: usize = 20_000;

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
    let isa = host()?;
    if ins.len() > MAX_INSTRUCTIONS || registers * lanes * 8 >= i32::MAX as usize {
        return None;
    }
    let pointer = isa.pointer_type();
    let mut sig = Signature::new(isa.default_call_conv());
    sig.params.extend([AbiParam::new(pointer); 5]);
    let mut func = Function::with_name_signature(UserFuncName::default(), sig);
    let mut fctx = FunctionBuilderContext::new();
    let mut b = FunctionBuilder::new(&mut func, &mut fctx);

    let mut unary = Signature::new(isa.default_call_conv());
    unary.params.push(AbiParam::new(types::F64));
    unary.returns.push(AbiParam::new(types::F64));
    let mut binary = unary.clone();
    binary.params.push(AbiParam::new(types::F64));
    let unary = b.import_signature(unary);
    let binary = b.import_signature(binary);

    let entry = b.create_block();
    let body = b.create_block();
    let exit = b.create_block();
    b.append_block_params_for_function_params(entry);
    b.append_block_param(body, pointer);
    b.switch_to_block(entry);
    let [regs, modes, observed_out, states, derivatives] =
        b.block_params(entry).try_into().expect("five pointers");
    let zero = b.ins().iconst(pointer, 0);
    b.ins().jump(body, &[zero.into()]);

    // `width` lanes at a time (two in one SSE register where there are pairs), at byte
    // offset `lane`
    let width = if lanes.is_multiple_of(2) { 2 } else { 1 };
    let (float, int) = match width {
        2 => (types::F64X2, types::I64X2),
        _ => (types::F64, types::I64),
    };
    b.switch_to_block(body);
    let lane = b.block_params(body)[0];
    // registers of lanes are f64-aligned, pairs of them not always 16-byte aligned
    let flags = MemFlagsData::new().with_notrap();
    let lanes_of = MemFlagsData::new().with_endianness(Endianness::Little);
    let base = b.ins().iadd(regs, lane);
    let mode = {
        let at = b.ins().iadd(modes, lane);
        b.ins().load(int, flags, at, 0)
    };
    let splat = |b: &mut FunctionBuilder, ty, v: Value| match width {
        2 => b.ins().splat(ty, v),
        _ => v,
    };
    let int_const = |b: &mut FunctionBuilder, v: u64| {
        let v = b.ins().iconst(types::I64, v as i64);
        splat(b, int, v)
    };
    let float_const = |b: &mut FunctionBuilder, v: f64| {
        let v = b.ins().f64const(v);
        splat(b, float, v)
    };
    let (int_zero, float_zero, float_one) = (
        int_const(&mut b, 0),
        float_const(&mut b, 0.0),
        float_const(&mut b, 1.0),
    );
    let mut observed = int_zero;
    let stride = (lanes * 8) as i32;
    let mut known: Vec<Option<Value>> = vec![None; registers];
    let get = |b: &mut FunctionBuilder, known: &mut [Option<Value>], r: u32| -> Value {
        *known[r as usize]
            .get_or_insert_with(|| b.ins().load(float, flags, base, r as i32 * stride))
    };
    if let Some(io) = io {
        // the states from the caller's vectors (not stored in the registers: every other
        // use loads them itself)
        let at = b.ins().iadd(states, lane);
        for &(i, slot) in &io.states {
            known[slot as usize] = Some(b.ins().load(float, flags, at, i32::from(i) * stride));
        }
    }
    // a library call per lane
    let call_each = |b: &mut FunctionBuilder, sig, address, args: &[Value]| -> Value {
        if width == 1 {
            return call(b, sig, address, args);
        }
        let mut out = None;
        for l in 0..2u8 {
            let lane_args: Vec<Value> = args.iter().map(|&a| b.ins().extractlane(a, l)).collect();
            let r = call(b, sig, address, &lane_args);
            out = Some(match out {
                None => b.ins().scalar_to_vector(float, r),
                Some(v) => b.ins().insertlane(v, r, l),
            });
        }
        out.expect("two lanes")
    };
    for i in ins {
        let x = get(&mut b, &mut known, i.a);
        let y = get(&mut b, &mut known, i.b);
        let value = match i.op {
            Op::Add => b.ins().fadd(x, y),
            Op::Sub => b.ins().fsub(x, y),
            Op::Mul => b.ins().fmul(x, y),
            Op::Div => b.ins().fdiv(x, y),
            Op::Pow => call_each(&mut b, binary, powf as *const () as usize, &[x, y]),
            Op::Powi => powi(&mut b, x, i.n, float_one),
            Op::Un(Func::Neg) => b.ins().fneg(x),
            Op::Un(Func::Sqrt) => b.ins().sqrt(x),
            Op::Un(f) => call_each(&mut b, unary, library(f), &[x]),
            Op::Select => {
                let m = if free { observed } else { mode };
                let bit = int_const(&mut b, 1u64 << i.k);
                let bit = b.ins().band(m, bit);
                let on = b.ins().icmp(IntCC::NotEqual, bit, int_zero);
                if width == 1 {
                    b.ins().select(on, x, y)
                } else {
                    let on = b.ins().bitcast(float, lanes_of, on);
                    b.ins().bitselect(on, x, y)
                }
            }
            Op::Sign | Op::SignStrict => {
                let cc = if i.op == Op::Sign {
                    FloatCC::GreaterThanOrEqual
                } else {
                    FloatCC::GreaterThan
                };
                let on = b.ins().fcmp(cc, x, float_zero);
                let bit = int_const(&mut b, 1u64 << i.k);
                let bits = if width == 1 {
                    let on = b.ins().uextend(types::I64, on);
                    b.ins().ishl_imm_u(on, i64::from(i.k))
                } else {
                    // a lane's comparison is all ones where it holds
                    b.ins().band(on, bit)
                };
                observed = b.ins().bor(observed, bits);
                continue;
            }
        };
        known[i.d as usize] = Some(value);
    }
    // what the caller reads; the rest stays in the machine's registers
    for &r in roots {
        let value = known[r as usize].expect("a root the tape computes");
        b.ins().store(flags, value, base, r as i32 * stride);
    }
    if let Some(io) = io {
        let at = b.ins().iadd(derivatives, lane);
        for (i, &r) in io.derivatives.iter().enumerate() {
            let value = get(&mut b, &mut known, r);
            b.ins().store(flags, value, at, i as i32 * stride);
        }
    }
    let at = b.ins().iadd(observed_out, lane);
    b.ins().store(flags, observed, at, 0);
    let next = b.ins().iadd_imm_u(lane, 8 * width as i64);
    let more = b
        .ins()
        .icmp_imm_u(IntCC::UnsignedLessThan, next, (lanes * 8) as i64);
    b.ins().brif(more, body, &[next.into()], exit, &[]);
    b.switch_to_block(exit);
    b.ins().return_(&[]);
    b.seal_all_blocks();
    b.finalize(isa.frontend_config());

    let mut ctx = Context::for_function(func);
    let compiled = match ctx.compile(isa, &mut ControlPlane::default()) {
        Ok(compiled) => compiled,
        Err(e) => {
            tracing::warn!(
                "a tape of {} instructions is interpreted: {:?}",
                ins.len(),
                e.inner
            );
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
        Neg, Sin, Cos, Tan, Exp, Ln, Sqrt, Sinh, Cosh, Tanh, Asin, Acos, Atan
    )
}
