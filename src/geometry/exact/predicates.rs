//! The exact predicates every construction of pixgeo decides with, and the
//! convex hull built on them. Orientation and in-circle tests are Shewchuk's
//! adaptive ones (`robust`) on the points scaled by a power of two into the
//! range where they neither overflow nor underflow (`crate::geometry::scale`), and
//! rational arithmetic where no power of two fits: their signs are exact for
//! the doubles given.

use glam::DVec2;

use super::filter::Bound;
use super::{incircle_exact, nearest_double, orient_exact};
use crate::geometry::frame::{distinct_by, lexicographic};
use crate::geometry::scale::{self, times_power_of_two};

fn coord(p: DVec2, shift: i32) -> robust::Coord<f64> {
    robust::Coord {
        x: times_power_of_two(p.x, shift),
        y: times_power_of_two(p.y, shift),
    }
}

/// `value` (the predicate of points scaled by 2^shift, of the given degree)
/// scaled back, its sign kept where the magnitude leaves the range of doubles.
fn unscaled(value: f64, shift: i32, degree: i32) -> f64 {
    if value == 0.0 {
        return 0.0;
    }
    let back = times_power_of_two(value, -shift * degree);
    if back == 0.0 && value != 0.0 {
        f64::from_bits(1).copysign(value)
    } else {
        back
    }
}

/// A rational predicate's value as a double, its sign kept.
fn signed_double(exact: &num_rational::BigRational) -> f64 {
    let value = nearest_double(exact);
    if value == 0.0 && !num_traits::Zero::is_zero(exact) {
        f64::from_bits(1).copysign(if num_traits::Signed::is_positive(exact) {
            1.0
        } else {
            -1.0
        })
    } else {
        value
    }
}

/// Positive when a, b, c turn counter-clockwise, negative when clockwise, zero
/// when collinear; its magnitude is about twice the triangle's signed area.
/// The sign is exact at every magnitude of the doubles given.
pub fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    if let Some(det) = orient_filtered(Bound::ORIENT, a, b, c) {
        return det;
    }
    match scale::predicate_exponent(&[a, b, c]).ok() {
        Some(shift) => unscaled(
            robust::orient2d(coord(a, shift), coord(b, shift), coord(c, shift)),
            shift,
            2,
        ),
        None => signed_double(&orient_exact(a, b, c)),
    }
}

/// Positive when `d` lies strictly inside the circle through the
/// counter-clockwise a, b, c; exact at every magnitude, as [`orient`].
pub fn incircle(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> f64 {
    if let Some(det) = incircle_filtered(Bound::INCIRCLE, a, b, c, d) {
        return det;
    }
    match scale::incircle_exponent(&[a, b, c, d]).ok() {
        Some(shift) => {
            let [a, b, c, d] = [a, b, c, d].map(|p| coord(p, shift));
            unscaled(robust::incircle(a, b, c, d), shift, 4)
        }
        None => signed_double(&incircle_exact(a, b, c, d)),
    }
}

/// Shewchuk's first filter of [`orient`], before any scaling: the
/// determinant in doubles where `bound` decides its sign.
pub(super) fn orient_filtered(bound: Bound, a: DVec2, b: DVec2, c: DVec2) -> Option<f64> {
    let (left, right) = ((b.x - a.x) * (c.y - a.y), (b.y - a.y) * (c.x - a.x));
    bound.decides(left - right, left.abs() + right.abs())
}

/// Shewchuk's first filter of [`incircle`].
pub(super) fn incircle_filtered(
    bound: Bound,
    a: DVec2,
    b: DVec2,
    c: DVec2,
    d: DVec2,
) -> Option<f64> {
    let [ad, bd, cd] = [a - d, b - d, c - d];
    let lift = |p: DVec2| p.x * p.x + p.y * p.y;
    let minor = |p: DVec2, q: DVec2| (p.x * q.y - q.x * p.y, (p.x * q.y).abs() + (q.x * p.y).abs());
    let ((bc, bc_m), (ca, ca_m), (ab, ab_m)) = (minor(bd, cd), minor(cd, ad), minor(ad, bd));
    let (la, lb, lc) = (lift(ad), lift(bd), lift(cd));
    let det = la * bc + lb * ca + lc * ab;
    let permanent = la * bc_m + lb * ca_m + lc * ab_m;
    bound.decides(det, permanent)
}

/// The turn of a simple ring (not closed) at its least corner, the first by
/// x then y, where the ring is convex: positive when it runs
/// counter-clockwise, negative when clockwise, with [`orient`]'s exact sign;
/// 0 for fewer than three corners or a ring that folds back there.
pub fn ring_turn(ring: &[DVec2]) -> f64 {
    let n = ring.len();
    if n < 3 {
        return 0.0;
    }
    let least = (0..n)
        .min_by_key(|&k| lexicographic(ring[k]))
        .expect("corners");
    orient(
        ring[(least + n - 1) % n],
        ring[least],
        ring[(least + 1) % n],
    )
}

/// Indices of the convex hull's vertices, counter-clockwise, points on its edges
/// left out (Andrew's monotone chain with exact orientation tests). Duplicates
/// appear once; one or two distinct points are their own hull.
#[expect(
    clippy::disallowed_methods,
    reason = "the hull's vertices, at most the points given"
)]
pub fn convex_hull(points: &[DVec2]) -> Vec<u32> {
    let turn = orient;
    // Akl–Toussaint: points strictly inside the octagon of the extreme points in
    // eight directions are no hull vertices; only the others are sorted.
    let mut octagon: Vec<DVec2> = Vec::new();
    if !points.is_empty() {
        let directions = [
            DVec2::new(1.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
            DVec2::new(-1.0, 1.0),
            DVec2::new(-1.0, 0.0),
            DVec2::new(-1.0, -1.0),
            DVec2::new(0.0, -1.0),
            DVec2::new(1.0, -1.0),
        ];
        for d in directions {
            let p = points
                .iter()
                .copied()
                .max_by(|a, b| a.dot(d).total_cmp(&b.dot(d)))
                .expect("points exist");
            if octagon.last() != Some(&p) && octagon.first() != Some(&p) {
                octagon.push(p);
            }
        }
    }
    let strictly_inside = |p: DVec2| {
        octagon.len() >= 3
            && (0..octagon.len())
                .all(|k| turn(octagon[k], octagon[(k + 1) % octagon.len()], p) > 0.0)
    };
    let outside = (0..points.len() as u32).filter(|&i| !strictly_inside(points[i as usize]));
    let order = distinct_by(points, outside, lexicographic).0;
    if order.len() < 3 {
        return order;
    }
    let turn =
        |o: u32, a: u32, b: u32| turn(points[o as usize], points[a as usize], points[b as usize]);
    let mut hull: Vec<u32> = Vec::with_capacity(2 * order.len());
    for pass in [
        &order[..],
        &order.iter().rev().copied().collect::<Vec<_>>()[..],
    ] {
        let start = hull.len();
        for &i in pass {
            while hull.len() >= start + 2
                && turn(hull[hull.len() - 2], hull[hull.len() - 1], i) <= 0.0
            {
                hull.pop();
            }
            hull.push(i);
        }
        // The last point of each chain starts the other.
        hull.pop();
    }
    hull
}
