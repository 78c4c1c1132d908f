//! Exact predicates of power (Laguerre) geometry, for sites `s` with weights
//! `w`: the power of a point `p` is `|p - s|² - w`, and a power diagram
//! gives each point to the site of least power. Each predicate is evaluated
//! in double-double with an error bound and, where the bound
//! cannot decide its sign, in rationals.

use std::cmp::Ordering;

use glam::DVec2;
use num_rational::BigRational;
use num_traits::{Signed, Zero};

use super::{bounded::Bounded, exact::rational};

/// A weighted site.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Weighted {
    pub at: DVec2,
    pub weight: f64,
}

impl Weighted {
    /// Each point with its weight, in order (the shorter list decides how many).
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
    let rows_bounded = [a, b, c].map(|s| {
        let x = Bounded::difference(s.at.x, d.at.x);
        let y = Bounded::difference(s.at.y, d.at.y);
        let lift = x * x + y * y - Bounded::difference(s.weight, d.weight);
        (x, y, lift)
    });
    if let Some(sign) = determinant(rows_bounded).sign() {
        return sign;
    }
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

/// How the power of `p` from `s` compares with its power from `t`.
pub fn compare_power(p: DVec2, s: Weighted, t: Weighted) -> Ordering {
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
        super::exact::nearest_double(&(&x * &x + &y * &y - rational(s.weight)))
    })
}
