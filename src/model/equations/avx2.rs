//! Our own code generator for a written model's plain step in lanes: four doubles to an AVX2
//! register, where Cranelift has two (it lowers only the 128-bit vectors WebAssembly needs).
//!
//! The step is recorded as straight-line code over one group of four lanes ([`Recorder`],
//! a [`LaneCode`]), given registers by Belady's rule (the value used furthest ahead leaves
//! a register first; constants and loads are read again rather than stored) and assembled
//! with `iced-x86` inside a loop over the groups. The operations and their order are those
//! Cranelift is given, each IEEE-rounded the same way, and library functions are called per
//! lane, so each lane's values are the same bits (tests hold this).

use iced_x86::IcedError;
use iced_x86::code_asm::registers::gpr64::{r12, r13, r14, rax, rbp, rbx, rdi, rsp};
use iced_x86::code_asm::registers::xmm::{xmm0, xmm1};
use iced_x86::code_asm::registers::ymm::*;
use iced_x86::code_asm::{AsmRegisterYmm, CodeAssembler, ptr, qword_ptr, ymmword_ptr};

use super::lane_code::{Arg, Arith, Compare, LaneCode};
use super::native::Native;

/// Lanes to a register.
pub(super) const WIDTH: usize = 4;

/// Whether this processor runs AVX2 (and `ISOLA_ISA` does not ask for the baseline, to
/// compare the two code generators).
pub(super) fn available() -> bool {
    static AVAILABLE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *AVAILABLE.get_or_init(|| {
        std::arch::is_x86_feature_detected!("avx2")
            && std::env::var("ISOLA_ISA").as_deref() != Ok("baseline")
    })
}

/// A value of the recorded code: the index of the instruction that makes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct V(u32);

/// Bitwise operations on 64-bit words.
#[derive(Debug, Clone, Copy)]
enum Bits {
    And,
    Or,
    Xor,
}

/// One instruction over a group of four lanes.
#[derive(Debug, Clone, Copy)]
enum Inst {
    /// The same 64 bits in every lane.
    Const(u64),
    /// The group's lanes of the lane-major array at pointer `arg`, or (`splat`) the double
    /// at `arg` + `offset` in every lane.
    Load {
        arg: Arg,
        offset: i32,
        splat: bool,
    },
    Arith(Arith, V, V),
    Sqrt(V),
    Bits(Bits, V, V),
    /// All ones where the words are equal.
    Equal(V, V),
    Compare(Compare, V, V),
    /// `x` where `on`, else `y`.
    Select {
        on: V,
        x: V,
        y: V,
    },
    /// The library function at `address` of `n` arguments, lane by lane.
    Call {
        address: usize,
        args: [V; 2],
        n: u8,
    },
    Store {
        arg: Arg,
        offset: i32,
        v: V,
    },
}

impl Inst {
    /// The values it reads.
    fn inputs(&self) -> Vec<V> {
        match *self {
            Inst::Const(_) | Inst::Load { .. } => vec![],
            Inst::Sqrt(a) => vec![a],
            Inst::Arith(_, a, b) | Inst::Bits(_, a, b) | Inst::Equal(a, b) => vec![a, b],
            Inst::Compare(_, a, b) => vec![a, b],
            Inst::Select { on, x, y } => vec![on, x, y],
            Inst::Call { args, n, .. } => args[..n as usize].to_vec(),
            Inst::Store { v, .. } => vec![v],
        }
    }

    /// Whether its value can be made again where it is needed (read from memory the code
    /// does not write) instead of kept.
    fn remade(&self) -> bool {
        matches!(self, Inst::Const(_) | Inst::Load { .. })
    }
}

/// Records a lane group's code.
#[derive(Default)]
pub(super) struct Recorder {
    insts: Vec<Inst>,
}

impl Recorder {
    fn push(&mut self, inst: Inst) -> V {
        self.insts.push(inst);
        V(self.insts.len() as u32 - 1)
    }
}

/// The sign bit of a double.
const SIGN: u64 = 1 << 63;

impl LaneCode for Recorder {
    type F = V;
    type M = V;

    fn float_const(&mut self, v: f64) -> V {
        self.push(Inst::Const(v.to_bits()))
    }

    fn int_const(&mut self, v: u64) -> V {
        self.push(Inst::Const(v))
    }

