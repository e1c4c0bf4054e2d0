//! Arithmetic written once for one Levenberg–Marquardt run (`f64`) and for four runs at once
//! ([`F4`], one run per lane of a 256-bit vector).
//!
//! [`F4`] applies each operation lane by lane with the same IEEE operation as `f64` (Rust never
//! fuses a multiply and an add on its own), so code generic over [`Real`] gives every lane
//! bit-identical results to the one-run instance; compiled for AVX2, the lanes become one
//! vector instruction each.

use std::ops::{Add, Div, Mul, Sub};

/// The numbers the step and the 6 × 6 solve are written over: `f64` or [`F4`].
pub(crate) trait Real:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// One truth value per lane.
    type Mask: Copy;
    /// `value` in every lane.
    fn splat(value: f64) -> Self;
    /// The correctly rounded square root, lane by lane.
    fn sqrt(self) -> Self;
    /// Lane by lane: `self > 0` and finite.
    fn positive_finite(self) -> Self::Mask;
    /// Lane by lane: `self == 0` (either sign).
    fn is_zero(self) -> Self::Mask;
    /// Lane by lane: `a` where `mask` holds, else `b`.
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self;
    /// Lane by lane: `a && b`.
    fn both(a: Self::Mask, b: Self::Mask) -> Self::Mask;
}

