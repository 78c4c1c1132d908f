//! Nearest sites in exact rational arithmetic: the pixel centre
//! `origin + (i + 1/2) / scale` and the sites' doubles taken as the rationals
//! they are, every metric's key compared without rounding. A float search
//! narrows each pixel to the sites within a generous tolerance of the nearest;
//! those are then ranked exactly.

use glam::DVec2;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{pow, Signed};
use rayon::prelude::*;

use crate::metric::{distance, pixels};
use pixgeo::geometry::{metric::Metric, Frame};

fn exact(x: f64) -> BigRational {
    BigRational::from_float(x).expect("finite")
}

/// The exact key of the offset from `site` to the centre of pixel `(i, j)`:
/// the squared distance for L2, Σ|d|^p for integer p, the distance for L1,
/// L∞ and polygons. Panics for other metrics: no rational holds their
/// distances.
pub fn exact_key(frame: &Frame, metric: Metric, site: DVec2, i: u32, j: u32) -> BigRational {
    let half = BigRational::new(BigInt::from(1), BigInt::from(2));
    let centre = |o: f64, k: u32| {
        exact(o) + (BigRational::from_integer(k.into()) + &half) / exact(frame.scale)
    };
    let (sx, sy) = (
        centre(frame.origin.x, i) - exact(site.x),
        centre(frame.origin.y, j) - exact(site.y),
    );
    if let Metric::Polygon(g) = metric {
        return polygon_gauge(&g.vertices, [sx, sy]);
    }
    let (dx, dy) = (sx.abs(), sy.abs());
    match metric {
        Metric::L2 => &dx * &dx + &dy * &dy,
        Metric::L1 => dx + dy,
        Metric::LInf => dx.max(dy),
        Metric::Lp(p) if p.fract() == 0.0 => pow(dx, p as usize) + pow(dy, p as usize),
        other => panic!("no exact key for {other:?}"),
    }
}

/// The gauge of `d` for the star-shaped polygon of `vertices` (around the
/// origin): 1/λ for the λ > 0 at which λ d meets the boundary, found by
/// solving for the crossing of the ray with each edge.
fn polygon_gauge(vertices: &[DVec2], d: [BigRational; 2]) -> BigRational {
    let zero = BigRational::from_integer(0.into());
    let one = BigRational::from_integer(1.into());
    if d[0] == zero && d[1] == zero {
        return zero;
    }
    let n = vertices.len();
    (0..n)
        .filter_map(|k| {
            let (p, q) = (point(vertices[k]), point(vertices[(k + 1) % n]));
            let e = [&q[0] - &p[0], &q[1] - &p[1]];
            // λ d - s e = p, by Cramer's rule.
            let det = &d[1] * &e[0] - &d[0] * &e[1];
            if det == zero {
                return None;
            }
            let lambda = (&p[1] * &e[0] - &p[0] * &e[1]) / &det;
            let s = (&d[0] * &p[1] - &d[1] * &p[0]) / &det;
            (lambda > zero && s >= zero && s <= one).then(|| one.clone() / lambda)
        })
        .next()
        .expect("a ray from the kernel meets the boundary")
}