    fn arith(&mut self, op: Arith, x: V, y: V) -> V {
        self.push(Inst::Arith(op, x, y))
    }

    fn sqrt(&mut self, x: V) -> V {
        self.push(Inst::Sqrt(x))
    }

    fn neg(&mut self, x: V) -> V {
        let sign = self.int_const(SIGN);
        self.push(Inst::Bits(Bits::Xor, x, sign))
    }

    fn call(&mut self, address: usize, args: &[V]) -> V {
        let n = args.len() as u8;
        let args = [args[0], args[n as usize - 1]];
        self.push(Inst::Call { address, args, n })
    }

    fn compare(&mut self, cc: Compare, x: V, y: V) -> V {
        self.push(Inst::Compare(cc, x, y))
    }

    fn sign_bit(&mut self, truth: V, k: u8) -> V {
        let bit = self.int_const(1 << k);
        self.push(Inst::Bits(Bits::And, truth, bit))
    }

    fn and(&mut self, a: V, b: V) -> V {
        self.push(Inst::Bits(Bits::And, a, b))
    }

    fn or(&mut self, a: V, b: V) -> V {
        self.push(Inst::Bits(Bits::Or, a, b))
    }

    fn xor(&mut self, a: V, b: V) -> V {
        self.push(Inst::Bits(Bits::Xor, a, b))
    }

    fn not(&mut self, a: V) -> V {
        let ones = self.int_const(u64::MAX);
        self.push(Inst::Bits(Bits::Xor, a, ones))
    }

    fn select_on_bit(&mut self, m: V, k: u8, x: V, y: V) -> V {
        let bit = self.int_const(1 << k);
        let set = self.push(Inst::Bits(Bits::And, m, bit));
        let on = self.push(Inst::Equal(set, bit));
        self.push(Inst::Select { on, x, y })
    }

    fn load(&mut self, arg: Arg, offset: i32) -> V {
        self.push(Inst::Load {
            arg,
            offset,
            splat: false,
        })
    }

    fn load_int(&mut self, arg: Arg, offset: i32) -> V {
        self.load(arg, offset)
    }

    fn load_splat(&mut self, arg: Arg, offset: i32) -> V {
        self.push(Inst::Load {
            arg,
            offset,
            splat: true,
        })
    }

    fn store(&mut self, arg: Arg, offset: i32, v: V) {
        self.push(Inst::Store { arg, offset, v });
    }

    fn store_int(&mut self, arg: Arg, offset: i32, v: V) {
        self.store(arg, offset, v);
    }
}

/// Compiles `body` (recorded for one group of four lanes) into a function of one pointer,
/// to a `#[repr(C)]` struct of the pointers `body` reads and writes through, that runs it
/// over `lanes` lanes. `None` where Cranelift's code is taken instead: code that reads memory
/// it writes, a frame too large, or an assembler error.
pub(super) fn compile(lanes: usize, body: impl FnOnce(&mut Recorder)) -> Option<Native> {
    let mut recorder = Recorder::default();
    body(&mut recorder);
    // loads are made again where read: only from memory the code does not write
    let stored: Vec<Arg> = (recorder.insts.iter())
        .filter_map(|i| match *i {
            Inst::Store { arg, .. } => Some(arg),
            _ => None,
        })
        .collect();
    if (recorder.insts.iter())
        .any(|i| matches!(*i, Inst::Load { arg, .. } if stored.contains(&arg)))
    {
        return None;
    }
    // the first pass counts the stack slots the second reserves (its own code is dropped)
    let (_, slots) = Lowering::new(&recorder.insts, 0).assemble(lanes).ok()?;
    if slots * SLOT > MAX_FRAME {
        // a model this large keeps Cranelift's code (whose frame is its own)
        return None;
    }
    match Lowering::new(&recorder.insts, slots).assemble(lanes) {
        Ok((bytes, _)) => Native::new(&bytes),
        Err(e) => {
            tracing::warn!("a written model's step is compiled by Cranelift: {e}");
            None
        }
    }
}

