//! Circles through points: the smallest enclosing circle (Welzl 1991), which
//! the homothet and α-hull algorithms start from. Exact for the doubles given:
//! whether a point lies in a circle is decided from the points that determine
//! the circle, with exact predicates, and the centre and radius are the
//! doubles nearest to the exact ones.

use std::cmp::Ordering;

use glam::DVec2;
use num_rational::BigRational;
use num_traits::Zero;
use rand::seq::SliceRandom;
use rand_chacha::{rand_core::SeedableRng, ChaCha8Rng};

use super::filter::Bound;
use super::predicates::{incircle, orient};
use super::{
    circumcentre_exact, distance_squared, nearest_double, nearest_double_sqrt, rational_point,
};
use crate::geometry::frame::lexicographic;

/// A circle and the indices (into the points given) of the points on it that
/// determine it.
#[derive(Clone, Debug, PartialEq)]
pub struct Circle {
    /// The doubles nearest to the exact centre and radius.
    pub centre: DVec2,
    pub radius: f64,
    pub support: Vec<usize>,
}

impl Circle {
    /// Whether `p` lies in the closed disc, decided exactly from the support
    /// points (indices into `points`).
    pub fn holds(&self, points: &[DVec2], p: DVec2) -> bool {
        let s = |k: usize| points[self.support[k]];
        match self.support.len() {
            0 => false,
            1 => p == s(0),
            2 => diametral_side(s(0), s(1), p) != Ordering::Greater,
            _ => {
                let turn = orient(s(0), s(1), s(2));
                incircle(s(0), s(1), s(2), p) * turn.signum() >= 0.0
            }
        }
    }
}

/// The sign of (p - a)·(p - b), exactly: negative inside the circle on the
/// segment ab as diameter, zero on it.
fn diametral_side(a: DVec2, b: DVec2, p: DVec2) -> Ordering {
    diametral_side_filtered(Bound::DIAMETRAL, a, b, p)
        .unwrap_or_else(|| diametral_side_exactly(a, b, p))
}

pub(super) fn diametral_side_filtered(
    bound: Bound,
    a: DVec2,
    b: DVec2,
    p: DVec2,
) -> Option<Ordering> {
    let (u, v) = (p - a, p - b);
    let magnitude = u.x.abs() * v.x.abs() + u.y.abs() * v.y.abs();
    bound.sign(u.x * v.x + u.y * v.y, magnitude)
}

pub(super) fn diametral_side_exactly(a: DVec2, b: DVec2, p: DVec2) -> Ordering {
    let [a, b, p] = [a, b, p].map(rational_point);
    let dot = (&p[0] - &a[0]) * (&p[0] - &b[0]) + (&p[1] - &a[1]) * (&p[1] - &b[1]);
    dot.cmp(&BigRational::zero())
}

/// The circle with the exact centre `centre` through `on`, rounded.
fn rounded(centre: &[BigRational; 2], on: DVec2, support: Vec<usize>) -> Circle {
    Circle {
        centre: DVec2::new(nearest_double(&centre[0]), nearest_double(&centre[1])),
        radius: nearest_double_sqrt(&distance_squared(centre, &rational_point(on))),
        support,
    }
}

/// The circle on the segment between two points as diameter.
pub(crate) fn through_two(a: DVec2, b: DVec2, ia: usize, ib: usize) -> Circle {
    let half = BigRational::new(1.into(), 2.into());
    let [ea, eb] = [a, b].map(rational_point);
    let centre = [(&ea[0] + &eb[0]) * &half, (&ea[1] + &eb[1]) * &half];
    rounded(&centre, a, Vec::from([ia, ib]))
}

/// The circle through three points (the two farthest apart when they are
/// collinear).
pub fn through_three(p: [DVec2; 3], i: [usize; 3]) -> Circle {
    match circumcentre_exact(p[0], p[1], p[2]) {
        Some(centre) => rounded(&centre, p[0], i.to_vec()),
        None => {
            // Collinear: the extremes of the line's order are the farthest apart.
            let mut by_order = [0, 1, 2];
            by_order.sort_by(|&u, &v| lexicographic(p[u]).cmp(&lexicographic(p[v])));
            let (x, y) = (by_order[0], by_order[2]);
            through_two(p[x], p[y], i[x], i[y])
        }
    }
}

