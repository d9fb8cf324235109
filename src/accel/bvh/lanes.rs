//! Four and eight f32 lanes as plain arrays with element-wise operators,
//! written so that LLVM's SLP vectorizer turns each four-lane operation into
//! one SSE instruction (safe Rust: no intrinsics, no `unsafe`). Eight lanes
//! are two explicit halves of four: left to itself, the vectorizer splits an
//! eight-element array at odd places and assembles registers from scalar
//! loads. Triangle packets use four lanes, nodes eight.

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Not, Sub};

/// Four f32 values, one per lane.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(16))]
pub(super) struct F4(pub [f32; 4]);

/// A four-lane mask: every bit set (true) or clear (false) in each lane, the
/// shape SSE comparisons produce, so `&`, `|` and `!` stay vector operations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(C, align(16))]
pub(super) struct M4(pub [u32; 4]);

/// Eight f32 values as two halves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct F8(pub [F4; 2]);

/// An eight-lane mask as two halves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct M8(pub [M4; 2]);

#[inline(always)]
fn map2(a: [f32; 4], b: [f32; 4], f: impl Fn(f32, f32) -> f32) -> [f32; 4] {
    [f(a[0], b[0]), f(a[1], b[1]), f(a[2], b[2]), f(a[3], b[3])]
}

#[inline(always)]
fn cmp(a: [f32; 4], b: [f32; 4], f: impl Fn(f32, f32) -> bool) -> M4 {
    let m = |x: f32, y: f32| if f(x, y) { u32::MAX } else { 0 };
    M4([m(a[0], b[0]), m(a[1], b[1]), m(a[2], b[2]), m(a[3], b[3])])
}

impl F4 {
    #[inline(always)]
    pub fn splat(x: f32) -> F4 {
        F4([x; 4])
    }

    /// Lane-wise minimum that returns `other` when either is NaN (the
    /// semantics of SSE `minps` with `self` first, so it stays one
    /// instruction). The slab test relies on it to ignore the NaN of
    /// `0 × ∞` (a ray parallel to a slab, starting on its plane).
    #[inline(always)]
    pub fn min_or(self, other: F4) -> F4 {
        F4(map2(self.0, other.0, |a, b| if a < b { a } else { b }))
    }

    /// Lane-wise maximum that returns `other` when either is NaN (`maxps`).
    #[inline(always)]
    pub fn max_or(self, other: F4) -> F4 {
        F4(map2(self.0, other.0, |a, b| if a > b { a } else { b }))
    }

    /// Lane-wise |x|.
    #[inline(always)]
    pub fn abs(self) -> F4 {
        F4(self.0.map(|x| f32::from_bits(x.to_bits() & 0x7fff_ffff)))
    }

    /// `self` with its sign flipped where `of` is negative (sign bit set).
    #[inline(always)]
    pub fn xor_sign_of(self, of: F4) -> F4 {
        let flip = |a: f32, b: f32| f32::from_bits(a.to_bits() ^ (b.to_bits() & 0x8000_0000));
        F4(map2(self.0, of.0, flip))
    }

    #[inline(always)]
    pub fn lt(self, o: F4) -> M4 {
        cmp(self.0, o.0, |a, b| a < b)
    }

    #[inline(always)]
    pub fn gt(self, o: F4) -> M4 {
        cmp(self.0, o.0, |a, b| a > b)
    }

    #[inline(always)]
    pub fn le(self, o: F4) -> M4 {
        cmp(self.0, o.0, |a, b| a <= b)
    }

    #[inline(always)]
    pub fn ge(self, o: F4) -> M4 {
        cmp(self.0, o.0, |a, b| a >= b)
    }

    /// Ordered "not equal": false for NaN (unlike `!=`), which is what the
    /// triangle test wants.
    #[inline(always)]
    pub fn ne(self, o: F4) -> M4 {
        self.lt(o) | self.gt(o)
    }
}

/// Bit `i` set when lane `i` of `m` is.
///
/// The mask goes through `black_box` first: without that barrier LLVM's SLP
/// vectorizer starts from this reduction, pulls the comparisons into its
/// lane order and scalarizes them (three times the instructions in the
/// triangle test, and scalar loads in the node test). The barrier costs a
/// store and a reload.
#[inline(always)]
fn lane_bits<const N: usize>(m: [u32; N]) -> u32 {
    let m = std::hint::black_box(m);
    let mut bits = 0;
    for (i, lane) in m.iter().enumerate() {
        bits |= (lane >> 31) << i;
    }
    bits
}

impl M4 {
    /// Bit `i` set when lane `i` is.
    #[inline(always)]
    pub fn bits(self) -> u32 {
        lane_bits(self.0)
    }
}

impl F8 {
    #[inline(always)]
    pub fn splat(x: f32) -> F8 {
        F8([F4::splat(x); 2])
    }

    #[inline(always)]
    pub fn load(a: &[f32; 8]) -> F8 {
        F8([F4([a[0], a[1], a[2], a[3]]), F4([a[4], a[5], a[6], a[7]])])
    }

