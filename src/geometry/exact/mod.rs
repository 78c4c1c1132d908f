//! The exact kernel: every number representation pixgeo decides with (the
//! error-free transformations, double-double values with an error bound,
//! rational intervals, surds and rationals) and the predicates and
//! constructions built on them. Algorithms call these by name; no other module
//! computes with rationals.
//!
//! Here: exact arithmetic on the user's doubles, the error-free
//! transformations that tell when a float computation was exact (Knuth's and
//! Dekker's), and rationals for the few comparisons that floats cannot decide.

#![allow(
    clippy::disallowed_types,
    reason = "the kernel is where pixgeo computes with rationals (clippy.toml)"
)]

pub(crate) mod bisector;
pub(crate) mod bounded;
pub(crate) mod cell;
pub mod circle;
pub(crate) mod clearing;
pub(crate) mod distance;
pub(crate) mod filter;
pub(crate) mod mean;
pub(crate) mod number;
pub mod power;
pub(crate) mod precise;
pub mod predicates;
pub(crate) mod site;
pub(crate) mod snap;
pub(crate) mod sphere;
pub(crate) mod surd;
pub(crate) mod triangle;

use glam::DVec2;
use num_bigint::BigInt;
use num_rational::BigRational;
use std::cmp::Ordering;

use num_traits::{Signed, Zero};

use super::{metric::Metric, Frame};
use filter::Bound;

/// `a - b` as `(x, e)` with `x + e == a - b` exactly.
pub(crate) fn two_difference(a: f64, b: f64) -> (f64, f64) {
    let x = a - b;
    let virtual_b = a - x;
    let virtual_a = x + virtual_b;
    (x, (a - virtual_a) + (virtual_b - b))
}

/// `a + b` as `(x, e)` with `x + e == a + b` exactly.
pub(crate) fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let x = a + b;
    let virtual_b = x - a;
    let virtual_a = x - virtual_b;
    (x, (a - virtual_a) + (b - virtual_b))
}

