//! The float filters in front of the kernel's exact predicates. A predicate
//! evaluates its value in doubles beside a magnitude (the permanent: the same
//! sum with every term's absolute value) and takes the double's sign where
//! the value exceeds its [`Bound`], the forward error of that evaluation;
//! elsewhere it goes on to slower, exact evaluations. Each bound is derived
//! once, here, and a test checks it against the rational path on
//! near-degenerate doubles from 1e-300 to 1e300, and finds a wrong answer
//! where the bound is zero.

use std::cmp::Ordering;

/// The unit roundoff of doubles, 2^-53.
pub(crate) const U: f64 = f64::EPSILON / 2.0;

/// A forward error bound: `factor` u of the magnitude computed beside a
/// value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Bound {
    factor: f64,
}

impl Bound {
    /// Orientation, `(b − a) × (c − a)` as `l − r`: (3 + 16u)u of
    /// `|l| + |r|` (Shewchuk 1997, `ccwerrboundA`).
    pub const ORIENT: Bound = Bound::of(3.0 + 16.0 * U);
    /// In-circle: (10 + 96u)u of the permanent (Shewchuk, `iccerrboundA`).
    pub const INCIRCLE: Bound = Bound::of(10.0 + 96.0 * U);
    /// The power test: each lift within 5u of `x² + y² + |Δw|`, each minor
    /// 4u of `|p s| + |q r|`, each product of the two 10u, and the sum 2u
    /// more.
    pub const POWER_TEST: Bound = Bound::of(16.0);
    /// Two powers `x² + y² − w` compared: each within 5u of `x² + y² + |w|`,
    /// their difference u more, of the two magnitudes' sum.
    pub const POWER_ORDER: Bound = Bound::of(8.0);
    /// `(p − a) · (p − b)`: each difference and product within u, the sum u
    /// more, of `|ux vx| + |uy vy|`, with room.
    pub const DIAMETRAL: Bound = Bound::of(16.0);
    /// A squared distance `x² + y²` of two points' differences: within 4u of
    /// itself; two are compared as each within 16u.
    pub const DISTANCE: Bound = Bound::of(16.0);
    /// Half an orientation, a triangle's area: (3 + 16u)u of `|l| + |r|`,
    /// doubled.
    pub const AREA: Bound = Bound::of(6.0 + 64.0 * U);

    const fn of(factor: f64) -> Self {
        Self { factor }
    }

    /// No bound: every double decides. A test's control, to show that a
    /// bound is needed.
    #[cfg(test)]
    pub const NONE: Bound = Bound::of(0.0);

    /// The bound on the error of a value computed beside `magnitude`.
    pub fn error(self, magnitude: f64) -> f64 {
        self.factor * U * magnitude
    }

    /// `value` where its error cannot change its sign. Magnitudes below
    /// 1e-250 may have lost bits to underflow that the bound does not count,
    /// and overflowed ones say nothing: both go on to exact evaluations.
    pub fn decides(self, value: f64, magnitude: f64) -> Option<f64> {
        let sure =
            magnitude.is_finite() && magnitude > 1e-250 && value.abs() > self.error(magnitude);
        sure.then_some(value)
    }

    /// The sign of `value`, where [`Bound::decides`] it.
    pub fn sign(self, value: f64, magnitude: f64) -> Option<Ordering> {
        self.decides(value, magnitude).map(|v| v.total_cmp(&0.0))
    }