/// Pixel `(i, j)`'s sites, nearest first, equal distances by index, with their
/// keys: the `k` nearest, and every site as near as the `k`-th.
pub fn ranked_sites(
    sites: &[DVec2],
    frame: &Frame,
    metric: Metric,
    i: u32,
    j: u32,
    k: usize,
) -> Vec<(u32, Key)> {
    // Measured from the frame's origin, so that far frames keep their
    // digits, in pixels, so that squares of 1e±300 neither overflow nor
    // vanish (every metric scales with its offset).
    let centre = DVec2::new(i as f64, j as f64) + 0.5;
    let places: Vec<DVec2> = sites
        .iter()
        .map(|s| (*s - frame.origin) * frame.scale)
        .collect();
    let float: Vec<f64> = places
        .iter()
        .map(|p| distance(metric, centre - *p))
        .collect();
    let mut sorted = float.clone();
    sorted.sort_by(f64::total_cmp);
    let kth = sorted[k.min(sorted.len()) - 1];
    // Doubles hold the offsets to within this.
    let magnitude = places
        .iter()
        .map(|p| p.abs().max_element())
        .fold(centre.abs().max_element(), f64::max);
    let tolerance = 1e-12 * (magnitude + kth) + 1e-300;
    let mut near: Vec<(u32, f64)> = float
        .iter()
        .enumerate()
        .filter(|(_, d)| **d <= kth + tolerance)
        .map(|(s, d)| (s as u32, *d))
        .collect();
    near.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
    // Floats decide where they are apart by more than their error.
    let apart = near.windows(2).all(|w| w[1].1 - w[0].1 > 2.0 * tolerance);
    if apart {
        return near.into_iter().map(|(s, d)| (s, Key::Float(d))).collect();
    }
    let mut near: Vec<(u32, BigRational)> = near
        .into_iter()
        .map(|(s, _)| (s, exact_key(frame, metric, sites[s as usize], i, j)))
        .collect();
    near.sort_by(|a, b| a.1.cmp(&b.1).then(a.0.cmp(&b.0)));
    let last = near[k.min(near.len()) - 1].1.clone();
    near.retain(|(_, key)| *key <= last);
    near.into_iter()
        .map(|(s, key)| (s, Key::Exact(key)))
        .collect()
}

/// A rank's key: a float where floats sufficed to rank, else exact.
#[derive(Clone, Debug, PartialEq)]
pub enum Key {
    Float(f64),
    Exact(BigRational),
}

/// Every pixel's `k` nearest sites (row-major, `k` to a pixel) and the number
/// of sites exactly as near as its nearest.
pub fn exact_k_nearest(
    sites: &[DVec2],
    frame: &Frame,
    metric: Metric,
    k: usize,
) -> (Vec<u32>, Vec<u32>) {
    let w = frame.width;
    let per_pixel: Vec<(Vec<u32>, u32)> = (0..pixels(frame) as u32)
        .into_par_iter()
        .map(|p| {
            let ranked = ranked_sites(sites, frame, metric, p % w, p / w, k);
            let ties = ranked.iter().filter(|(_, key)| *key == ranked[0].1).count() as u32;
            let mut labels: Vec<u32> = ranked.iter().take(k).map(|(s, _)| *s).collect();
            labels.resize(k, u32::MAX);
            (labels, ties)
        })
        .collect();
    let mut labels = Vec::with_capacity(pixels(frame) * k);
    let mut ties = Vec::with_capacity(pixels(frame));
    for (l, t) in per_pixel {
        labels.extend(l);
        ties.push(t);
    }
    (labels, ties)
}

/// Each pixel's Euclidean distance (world units) to the site `labels` names,
/// as the float32 nearest the exact distance (ties to even).
pub fn exact_distances(sites: &[DVec2], frame: &Frame, labels: &[u32]) -> Vec<f32> {
    let w = frame.width;
    labels
        .par_iter()
        .enumerate()
        .map(|(p, &l)| {
            let square = exact_key(
                frame,
                Metric::L2,
                sites[l as usize],
                p as u32 % w,
                p as u32 / w,
            );
            rounded_sqrt(&square)
        })
        .collect()
}

/// The float32 nearest the square root of `square` (ties to even): from the
/// double estimate, stepped to the float32 whose midpoints with its
/// neighbours bracket the root, compared exactly by their squares.
fn rounded_sqrt(square: &BigRational) -> f32 {
    use num_traits::ToPrimitive;
    let mut c = (square.to_f64().unwrap_or(f64::INFINITY).sqrt()) as f32;
    // Is the root beyond the midpoint of a and b (a < b), ties to the even one?
    let beyond = |a: f32, b: f32| {
        let m = exact((a as f64 + b as f64) / 2.0);
        match square.cmp(&(&m * &m)) {
            std::cmp::Ordering::Equal => a.to_bits() % 2 == 1,
            order => order == std::cmp::Ordering::Greater,
        }
    };
    loop {
        let (down, up) = (
            f32::from_bits(c.to_bits().wrapping_sub(1)),
            f32::from_bits(c.to_bits() + 1),
        );
        if c > 0.0 && c.is_finite() && !beyond(down, c) {
            c = down;
        } else if up.is_finite() && beyond(c, up) {
            c = up;
        } else {
            return c;
        }
    }
}