/// A circle with an exact centre and squared radius, through sites given as
/// doubles, for searches that compare circles before rounding any.
#[derive(Clone, Debug)]
pub(crate) struct ExactCircle {
    centre: [BigRational; 2],
    radius_squared: BigRational,
    /// The doubles nearest the centre and the squared radius.
    rounded: (DVec2, f64),
}

impl ExactCircle {
    /// The circle on the segment `a b` as diameter.
    pub fn on_diameter(a: DVec2, b: DVec2) -> Self {
        let half = BigRational::new(1.into(), 2.into());
        let [ea, eb] = [a, b].map(rational_point);
        Self::centred([(&ea[0] + &eb[0]) * &half, (&ea[1] + &eb[1]) * &half], a)
    }

    /// The circle through `a`, `b` and `c`; `None` where they are collinear.
    pub fn through(a: DVec2, b: DVec2, c: DVec2) -> Option<Self> {
        circumcentre_exact(a, b, c).map(|centre| Self::centred(centre, a))
    }

    fn centred(centre: [BigRational; 2], on: DVec2) -> Self {
        let radius_squared = distance_squared(&centre, &rational_point(on));
        let rounded = (
            DVec2::new(nearest_double(&centre[0]), nearest_double(&centre[1])),
            nearest_double(&radius_squared),
        );
        Self {
            centre,
            radius_squared,
            rounded,
        }
    }

    /// The order of the two circles' radii.
    pub fn compare_radius(&self, other: &Self) -> Ordering {
        self.radius_squared.cmp(&other.radius_squared)
    }

    /// Whether `p` lies in the closed disc: by floats where the rounded
    /// centre's distance is clear of the radius, exactly where not.
    pub fn holds(&self, p: DVec2) -> bool {
        let (centre, r2) = self.rounded;
        // The rounded centre is within `delta` of the exact one.
        let delta = centre.abs().max_element() * f64::EPSILON;
        let d = p.distance_squared(centre);
        let margin = 3.0 * d.sqrt() * delta + 2.0 * delta * delta + 1e-12 * (d + r2);
        if (d - r2).abs() > margin + f64::MIN_POSITIVE {
            return d < r2;
        }
        self.distance_squared_to(p) <= self.radius_squared
    }

    /// Whether `p` lies exactly on the circle.
    pub fn passes_through(&self, p: DVec2) -> bool {
        self.distance_squared_to(p) == self.radius_squared
    }

    fn distance_squared_to(&self, p: DVec2) -> BigRational {
        distance_squared(&self.centre, &rational_point(p))
    }

    /// The doubles nearest the centre and the radius.
    pub fn rounded(&self) -> (DVec2, f64) {
        (self.rounded.0, nearest_double_sqrt(&self.radius_squared))
    }
}

/// The smallest circle holding every point (Welzl 1991, iterative
/// move-to-front form, in a fixed random order). Empty input gives radius 0 at
/// the origin.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub fn welzl(points: &[DVec2]) -> Circle {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.shuffle(&mut ChaCha8Rng::seed_from_u64(0x5e1f));
    let p = |k: usize| points[order[k]];
    let mut c = match order.first() {
        None => {
            return Circle {
                centre: DVec2::ZERO,
                radius: 0.0,
                support: Vec::new(),
            }
        }
        Some(&i) => Circle {
            centre: points[i],
            radius: 0.0,
            support: Vec::from([i]),
        },
    };
    for i in 1..order.len() {
        if c.holds(points, p(i)) {
            continue;
        }
        c = Circle {
            centre: p(i),
            radius: 0.0,
            support: Vec::from([order[i]]),
        };
        for j in 0..i {
            if c.holds(points, p(j)) {
                continue;
            }
            c = through_two(p(i), p(j), order[i], order[j]);
            for k in 0..j {
                if !c.holds(points, p(k)) {
                    c = through_three([p(i), p(j), p(k)], [order[i], order[j], order[k]]);
                }
            }
        }
    }
    c
}