    /// The order of two non-negative values, each within the bound of
    /// itself, where it is clear; both normal (above 2^-900, where their
    /// roundings stay relative) and finite.
    pub fn order(self, x: f64, y: f64) -> Option<Ordering> {
        let normal = |v: f64| v.is_finite() && v >= 2f64.powi(-900);
        let slack = self.factor * U;
        if !(normal(x) && normal(y)) {
            return None;
        }
        if x * (1.0 + slack) < y * (1.0 - slack) {
            return Some(Ordering::Less);
        }
        if y * (1.0 + slack) < x * (1.0 - slack) {
            return Some(Ordering::Greater);
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use std::cmp::Ordering;

    use glam::DVec2;
    use num_rational::BigRational;
    use num_traits::Zero;

    use super::Bound;
    use crate::geometry::exact::next_toward;
    use crate::geometry::exact::{
        circle::{diametral_side_exactly, diametral_side_filtered},
        compare_distances_exactly, incircle_exact, orient_exact,
        power::{
            compare_power_exactly, power_test_exactly, power_test_filtered, PowerEstimate, Weighted,
        },
        predicates::{incircle_filtered, orient_filtered},
        triangle::{area_bounds_within, exact_double_area},
    };

    /// Magnitudes from 1e-300 to 1e300, most not powers of two, and offsets
    /// to 1e15: each base configuration is placed at every one.
    fn placements() -> Vec<(f64, f64)> {
        let scales: [f64; 7] = [1.0, 0.1, 7.0, 1.37e-300, 2.3e-150, 7.7e149, 6.1e299];
        let offsets = [0.0, 1e9 + 0.3, 1e15];
        scales
            .iter()
            .flat_map(|&s| offsets.iter().map(move |&o| (s, o * s.min(1.0))))
            .collect()
    }

    /// `x` moved by `k` ulps.
    fn step(mut x: f64, k: i64) -> f64 {
        for _ in 0..k.unsigned_abs() {
            x = next_toward(x, k as f64 * f64::INFINITY);
        }
        x
    }

    /// Nudges of a coordinate: ulps near a tie, and some far enough that a
    /// filter must decide them.
    fn nudges() -> impl Iterator<Item = (i64, i64)> {
        let near = (-16..=16).flat_map(|i| (-16..=16).map(move |j| (i, j)));
        near.chain(FAR)
    }

    const FAR: [(i64, i64); 3] = [(1 << 12, 0), (0, -(1 << 13)), (1 << 14, 1 << 12)];

    /// Angles around a circle: points rounded onto it lie as near it as
    /// doubles can.
    fn angles() -> impl Iterator<Item = f64> {
        (0..96).map(|k| 0.1 + k as f64 * 0.0653)
    }

    fn sign(r: &BigRational) -> Ordering {
        r.cmp(&BigRational::zero())
    }

    /// Over `cases`, how many the filter decided and how many of those
    /// disagree with the exact answer.
    fn audit<T>(
        cases: &[T],
        filtered: impl Fn(&T) -> Option<Ordering>,
        exact: impl Fn(&T) -> Ordering,
    ) -> (usize, usize) {
        let decided: Vec<(Ordering, &T)> = cases
            .iter()
            .filter_map(|c| filtered(c).map(|o| (o, c)))
            .collect();
        let wrong = decided.iter().filter(|(o, c)| *o != exact(c)).count();
        (decided.len(), wrong)
    }

    /// The bound decides some cases and errs on none; with no bound, some
    /// decision is wrong.
    fn holds<T>(
        cases: &[T],
        bound: Bound,
        filtered: impl Fn(Bound, &T) -> Option<Ordering>,
        exact: impl Fn(&T) -> Ordering,
    ) {
        let (decided, wrong) = audit(cases, |c| filtered(bound, c), &exact);
        assert!(decided > 0, "{bound:?} decided none of {}", cases.len());
        assert_eq!(wrong, 0, "{bound:?} decided {wrong} of {decided} wrongly");
        let (_, unbounded) = audit(cases, |c| filtered(Bound::NONE, c), &exact);
        assert!(unbounded > 0, "without {bound:?} every decision was right");
    }

    /// Points on a line, the first nudged (Shewchuk's example, placed).
    fn near_lines() -> Vec<[DVec2; 3]> {
        let mut cases = Vec::new();
        for (s, o) in placements() {
            let at = |x: f64, y: f64| DVec2::new(x * s + o, y * s + o);
            let (b, c) = (at(12.0, 12.0), at(24.0, 24.0));
            let a = at(0.5, 0.5);
            for (i, j) in nudges() {
                cases.push([DVec2::new(step(a.x, i), step(a.y, j)), b, c]);
            }
        }
        cases
    }

    /// Four points on a circle, the last at many places on it, and nudged.
    fn near_circles() -> Vec<[DVec2; 4]> {
        let mut cases = Vec::new();
        for (s, o) in placements() {
            let on =
                |t: f64| DVec2::new(o + s * (3.1 + 2.7 * t.cos()), o + s * (1.3 + 2.7 * t.sin()));
            let [a, b, c] = [0.03, 2.1, 4.2].map(on);
            for d in angles().map(on) {
                for (i, j) in [(0, 0), (1, 0), (0, -1)].into_iter().chain(FAR) {
                    cases.push([a, b, c, DVec2::new(step(d.x, i), step(d.y, j))]);
                }
            }
        }
        cases
    }

    #[test]
    fn the_orientation_bound_holds_and_is_needed() {
        holds(
            &near_lines(),
            Bound::ORIENT,
            |bound, &[a, b, c]| orient_filtered(bound, a, b, c).map(|v| v.total_cmp(&0.0)),
            |&[a, b, c]| sign(&orient_exact(a, b, c)),
        );
    }

    #[test]
    fn the_in_circle_bound_holds_and_is_needed() {
        holds(
            &near_circles(),
            Bound::INCIRCLE,
            |bound, &[a, b, c, d]| incircle_filtered(bound, a, b, c, d).map(|v| v.total_cmp(&0.0)),
            |&[a, b, c, d]| sign(&incircle_exact(a, b, c, d)),
        );
    }

    #[test]
    fn the_power_test_bound_holds_and_is_needed() {
        // Weights alike (the in-circle test) and weights apart.
        let cases: Vec<[Weighted; 4]> = near_circles()
            .into_iter()
            .enumerate()
            .map(|(k, points)| {
                let weight = |i: usize| match k % 2 {
                    0 => 0.0,
                    _ => (points[i] - points[3]).length_squared() * [0.0, 0.25, 0.5, 0.0][i],
                };
                [0, 1, 2, 3].map(|i| Weighted {
                    at: points[i],
                    weight: weight(i),
                })
            })
            .collect();
        holds(
            &cases,
            Bound::POWER_TEST,
            |bound, &[a, b, c, d]| power_test_filtered(bound, a, b, c, d),
            |&[a, b, c, d]| power_test_exactly(a, b, c, d),
        );
    }

    /// A point and two sites mirrored about it, one nudged.
    fn near_mirrors() -> Vec<[DVec2; 3]> {
        let mut cases = Vec::new();
        for (s, o) in placements() {
            let p = DVec2::new(o + 0.7 * s, o + 0.3 * s);
            let v = DVec2::new(2.9 * s, 1.1 * s);
            let (a, b) = (p + v, p - DVec2::new(-v.y, v.x));
            for (i, j) in nudges() {
                cases.push([p, a, DVec2::new(step(b.x, i), step(b.y, j))]);
            }
        }
        cases
    }

    #[test]
    fn the_power_order_bound_holds_and_is_needed() {
        let weighted = |at: DVec2| Weighted { at, weight: 0.0 };
        holds(
            &near_mirrors(),
            Bound::POWER_ORDER,
            |bound, &[p, a, b]| {
                PowerEstimate::of(p, weighted(a))
                    .compare_within(bound, PowerEstimate::of(p, weighted(b)))
            },
            |&[p, a, b]| compare_power_exactly(p, weighted(a), weighted(b)),
        );
    }

    #[test]
    fn the_distance_bound_holds_and_is_needed() {
        holds(
            &near_mirrors(),
            Bound::DISTANCE,
            |bound, &[p, a, b]| bound.order(p.distance_squared(a), p.distance_squared(b)),
            |&[p, a, b]| compare_distances_exactly(p, a, p, b),
        );
    }

    #[test]
    fn the_diametral_bound_holds_and_is_needed() {
        // Each last point of a circle a b c d, and a diameter of it: the
        // first point and its mirror image (Thales).
        let centre = |[a, b, c, _]: [DVec2; 4]| {
            let (b, c) = (b - a, c - a);
            let (lb, lc) = (b.length_squared(), c.length_squared());
            a + DVec2::new(c.y * lb - b.y * lc, b.x * lc - c.x * lb) / (2.0 * b.perp_dot(c))
        };
        let cases: Vec<[DVec2; 3]> = near_circles()
            .into_iter()
            .map(|points| [points[0], 2.0 * centre(points) - points[0], points[3]])
            .collect();
        holds(
            &cases,
            Bound::DIAMETRAL,
            |bound, &[a, b, p]| diametral_side_filtered(bound, a, b, p),
            |&[a, b, p]| diametral_side_exactly(a, b, p),
        );
    }

    #[test]
    fn the_area_bound_holds_and_is_needed() {
        // A triangle and itself turned about its first corner, as near one
        // area as doubles allow, then nudged.
        let mut cases = Vec::new();
        for (s, o) in placements() {
            let at = |x: f64, y: f64| DVec2::new(o + x * s, o + y * s);
            let first = [at(0.1, 0.2), at(3.1, 0.7), at(0.9, 7.2)];
            for t in angles() {
                let turn = |p: DVec2| first[0] + DVec2::from_angle(t).rotate(p - first[0]);
                for (i, j) in [(0, 0), (1, 0), (0, -1)].into_iter().chain(FAR) {
                    let mut sites = [first, first.map(turn)].concat();
                    sites[5] = DVec2::new(step(sites[5].x, i), step(sites[5].y, j));
                    cases.push(sites);
                }
            }
        }
        holds(
            &cases,
            Bound::AREA,
            |bound, sites| {
                let (va, ea) = area_bounds_within(bound, sites, &[0, 1, 2]);
                let (vb, eb) = area_bounds_within(bound, sites, &[3, 4, 5]);
                match () {
                    _ if va + ea < vb - eb => Some(Ordering::Less),
                    _ if vb + eb < va - ea => Some(Ordering::Greater),
                    _ => None,
                }
            },
            |sites| exact_double_area(sites, &[0, 1, 2]).cmp(&exact_double_area(sites, &[3, 4, 5])),
        );
    }
}
