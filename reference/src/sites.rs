//! Nearest general sites (weighted points, segments, circles, arcs) by
//! interval arithmetic on rationals: the pixel centre `origin + (i + 1/2) /
//! scale` and the sites' doubles taken as the rationals they are (world
//! coordinates), each square root bracketed to 2^-128. A float search narrows
//! each pixel to the sites within 1e-7 of the nearest (a site alone there is
//! the nearest); their intervals then name the nearest, or every site that
//! may tie with it.
//!
//! Arcs end at angles: their ends, and which side of them a point lies on,
//! from power series of the cosine and sine to 2^-128.

use std::f64::consts::TAU;

use glam::DVec2;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Signed, ToPrimitive, Zero};
use rayon::prelude::*;

use crate::metric::{site_distance, to_world};
use pixgeo::geometry::{
    metric::Metric,
    site::{Shape, Site},
    Frame,
};

const BITS: u64 = 128;

fn exact(x: f64) -> BigRational {
    BigRational::from_float(x).expect("finite")
}

fn int(k: i64) -> BigRational {
    BigRational::from_integer(k.into())
}

/// A real number known to lie in `[lo, hi]`.
#[derive(Clone, Debug)]
struct Interval {
    lo: BigRational,
    hi: BigRational,
}

impl Interval {
    fn point(r: BigRational) -> Self {
        Self {
            lo: r.clone(),
            hi: r,
        }
    }

    /// √r for r >= 0, to 2^-BITS (exactly where that holds it).
    fn root(r: &BigRational) -> Self {
        let scale = BigInt::from(1) << BITS;
        let scaled = r * BigRational::from_integer(&scale * &scale);
        let s = scaled.floor().to_integer().sqrt();
        let exact = BigRational::from_integer(&s * &s) == scaled;
        Self {
            lo: BigRational::new(s.clone(), scale.clone()),
            hi: BigRational::new(if exact { s } else { s + 1 }, scale),
        }
    }

    fn plus(&self, o: &Self) -> Self {
        Self {
            lo: &self.lo + &o.lo,
            hi: &self.hi + &o.hi,
        }
    }

    fn times(&self, k: &BigRational) -> Self {
        let (a, b) = (&self.lo * k, &self.hi * k);
        if k.is_negative() {
            Self { lo: b, hi: a }
        } else {
            Self { lo: a, hi: b }
        }
    }

    fn shifted(&self, c: &BigRational) -> Self {
        self.plus(&Self::point(c.clone()))
    }

    fn abs(&self) -> Self {
        let zero = BigRational::zero();
        if self.lo >= zero {
            self.clone()
        } else if self.hi <= zero {
            self.times(&int(-1))
        } else {
            Self {
                lo: zero,
                hi: self.hi.clone().max(-self.lo.clone()),
            }
        }
    }

    fn min(self, o: Self) -> Self {
        Self {
            lo: self.lo.min(o.lo),
            hi: self.hi.min(o.hi),
        }
    }
}

type Point = [BigRational; 2];

fn minus(a: &Point, b: &Point) -> Point {
    [&a[0] - &b[0], &a[1] - &b[1]]
}

fn point(p: DVec2) -> Point {
    [exact(p.x), exact(p.y)]
}

fn product(a: &Interval, b: &Interval) -> Interval {
    let products = [&a.lo * &b.lo, &a.lo * &b.hi, &a.hi * &b.lo, &a.hi * &b.hi];
    Interval {
        lo: products.iter().min().expect("four").clone(),
        hi: products.iter().max().expect("four").clone(),
    }
}

/// The rational distance under L1 or L∞ of an exact offset.
fn norm(metric: Metric, d: &Point) -> BigRational {
    let (x, y) = (d[0].abs(), d[1].abs());
    match metric {
        Metric::L1 => x + y,
        _ => x.max(y),
    }
}