impl Real for f64 {
    type Mask = bool;
    #[inline(always)]
    fn splat(value: f64) -> Self {
        value
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn positive_finite(self) -> bool {
        self > 0.0 && self.is_finite()
    }
    #[inline(always)]
    fn is_zero(self) -> bool {
        self == 0.0
    }
    #[inline(always)]
    fn select(mask: bool, a: Self, b: Self) -> Self {
        if mask {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn both(a: bool, b: bool) -> bool {
        a && b
    }
}

/// Four `f64` lanes, one per run.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[repr(transparent)]
pub(crate) struct F4(pub [f64; 4]);

impl F4 {
    /// `values` seen as plain arrays of four lanes.
    pub(crate) fn as_arrays(values: &[F4]) -> &[[f64; 4]] {
        // SAFETY: `F4` is a transparent wrapper of `[f64; 4]` (same size, alignment and
        // validity), so the slice's memory holds `values.len()` valid arrays.
        unsafe { std::slice::from_raw_parts(values.as_ptr().cast(), values.len()) }
    }

    /// `values` seen as plain arrays of four lanes, writable.
    pub(crate) fn as_arrays_mut(values: &mut [F4]) -> &mut [[f64; 4]] {
        // SAFETY: as in `as_arrays`; the borrow is unique and lasts as long as `values`'s.
        unsafe { std::slice::from_raw_parts_mut(values.as_mut_ptr().cast(), values.len()) }
    }

    /// Lane `lane` of `f(lane)`.
    #[inline(always)]
    pub(crate) fn from_fn(f: impl FnMut(usize) -> f64) -> Self {
        Self(std::array::from_fn(f))
    }

    #[inline(always)]
    fn zip(self, other: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        Self([
            f(self.0[0], other.0[0]),
            f(self.0[1], other.0[1]),
            f(self.0[2], other.0[2]),
            f(self.0[3], other.0[3]),
        ])
    }
}

impl Add for F4 {
    type Output = Self;
    #[inline(always)]
    fn add(self, other: Self) -> Self {
        self.zip(other, |a, b| a + b)
    }
}

impl Sub for F4 {
    type Output = Self;
    #[inline(always)]
    fn sub(self, other: Self) -> Self {
        self.zip(other, |a, b| a - b)
    }
}

impl Mul for F4 {
    type Output = Self;
    #[inline(always)]
    fn mul(self, other: Self) -> Self {
        self.zip(other, |a, b| a * b)
    }
}

impl Div for F4 {
    type Output = Self;
    #[inline(always)]
    fn div(self, other: Self) -> Self {
        self.zip(other, |a, b| a / b)
    }
}

impl F4 {
    /// Lane by lane: the larger of the two, as [`f64::max`] (a NaN loses).
    #[inline(always)]
    pub(crate) fn max(self, other: Self) -> Self {
        self.zip(other, f64::max)
    }

    /// Lane by lane: the smaller of the two, as [`f64::min`] (a NaN loses).
    #[inline(always)]
    pub(crate) fn min(self, other: Self) -> Self {
        self.zip(other, f64::min)
    }

    /// Lane by lane: the absolute value.
    #[inline(always)]
    pub(crate) fn abs(self) -> Self {
        Self(self.0.map(f64::abs))
    }
}

impl F4 {
    /// Lane by lane: `self < other` (false with a NaN).
    #[inline(always)]
    pub(crate) fn lt(self, other: Self) -> Mask4 {
        Mask4::from_fn(|l| self.0[l] < other.0[l])
    }

    /// Lane by lane: `self <= other` (false with a NaN).
    #[inline(always)]
    pub(crate) fn le(self, other: Self) -> Mask4 {
        Mask4::from_fn(|l| self.0[l] <= other.0[l])
    }
}

/// One truth value per lane of an [`F4`]: all bits set for true, none for false (the form of
/// a vector comparison, so that selections compile to blends).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Mask4(pub [u64; 4]);

impl Mask4 {
    /// `lanes[l]` in lane `l`.
    #[inline(always)]
    pub(crate) fn from_bools(lanes: [bool; 4]) -> Self {
        Self(lanes.map(|b| if b { u64::MAX } else { 0 }))
    }

    /// Lane `lane` of `f(lane)`.
    #[inline(always)]
    pub(crate) fn from_fn(f: impl FnMut(usize) -> bool) -> Self {
        Self::from_bools(std::array::from_fn(f))
    }

    /// Lane by lane: `self || other`.
    #[inline(always)]
    pub(crate) fn or(self, other: Self) -> Self {
        Self(std::array::from_fn(|lane| self.0[lane] | other.0[lane]))
    }

    /// Lane by lane: `self != other` (exclusive or).
    #[inline(always)]
    pub(crate) fn differs(self, other: Self) -> Self {
        Self(std::array::from_fn(|lane| self.0[lane] ^ other.0[lane]))
    }

    /// Whether lane `lane` holds.
    #[inline(always)]
    pub(crate) fn lane(self, lane: usize) -> bool {
        self.0[lane] != 0
    }
}

impl Real for F4 {
    type Mask = Mask4;
    #[inline(always)]
    fn splat(value: f64) -> Self {
        Self([value; 4])
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Self(self.0.map(f64::sqrt))
    }
    #[inline(always)]
    fn positive_finite(self) -> Mask4 {
        Mask4::from_bools(self.0.map(Real::positive_finite))
    }
    #[inline(always)]
    fn is_zero(self) -> Mask4 {
        Mask4::from_bools(self.0.map(|v| v == 0.0))
    }
    #[inline(always)]
    fn select(mask: Mask4, a: Self, b: Self) -> Self {
        Self::from_fn(|lane| {
            f64::from_bits(
                (a.0[lane].to_bits() & mask.0[lane]) | (b.0[lane].to_bits() & !mask.0[lane]),
            )
        })
    }
    #[inline(always)]
    fn both(a: Mask4, b: Mask4) -> Mask4 {
        Mask4(std::array::from_fn(|lane| a.0[lane] & b.0[lane]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_give_the_scalar_operations_bit_for_bit() {
        let values = [
            0.1,
            -3.5,
            1e-300,
            7.25e12,
            -0.0,
            f64::MIN_POSITIVE,
            2.0f64.sqrt(),
            -1e-7,
        ];
        for (i, &a) in values.iter().enumerate() {
            let b = values[(i * 5 + 3) % values.len()];
            let lanes_a = F4::from_fn(|l| a * (l as f64 + 1.0));
            let lanes_b = F4::from_fn(|l| b - l as f64);
            for l in 0..4 {
                let (x, y) = (lanes_a.0[l], lanes_b.0[l]);
                assert_eq!((lanes_a + lanes_b).0[l].to_bits(), (x + y).to_bits());
                assert_eq!((lanes_a - lanes_b).0[l].to_bits(), (x - y).to_bits());
                assert_eq!((lanes_a * lanes_b).0[l].to_bits(), (x * y).to_bits());
                assert_eq!((lanes_a / lanes_b).0[l].to_bits(), (x / y).to_bits());
                let root = Real::sqrt(lanes_a).0[l];
                assert_eq!(root.to_bits(), x.sqrt().to_bits());
                assert_eq!(lanes_a.positive_finite().lane(l), x > 0.0 && x.is_finite());
                assert_eq!(lanes_a.is_zero().lane(l), x == 0.0);
                let other = lanes_b.0[l];
                assert_eq!(lanes_a.max(lanes_b).0[l].to_bits(), x.max(other).to_bits());
                assert_eq!(lanes_a.min(lanes_b).0[l].to_bits(), x.min(other).to_bits());
                assert_eq!(lanes_b.abs().0[l].to_bits(), other.abs().to_bits());
                assert_eq!(lanes_a.lt(lanes_b).lane(l), x < other);
                assert_eq!(lanes_a.le(lanes_b).lane(l), x <= other);
            }
        }
        let mixed = F4([1.0, f64::INFINITY, f64::NAN, -2.0]);
        assert_eq!(
            mixed.positive_finite(),
            Mask4::from_bools([true, false, false, false])
        );
        let chosen = F4::select(
            Mask4::from_bools([true, false, true, false]),
            mixed,
            F4::splat(9.0),
        );
        assert_eq!(chosen.0[0], 1.0);
        assert_eq!(chosen.0[1], 9.0);
        assert!(chosen.0[2].is_nan());
        assert_eq!(chosen.0[3], 9.0);
        let (p, q) = (
            Mask4::from_bools([true, true, false, false]),
            Mask4::from_bools([true, false, true, false]),
        );
        assert_eq!(p.or(q), Mask4::from_bools([true, true, true, false]));
        assert_eq!(p.differs(q), Mask4::from_bools([false, true, true, false]));
        assert!(!F4::splat(f64::NAN).le(F4::splat(1.0)).lane(0));
    }
}
