//! Rational intervals to a chosen precision: square roots bracketed by
//! integer roots, and the cosine and sine of a double by their Taylor series
//! with the remainder bounded. They order numbers that no exact form holds
//! (an arc's end at a double angle is a transcendental point) whenever the
//! numbers differ.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Signed, Zero};

/// A real number known to lie in `[lo, hi]`.
#[derive(Clone, Debug)]
pub(crate) struct Interval {
    pub lo: BigRational,
    pub hi: BigRational,
}

impl Interval {
    /// √r for a rational r >= 0, to within 2^-bits.
    pub fn sqrt(r: &BigRational, bits: u64) -> Self {
        let scale = BigInt::from(1) << bits;
        let scaled = r * BigRational::from_integer(&scale * &scale);
        let low = scaled.floor().to_integer().sqrt();
        let exact = BigRational::from_integer(&low * &low) == scaled;
        let high = if exact { low.clone() } else { &low + 1 };
        Self {
            lo: BigRational::new(low, scale.clone()),
            hi: BigRational::new(high, scale),
        }
    }

    /// The one number r.
    pub fn point(r: BigRational) -> Self {
        Self {
            lo: r.clone(),
            hi: r,
        }
    }

    /// √x for an interval x whose true value is >= 0 (a negative lower end is
    /// rounding, taken as 0).
    pub fn sqrt_of(&self, bits: u64) -> Self {
        let lo = if self.lo.is_negative() {
            BigRational::zero()
        } else {
            Self::sqrt(&self.lo, bits).lo
        };
        Self {
            lo,
            hi: Self::sqrt(&self.hi.clone().max(BigRational::zero()), bits).hi,
        }
    }

    /// `self / o`; `None` where o may be 0.
    pub fn over(&self, o: &Self) -> Option<Self> {
        if !o.lo.is_positive() && !o.hi.is_negative() {
            return None;
        }
        let inverse = Self {
            lo: o.hi.recip(),
            hi: o.lo.recip(),
        };
        Some(self.times(&inverse))
    }

    /// The interval widened to ends on the grid 2^-bits, so that sums and
    /// products of many steps keep their integers short.
    pub fn rounded_out(&self, bits: u64) -> Self {
        let one = BigRational::from_integer(BigInt::from(1) << bits);
        Self {
            lo: (&self.lo * &one).floor() / &one,
            hi: (&self.hi * &one).ceil() / &one,
        }
    }

    pub fn negated(&self) -> Self {
        Self {
            lo: -self.hi.clone(),
            hi: -self.lo.clone(),
        }
    }

    /// Whether the interval excludes 0.
    pub fn is_nonzero(&self) -> bool {
        self.lo.is_positive() || self.hi.is_negative()
    }

    pub fn plus(&self, o: &Self) -> Self {
        Self {
            lo: &self.lo + &o.lo,
            hi: &self.hi + &o.hi,
        }
    }

    pub fn minus(&self, o: &Self) -> Self {
        Self {
            lo: &self.lo - &o.hi,
            hi: &self.hi - &o.lo,
        }
    }

    pub fn times(&self, o: &Self) -> Self {
        let products = [
            &self.lo * &o.lo,
            &self.lo * &o.hi,
            &self.hi * &o.lo,
            &self.hi * &o.hi,
        ];
        let lo = products.iter().min().expect("four").clone();
        let hi = products.iter().max().expect("four").clone();
        Self { lo, hi }
    }

    /// `self * k + c` for rationals k and c.
    pub fn affine(&self, k: &BigRational, c: &BigRational) -> Self {
        let (a, b) = (&self.lo * k + c, &self.hi * k + c);
        if k.is_negative() {
            Self { lo: b, hi: a }
        } else {
            Self { lo: a, hi: b }
        }
    }

    /// `c - self` for a rational c.
    pub fn subtracted_from(&self, c: &BigRational) -> Self {
        Self {
            lo: c - &self.hi,
            hi: c - &self.lo,
        }
    }

    pub fn abs(&self) -> Self {
        let zero = BigRational::zero();
        if !self.lo.is_negative() {
            self.clone()
        } else if !self.hi.is_positive() {
            self.affine(&-BigRational::from_integer(1.into()), &zero)
        } else {
            Self {
                lo: zero,
                hi: self.hi.clone().max(-self.lo.clone()),
            }
        }
    }

    /// The square of an interval.
    pub fn square(&self) -> Self {
        let a = self.abs();
        Self {
            lo: &a.lo * &a.lo,
            hi: &a.hi * &a.hi,
        }
    }

    pub fn min(self, o: Self) -> Self {
        Self {
            lo: self.lo.min(o.lo),
            hi: self.hi.min(o.hi),
        }
    }

    pub fn max(self, o: Self) -> Self {
        Self {
            lo: self.lo.max(o.lo),
            hi: self.hi.max(o.hi),
        }
    }
}