const YMM: [AsmRegisterYmm; 16] = [
    ymm0, ymm1, ymm2, ymm3, ymm4, ymm5, ymm6, ymm7, ymm8, ymm9, ymm10, ymm11, ymm12, ymm13, ymm14,
    ymm15,
];
/// Bytes of a register (and a stack slot).
const SLOT: i32 = 32;
/// Most bytes of stack slots: far below a worker thread's stack (2 MiB).
const MAX_FRAME: i32 = 1 << 18;
/// The pointer [`Arg`] kept in `r14` (the register file, read most).
const KEPT_ARG: Arg = 0;

/// The recorded code given registers and assembled.
struct Lowering<'i> {
    insts: &'i [Inst],
    /// Each value's readers (instruction indices, ascending), and how many are behind.
    uses: Vec<Vec<u32>>,
    passed: Vec<usize>,
    /// Where each value is: a register, a stack slot.
    reg: Vec<Option<usize>>,
    slot: Vec<Option<i32>>,
    holds: [Option<u32>; 16],
    /// Stack slots used, and reserved (the frame).
    slots: i32,
    frame: i32,
    /// Constants' bits, each once, at `pool` after the code.
    pool: Vec<u64>,
}

impl<'i> Lowering<'i> {
    fn new(insts: &'i [Inst], frame: i32) -> Self {
        let n = insts.len();
        let mut uses = vec![Vec::new(); n];
        for (i, inst) in insts.iter().enumerate() {
            for v in inst.inputs() {
                uses[v.0 as usize].push(i as u32);
            }
        }
        Lowering {
            insts,
            uses,
            passed: vec![0; n],
            reg: vec![None; n],
            slot: vec![None; n],
            holds: [None; 16],
            slots: 0,
            frame,
            pool: Vec::new(),
        }
    }

    /// The instruction that next reads `v` (`u32::MAX` if none does).
    fn next_use(&self, v: u32) -> u32 {
        let uses = &self.uses[v as usize];
        uses.get(self.passed[v as usize])
            .copied()
            .unwrap_or(u32::MAX)
    }

    fn pool_offset(&mut self, bits: u64) -> i32 {
        let at = match self.pool.iter().position(|&b| b == bits) {
            Some(at) => at,
            None => {
                self.pool.push(bits);
                self.pool.len() - 1
            }
        };
        8 * at as i32
    }

    /// The stack slot of `v`, taken now if it has none.
    fn slot_of(&mut self, v: u32) -> i32 {
        match self.slot[v as usize] {
            Some(s) => s,
            None => {
                let s = self.slots * SLOT;
                self.slots += 1;
                *self.slot[v as usize].insert(s)
            }
        }
    }

    /// The machine code, and the stack slots it uses (valid code only if they are at most
    /// the frame's).
    fn assemble(mut self, lanes: usize) -> Result<(Vec<u8>, i32), IcedError> {
        let mut a = CodeAssembler::new(64)?;
        let mut pool = a.create_label();
        let mut top = a.create_label();
        // rbx: the struct of pointers; r12: the group's byte offset; r13: the constants;
        // r14: the register file; rbp: the caller's stack
        a.push(rbp)?;
        a.mov(rbp, rsp)?;
        for r in [rbx, r12, r13, r14] {
            a.push(r)?;
        }
        a.and(rsp, -SLOT)?;
        a.sub(rsp, self.frame * SLOT)?;
        a.mov(rbx, rdi)?;
        a.lea(r13, ptr(pool))?;
        a.mov(r14, qword_ptr(rbx + 8 * KEPT_ARG as i32))?;
        a.xor(r12, r12)?;
        a.set_label(&mut top)?;
        for i in 0..self.insts.len() {
            self.lower(&mut a, i)?;
        }
        a.add(r12, SLOT)?;
        a.cmp(r12, (8 * lanes) as i32)?;
        a.jb(top)?;
        a.vzeroupper()?;
        a.lea(rsp, qword_ptr(rbp - 32))?;
        for r in [r14, r13, r12, rbx] {
            a.pop(r)?;
        }
        a.pop(rbp)?;
        a.ret()?;
        a.set_label(&mut pool)?;
        if self.pool.is_empty() {
            // the label needs something after it
            self.pool.push(0);
        }
        a.dq(&self.pool)?;
        Ok((a.assemble(0)?, self.slots))
    }