/// The distance under `metric` (L1, L2 or L∞) from `q` to the shape.
fn shape_distance(metric: Metric, shape: Shape, q: &Point) -> Interval {
    match shape {
        Shape::Point(p) => offset_distance(metric, &minus(q, &point(p))),
        Shape::Segment(a, b) => {
            let (a, b) = (point(a), point(b));
            let e = minus(&b, &a);
            let o = minus(q, &a);
            let at = |t: &BigRational| [&o[0] - t * &e[0], &o[1] - t * &e[1]];
            let length2 = &e[0] * &e[0] + &e[1] * &e[1];
            if length2.is_zero() {
                return offset_distance(metric, &o);
            }
            if metric == Metric::L2 {
                // The nearest point, by projection clamped to the segment.
                let t = ((&o[0] * &e[0] + &o[1] * &e[1]) / &length2).clamp(int(0), int(1));
                return offset_distance(metric, &at(&t));
            }
            // Piecewise linear along the segment: ends and kinks.
            let mut ts = vec![int(0), int(1)];
            let kinks: &[(i64, i64)] = if metric == Metric::L1 {
                &[(1, 0), (0, 1)]
            } else {
                &[(1, 1), (1, -1)]
            };
            for &(kx, ky) in kinks {
                // The offset's projection on (ky, -kx) vanishes: x ky = y kx.
                let den = &e[0] * int(ky) - &e[1] * int(kx);
                if !den.is_zero() {
                    let t = (&o[0] * int(ky) - &o[1] * int(kx)) / den;
                    if t > int(0) && t < int(1) {
                        ts.push(t);
                    }
                }
            }
            let best = ts.iter().map(|t| norm(metric, &at(t))).min().expect("ends");
            Interval::point(best)
        }
        Shape::Circle { center, radius } => curve(metric, q, center, radius, None),
        Shape::Arc {
            center,
            radius,
            start,
            end,
        } => curve(metric, q, center, radius, Some((start, end))),
    }
}

fn offset_distance(metric: Metric, d: &Point) -> Interval {
    match metric {
        Metric::L2 => Interval::root(&(&d[0] * &d[0] + &d[1] * &d[1])),
        _ => Interval::point(norm(metric, d)),
    }
}