/// The cosine and sine of the double `x`, to within 2^-bits, from their
/// Taylor series in fixed point, each term's rounding tracked, and the remainder after the terms of degree below N bounded by
/// |x|^N / N!. `None` for |x| above 64, whose terms would grow too large
/// before they shrink.
pub(crate) fn cos_sin(x: f64, bits: u64) -> Option<(Interval, Interval)> {
    if x.is_nan() {
        return None;
    }
    cos_sin_of(&super::rational(x), bits)
}

/// [`cos_sin`] of a rational `x`.
pub(crate) fn cos_sin_of(x: &BigRational, bits: u64) -> Option<(Interval, Interval)> {
    let magnitude = num_traits::ToPrimitive::to_f64(&x.abs()).unwrap_or(f64::INFINITY);
    if magnitude > 64.0 {
        return None;
    }
    // Terms grow to about e^|x| before they shrink, and their roundings with
    // them: the working precision has room for both.
    let p = bits + 24 + (1.5 * magnitude).ceil() as u64;
    let one = BigInt::from(1) << p;
    // X: x in units of 2^-p, off by at most `ex` units.
    let scaled = x * BigRational::from_integer(one.clone());
    let big_x = scaled.floor().to_integer();
    let ex = if scaled.is_integer() { 0 } else { 1 };
    let limit = BigInt::from(1) << (p - bits - 2);
    // The term x^n / n! in units, and a bound on its error.
    let (mut term, mut error) = (one.clone(), BigInt::zero());
    let (mut sums, mut errors) = (
        [BigInt::zero(), BigInt::zero()],
        [BigInt::zero(), BigInt::zero()],
    );
    let mut n: u32 = 0;
    loop {
        let size = term.abs() + &error;
        if n as f64 > magnitude && size < limit {
            let interval = |v: &BigInt, e: &BigInt| {
                let spread = e + &size;
                Interval {
                    lo: BigRational::new(v - &spread, one.clone()),
                    hi: BigRational::new(v + spread, one.clone()),
                }
            };
            return Some((
                interval(&sums[0], &errors[0]),
                interval(&sums[1], &errors[1]),
            ));
        }
        let k = (n % 2) as usize;
        match n % 4 {
            0 | 1 => sums[k] += &term,
            _ => sums[k] -= &term,
        }
        errors[k] += &error;
        n += 1;
        // (t + δ)(X + η) / (n 2^p), floored: off by at most
        // (|t| ex + e |X| + e ex) / (n 2^p) + 1.
        let divisor = BigInt::from(n) << p;
        let spread = term.abs() * ex + &error * big_x.abs() + &error * ex;
        error = spread / &divisor + 2;
        let product = &term * &big_x;
        let (quotient, rest) = (&product / &divisor, &product % &divisor);
        term = if rest.is_negative() {
            quotient - 1
        } else {
            quotient
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_traits::ToPrimitive;

    /// π as people type it.
    #[allow(clippy::approx_constant)]
    const TYPED_PI: f64 = 3.14159265;

    #[test]
    fn brackets_hold_the_values() {
        for angle in [
            0.0,
            0.5,
            -1.0,
            TYPED_PI,
            std::f64::consts::PI,
            6.2,
            -12.5,
            40.0,
            1e-30,
        ] {
            let (c, s) = cos_sin(angle, 80).unwrap();
            for (i, f) in [(&c, angle.cos()), (&s, angle.sin())] {
                assert!(
                    i.lo <= i.hi
                        && (&i.hi - &i.lo) < BigRational::new(1.into(), BigInt::from(1) << 78)
                );
                let mid = ((&i.lo + &i.hi) / BigRational::from_integer(2.into()))
                    .to_f64()
                    .unwrap();
                assert!((mid - f).abs() <= 1e-15, "{angle}: {mid} against {f}");
            }
        }
        // cos(3.14159265) is -1 + 5.2e-17 and some: above -1, which its
        // double does not show.
        let (c, _) = cos_sin(TYPED_PI, 120).unwrap();
        let minus_one = BigRational::from_integer((-1).into());
        let near = BigRational::new(1.into(), BigInt::from(1) << 50);
        assert!(c.lo > minus_one && c.hi < minus_one + near);
        assert_eq!(TYPED_PI.cos(), -1.0);
        let two = BigRational::from_integer(2.into());
        let root = Interval::sqrt(&two, 100);
        assert!(&root.lo * &root.lo <= two && &root.hi * &root.hi >= two);
        let four = Interval::sqrt(&BigRational::from_integer(4.into()), 10);
        assert_eq!(four.lo, four.hi);
        assert!(cos_sin(65.0, 64).is_none() && cos_sin(f64::NAN, 64).is_none());
    }
}