fn point(p: DVec2) -> [BigRational; 2] {
    [exact(p.x), exact(p.y)]
}

fn squared_distance(a: &[BigRational; 2], b: &[BigRational; 2]) -> BigRational {
    let (x, y) = (&a[0] - &b[0], &a[1] - &b[1]);
    &x * &x + &y * &y
}

/// The smallest circle holding every point: its exact centre and squared
/// radius.
pub fn smallest_enclosing_circle(points: &[DVec2]) -> ([BigRational; 2], BigRational) {
    smallest_k_enclosing_circle(points, points.len())
}

/// The smallest circle holding at least `k` of the points, by its
/// definition: of the circles centred at a point, on two points as diameter
/// and through three points, each as small as its centre allows (its k-th
/// nearest point on it), the smallest. Its exact centre and squared radius.
pub fn smallest_k_enclosing_circle(points: &[DVec2], k: usize) -> ([BigRational; 2], BigRational) {
    let exact_points: Vec<[BigRational; 2]> = points.iter().map(|p| point(*p)).collect();
    let two = BigRational::from_integer(2.into());
    let mut circles: Vec<[BigRational; 2]> = exact_points.clone();
    for i in 0..points.len() {
        for j in i + 1..points.len() {
            let (a, b) = (&exact_points[i], &exact_points[j]);
            circles.push([(&a[0] + &b[0]) / &two, (&a[1] + &b[1]) / &two]);
            for c in &exact_points[j + 1..] {
                let (bx, by) = (&b[0] - &a[0], &b[1] - &a[1]);
                let (cx, cy) = (&c[0] - &a[0], &c[1] - &a[1]);
                let d = (&bx * &cy - &by * &cx) * &two;
                if d == BigRational::from_integer(0.into()) {
                    continue;
                }
                let (b2, c2) = (&bx * &bx + &by * &by, &cx * &cx + &cy * &cy);
                circles.push([
                    &a[0] + (&cy * &b2 - &by * &c2) / &d,
                    &a[1] + (&bx * &c2 - &cx * &b2) / &d,
                ]);
            }
        }
    }
    circles
        .into_iter()
        .map(|centre| {
            let mut d: Vec<BigRational> = exact_points
                .iter()
                .map(|p| squared_distance(&centre, p))
                .collect();
            d.sort();
            let r2 = d.swap_remove(k - 1);
            (centre, r2)
        })
        .min_by(|a, b| a.1.cmp(&b.1))
        .expect("points")
}

/// Whether `value` is the double nearest to the square root of `square`:
/// the root lies within half an ulp of it.
pub fn is_nearest_root(value: f64, square: &BigRational) -> bool {
    if value == 0.0 {
        return *square == BigRational::from_integer(0.into());
    }
    let ulp = |v: f64| exact(f64::from_bits(v.to_bits() + 1)) - exact(v);
    let half = BigRational::new(1.into(), 2.into());
    let below = exact(value) - ulp(f64::from_bits(value.to_bits() - 1).max(0.0)) * &half;
    let above = exact(value) + ulp(value) * &half;
    let below = if below < BigRational::from_integer(0.into()) {
        BigRational::from_integer(0.into())
    } else {
        below
    };
    &below * &below <= *square && *square <= &above * &above
}

/// Whether `value` is the double nearest to the rational `r`.
pub fn is_nearest(value: f64, r: &BigRational) -> bool {
    if value == 0.0 {
        return r.abs() <= exact(f64::from_bits(1)) / BigRational::from_integer(2.into());
    }
    let next = |v: f64, up: bool| {
        let bits = v.to_bits();
        f64::from_bits(if (v >= 0.0) == up { bits + 1 } else { bits - 1 })
    };
    let half = BigRational::new(1.into(), 2.into());
    let lo = (exact(next(value, false)) + exact(value)) * &half;
    let hi = (exact(next(value, true)) + exact(value)) * &half;
    lo <= *r && *r <= hi
}