/// The distance to a circle, or the arc of it from `start` to `end`: under L2
/// along the ray from the centre; under L1 and L∞ the least over the points
/// where the offset is parallel to a corner of the unit ball and where a side
/// of the ball touches the circle; and the arc's ends.
fn curve(
    metric: Metric,
    q: &Point,
    center: DVec2,
    radius: f64,
    arc: Option<(f64, f64)>,
) -> Interval {
    let (c, r) = (point(center), exact(radius));
    let e = minus(q, &c);
    let ef = DVec2::new(e[0].to_f64().unwrap(), e[1].to_f64().unwrap());
    // Whether direction `v` (from the centre) lies on the arc: its side of
    // each end from the end's cosine and sine to 2^-128 (exact at angle 0).
    let faces = |v: &[Interval; 2]| {
        arc.is_none_or(|(start, end)| {
            let side = |a: f64| {
                let zero = int(0);
                let cross = if a == 0.0 {
                    v[1].clone()
                } else {
                    let ([cos, sin], tail) = cos_sin(a);
                    let widen = |x: BigRational| Interval {
                        lo: &x - &tail,
                        hi: x + &tail,
                    };
                    product(&widen(cos), &v[1]).plus(&product(&widen(sin), &v[0]).times(&int(-1)))
                };
                if cross.lo > zero {
                    std::cmp::Ordering::Greater
                } else if cross.hi < zero {
                    std::cmp::Ordering::Less
                } else {
                    assert!(
                        cross.lo == zero && cross.hi == zero,
                        "a side the oracle cannot tell"
                    );
                    std::cmp::Ordering::Equal
                }
            };
            let after = side(start) != std::cmp::Ordering::Less;
            let before = side(end) != std::cmp::Ordering::Greater;
            end - start >= TAU
                || if end - start <= std::f64::consts::PI {
                    after && before
                } else {
                    after || before
                }
        })
    };
    let r2 = &r * &r;
    let point = |x: &BigRational| Interval::point(x.clone());
    let mut candidates: Vec<(Interval, [Interval; 2])> = Vec::new();
    match metric {
        Metric::L2 => {
            if ef == DVec2::ZERO {
                return Interval::point(r);
            }
            let d = Interval::root(&(&e[0] * &e[0] + &e[1] * &e[1])).shifted(&-&r);
            candidates.push((d.abs(), [point(&e[0]), point(&e[1])]));
        }
        Metric::L1 => {
            for k in 0..2 {
                let rest = &r2 - &e[k] * &e[k];
                if !rest.is_negative() {
                    let root = Interval::root(&rest);
                    for sign in [1, -1] {
                        let d = root.times(&int(-sign)).shifted(&e[1 - k]).abs();
                        let mut at = [point(&e[0]), point(&e[1])];
                        at[1 - k] = root.times(&int(sign));
                        candidates.push((d, at));
                    }
                }
            }
            let h = Interval::root(&(&r2 / int(2)));
            for (sx, sy) in [(1, 1), (1, -1), (-1, 1), (-1, -1)] {
                let x = h.times(&int(-sx)).shifted(&e[0]).abs();
                let y = h.times(&int(-sy)).shifted(&e[1]).abs();
                candidates.push((x.plus(&y), [point(&int(sx)), point(&int(sy))]));
            }
        }
        _ => {
            for sigma in [1, -1] {
                let b = &e[0] + int(sigma) * &e[1];
                let w = &e[0] - int(sigma) * &e[1];
                let d = int(2) * &r2 - &w * &w;
                if !d.is_negative() {
                    let root = Interval::root(&d);
                    for sign in [1, -1] {
                        let t = root
                            .times(&BigRational::new(sign.into(), 2.into()))
                            .shifted(&(&b / int(2)));
                        // The point e - t (1, σ).
                        let at = [
                            t.times(&int(-1)).shifted(&e[0]),
                            t.times(&int(-sigma)).shifted(&e[1]),
                        ];
                        candidates.push((t.abs(), at));
                    }
                }
            }
            for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                let p = [&e[0] - &r * int(dx), &e[1] - &r * int(dy)];
                candidates.push((
                    Interval::point(norm(metric, &p)),
                    [point(&int(dx)), point(&int(dy))],
                ));
            }
        }
    }
    let mut best: Option<Interval> = None;
    for (d, at) in candidates {
        if faces(&at) {
            best = Some(best.map_or(d.clone(), |b| b.min(d)));
        }
    }
    if let Some((start, end)) = arc.filter(|(s, e)| e - s < TAU) {
        for a in [start, end] {
            let d = end_distance(metric, &e, &r, a);
            best = Some(best.map_or(d.clone(), |b| b.min(d)));
        }
    }
    best.expect("a candidate")
}

/// The distance from offset `e` (from the centre) to the circle's point at
/// angle `a`: its cosine and sine summed as power series in rationals to
/// 2^-128, the tail bounded by the first term left out (past |a| the terms
/// shrink and alternate in sign within each series).
fn end_distance(metric: Metric, e: &Point, r: &BigRational, a: f64) -> Interval {
    let (sums, tail) = cos_sin(a);
    // Each coordinate of the offset to the point, widened by the tail.
    let along = |k: usize| {
        let v = &e[k] - r * &sums[k];
        let spread = r * &tail;
        Interval {
            lo: &v - &spread,
            hi: v + spread,
        }
        .abs()
    };
    let (dx, dy) = (along(0), along(1));
    match metric {
        Metric::L1 => dx.plus(&dy),
        Metric::L2 => {
            let squares = |lo: bool| {
                let pick = |i: &Interval| if lo { i.lo.clone() } else { i.hi.clone() };
                pick(&dx) * pick(&dx) + pick(&dy) * pick(&dy)
            };
            Interval {
                lo: Interval::root(&squares(true)).lo,
                hi: Interval::root(&squares(false)).hi,
            }
        }
        _ => Interval {
            lo: dx.lo.clone().max(dy.lo.clone()),
            hi: dx.hi.max(dy.hi),
        },
    }
}

