//! Double-double values that carry a bound on their error: a float
//! evaluation, about twice as precise as plain doubles, that knows when it
//! has decided a sign or a rounding, so that only the undecided cases pay for
//! rationals.

use std::ops::{Add, Div, Mul, Sub};

use super::two_product;
use super::two_sum;

/// The unevaluated sum `hi + lo` (`|lo|` at most half an ulp of `hi`),
/// within `e` of the exact value.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bounded {
    pub hi: f64,
    pub lo: f64,
    pub e: f64,
}

/// The relative error of one double-double operation, generously (about
/// 2^-104 is proven for these; the rest spares the bound's own rounding).
const RELATIVE: f64 = 1.0 / (1u128 << 100) as f64;

/// An absolute error for results near underflow, where the error-free
/// transformations lose their low parts.
const ABSOLUTE: f64 = 1e-290;

/// The bound of a result of size `size` given the `propagated` errors of its
/// operands.
fn bound(propagated: f64, size: f64) -> f64 {
    (propagated + size * RELATIVE) * (1.0 + 4.0 * f64::EPSILON) + ABSOLUTE
}

impl Bounded {
    pub fn exact(v: f64) -> Self {
        Self {
            hi: v,
            lo: 0.0,
            e: 0.0,
        }
    }

    /// `a - b` of two exact doubles.
    pub fn difference(a: f64, b: f64) -> Self {
        let (hi, lo) = two_sum(a, -b);
        let e = if hi.abs() < ABSOLUTE { ABSOLUTE } else { 0.0 };
        Self { hi, lo, e }
    }

    fn normalized(hi: f64, lo: f64, e: f64) -> Self {
        let (hi, lo) = two_sum(hi, lo);
        Self { hi, lo, e }
    }

    fn magnitude(self) -> f64 {
        self.hi.abs()
    }

    fn is_finite(self) -> bool {
        self.hi.is_finite() && self.lo.is_finite() && self.e.is_finite()
    }

    /// The sign of the exact value, where the bound decides it.
    pub fn sign(self) -> Option<std::cmp::Ordering> {
        (self.is_finite() && self.hi.abs() - self.lo.abs() * 2.0 > self.e)
            .then(|| self.hi.total_cmp(&0.0))
    }

    /// The double nearest `a + self` where the bound settles it: the float sum
    /// and its exact error put `a + self` within a distance of the rounded sum
    /// that is short of half the gap to its neighbours.
    pub fn nearest_plus(self, a: f64) -> Option<f64> {
        if !self.is_finite() {
            return None;
        }
        // a + hi = x + error exactly; y is the double nearest x + error + lo,
        // and the exact value lies within |x - y + error + lo| + e of it.
        let (x, error) = two_sum(a, self.hi);
        let rest = error + self.lo;
        let y = x + rest;
        let m = y.abs();
        if !m.is_finite() {
            return None;
        }
        let up = f64::from_bits(m.to_bits() + 1);
        let gap = match m {
            0.0 => up,
            _ => (up - m).min(m - f64::from_bits(m.to_bits() - 1)),
        };
        let off = (((x - y) + rest).abs() + rest.abs() * f64::EPSILON + self.e)
            * (1.0 + 4.0 * f64::EPSILON);
        (off < 0.5 * gap).then_some(y)
    }
}

impl Add for Bounded {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        let (s, t) = two_sum(self.hi, o.hi);
        let e = bound(self.e + o.e, self.magnitude() + o.magnitude());
        Self::normalized(s, t + (self.lo + o.lo), e)
    }
}

impl Sub for Bounded {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        self + Self {
            hi: -o.hi,
            lo: -o.lo,
            e: o.e,
        }
    }
}

impl Mul for Bounded {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        let (p, t) = two_product(self.hi, o.hi);
        let t = t + (self.hi * o.lo + self.lo * o.hi);
        let (a, b) = (self.magnitude() * 2.0, o.magnitude() * 2.0);
        let propagated = a * o.e + b * self.e + self.e * o.e;
        Self::normalized(p, t, bound(propagated, a * b))
    }
}

impl Div for Bounded {
    type Output = Self;
    /// Unbounded where the divisor's bound reaches zero.
    fn div(self, o: Self) -> Self {
        let room = o.magnitude() * 0.5 - o.e;
        if room.is_nan() || room <= 0.0 {
            return Self {
                hi: f64::NAN,
                lo: 0.0,
                e: f64::INFINITY,
            };
        }
        let q1 = self.hi / o.hi;
        // The remainder self - q1 o, to double-double precision.
        let r = self
            - Self {
                e: 0.0,
                ..o * Self::exact(q1)
            };
        let q2 = r.hi / o.hi;
        let v = (q1.abs() + q2.abs()) * 2.0;
        // a/b - a'/b' = (δa - (a'/b') δb) / b, with |b| > room.
        let propagated = (self.e + v * o.e) / room;
        Self::normalized(q1, q2, bound(propagated, v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cmp::Ordering;

    #[test]
    fn bounds_hold_and_decide() {
        // 0.1 + 0.2 - 0.3 for these doubles is exactly 2^-55 (the sum of
        // their errors); double-double finds it.
        let s = Bounded::exact(0.1) + Bounded::exact(0.2) - Bounded::exact(0.3);
        assert!((s.hi + s.lo - 2f64.powi(-55)).abs() <= s.e);
        assert_eq!(s.sign(), Some(Ordering::Greater));
        // A cancellation to zero is not decided.
        let zero = Bounded::difference(1e16, 1e16 - 2.0) - Bounded::exact(2.0);
        assert_eq!(zero.sign(), None);
        assert!((Bounded::exact(1.0) / Bounded::difference(1.0, 1.0))
            .sign()
            .is_none());
        // A third to double-double precision rounds as the exact third does.
        let third = Bounded::exact(1.0) / Bounded::exact(3.0);
        assert_eq!(third.nearest_plus(0.0), Some(1.0 / 3.0));
        assert_eq!(third.nearest_plus(1.0), Some(4.0 / 3.0));
    }
}
