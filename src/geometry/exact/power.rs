//! Exact predicates of power (Laguerre) geometry, for sites `s` with weights
//! `w`: the power of a point `p` is `|p - s|² - w`, and a power diagram
//! gives each point to the site of least power. Each predicate is evaluated
//! in doubles with a forward error bound; where that bound cannot decide its
//! sign (or underflow or overflow void it), in double-double with an error
//! bound; and where that cannot either, in rationals.

use std::cmp::Ordering;

use glam::DVec2;
use num_rational::BigRational;
use num_traits::{Signed, Zero};

use super::bounded::Bounded;
use super::filter::Bound;
use super::rational;

/// A weighted site.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Weighted {
    pub at: DVec2,
    pub weight: f64,
}

impl Weighted {
    /// Each point with its weight, in order (the shorter list decides how many).
    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    pub fn zip(points: &[DVec2], weights: &[f64]) -> Vec<Self> {
        points
            .iter()
            .zip(weights)
            .map(|(&at, &weight)| Self { at, weight })
            .collect()
    }
}

fn sign_of(r: &BigRational) -> Ordering {
    if r.is_zero() {
        Ordering::Equal
    } else if r.is_positive() {
        Ordering::Greater
    } else {
        Ordering::Less
    }
}

/// The power test: `Greater` when `d` conflicts with the counter-clockwise
/// triangle `a, b, c` (its lifted point `(x, y, x² + y² - w)` lies below the
/// plane through theirs: the regular triangulation holds no such triangle),
/// `Equal` on the plane. Without weights it is the in-circle test.
pub fn power_test(a: Weighted, b: Weighted, c: Weighted, d: Weighted) -> Ordering {
    if let Some(sign) = power_test_filtered(Bound::POWER_TEST, a, b, c, d) {
        return sign;
    }
    let rows_bounded = [a, b, c].map(|s| {
        let x = Bounded::difference(s.at.x, d.at.x);
        let y = Bounded::difference(s.at.y, d.at.y);
        let lift = x * x + y * y - Bounded::difference(s.weight, d.weight);
        (x, y, lift)
    });
    if let Some(sign) = determinant(rows_bounded).sign() {
        return sign;
    }
    power_test_exactly(a, b, c, d)
}

/// The power test in doubles, where `bound` decides its sign.
pub(super) fn power_test_filtered(
    bound: Bound,
    a: Weighted,
    b: Weighted,
    c: Weighted,
    d: Weighted,
) -> Option<Ordering> {
    let rows = [a, b, c].map(|s| {
        let (x, y) = (s.at.x - d.at.x, s.at.y - d.at.y);
        let gap = s.weight - d.weight;
        (x, y, x * x + y * y - gap, x * x + y * y + gap.abs())
    });
    let [(ax, ay, al, am), (bx, by, bl, bm), (cx, cy, cl, cm)] = rows;
    let value = al * (bx * cy - by * cx) - bl * (ax * cy - ay * cx) + cl * (ax * by - ay * bx);
    let permanent = am * ((bx * cy).abs() + (by * cx).abs())
        + bm * ((ax * cy).abs() + (ay * cx).abs())
        + cm * ((ax * by).abs() + (ay * bx).abs());
    bound.sign(value, permanent)
}

/// The power test in rationals.
pub(super) fn power_test_exactly(a: Weighted, b: Weighted, c: Weighted, d: Weighted) -> Ordering {
    let rows = [a, b, c].map(|s| {
        let x = rational(s.at.x) - rational(d.at.x);
        let y = rational(s.at.y) - rational(d.at.y);
        let lift = &x * &x + &y * &y - (rational(s.weight) - rational(d.weight));
        (x, y, lift)
    });
    sign_of(&determinant(rows))
}

/// The 3 x 3 determinant of the rows `(x, y, lift)`.
fn determinant<T>(r: [(T, T, T); 3]) -> T
where
    T: Clone + std::ops::Add<Output = T> + std::ops::Sub<Output = T> + std::ops::Mul<Output = T>,
{
    let [(ax, ay, al), (bx, by, bl), (cx, cy, cl)] = r;
    let minor = |p: &T, q: &T, r: &T, s: &T| p.clone() * s.clone() - q.clone() * r.clone();
    al * minor(&bx, &by, &cx, &cy) - bl * minor(&ax, &ay, &cx, &cy) + cl * minor(&ax, &ay, &bx, &by)
}

/// A power in doubles: within 5u of `magnitude`, `x² + y² + |w|`, of the
/// exact one.
#[derive(Clone, Copy, Debug)]
pub struct PowerEstimate {
    value: f64,
    magnitude: f64,
}

impl PowerEstimate {
    /// The power of `p` from `s`, in doubles.
    #[inline]
    pub fn of(p: DVec2, s: Weighted) -> Self {
        let (x, y) = (p.x - s.at.x, p.y - s.at.y);
        let square = x * x + y * y;
        Self {
            value: square - s.weight,
            magnitude: square + s.weight.abs(),
        }
    }

    /// How the exact power this estimates compares with `other`'s, where
    /// the error bounds decide it: the difference adds u, so 8u of the
    /// magnitudes bounds its error.
    #[inline]
    pub fn compare(self, other: Self) -> Option<Ordering> {
        self.compare_within(Bound::POWER_ORDER, other)
    }

    pub(super) fn compare_within(self, bound: Bound, other: Self) -> Option<Ordering> {
        bound.sign(self.value - other.value, self.magnitude + other.magnitude)
    }
}

/// How the power of `p` from `s` compares with its power from `t`.
pub fn compare_power(p: DVec2, s: Weighted, t: Weighted) -> Ordering {
    if let Some(sign) = PowerEstimate::of(p, s).compare(PowerEstimate::of(p, t)) {
        return sign;
    }
    let power = |s: Weighted| {
        let (x, y) = (
            Bounded::difference(p.x, s.at.x),
            Bounded::difference(p.y, s.at.y),
        );
        x * x + y * y - Bounded::exact(s.weight)
    };
    if let Some(sign) = (power(s) - power(t)).sign() {
        return sign;
    }
    compare_power_exactly(p, s, t)
}

/// How the power of `p` from `s` compares with its power from `t`, in
/// rationals.
pub(super) fn compare_power_exactly(p: DVec2, s: Weighted, t: Weighted) -> Ordering {
    let exact = |s: Weighted| {
        let (x, y) = (
            rational(p.x) - rational(s.at.x),
            rational(p.y) - rational(s.at.y),
        );
        &x * &x + &y * &y - rational(s.weight)
    };
    exact(s).cmp(&exact(t))
}

/// The double nearest the power of `p` from `s`.
pub fn power_of(p: DVec2, s: Weighted) -> f64 {
    let (x, y) = (
        Bounded::difference(p.x, s.at.x),
        Bounded::difference(p.y, s.at.y),
    );
    let power = x * x + y * y - Bounded::exact(s.weight);
    power.nearest_plus(0.0).unwrap_or_else(|| {
        let (x, y) = (
            rational(p.x) - rational(s.at.x),
            rational(p.y) - rational(s.at.y),
        );
        super::nearest_double(&(&x * &x + &y * &y - rational(s.weight)))
    })
}
