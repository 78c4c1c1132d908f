//! Exact numbers `w + u √a` with rationals w, u and a >= 0: every Euclidean
//! distance to a point, a segment or a circle, and every L1 and L∞ distance to
//! a circle, is one of them (the radicand a square, a squared cross product
//! over a squared length, the discriminant where a line through the pixel
//! meets the circle). Two of them are ordered exactly by squaring out the
//! roots.

use std::cmp::Ordering;

use num_rational::BigRational;
use num_traits::{Signed, Zero};

use super::precise::Interval;
use super::sign_with_root;

/// The number `w + u √a`, a >= 0.
#[derive(Clone, Debug)]
pub(crate) struct Surd {
    w: BigRational,
    u: BigRational,
    a: BigRational,
}

impl Surd {
    /// The rational `w`.
    pub fn rational(w: BigRational) -> Self {
        Self {
            w,
            u: BigRational::zero(),
            a: BigRational::zero(),
        }
    }

    /// `w + u √a` for `a >= 0`.
    pub fn new(w: BigRational, u: BigRational, a: BigRational) -> Self {
        debug_assert!(!a.is_negative());
        Self { w, u, a }
    }

    /// Its sign.
    pub fn sign(&self) -> Ordering {
        sign_with_root(&self.w, &self.u, &self.a)
    }

    /// Its magnitude.
    pub fn abs(self) -> Self {
        if self.sign() == Ordering::Less {
            Self::new(-self.w, -self.u, self.a)
        } else {
            self
        }
    }

    /// `self * k + c` for rationals `k` and `c`.
    pub fn affine(self, k: &BigRational, c: &BigRational) -> Self {
        Self::new(self.w * k + c, self.u * k, self.a)
    }

    /// The sum of two numbers with the same radicand; `None` for different ones.
    pub fn plus(self, other: Self) -> Option<Self> {
        if self.u.is_zero() || other.u.is_zero() || self.a == other.a {
            let a = if self.u.is_zero() { other.a } else { self.a };
            Some(Self::new(self.w + other.w, self.u + other.u, a))
        } else {
            None
        }
    }

    /// The exact order of `self` and `other`.
    pub fn cmp(&self, other: &Self) -> Ordering {
        let b = &self.w - &other.w;
        if self.a == other.a {
            return sign_with_root(&b, &(&self.u - &other.u), &self.a);
        }
        sign_with_two_roots(&b, &self.u, &self.a, &-&other.u, &other.a)
    }

    /// The smaller of the two, exactly.
    pub fn min(self, other: Self) -> Self {
        if other.cmp(&self) == Ordering::Less {
            other
        } else {
            self
        }
    }

    /// An interval holding it, the root to within 2^-bits.
    pub fn interval(&self, bits: u64) -> Interval {
        Interval::sqrt(&self.a, bits).affine(&self.u, &self.w)
    }

    /// Its value to within a few ulps.
    pub fn approximate(&self) -> f64 {
        use num_traits::ToPrimitive;
        let f = |r: &BigRational| r.to_f64().unwrap_or(f64::NAN);
        f(&self.w) + f(&self.u) * f(&self.a).sqrt()
    }
}

/// The sign of `b + c √u + d √v` for rationals u, v >= 0.
fn sign_with_two_roots(
    b: &BigRational,
    c: &BigRational,
    u: &BigRational,
    d: &BigRational,
    v: &BigRational,
) -> Ordering {
    let zero = BigRational::zero();
    let sign = |x: &BigRational, r: &BigRational| {
        if r.is_zero() {
            Ordering::Equal
        } else {
            x.cmp(&zero)
        }
    };
    let (cu, dv) = (c * c * u, d * d * v);
    // The sign of s = c √u + d √v: the larger magnitude's where they differ.
    let (sc, sd) = (sign(c, u), sign(d, v));
    let ss = match (sc, sd) {
        (Ordering::Equal, s) | (s, Ordering::Equal) => s,
        (x, y) if x == y => x,
        _ => match cu.cmp(&dv) {
            Ordering::Greater => sc,
            Ordering::Less => sd,
            Ordering::Equal => Ordering::Equal,
        },
    };
    let sb = b.cmp(&zero);
    if ss == Ordering::Equal || sb == Ordering::Equal || sb == ss {
        return if sb == Ordering::Equal { ss } else { sb };
    }
    // Opposite signs: the sign of s² - b² = (cu + dv - b²) + 2cd √(uv) says
    // which magnitude is larger.
    let two = BigRational::from_integer(2.into());
    match sign_with_root(&(&cu + &dv - b * b), &(two * c * d), &(u * v)) {
        Ordering::Greater => ss,
        Ordering::Less => sb,
        Ordering::Equal => Ordering::Equal,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_bigint::BigInt;

    fn r(n: i64, d: i64) -> BigRational {
        BigRational::new(BigInt::from(n), BigInt::from(d))
    }

    #[test]
    fn orders_sums_of_roots_exactly() {
        let surd = |w, u, a| Surd::new(r(w, 1), r(u, 1), r(a, 1));
        // √2 + √3 = 3.1463 against √10 = 3.1623: different radicands.
        let sum = Surd::new(r(0, 1), r(1, 1), r(2, 1)).plus(surd(0, 1, 3));
        assert!(sum.is_none());
        assert_eq!(
            sign_with_two_roots(&r(0, 1), &r(1, 1), &r(2, 1), &r(-1, 1), &r(10, 1)),
            Ordering::Less
        );
        assert_eq!(surd(0, 1, 10).cmp(&surd(0, 1, 3)), Ordering::Greater);
        // 1 + √2 against 1 + √8 / 2, and √5 - 1 against √20 / 2 - 1: equal.
        let half = Surd::new(r(1, 1), r(1, 2), r(8, 1));
        assert_eq!(surd(1, 1, 2).cmp(&half), Ordering::Equal);
        let e = surd(-1, 1, 5);
        let f = Surd::new(r(-1, 1), r(1, 2), r(20, 1));
        assert_eq!(e.cmp(&f), Ordering::Equal);
        // √(10^60 + 1) against 10^30: one part in 10^60.
        let big = BigRational::from_integer(BigInt::from(10).pow(30));
        let c = Surd::new(r(0, 1), r(1, 1), &big * &big + r(1, 1));
        let d = Surd::rational(big);
        assert_eq!(c.cmp(&d), Ordering::Greater);
        assert_eq!(d.cmp(&c), Ordering::Less);
        // 1 - √5 is negative; its magnitude is √5 - 1.
        let neg = surd(1, -1, 5);
        assert_eq!(neg.sign(), Ordering::Less);
        assert_eq!(neg.abs().cmp(&e), Ordering::Equal);
        assert_eq!(surd(0, 1, 3).cmp(&surd(0, 1, 2)), Ordering::Greater);
        // 5 - √2 - √3 = 1.8537 > 0, and 3 - √2 - √3 = -0.146 < 0.
        let two_roots = |b| sign_with_two_roots(&r(b, 1), &r(-1, 1), &r(2, 1), &r(-1, 1), &r(3, 1));
        assert_eq!(two_roots(5), Ordering::Greater);
        assert_eq!(two_roots(3), Ordering::Less);
    }
}
