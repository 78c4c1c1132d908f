//! Sibson's interpolant by its definition, in rationals: the Voronoi region
//! a new site at `q` would have (a large box cut by the bisectors of `q` and
//! every site), then the piece of it each site loses (that region cut by the
//! bisectors of the site and every other site), and the area-weighted mean.

use glam::DVec2;
use num_rational::BigRational;
use num_traits::{Signed, Zero};

type Point = [BigRational; 2];

fn exact(x: f64) -> BigRational {
    BigRational::from_float(x).expect("finite")
}

fn point(p: DVec2) -> Point {
    [exact(p.x), exact(p.y)]
}

/// The part of `polygon` where `a · p <= b`.
fn clip(polygon: &[Point], a: &Point, b: &BigRational) -> Vec<Point> {
    let f = |p: &Point| &a[0] * &p[0] + &a[1] * &p[1] - b;
    let mut out = Vec::new();
    for k in 0..polygon.len() {
        let (p, r) = (&polygon[k], &polygon[(k + 1) % polygon.len()]);
        let (fp, fr) = (f(p), f(r));
        if !fp.is_positive() {
            out.push(p.clone());
        }
        if (fp.is_positive() && fr.is_negative()) || (fp.is_negative() && fr.is_positive()) {
            let t = &fp / (&fp - &fr);
            out.push([&p[0] + (&r[0] - &p[0]) * &t, &p[1] + (&r[1] - &p[1]) * &t]);
        }
    }
    out
}

/// Points nearer `s` than `o` (or as near): `2 p · (o - s) <= |o|² - |s|²`.
fn nearer(polygon: &[Point], s: &Point, o: &Point) -> Vec<Point> {
    let two = BigRational::from_integer(2.into());
    let a = [(&o[0] - &s[0]) * &two, (&o[1] - &s[1]) * &two];
    let lift = |p: &Point| &p[0] * &p[0] + &p[1] * &p[1];
    clip(polygon, &a, &(lift(o) - lift(s)))
}

fn area(polygon: &[Point]) -> BigRational {
    let mut twice = BigRational::zero();
    for k in 0..polygon.len() {
        let (p, r) = (&polygon[k], &polygon[(k + 1) % polygon.len()]);
        twice += &p[0] * &r[1] - &p[1] * &r[0];
    }
    twice.abs()
}

/// Sibson's interpolant of `values` at `q`, or `None` where `q`'s region
/// reaches the box `half` around it (outside the hull or on its edge).
/// Repeated sites must carry equal values; `q` at a site gives its value.
pub fn sibson(sites: &[DVec2], values: &[f64], q: DVec2, half: f64) -> Option<BigRational> {
    if let Some(i) = sites.iter().position(|&s| s == q) {
        return Some(exact(values[i]));
    }
    let box_corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let mut region: Vec<Point> = box_corners
        .iter()
        .map(|&(x, y)| point(q + DVec2::new(x, y) * half))
        .collect();
    let bound = region.clone();
    let pq = point(q);
    let points: Vec<Point> = sites.iter().map(|&s| point(s)).collect();
    for s in &points {
        region = nearer(&region, &pq, s);
    }
    let on_box = |p: &Point| {
        p[0] == bound[0][0] || p[0] == bound[1][0] || p[1] == bound[0][1] || p[1] == bound[2][1]
    };
    if region.iter().any(on_box) {
        return None;
    }
    let (mut sum, mut total) = (BigRational::zero(), BigRational::zero());
    for (i, s) in points.iter().enumerate() {
        let mut piece = region.clone();
        for (j, o) in points.iter().enumerate() {
            if j != i && o != s && piece.len() >= 3 {
                piece = nearer(&piece, s, o);
            }
        }
        if points[..i].contains(s) || piece.len() < 3 {
            continue;
        }
        let a = area(&piece);
        sum += &a * exact(values[i]);
        total += a;
    }
    Some(sum / total)
}