/// A cosine and sine, and a bound on their errors.
type CosSin = ([BigRational; 2], BigRational);

/// The cosine and sine of `a` to 2^-128 and the bound on their tails,
/// remembered: every pixel near an arc asks for its ends.
fn cos_sin(a: f64) -> CosSin {
    use std::{collections::HashMap, sync::Mutex};
    static KNOWN: Mutex<Option<HashMap<u64, CosSin>>> = Mutex::new(None);
    if let Some(known) = KNOWN
        .lock()
        .unwrap()
        .as_ref()
        .and_then(|m| m.get(&a.to_bits()).cloned())
    {
        return known;
    }
    let x = exact(a);
    let tolerance = BigRational::new(1.into(), BigInt::from(1) << BITS);
    let (mut sums, mut term, mut n) = ([int(0), int(0)], int(1), 0i64);
    while int(n) <= x.abs() || term.abs() >= tolerance {
        let sign = if n % 4 < 2 { 1 } else { -1 };
        sums[(n % 2) as usize] += &term * int(sign);
        n += 1;
        term = term * &x / int(n);
    }
    // Rounded to 2^-(BITS + 20), the rounding added to the tail, so that
    // every pixel's arithmetic stays small.
    let grain = BigInt::from(1) << (BITS + 20);
    let rounded = sums.map(|v| {
        BigRational::new(
            (v * BigRational::from_integer(grain.clone()))
                .floor()
                .to_integer(),
            grain.clone(),
        )
    });
    let found = (rounded, term.abs() + BigRational::new(1.into(), grain));
    KNOWN
        .lock()
        .unwrap()
        .get_or_insert_with(HashMap::new)
        .insert(a.to_bits(), found.clone());
    found
}

/// Every pixel's sites that may be nearest, by their weighted distance, as
/// intervals to 2^-128 show: one where it is certainly nearest, more where
/// they are equally near to that precision. Metrics L1, L2 and L∞.
pub fn nearest_general_sites(sites: &[Site], frame: &Frame, metric: Metric) -> Vec<Vec<u32>> {
    let (w, h) = (frame.width as usize, frame.height as usize);
    let half = BigRational::new(1.into(), 2.into());
    (0..w * h)
        .into_par_iter()
        .map(|k| {
            let (i, j) = ((k % w) as i64, (k / w) as i64);
            let centre = |o: f64, i: i64| exact(o) + (int(i) + &half) / exact(frame.scale);
            let q = [centre(frame.origin.x, i), centre(frame.origin.y, j)];
            let world = to_world(frame, DVec2::new(i as f64, j as f64));
            let floats: Vec<f64> = sites
                .iter()
                .map(|s| site_distance(metric, s, world, 0))
                .collect();
            let least = floats.iter().copied().fold(f64::INFINITY, f64::min);
            // Far beyond the doubles' errors (a few ulps of the sizes):
            // a site alone within it is the nearest.
            let tolerance = 1e-7 * (1.0 + least.abs());
            let close: Vec<usize> = (0..sites.len())
                .filter(|&s| floats[s] <= least + tolerance)
                .collect();
            if let [only] = close[..] {
                return vec![only as u32];
            }
            let near: Vec<(u32, Interval)> = close
                .into_iter()
                .map(|s| {
                    let site = &sites[s];
                    let d = shape_distance(metric, site.shape, &q)
                        .times(&exact(site.multiplicative).recip())
                        .shifted(&exact(site.additive));
                    (s as u32, d)
                })
                .collect();
            let best_hi = near
                .iter()
                .map(|(_, d)| d.hi.clone())
                .min()
                .expect("a site");
            near.into_iter()
                .filter(|(_, d)| d.lo <= best_hi)
                .map(|(s, _)| s)
                .collect()
        })
        .collect()
}