    /// Lane `i`.
    #[inline(always)]
    pub fn lane(&self, i: usize) -> f32 {
        self.0[i / 4].0[i % 4]
    }

    /// See [`F4::min_or`].
    #[inline(always)]
    pub fn min_or(self, o: F8) -> F8 {
        F8([self.0[0].min_or(o.0[0]), self.0[1].min_or(o.0[1])])
    }

    /// See [`F4::max_or`].
    #[inline(always)]
    pub fn max_or(self, o: F8) -> F8 {
        F8([self.0[0].max_or(o.0[0]), self.0[1].max_or(o.0[1])])
    }

    #[inline(always)]
    pub fn le(self, o: F8) -> M8 {
        M8([self.0[0].le(o.0[0]), self.0[1].le(o.0[1])])
    }
}

impl M8 {
    /// Bit `i` set when lane `i` is.
    #[inline(always)]
    pub fn bits(self) -> u32 {
        let [lo, hi] = self.0;
        lane_bits([
            lo.0[0], lo.0[1], lo.0[2], lo.0[3], hi.0[0], hi.0[1], hi.0[2], hi.0[3],
        ])
    }
}

macro_rules! lanewise {
    ($tr:ident, $f:ident, $op:tt) => {
        impl $tr for F4 {
            type Output = F4;
            #[inline(always)]
            fn $f(self, o: F4) -> F4 {
                F4(map2(self.0, o.0, |a, b| a $op b))
            }
        }
        impl $tr<f32> for F4 {
            type Output = F4;
            #[inline(always)]
            fn $f(self, o: f32) -> F4 {
                F4(map2(self.0, [o; 4], |a, b| a $op b))
            }
        }
        impl $tr for F8 {
            type Output = F8;
            #[inline(always)]
            fn $f(self, o: F8) -> F8 {
                F8([self.0[0] $op o.0[0], self.0[1] $op o.0[1]])
            }
        }
        impl $tr<f32> for F8 {
            type Output = F8;
            #[inline(always)]
            fn $f(self, o: f32) -> F8 {
                F8([self.0[0] $op o, self.0[1] $op o])
            }
        }
    };
}
lanewise!(Add, add, +);
lanewise!(Sub, sub, -);
lanewise!(Mul, mul, *);
lanewise!(Div, div, /);

impl BitAnd for M4 {
    type Output = M4;
    #[inline(always)]
    fn bitand(self, o: M4) -> M4 {
        M4([
            self.0[0] & o.0[0],
            self.0[1] & o.0[1],
            self.0[2] & o.0[2],
            self.0[3] & o.0[3],
        ])
    }
}

impl BitOr for M4 {
    type Output = M4;
    #[inline(always)]
    fn bitor(self, o: M4) -> M4 {
        M4([
            self.0[0] | o.0[0],
            self.0[1] | o.0[1],
            self.0[2] | o.0[2],
            self.0[3] | o.0[3],
        ])
    }
}

impl Not for M4 {
    type Output = M4;
    #[inline(always)]
    fn not(self) -> M4 {
        M4([!self.0[0], !self.0[1], !self.0[2], !self.0[3]])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn min_max_ignore_nan_in_the_first_operand() {
        let nan = F4([f32::NAN, 1.0, 2.0, f32::NAN]);
        let other = F4([5.0, 0.0, 3.0, -1.0]);
        assert_eq!(nan.min_or(other).0, [5.0, 0.0, 2.0, -1.0]);
        assert_eq!(nan.max_or(other).0, [5.0, 1.0, 3.0, -1.0]);
    }

    #[test]
    fn sign_helpers() {
        let a = F4([1.0, -2.0, 3.0, -0.0]);
        let s = F4([-1.0, -1.0, 0.0, -5.0]);
        assert_eq!(a.xor_sign_of(s).0, [-1.0, 2.0, 3.0, 0.0]);
        assert_eq!(a.abs().0, [1.0, 2.0, 3.0, 0.0]);
    }

    #[test]
    fn comparisons_are_false_for_nan() {
        let a = F4([f32::NAN, 1.0, 1.0, 0.0]);
        let b = F4::splat(1.0);
        assert_eq!(a.le(b).0, [0, u32::MAX, u32::MAX, u32::MAX]);
        assert_eq!(a.ne(b).0, [0, 0, 0, u32::MAX]);
        assert_eq!((a.lt(b) & a.gt(b)).bits(), 0);
        assert_eq!((!a.ge(b)).bits(), 0b1001);
        assert_eq!(a.le(b).bits(), 0b1110);
    }

    #[test]
    fn eight_lanes_are_two_halves_in_order() {
        let a = F8::load(&[0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
        assert_eq!(F8::splat(4.5).le(a).bits(), 0b1110_0000);
        assert_eq!((a * 2.0).lane(5), 10.0);
        let m = a.min_or(F8::splat(2.5));
        assert_eq!((m.lane(1), m.lane(7)), (1.0, 2.5));
    }
}
