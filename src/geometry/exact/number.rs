//! The two kinds of number a formula written once is evaluated in: double-
//! double values that carry an error bound ([`Bounded`]), which settle the
//! correctly rounded answer almost everywhere, and exact rationals
//! ([`Exact`]), which settle the rest.

use std::ops::{Add, Div, Mul, Sub};

use num_rational::BigRational;

use super::{bounded::Bounded, nearest_double, rational};

/// A number a formula is evaluated in.
pub(crate) trait Number:
    Clone + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    fn exact(v: f64) -> Self;
    /// `a - b` of two doubles, exactly.
    fn difference(a: f64, b: f64) -> Self;
}

impl Number for Bounded {
    fn exact(v: f64) -> Self {
        Bounded::exact(v)
    }
    fn difference(a: f64, b: f64) -> Self {
        Bounded::difference(a, b)
    }
}

/// A rational number: a formula's exact value.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Exact(BigRational);

impl Number for Exact {
    fn exact(v: f64) -> Self {
        Exact(rational(v))
    }
    fn difference(a: f64, b: f64) -> Self {
        Exact(rational(a) - rational(b))
    }
}

macro_rules! exact_operator {
    ($trait:ident, $method:ident) => {
        impl $trait for Exact {
            type Output = Exact;
            fn $method(self, other: Exact) -> Exact {
                Exact(self.0.$method(other.0))
            }
        }
    };
}
exact_operator!(Add, add);
exact_operator!(Sub, sub);
exact_operator!(Mul, mul);
exact_operator!(Div, div);

impl Exact {
    /// The nearest double.
    pub fn nearest(&self) -> f64 {
        nearest_double(&self.0)
    }
}

/// The double nearest the value that `bounded` and `exact` evaluate alike:
/// settled by the bounded evaluation where it can, else exactly. Also says
/// whether the exact evaluation was needed.
pub(crate) fn nearest(bounded: impl Fn() -> Bounded, exact: impl Fn() -> Exact) -> (f64, bool) {
    match bounded().nearest_plus(0.0) {
        Some(v) => (v, false),
        None => (exact().nearest(), true),
    }
}