    /// Pointer `arg` in a register (`rax` unless it is the one kept in `r14`).
    fn pointer(
        a: &mut CodeAssembler,
        arg: Arg,
    ) -> Result<iced_x86::code_asm::AsmRegister64, IcedError> {
        if arg == KEPT_ARG {
            return Ok(r14);
        }
        a.mov(rax, qword_ptr(rbx + 8 * arg as i32))?;
        Ok(rax)
    }

    /// Makes `v` (from instruction `v`) into register `r`: computes a constant or a load,
    /// or reads its slot.
    fn fill(&mut self, a: &mut CodeAssembler, v: u32, r: usize) -> Result<(), IcedError> {
        match self.insts[v as usize] {
            Inst::Const(bits) => {
                let at = self.pool_offset(bits);
                a.vbroadcastsd(YMM[r], qword_ptr(r13 + at))?;
            }
            Inst::Load {
                arg,
                offset,
                splat: false,
            } => {
                let p = Self::pointer(a, arg)?;
                a.vmovupd(YMM[r], ymmword_ptr(p + r12 + offset))?;
            }
            Inst::Load {
                arg,
                offset,
                splat: true,
            } => {
                let p = Self::pointer(a, arg)?;
                a.vbroadcastsd(YMM[r], qword_ptr(p + offset))?;
            }
            _ => {
                let s = self.slot[v as usize].expect("a value kept in its slot");
                a.vmovupd(YMM[r], ymmword_ptr(rsp + s))?;
            }
        }
        self.reg[v as usize] = Some(r);
        self.holds[r] = Some(v);
        Ok(())
    }

    /// Frees register `r`, storing its value first if it is read again and cannot be made
    /// again.
    fn evict(&mut self, a: &mut CodeAssembler, r: usize) -> Result<(), IcedError> {
        if let Some(v) = self.holds[r].take() {
            self.reg[v as usize] = None;
            let kept = self.slot[v as usize].is_some() || self.insts[v as usize].remade();
            if !kept && self.next_use(v) != u32::MAX {
                let s = self.slot_of(v);
                a.vmovupd(ymmword_ptr(rsp + s), YMM[r])?;
            }
        }
        Ok(())
    }

    /// A free register, freeing the one whose value is read furthest ahead (not one of
    /// `busy`).
    fn free_register(&mut self, a: &mut CodeAssembler, busy: &[usize]) -> Result<usize, IcedError> {
        if let Some(r) = (0..16).find(|&r| self.holds[r].is_none()) {
            return Ok(r);
        }
        let r = (0..16)
            .filter(|r| !busy.contains(r))
            .max_by_key(|&r| self.next_use(self.holds[r].expect("held")))
            .expect("a register not in use");
        self.evict(a, r)?;
        Ok(r)
    }

    /// The register holding `v`, filled now (in a register not among `busy`) if none does.
    fn in_register(
        &mut self,
        a: &mut CodeAssembler,
        v: V,
        busy: &[usize],
    ) -> Result<usize, IcedError> {
        if let Some(r) = self.reg[v.0 as usize] {
            return Ok(r);
        }
        let r = self.free_register(a, busy)?;
        self.fill(a, v.0, r)?;
        Ok(r)
    }

    /// Marks `v`'s reads up to instruction `i` as behind.
    fn read_by(&mut self, v: V, i: usize) {
        let uses = &self.uses[v.0 as usize];
        self.passed[v.0 as usize] = uses.partition_point(|&u| u <= i as u32);
    }

    /// Values in registers for instruction `i`'s inputs.
    fn inputs(&mut self, a: &mut CodeAssembler, i: usize) -> Result<Vec<usize>, IcedError> {
        let inputs = self.insts[i].inputs();
        let mut regs = Vec::with_capacity(inputs.len());
        for &v in &inputs {
            let r = self.in_register(a, v, &regs)?;
            regs.push(r);
        }
        // this instruction's reads are behind; a value no longer read frees its register
        for &v in &inputs {
            self.read_by(v, i);
            if self.next_use(v.0) == u32::MAX
                && let Some(r) = self.reg[v.0 as usize].take()
            {
                self.holds[r] = None;
            }
        }
        Ok(regs)
    }

    /// A register for instruction `i`'s value (the value is then in it).
    fn output(&mut self, a: &mut CodeAssembler, i: usize) -> Result<usize, IcedError> {
        let r = self.free_register(a, &[])?;
        self.reg[i] = Some(r);
        self.holds[r] = Some(i as u32);
        Ok(r)
    }

