//! Numbers the split step is written over: one `f64`, or a [`Batch`] of them that every
//! operation treats lane by lane, so that a batch of lanes goes through exactly the
//! arithmetic each lane would go through alone (the same operations in the same order, the
//! same bits), only side by side in SIMD registers.

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

/// A number, or several numbers side by side, with a lane-wise condition type.
pub trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// One condition per lane.
    type Mask: Copy
        + BitAnd<Output = Self::Mask>
        + BitOr<Output = Self::Mask>
        + Not<Output = Self::Mask>
        + PartialEq;

    /// `x` in every lane.
    fn splat(x: f64) -> Self;
    /// `self`·`a` + `b` with one rounding.
    fn mul_add(self, a: Self, b: Self) -> Self;
    /// |self|.
    fn abs(self) -> Self;
    /// `self` < `other`, lane by lane (false where either is NaN).
    fn lt(self, other: Self) -> Self::Mask;
    /// `self` ≤ `other`, lane by lane (false where either is NaN).
    fn le(self, other: Self) -> Self::Mask;
    /// `a` where `m` holds, `b` elsewhere.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// True if `m` holds in some lane.
    fn any(m: Self::Mask) -> bool;

    /// Lanes side by side.
    const LANES: usize;
    /// Lane `j` from `f(j)`.
    fn gather(f: impl Fn(usize) -> f64) -> Self;
    /// Lane `j`'s number.
    fn lane(self, j: usize) -> f64;
    /// Lane `j`'s condition in `m`.
    fn lane_holds(m: Self::Mask, j: usize) -> bool;
    /// Lane `j`'s condition from `f(j)`.
    fn gather_mask(f: impl Fn(usize) -> bool) -> Self::Mask;

    /// `self` > `other`, lane by lane.
    #[inline(always)]
    fn gt(self, other: Self) -> Self::Mask {
        other.lt(self)
    }
}

impl Real for f64 {
    type Mask = bool;

    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        f64::mul_add(self, a, b)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f64::abs(self)
    }
    #[inline(always)]
    fn lt(self, other: Self) -> bool {
        self < other
    }
    #[inline(always)]
    fn le(self, other: Self) -> bool {
        self <= other
    }
    #[inline(always)]
    fn select(m: bool, a: Self, b: Self) -> Self {
        if m { a } else { b }
    }
    #[inline(always)]
    fn any(m: bool) -> bool {
        m
    }
    const LANES: usize = 1;
    #[inline(always)]
    fn gather(f: impl Fn(usize) -> f64) -> Self {
        f(0)
    }
    #[inline(always)]
    fn lane(self, _: usize) -> f64 {
        self
    }
    #[inline(always)]
    fn lane_holds(m: bool, _: usize) -> bool {
        m
    }
    #[inline(always)]
    fn gather_mask(f: impl Fn(usize) -> bool) -> bool {
        f(0)
    }
}

/// `N` numbers side by side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Batch<const N: usize>(pub [f64; N]);

/// `N` conditions side by side.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Bits<const N: usize>(pub [bool; N]);

impl<const N: usize> Batch<N> {
    #[inline(always)]
    fn map2(self, other: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        Batch(std::array::from_fn(|i| f(self.0[i], other.0[i])))
    }

    #[inline(always)]
    fn test(self, other: Self, f: impl Fn(f64, f64) -> bool) -> Bits<N> {
        Bits(std::array::from_fn(|i| f(self.0[i], other.0[i])))
    }
}

macro_rules! lane_wise {
    ($trait:ident, $method:ident, $op:tt) => {
        impl<const N: usize> $trait for Batch<N> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, other: Self) -> Self {
                self.map2(other, |a, b| a $op b)
            }
        }
    };
}
lane_wise!(Add, add, +);
lane_wise!(Sub, sub, -);
lane_wise!(Mul, mul, *);
lane_wise!(Div, div, /);

impl<const N: usize> Neg for Batch<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Batch(self.0.map(|a| -a))
    }
}

macro_rules! bit_wise {
    ($trait:ident, $method:ident, $op:tt) => {
        impl<const N: usize> $trait for Bits<N> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, other: Self) -> Self {
                Bits(std::array::from_fn(|i| self.0[i] $op other.0[i]))
            }
        }
    };
}
bit_wise!(BitAnd, bitand, &);
bit_wise!(BitOr, bitor, |);

impl<const N: usize> Not for Bits<N> {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        Bits(self.0.map(|a| !a))
    }
}

impl<const N: usize> Real for Batch<N> {
    type Mask = Bits<N>;

    #[inline(always)]
    fn splat(x: f64) -> Self {
        Batch([x; N])
    }
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        Batch(std::array::from_fn(|i| self.0[i].mul_add(a.0[i], b.0[i])))
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Batch(self.0.map(f64::abs))
    }
    #[inline(always)]
    fn lt(self, other: Self) -> Bits<N> {
        self.test(other, |a, b| a < b)
    }
    #[inline(always)]
    fn le(self, other: Self) -> Bits<N> {
        self.test(other, |a, b| a <= b)
    }
    #[inline(always)]
    fn select(m: Bits<N>, a: Self, b: Self) -> Self {
        Batch(std::array::from_fn(
            |i| if m.0[i] { a.0[i] } else { b.0[i] },
        ))
    }
    #[inline(always)]
    fn any(m: Bits<N>) -> bool {
        m.0.iter().any(|&b| b)
    }
    const LANES: usize = N;
    #[inline(always)]
    fn gather(f: impl Fn(usize) -> f64) -> Self {
        Batch(std::array::from_fn(f))
    }
    #[inline(always)]
    fn lane(self, j: usize) -> f64 {
        self.0[j]
    }
    #[inline(always)]
    fn lane_holds(m: Bits<N>, j: usize) -> bool {
        m.0[j]
    }
    #[inline(always)]
    fn gather_mask(f: impl Fn(usize) -> bool) -> Bits<N> {
        Bits(std::array::from_fn(f))
    }
}