/// Whether `value` is the double nearest to w + u √s (u ≠ 0, s >= 0).
pub fn is_nearest_surd(value: f64, w: &BigRational, u: &BigRational, s: &BigRational) -> bool {
    let next = |v: f64, up: bool| {
        let bits = v.to_bits();
        f64::from_bits(if (v >= 0.0) == up { bits + 1 } else { bits - 1 })
    };
    let half = BigRational::new(1.into(), 2.into());
    let zero = BigRational::from_integer(0.into());
    // lo <= w + u √s <= hi, as a <= √s <= b.
    let a = ((exact(next(value, false)) + exact(value)) * &half - w) / u;
    let b = ((exact(next(value, true)) + exact(value)) * &half - w) / u;
    let (a, b) = if *u < zero { (b, a) } else { (a, b) };
    (a < zero || &a * &a <= *s) && b >= zero && *s <= &b * &b
}

/// Twice the exact area of triangle a, b, c.
pub fn double_area(a: DVec2, b: DVec2, c: DVec2) -> BigRational {
    let [a, b, c] = [a, b, c].map(point);
    ((&b[0] - &a[0]) * (&c[1] - &a[1]) - (&b[1] - &a[1]) * (&c[0] - &a[0])).abs()
}

/// Every triple of the smallest (or largest) exact area, and twice that area,
/// by looking at every triple.
pub fn extremal_triangles(points: &[DVec2], largest: bool) -> (Vec<[u32; 3]>, BigRational) {
    let mut best: Option<(Vec<[u32; 3]>, BigRational)> = None;
    let n = points.len() as u32;
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let area = double_area(points[i as usize], points[j as usize], points[k as usize]);
                let order = best.as_ref().map(|b| area.cmp(&b.1));
                match order {
                    Some(std::cmp::Ordering::Equal) => best.as_mut().unwrap().0.push([i, j, k]),
                    Some(o) if (o == std::cmp::Ordering::Greater) != largest => {}
                    _ => best = Some((vec![[i, j, k]], area)),
                }
            }
        }
    }
    best.expect("three points")
}

/// The exact squared distance between two points.
pub fn squared(a: DVec2, b: DVec2) -> BigRational {
    squared_distance(&point(a), &point(b))
}

/// The largest exact squared distance from a point of `a` to a point of `b`.
pub fn max_squared_distance(a: &[DVec2], b: &[DVec2]) -> BigRational {
    a.iter()
        .flat_map(|p| b.iter().map(move |q| squared(*p, *q)))
        .max()
        .expect("points")
}

/// The exact squared directed Hausdorff distance from `a` to `b`.
pub fn directed_hausdorff_squared(a: &[DVec2], b: &[DVec2]) -> BigRational {
    a.iter()
        .map(|p| b.iter().map(|q| squared(*p, *q)).min().expect("points"))
        .max()
        .expect("points")
}

pub fn signed_double_area(a: DVec2, b: DVec2, c: DVec2) -> BigRational {
    let [a, b, c] = [a, b, c].map(point);
    (&b[0] - &a[0]) * (&c[1] - &a[1]) - (&b[1] - &a[1]) * (&c[0] - &a[0])
}

/// Twice the smallest (or largest) exact area of a quadrangle: a diagonal
/// p q with one site strictly on each side, by looking at every choice.
pub fn extremal_quadrangle_double_area(points: &[DVec2], largest: bool) -> Option<BigRational> {
    let zero = BigRational::from_integer(0.into());
    let mut best: Option<BigRational> = None;
    for (p, &a) in points.iter().enumerate() {
        for &b in &points[p + 1..] {
            let sides: Vec<BigRational> = points
                .iter()
                .map(|&c| signed_double_area(a, b, c))
                .collect();
            let left = sides.iter().filter(|s| **s > zero);
            let right: Vec<&BigRational> = sides.iter().filter(|s| **s < zero).collect();
            for l in left {
                for r in &right {
                    let area = l - *r;
                    let better = best
                        .as_ref()
                        .is_none_or(|x| (area > *x) == largest && area != *x);
                    if better {
                        best = Some(area);
                    }
                }
            }
        }
    }
    best
}