/// `a * b` as `(p, e)` with `p + e == a * b` exactly, unless the product is so
/// small that `e` underflows.
pub(crate) fn two_product(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// Below this, a product's rounding error may underflow and read as zero.
const SMALLEST_EXACT_PRODUCT: f64 = 1e-280;

/// The exact value of a finite double.
pub(crate) fn rational(x: f64) -> BigRational {
    BigRational::from_float(x).expect("a finite double")
}

/// The exact offset from site `site` (world) to the centre of pixel `pixel`,
/// measured in pixels: `s (c - a)` for the centre `c = origin + (pixel + 1/2) / s`
/// of a frame of scale `s`. Every metric is homogeneous, so these offsets order
/// sites as the world's do.
pub(crate) fn pixel_offset(frame: &Frame, site: DVec2, pixel: [i64; 2]) -> [BigRational; 2] {
    let scale = rational(frame.scale);
    let half = BigRational::new(BigInt::from(1), BigInt::from(2));
    let along = |a: f64, o: f64, i: i64| {
        BigRational::from_integer(BigInt::from(i)) + &half - (rational(a) - rational(o)) * &scale
    };
    [
        along(site.x, frame.origin.x, pixel[0]),
        along(site.y, frame.origin.y, pixel[1]),
    ]
}

/// An exact key of `metric` for offset `d`: a monotone function of the distance
/// (the squared distance for L2, Σ |d_i|^p for integer p, a polygon's gauge).
/// `None` where no rational is one: L_p with p not an integer.
pub(crate) fn exact_key(metric: Metric, d: &[BigRational; 2]) -> Option<BigRational> {
    let [x, y] = [d[0].abs(), d[1].abs()];
    match metric {
        Metric::L2 => Some(&x * &x + &y * &y),
        Metric::L1 => Some(x + y),
        Metric::LInf => Some(x.max(y)),
        Metric::Lp(p) if p.fract() == 0.0 && p <= 64.0 => {
            let p = p as i32;
            Some(num_traits::pow(x, p as usize) + num_traits::pow(y, p as usize))
        }
        Metric::Polygon(g) => Some(exact_gauge(&g.vertices, d)),
        Metric::Lp(_) => None,
    }
}

/// The gauge of offset `d` for the polygon of `vertices` (counter-clockwise,
/// star-shaped around the origin), exactly: on the sector of the edge p q
/// that holds d, the linear `(d × (q - p)) / (p × q)`.
#[expect(clippy::disallowed_methods, reason = "the unit ball's corners")]
fn exact_gauge(vertices: &[DVec2], d: &[BigRational; 2]) -> BigRational {
    if d[0].is_zero() && d[1].is_zero() {
        return BigRational::zero();
    }
    let n = vertices.len();
    let cross = |a: &[BigRational; 2], b: &[BigRational; 2]| &a[0] * &b[1] - &a[1] * &b[0];
    let corners: Vec<[BigRational; 2]> = vertices.iter().map(|&v| rational_point(v)).collect();
    let zero = BigRational::zero();
    (0..n)
        .find_map(|k| {
            let (p, q) = (&corners[k], &corners[(k + 1) % n]);
            // The sector from p (inclusive) to q, counter-clockwise.
            (cross(p, d) >= zero && cross(d, q) > zero).then(|| {
                let edge = [&q[0] - &p[0], &q[1] - &p[1]];
                cross(d, &edge) / cross(p, q)
            })
        })
        .expect("a star-shaped polygon's sectors cover every direction")
}

/// The order of offsets `a` and `b` by their L_p distance for a fractional
/// p = m / n (n up to 64, p read as that fraction): for n = 2 exactly, by
/// squaring out the square roots; else each term |d|^(m/n) is bracketed by
/// integer n-th roots at a growing number of bits until the two sums
/// separate. `None` where p is no such fraction, or the sums agree to 4096
/// bits without the offsets being mirror images.
pub(crate) fn lp_order(a: &[BigRational; 2], b: &[BigRational; 2], p: f64) -> Option<Ordering> {
    if mirror_images(a, b) {
        return Some(Ordering::Equal);
    }
    let n = (1..=64u32).find(|&n| (p * n as f64).fract() == 0.0)?;
    let m = (p * n as f64) as u32;
    if n == 2 {
        let s = |x: &BigRational| num_traits::pow(x.abs(), m as usize);
        return Some(root_sums_order([s(&a[0]), s(&a[1])], [s(&b[0]), s(&b[1])]));
    }
    for bits in [64u64, 256, 1024, 4096] {
        let sum = |d: &[BigRational; 2]| {
            d.iter()
                .map(|x| power_bracket(&x.abs(), m, n, bits))
                .fold((BigInt::zero(), BigInt::zero()), |(lo, hi), (l, h)| {
                    (lo + l, hi + h)
                })
        };
        let ((a_lo, a_hi), (b_lo, b_hi)) = (sum(a), sum(b));
        if a_hi <= b_lo {
            return Some(Ordering::Less);
        }
        if b_hi <= a_lo {
            return Some(Ordering::Greater);
        }
    }
    None
}

/// The order of √a0 + √a1 and √b0 + √b1 for rationals at least 0: squared,
/// it is the sign of A + 2√(a0 a1) - 2√(b0 b1) with A = a0 + a1 - b0 - b1,
/// which is negative where A + 2√(a0 a1) is, and else squared once more.
fn root_sums_order(a: [BigRational; 2], b: [BigRational; 2]) -> Ordering {
    let big_a = &a[0] + &a[1] - &b[0] - &b[1];
    let (u, v) = (&a[0] * &a[1], &b[0] * &b[1]);
    let two = BigRational::from_integer(BigInt::from(2));
    let four = BigRational::from_integer(BigInt::from(4));
    if sign_with_root(&big_a, &two, &u) == Ordering::Less {
        return Ordering::Less;
    }
    // (A + 2√u)² - 4v = A² + 4u - 4v + 4A√u.
    let rest = &big_a * &big_a + &four * &u - &four * &v;
    sign_with_root(&rest, &(&four * &big_a), &u)
}

/// The sign of `b + c √u` for a rational `u >= 0`.
pub(crate) fn sign_with_root(b: &BigRational, c: &BigRational, u: &BigRational) -> Ordering {
    let zero = BigRational::zero();
    let sb = b.cmp(&zero);
    let sc = if u.is_zero() {
        Ordering::Equal
    } else {
        c.cmp(&zero)
    };
    if sc == Ordering::Equal {
        return sb;
    }
    if sb == Ordering::Equal || sb == sc {
        return sc;
    }
    // Opposite signs: the larger magnitude wins.
    match (b * b).cmp(&(c * c * u)) {
        Ordering::Greater => sb,
        Ordering::Less => sc,
        Ordering::Equal => Ordering::Equal,
    }
}

/// Integers `lo <= x^(m/n) 2^bits < hi` for a rational `x >= 0`.
fn power_bracket(x: &BigRational, m: u32, n: u32, bits: u64) -> (BigInt, BigInt) {
    let scaled = num_traits::pow(x.clone(), m as usize)
        * BigRational::from_integer(BigInt::from(1) << (bits * n as u64));
    let floor = scaled.floor().to_integer();
    let root = floor.nth_root(n);
    // root^n <= floor <= scaled < floor + 1 <= (root + 1)^n.
    (root.clone(), root + 1)
}

/// The order of exact offsets `a` and `b` by their distance under `metric`:
/// by [`exact_key`], or [`lp_order`] for fractional p; `None` where neither
/// decides.
pub(crate) fn exact_order(
    metric: Metric,
    a: &[BigRational; 2],
    b: &[BigRational; 2],
) -> Option<Ordering> {
    match (exact_key(metric, a), exact_key(metric, b)) {
        (Some(x), Some(y)) => Some(x.cmp(&y)),
        _ => match metric {
            Metric::Lp(p) => lp_order(a, b, p),
            _ => None,
        },
    }
}

/// Whether offsets `a` and `b` are at exactly the same distance for every
/// metric symmetric in its coordinates: equal absolute values, in some order.
pub(crate) fn mirror_images(a: &[BigRational; 2], b: &[BigRational; 2]) -> bool {
    let sorted = |d: &[BigRational; 2]| {
        let (x, y) = (d[0].abs(), d[1].abs());
        if x <= y {
            (x, y)
        } else {
            (y, x)
        }
    };
    sorted(a) == sorted(b)
}

/// The key of `metric` for offset `(dx, dy)` when float arithmetic computes it
/// without rounding; `None` when it might round.
pub(crate) fn exact_float_key(metric: Metric, dx: f64, dy: f64) -> Option<f64> {
    let (x, y) = (dx.abs(), dy.abs());
    match metric {
        Metric::LInf => Some(x.max(y)),
        Metric::L1 => {
            let (s, e) = two_sum(x, y);
            (e == 0.0 && s.is_finite()).then_some(s)
        }
        Metric::L2 => {
            let square = |v: f64| {
                let (p, e) = two_product(v, v);
                (e == 0.0 && (v == 0.0 || p >= SMALLEST_EXACT_PRODUCT)).then_some(p)
            };
            let (s, e) = two_sum(square(x)?, square(y)?);
            (e == 0.0 && s.is_finite()).then_some(s)
        }
        Metric::Lp(_) | Metric::Polygon(_) => None,
    }
}

/// `x` as a double in pixel coordinates, `(x - o) s - 1/2`, with a bound on its
/// error (zero when it is exact).
pub(crate) fn to_pixel_bounded(x: f64, origin: f64, scale: f64) -> (f64, f64) {
    let (q, _, error) = to_pixel_parts(x, origin, scale);
    (q, error)
}

/// [`to_pixel_bounded`] with the signed rest: `(q, rest, bound)`, where the
/// exact value is within `4ε bound` (and a few smallest normals) of
/// `q + rest`.
pub(crate) fn to_pixel_parts(x: f64, origin: f64, scale: f64) -> (f64, f64, f64) {
    let (t, e1) = two_difference(x, origin);
    let (m, e2) = two_product(t, scale);
    let (q, e3) = two_difference(m, 0.5);
    // The exact value is q + e3 + e2 + e1 s; products near underflow lose
    // their error term, so they are bounded instead.
    let tiny = if m != 0.0 && m.abs() < SMALLEST_EXACT_PRODUCT {
        f64::MIN_POSITIVE
    } else {
        0.0
    };
    let error = e3.abs() + e2.abs() + e1.abs() * scale + tiny;
    let error = if error == 0.0 {
        0.0
    } else {
        error * (1.0 + 1e-9) + f64::MIN_POSITIVE
    };
    (q, e3 + e2 + e1 * scale, error)
}

/// The double nearest to `r` (ties to even).
pub(crate) fn nearest_double(r: &BigRational) -> f64 {
    use num_traits::ToPrimitive;
    // num-rational rounds a ratio of big integers to nearest.
    r.to_f64().unwrap_or(f64::NAN)
}

/// The double nearest to the square root of `r >= 0`: an integer square root
/// of r 4^k to at least 110 bits brackets it between s and s + 1 (over 2^k),
/// where no rounding boundary lies strictly inside; their midpoint, unless s
/// is exact, rounds as the root does.
pub(crate) fn nearest_double_sqrt(r: &BigRational) -> f64 {
    if r.is_zero() {
        return 0.0;
    }
    let (n, d) = (r.numer(), r.denom());
    let spare = n.bits() as i64 - d.bits() as i64;
    let k = ((220 - spare).max(0) as u64).div_ceil(2);
    let scaled = n << (2 * k);
    let (m, rest) = (&scaled / d, &scaled % d);
    let s = m.sqrt();
    let exact = rest.is_zero() && &s * &s == m;
    let root = if exact {
        BigRational::new(s, BigInt::from(1) << k)
    } else {
        BigRational::new(s * 2 + 1, BigInt::from(1) << (k + 1))
    };
    nearest_double(&root)
}

/// The exact point `p` as rationals.
pub(crate) fn rational_point(p: DVec2) -> [BigRational; 2] {
    [rational(p.x), rational(p.y)]
}

/// Twice the signed area of triangle a, b, c, exactly.
pub(crate) fn orient_exact(a: DVec2, b: DVec2, c: DVec2) -> BigRational {
    let [a, b, c] = [a, b, c].map(rational_point);
    (&b[0] - &a[0]) * (&c[1] - &a[1]) - (&b[1] - &a[1]) * (&c[0] - &a[0])
}

/// The in-circle determinant of d against a, b, c, exactly: positive when d
/// lies inside the circle through the counter-clockwise a, b, c.
pub(crate) fn incircle_exact(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> BigRational {
    let [a, b, c, d] = [a, b, c, d].map(rational_point);
    let row = |p: &[BigRational; 2]| {
        let (x, y) = (&p[0] - &d[0], &p[1] - &d[1]);
        let lift = &x * &x + &y * &y;
        (x, y, lift)
    };
    let (ax, ay, al) = row(&a);
    let (bx, by, bl) = row(&b);
    let (cx, cy, cl) = row(&c);
    &al * (&bx * &cy - &cx * &by) - &bl * (&ax * &cy - &cx * &ay) + &cl * (&ax * &by - &bx * &ay)
}

/// The centre of the circle through a, b, c, exactly; `None` when they are
/// collinear.
pub(crate) fn circumcentre_exact(a: DVec2, b: DVec2, c: DVec2) -> Option<[BigRational; 2]> {
    let [a, b, c] = [a, b, c].map(rational_point);
    let (bx, by) = (&b[0] - &a[0], &b[1] - &a[1]);
    let (cx, cy) = (&c[0] - &a[0], &c[1] - &a[1]);
    let d = (&bx * &cy - &by * &cx) * BigInt::from(2);
    if d.is_zero() {
        return None;
    }
    let (b2, c2) = (&bx * &bx + &by * &by, &cx * &cx + &cy * &cy);
    Some([
        &a[0] + (&cy * &b2 - &by * &c2) / &d,
        &a[1] + (&bx * &c2 - &cx * &b2) / &d,
    ])
}

/// The squared distance between exact points.
pub(crate) fn distance_squared(a: &[BigRational; 2], b: &[BigRational; 2]) -> BigRational {
    let (x, y) = (&a[0] - &b[0], &a[1] - &b[1]);
    &x * &x + &y * &y
}

/// The order of |a - b| and |c - d|, exactly: floats where their rounding
/// keeps the squared distances apart, rationals where not.
pub(crate) fn compare_distances(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> Ordering {
    let (x, y) = (a.distance_squared(b), c.distance_squared(d));
    Bound::DISTANCE
        .order(x, y)
        .unwrap_or_else(|| compare_distances_exactly(a, b, c, d))
}

pub(super) fn compare_distances_exactly(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> Ordering {
    let exact = |p: DVec2, q: DVec2| distance_squared(&rational_point(p), &rational_point(q));
    exact(a, b).cmp(&exact(c, d))
}

/// |a - b| rounded to the nearest double.
pub(crate) fn nearest_distance(a: DVec2, b: DVec2) -> f64 {
    nearest_double_sqrt(&distance_squared(&rational_point(a), &rational_point(b)))
}

/// The double next to `x` toward `target`.
pub(crate) fn next_toward(x: f64, target: f64) -> f64 {
    if x == target || x.is_nan() {
        return x;
    }
    if x == 0.0 {
        return f64::from_bits(1).copysign(target);
    }
    let bits = x.to_bits();
    if (target > x) == (x > 0.0) {
        f64::from_bits(bits + 1)
    } else {
        f64::from_bits(bits - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn offset(x: i64, y: i64) -> [BigRational; 2] {
        [x, y].map(|v| BigRational::from_integer(BigInt::from(v)))
    }

    #[test]
    fn fractional_powers_order_exactly() {
        // √1 + √4 = √9 + √0: a tie that is no mirror image.
        assert_eq!(
            lp_order(&offset(1, 4), &offset(9, 0), 0.5),
            Some(Ordering::Equal)
        );
        assert_eq!(
            lp_order(&offset(1, 4), &offset(9, 1), 0.5),
            Some(Ordering::Less)
        );
        assert_eq!(
            lp_order(&offset(-4, 1), &offset(1, 4), 1.5),
            Some(Ordering::Equal)
        );
        // 2^1.5 + 2^1.5 = 2^2.5 < 6^1.5: apart by brackets of a third root.
        assert_eq!(
            lp_order(&offset(2, 2), &offset(6, 0), 1.0 / 3.0 * 4.0),
            Some(Ordering::Less)
        );
        // p = 0.7 = 7/10, bracketed: 1 + 1 = 2 · 1 against 2^0.7 ≈ 1.62.
        assert_eq!(
            lp_order(&offset(1, 1), &offset(2, 0), 0.7),
            Some(Ordering::Greater)
        );
        // An irrational-looking p with no small denominator: undecided.
        assert_eq!(
            lp_order(&offset(1, 2), &offset(2, 1), std::f64::consts::E),
            Some(Ordering::Equal)
        );
        assert_eq!(
            lp_order(&offset(1, 3), &offset(2, 1), std::f64::consts::E),
            None
        );
    }
}