    /// Frees instruction `i`'s register if nothing reads its value.
    fn drop_unread(&mut self, i: usize) {
        if self.uses[i].is_empty()
            && let Some(r) = self.reg[i].take()
        {
            self.holds[r] = None;
        }
    }

    fn lower(&mut self, a: &mut CodeAssembler, i: usize) -> Result<(), IcedError> {
        let inst = self.insts[i];
        match inst {
            // made where read
            Inst::Const(_) | Inst::Load { .. } => return Ok(()),
            Inst::Call { address, args, n } => {
                return self.call(a, i, address, &args[..n as usize]);
            }
            Inst::Store { arg, offset, .. } => {
                let [v] = self.inputs(a, i)?[..] else {
                    unreachable!("a store reads one value")
                };
                let p = Self::pointer(a, arg)?;
                return a.vmovupd(ymmword_ptr(p + r12 + offset), YMM[v]);
            }
            _ => {}
        }
        let src = self.inputs(a, i)?;
        // the inputs' registers may be reused for the value: they are read first
        let d = self.output(a, i)?;
        let (d, s) = (YMM[d], src.iter().map(|&r| YMM[r]).collect::<Vec<_>>());
        match inst {
            Inst::Arith(op, ..) => match op {
                Arith::Add => a.vaddpd(d, s[0], s[1])?,
                Arith::Sub => a.vsubpd(d, s[0], s[1])?,
                Arith::Mul => a.vmulpd(d, s[0], s[1])?,
                Arith::Div => a.vdivpd(d, s[0], s[1])?,
            },
            Inst::Sqrt(_) => a.vsqrtpd(d, s[0])?,
            Inst::Bits(op, ..) => match op {
                Bits::And => a.vpand(d, s[0], s[1])?,
                Bits::Or => a.vpor(d, s[0], s[1])?,
                Bits::Xor => a.vpxor(d, s[0], s[1])?,
            },
            Inst::Equal(..) => a.vpcmpeqq(d, s[0], s[1])?,
            Inst::Compare(cc, ..) => {
                // ordered and quiet; unordered-or: not-less-than, not-less-or-equal
                let predicate = match cc {
                    Compare::Ge => 0x1d,
                    Compare::Gt => 0x1e,
                    Compare::UnorderedOrGe => 0x15,
                    Compare::UnorderedOrGt => 0x16,
                };
                a.vcmppd(d, s[0], s[1], predicate)?
            }
            // the second source where the mask's sign is clear, the third where set
            Inst::Select { .. } => a.vblendvpd(d, s[2], s[1], s[0])?,
            Inst::Const(_) | Inst::Load { .. } | Inst::Call { .. } | Inst::Store { .. } => {
                unreachable!("lowered above")
            }
        }
        self.drop_unread(i);
        Ok(())
    }

    /// A library call lane by lane: every value still to be read is kept in its slot (or
    /// made again) across the calls, which may change every vector register.
    fn call(
        &mut self,
        a: &mut CodeAssembler,
        i: usize,
        address: usize,
        args: &[V],
    ) -> Result<(), IcedError> {
        // the arguments in slots of their own, read lane by lane
        let mut at = Vec::with_capacity(args.len());
        for &v in args {
            let r = self.in_register(a, v, &[])?;
            let s = match self.slot[v.0 as usize] {
                Some(s) => s,
                None => {
                    let s = self.slot_of(v.0);
                    a.vmovupd(ymmword_ptr(rsp + s), YMM[r])?;
                    s
                }
            };
            at.push(s);
        }
        for &v in args {
            self.read_by(v, i);
        }
        for r in 0..16 {
            self.evict(a, r)?;
        }
        let out = self.slot_of(i as u32);
        a.vzeroupper()?;
        for lane in 0..WIDTH as i32 {
            a.vmovsd(xmm0, qword_ptr(rsp + at[0] + 8 * lane))?;
            if let Some(&s) = at.get(1) {
                a.vmovsd(xmm1, qword_ptr(rsp + s + 8 * lane))?;
            }
            a.mov(rax, address as u64)?;
            a.call(rax)?;
            a.vmovsd(qword_ptr(rsp + out + 8 * lane), xmm0)?;
        }
        Ok(())
    }
}