/// The corners of the Euclidean Voronoi diagram of the distinct `sites`
/// clipped to the rectangle `[lo, hi]`, exactly: each point of the closed
/// rectangle that is a rectangle corner, a point of a side where the bisector
/// of two nearest sites crosses it, or a point with three or more nearest
/// sites, with its nearest sites. By looking at every triple, pair and corner.
pub fn clipped_voronoi_corners(
    sites: &[DVec2],
    lo: DVec2,
    hi: DVec2,
) -> Vec<([BigRational; 2], Vec<u32>)> {
    clipped_power_corners(sites, &vec![0.0; sites.len()], lo, hi)
}

/// [`clipped_voronoi_corners`] of the power diagram of the distinct `sites`
/// with power `weights`: a point's power from site `s` is `|p - s|² - w`,
/// and its owners are the sites of least power.
pub fn clipped_power_corners(
    sites: &[DVec2],
    weights: &[f64],
    lo: DVec2,
    hi: DVec2,
) -> Vec<([BigRational; 2], Vec<u32>)> {
    let s: Vec<[BigRational; 2]> = sites.iter().map(|&p| point(p)).collect();
    let w: Vec<BigRational> = weights.iter().map(|&x| exact(x)).collect();
    let (lo, hi) = (point(lo), point(hi));
    let two = BigRational::from_integer(2.into());
    let mut candidates: Vec<[BigRational; 2]> = vec![
        [lo[0].clone(), lo[1].clone()],
        [hi[0].clone(), lo[1].clone()],
        [hi[0].clone(), hi[1].clone()],
        [lo[0].clone(), hi[1].clone()],
    ];
    let n = s.len();
    // The radical axis of sites i and j: p . d = c, d = s_j - s_i,
    // c = (|s_j|² - w_j - |s_i|² + w_i) / 2.
    let bisector = |i: usize, j: usize| {
        let d = [&s[j][0] - &s[i][0], &s[j][1] - &s[i][1]];
        let lift = |k: usize| &s[k][0] * &s[k][0] + &s[k][1] * &s[k][1] - &w[k];
        let c = (lift(j) - lift(i)) / &two;
        (d, c)
    };
    for i in 0..n {
        for j in i + 1..n {
            let (d, c) = bisector(i, j);
            for (axis, at) in [(0, &lo[0]), (0, &hi[0]), (1, &lo[1]), (1, &hi[1])] {
                let other = 1 - axis;
                if d[other] != BigRational::from_integer(0.into()) {
                    let mut p = [at.clone(), at.clone()];
                    p[other] = (&c - &d[axis] * at) / &d[other];
                    candidates.push(p);
                }
            }
            for k in j + 1..n {
                let (e, f) = bisector(i, k);
                let det = &d[0] * &e[1] - &d[1] * &e[0];
                if det != BigRational::from_integer(0.into()) {
                    candidates.push([
                        (&c * &e[1] - &f * &d[1]) / &det,
                        (&d[0] * &f - &e[0] * &c) / &det,
                    ]);
                }
            }
        }
    }
    candidates.sort();
    candidates.dedup();
    candidates
        .into_iter()
        .filter(|p| lo[0] <= p[0] && p[0] <= hi[0] && lo[1] <= p[1] && p[1] <= hi[1])
        .filter_map(|p| {
            let d: Vec<BigRational> = s
                .iter()
                .zip(&w)
                .map(|(q, w)| squared_distance(&p, q) - w)
                .collect();
            let nearest = d.iter().min().expect("sites").clone();
            let owners: Vec<u32> = (0..n as u32)
                .filter(|&i| d[i as usize] == nearest)
                .collect();
            let on = [
                p[0] == lo[0] || p[0] == hi[0],
                p[1] == lo[1] || p[1] == hi[1],
            ];
            // On a side, two nearest sites make a corner where their bisector
            // crosses the side: where they differ along it.
            let crossing = |along: usize| {
                owners
                    .iter()
                    .any(|&i| s[i as usize][along] != s[owners[0] as usize][along])
            };
            let corner = match on {
                [true, true] => true,
                [true, false] => crossing(1),
                [false, true] => crossing(0),
                [false, false] => owners.len() >= 3,
            };
            corner.then_some((p, owners))
        })
        .collect()
}
