//! Straight-line code over one group of lanes: the interface the written model's tapes and
//! plain step are emitted through, with two code generators behind it, Cranelift (one or
//! two doubles to a register, [`super::native`]) and our own AVX2 emitter (four,
//! [`super::avx2`]). Both emit the same operations in the same order, so a lane's values
//! are the same bits whichever runs it.

use super::graph::Func;
use super::tape::{Ins, Op};

/// A pointer the code reads or writes through: the `k`th of the compiled function's.
pub(super) type Arg = usize;

/// The four operations of arithmetic on doubles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Arith {
    Add,
    Sub,
    Mul,
    Div,
}

/// A comparison of doubles; the unordered ones also hold where either is NaN.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Compare {
    Ge,
    Gt,
    UnorderedOrGe,
    UnorderedOrGt,
}

/// Emits code over a group of lanes. `F` holds a double per lane; `M` a 64-bit word per lane
/// (a mode), or a comparison's truth per lane (all ones where it holds, or in code of one
/// lane, a boolean), which `and`, `or` and `not` combine and `sign_bit` turns into a word.
pub(super) trait LaneCode {
    type F: Copy;
    type M: Copy;
    fn float_const(&mut self, v: f64) -> Self::F;
    fn int_const(&mut self, v: u64) -> Self::M;
    fn arith(&mut self, op: Arith, x: Self::F, y: Self::F) -> Self::F;
    fn sqrt(&mut self, x: Self::F) -> Self::F;
    fn neg(&mut self, x: Self::F) -> Self::F;
    /// The library function at `address` (of one or two doubles) in each lane.
    fn call(&mut self, address: usize, args: &[Self::F]) -> Self::F;
    /// Whether `x cc y` in each lane.
    fn compare(&mut self, cc: Compare, x: Self::F, y: Self::F) -> Self::M;
    /// The word with bit `k` set in the lanes where `truth` holds, else 0.
    fn sign_bit(&mut self, truth: Self::M, k: u8) -> Self::M;
    fn and(&mut self, a: Self::M, b: Self::M) -> Self::M;
    fn or(&mut self, a: Self::M, b: Self::M) -> Self::M;
    fn xor(&mut self, a: Self::M, b: Self::M) -> Self::M;
    fn not(&mut self, a: Self::M) -> Self::M;
    /// `x` in the lanes whose word `m` has bit `k` set, else `y`.
    fn select_on_bit(&mut self, m: Self::M, k: u8, x: Self::F, y: Self::F) -> Self::F;
    /// The group's lanes of the lane-major array at pointer `arg`, row at byte `offset`.
    fn load(&mut self, arg: Arg, offset: i32) -> Self::F;
    fn load_int(&mut self, arg: Arg, offset: i32) -> Self::M;
    /// The double at byte `offset` of pointer `arg`, in every lane.
    fn load_splat(&mut self, arg: Arg, offset: i32) -> Self::F;
    fn store(&mut self, arg: Arg, offset: i32, v: Self::F);
    /// Stores a word per lane (a truth as a nonzero word where it holds).
    fn store_int(&mut self, arg: Arg, offset: i32, v: Self::M);
}

/// Emits `ins` with each kink held on `mode`'s branch (or, `free`, on its switching value's
/// sign), and returns the mode the switching values' signs select. `known` holds the
/// registers' values so far (given or computed); a register not in it is `read` once.
pub(super) fn tape<E: LaneCode>(
    e: &mut E,
    ins: &[Ins],
    free: bool,
    mode: E::M,
    known: &mut [Option<E::F>],
    read: &mut dyn FnMut(&mut E, u32) -> E::F,
) -> E::M {
    let mut observed = e.int_const(0);
    let zero = e.float_const(0.0);
    for i in ins {
        let x = match known[i.a as usize] {
            Some(x) => x,
            None => *known[i.a as usize].insert(read(e, i.a)),
        };
        let y = match known[i.b as usize] {
            Some(y) => y,
            None => *known[i.b as usize].insert(read(e, i.b)),
        };
        let value = match i.op {
            Op::Add => e.arith(Arith::Add, x, y),
            Op::Sub => e.arith(Arith::Sub, x, y),
            Op::Mul => e.arith(Arith::Mul, x, y),
            Op::Div => e.arith(Arith::Div, x, y),
            Op::Pow => e.call(powf as *const () as usize, &[x, y]),
            Op::Powi => powi(e, x, i.n),
            Op::Un(Func::Neg) => e.neg(x),
            Op::Un(Func::Sqrt) => e.sqrt(x),
            Op::Un(Func::Undefined) => e.arith(Arith::Sub, x, x),
            Op::Un(f) => e.call(library(f), &[x]),
            Op::Select => {
                let m = if free { observed } else { mode };
                e.select_on_bit(m, i.k, x, y)
            }
            Op::Sign | Op::SignStrict => {
                let cc = if i.op == Op::Sign {
                    Compare::Ge
                } else {
                    Compare::Gt
                };
                let on = e.compare(cc, x, zero);
                let bits = e.sign_bit(on, i.k);
                observed = e.or(observed, bits);
                continue;
            }
        };
        known[i.d as usize] = Some(value);
    }
    observed
}

/// x^n by the multiplications of the runtime's `__powidf2`, which the interpreter's
/// `f64::powi` calls: bit for bit its value.
fn powi<E: LaneCode>(e: &mut E, x: E::F, n: i32) -> E::F {
    let mut a = x;
    let mut left = n.unsigned_abs();
    let mut product: Option<E::F> = None;
    loop {
        if left & 1 != 0 {
            // 1 · a is a exactly
            product = Some(match product {
                None => a,
                Some(p) => e.arith(Arith::Mul, p, a),
            });
        }
        left >>= 1;
        if left == 0 {
            break;
        }
        a = e.arith(Arith::Mul, a, a);
    }
    let one = e.float_const(1.0);
    let product = product.unwrap_or(one);
    if n < 0 {
        e.arith(Arith::Div, one, product)
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
