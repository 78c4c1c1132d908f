//! The linear and Sibson interpolants at a point, written once for the
//! exact kernel's two kinds of [`Number`]: double-double values that carry
//! an error bound, which settle the correctly rounded answer almost
//! everywhere, and rationals, which settle the rest exactly.
//!
//! Coordinates are taken relative to the query point `q`; differences of two
//! doubles are exact in both kinds.
//!
//! Sibson's weight of a natural neighbour `a` is the area a new site at `q`
//! steals from `a`'s Voronoi region. That region piece is the polygon
//! `M, h0, C1, ..., Cm, hm`, where `C1..Cm` are the circumcentres of the
//! cavity triangles around `a` (counter-clockwise), `h0` and `hm` are the
//! circumcentres of `q` with `a` and its two neighbours on the cavity's
//! boundary, and `M` is the midpoint of `q` and `a` (on the line through `h0`
//! and `hm`, the bisector of `q` and `a`). Its shoelace sum splits over the
//! cavity triangles, so each triangle adds its own terms; no circumcentre of
//! `q` with an inner edge is needed, so `q` on an inner edge is no special
//! case.

use glam::DVec2;

use super::walk::Triangles;
use crate::geometry::exact::number::Number;

#[derive(Clone)]
pub(crate) struct Point<T> {
    x: T,
    y: T,
}

impl<T: Number> Point<T> {
    /// `p - q`.
    fn relative(p: DVec2, q: DVec2) -> Self {
        Self {
            x: T::difference(p.x, q.x),
            y: T::difference(p.y, q.y),
        }
    }

    fn plus(&self, o: &Self) -> Self {
        Self {
            x: self.x.clone() + o.x.clone(),
            y: self.y.clone() + o.y.clone(),
        }
    }

    fn half(&self) -> Self {
        Self {
            x: self.x.clone() * T::exact(0.5),
            y: self.y.clone() * T::exact(0.5),
        }
    }
}

/// `a × b`.
fn cross<T: Number>(a: &Point<T>, b: &Point<T>) -> T {
    a.x.clone() * b.y.clone() - a.y.clone() * b.x.clone()
}

/// The circumcentre of the origin, `a` and `b` (not collinear).
fn circumcentre<T: Number>(a: &Point<T>, b: &Point<T>) -> Point<T> {
    let la = a.x.clone() * a.x.clone() + a.y.clone() * a.y.clone();
    let lb = b.x.clone() * b.x.clone() + b.y.clone() * b.y.clone();
    let inverse = T::exact(0.5) / cross(a, b);
    Point {
        x: (la.clone() * b.y.clone() - lb.clone() * a.y.clone()) * inverse.clone(),
        y: (lb * a.x.clone() - la * b.x.clone()) * inverse,
    }
}

/// The linear interpolant of triangle `t` at `q` (in it or on its edges):
/// `q`'s barycentric coordinates are the triangles it makes with the edges.
pub(crate) fn linear<T: Number>(q: DVec2, triangles: &Triangles, t: u32, values: &[f64]) -> T {
    let corners = triangles.corners[t as usize];
    let p = triangles
        .corner_points(t)
        .map(|c| Point::<T>::relative(c, q));
    let areas: [T; 3] = std::array::from_fn(|k| cross(&p[(k + 1) % 3], &p[(k + 2) % 3]));
    let mut sum = T::exact(0.0);
    let mut total = T::exact(0.0);
    for k in 0..3 {
        sum = sum + areas[k].clone() * T::exact(values[corners[k] as usize]);
        total = total + areas[k].clone();
    }
    sum / total
}

/// The circumcentre of triangle `t` relative to its first corner: the part
/// of its circumcentre that does not depend on the query point.
pub(crate) fn centre_offset<T: Number>(triangles: &Triangles, t: u32) -> Point<T> {
    let [a, b, c] = triangles.corner_points(t);
    let ab = Point {
        x: T::difference(b.x, a.x),
        y: T::difference(b.y, a.y),
    };
    let ac = Point {
        x: T::difference(c.x, a.x),
        y: T::difference(c.y, a.y),
    };
    circumcentre(&ab, &ac)
}

/// Triangle `t`'s linear interpolant as a plane through its first corner
/// `a`: the slopes `[B, C]` of `v(q) = v(a) + B (q.x - a.x) + C (q.y - a.y)`.
pub(crate) fn slopes<T: Number>(triangles: &Triangles, t: u32, values: &[f64]) -> [T; 2] {
    let corners = triangles.corners[t as usize];
    let [a, b, c] = triangles.corner_points(t);
    let ab = Point::<T>::relative(b, a);
    let ac = Point::<T>::relative(c, a);
    let [va, vb, vc] = corners.map(|k| values[k as usize]);
    let (rise_b, rise_c) = (T::difference(vb, va), T::difference(vc, va));
    let inverse = T::exact(1.0) / cross(&ab, &ac);
    [
        (rise_b.clone() * ac.y.clone() - rise_c.clone() * ab.y.clone()) * inverse.clone(),
        (rise_c * ab.x.clone() - rise_b * ac.x.clone()) * inverse,
    ]
}

/// The linear interpolant of triangle `t` at `q` from its [`slopes`].
pub(crate) fn on_plane<T: Number>(
    q: DVec2,
    triangles: &Triangles,
    t: u32,
    slopes: &[T; 2],
    values: &[f64],
) -> T {
    let a = triangles.corners[t as usize][0];
    let d = Point::<T>::relative(q, triangles.sites[a as usize]);
    T::exact(values[a as usize]) + slopes[0].clone() * d.x + slopes[1].clone() * d.y
}

/// Sibson's interpolant at `q`, strictly inside the hull, given the cavity
/// of triangles whose circumcircles hold `q` and each triangle's
/// [`centre_offset`].
#[expect(clippy::disallowed_methods, reason = "one query's cavity")]
pub(crate) fn sibson<T: Number>(
    q: DVec2,
    triangles: &Triangles,
    cavity: &[u32],
    offset: impl Fn(u32) -> Point<T>,
    values: &[f64],
) -> T {
    let relative = |v: u32| Point::<T>::relative(triangles.sites[v as usize], q);
    let centres: Vec<Point<T>> = cavity
        .iter()
        .map(|&t| relative(triangles.corners[t as usize][0]).plus(&offset(t)))
        .collect();
    // Twice the stolen area of each natural neighbour, by site.
    #[expect(clippy::disallowed_methods, reason = "one query's cavity")]
    let mut stolen: Vec<(u32, T)> = Vec::with_capacity(cavity.len() + 2);
    for (i, &t) in cavity.iter().enumerate() {
        let corners = triangles.corners[t as usize];
        let across = triangles.across(t);
        let p: [Point<T>; 3] = corners.map(relative);
        // The circumcentre of q with each boundary edge, once for the two
        // corners that use it.
        let h: [Option<Point<T>>; 3] = std::array::from_fn(|e| {
            (!cavity.contains(&across[e])).then(|| circumcentre(&p[e], &p[(e + 1) % 3]))
        });
        let centre = &centres[i];
        for k in 0..3 {
            let midpoint = p[k].half();
            let mut area = T::exact(0.0);
            // The edge a -> x it enters by: on the boundary, M -> h0 -> C.
            if let Some(h) = &h[k] {
                area = area + cross(&midpoint, h) + cross(h, centre);
            }
            // The edge y -> a it leaves by: C -> C' inside, else C -> hm -> M.
            let exit = (k + 2) % 3;
            match &h[exit] {
                Some(h) => area = area + cross(centre, h) + cross(h, &midpoint),
                None => {
                    let j = cavity.iter().position(|&u| u == across[exit]);
                    area = area + cross(centre, &centres[j.expect("an inner edge's triangle")]);
                }
            }
            match stolen.iter_mut().find(|(s, _)| *s == corners[k]) {
                Some((_, sum)) => *sum = sum.clone() + area,
                None => stolen.push((corners[k], area)),
            }
        }
    }
    let mut sum = T::exact(0.0);
    let mut total = T::exact(0.0);
    for (a, area) in stolen {
        sum = sum + area.clone() * T::exact(values[a as usize]);
        total = total + area;
    }
    sum / total
}
