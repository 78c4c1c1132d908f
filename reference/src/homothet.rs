//! Smallest enclosing and largest empty circles and polygon homothets on the CPU:
//! Welzl's algorithm, and exhaustive searches over every candidate centre that
//! two or three sites (or region edges) determine.

use glam::DVec2;

use rand::{seq::SliceRandom, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A circle in doubles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Circle {
    pub centre: DVec2,
    pub radius: f64,
}

impl Circle {
    fn on_diameter(a: DVec2, b: DVec2) -> Self {
        let centre = (a + b) / 2.0;
        Circle {
            centre,
            radius: a.distance(centre).max(b.distance(centre)),
        }
    }

    /// Holds `p`, with a relative slack for the doubles' rounding.
    fn holds(&self, p: DVec2) -> bool {
        p.distance(self.centre) <= self.radius * (1.0 + 1e-12) + f64::MIN_POSITIVE
    }
}

/// The circle through `a`, `b` and `c` (their circumcircle); `None` on a
/// line.
pub fn through_three(a: DVec2, b: DVec2, c: DVec2) -> Option<Circle> {
    let (u, v) = (b - a, c - a);
    let d = 2.0 * u.perp_dot(v);
    if d == 0.0 {
        return None;
    }
    let (uu, vv) = (u.length_squared(), v.length_squared());
    let centre = a + DVec2::new(v.y * uu - u.y * vv, u.x * vv - v.x * uu) / d;
    let radius = [a, b, c]
        .map(|p| p.distance(centre))
        .into_iter()
        .fold(0.0, f64::max);
    Some(Circle { centre, radius })
}

/// The smallest circle holding every point: Welzl's algorithm in its
/// iterative form (Welzl 1991, three nested passes over the points in a
/// shuffled order), in doubles. Points on a line take the circle on their
/// two farthest as diameter.
pub fn welzl(points: &[DVec2]) -> Circle {
    let mut p = points.to_vec();
    p.shuffle(&mut ChaCha8Rng::seed_from_u64(7));
    let Some(&first) = p.first() else {
        return Circle {
            centre: DVec2::ZERO,
            radius: 0.0,
        };
    };
    let mut c = Circle {
        centre: first,
        radius: 0.0,
    };
    for i in 1..p.len() {
        if c.holds(p[i]) {
            continue;
        }
        c = Circle {
            centre: p[i],
            radius: 0.0,
        };
        for j in 0..i {
            if c.holds(p[j]) {
                continue;
            }
            c = Circle::on_diameter(p[i], p[j]);
            for k in 0..j {
                if c.holds(p[k]) {
                    continue;
                }
                c = through_three(p[i], p[j], p[k]).unwrap_or_else(|| {
                    let pairs = [(p[i], p[j]), (p[i], p[k]), (p[j], p[k])];
                    let (a, b) = pairs
                        .into_iter()
                        .max_by(|x, y| x.0.distance(x.1).total_cmp(&y.0.distance(y.1)))
                        .expect("three pairs");
                    Circle::on_diameter(a, b)
                });
            }
        }
    }
    c
}

/// The k-th smallest of `values` (1-based).
fn kth(mut values: Vec<f64>, k: usize) -> f64 {
    let (_, v, _) = values.select_nth_unstable_by(k - 1, f64::total_cmp);
    *v
}

/// Every centre two or three points determine for circles: midpoints and
/// circumcentres.
fn circle_centres(points: &[DVec2]) -> Vec<DVec2> {
    let n = points.len();
    let mut out = points.to_vec();
    for a in 0..n {
        for b in a + 1..n {
            out.push((points[a] + points[b]) / 2.0);
            for c in b + 1..n {
                if let Some(t) = through_three(points[a], points[b], points[c]) {
                    out.push(t.centre);
                }
            }
        }
    }
    out
}

/// The radius and centre of the smallest circle holding at least `k` points,
/// by trying every circle two or three of them determine: O(n⁴).
pub fn smallest_k_circle(points: &[DVec2], k: usize) -> (DVec2, f64) {
    circle_centres(points)
        .into_iter()
        .map(|c| (c, kth(points.iter().map(|p| p.distance(c)).collect(), k)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("at least one point")
}

/// The gauge-linear pieces and their breaking rays of every site: the planes
/// `a · c + b λ = r` of a polygon's distance, with `(v × e)/(p × q)` the gauge of
/// v in the sector of edge (p, q).
fn polygon_planes(points: &[DVec2], vertices: &[DVec2]) -> Vec<(DVec2, f64, f64)> {
    let n = vertices.len();
    let mut planes = Vec::new();
    for s in points {
        for k in 0..n {
            let (p, q) = (vertices[k], vertices[(k + 1) % n]);
            let e = q - p;
            planes.push((DVec2::new(e.y, -e.x), p.perp_dot(q), s.perp_dot(e)));
            planes.push((DVec2::new(-p.y, p.x), 0.0, p.perp_dot(*s)));
        }
    }
    planes
}

/// Every centre where three planes (or two lines) meet.
fn plane_vertices(planes: &[(DVec2, f64, f64)]) -> Vec<DVec2> {
    let m = planes.len();
    let mut out = Vec::new();
    for x in 0..m {
        for y in x + 1..m {
            let (p, q) = (planes[x], planes[y]);
            let det2 = p.0.perp_dot(q.0);
            if p.1 == 0.0 && q.1 == 0.0 && det2 != 0.0 {
                out.push(DVec2::new(
                    (p.2 * q.0.y - q.2 * p.0.y) / det2,
                    (p.0.x * q.2 - q.0.x * p.2) / det2,
                ));
            }
            for &r in &planes[y + 1..] {
                let mat = glam::DMat3::from_cols(
                    glam::DVec3::new(p.0.x, q.0.x, r.0.x),
                    glam::DVec3::new(p.0.y, q.0.y, r.0.y),
                    glam::DVec3::new(p.1, q.1, r.1),
                );
                if mat.determinant().abs() > 1e-12 {
                    let x = mat.inverse() * glam::DVec3::new(p.2, q.2, r.2);
                    out.push(DVec2::new(x.x, x.y));
                }
            }
        }
    }
    out
}

/// The smallest scale of a homothet of the polygon (star-shaped around the
/// origin, counter-clockwise) holding at least `k` points, and its centre, by
/// trying every centre three of the sites' distance pieces determine.
pub fn smallest_k_homothet(
    points: &[DVec2],
    vertices: &[DVec2],
    gauge: impl Fn(DVec2) -> f64,
    k: usize,
) -> (DVec2, f64) {
    plane_vertices(&polygon_planes(points, vertices))
        .into_iter()
        .chain(points.iter().copied())
        .map(|c| (c, kth(points.iter().map(|p| gauge(*p - c)).collect(), k)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("at least one point")
}

/// The largest scale of an empty homothet whose centre satisfies `allowed`, and
/// its centre, trying every candidate the sites' pieces and the region's
/// `edges` determine, and the edges' ends. `gauge` is the polygon's (or the
/// Euclidean norm with `vertices` empty).
pub fn largest_empty(
    points: &[DVec2],
    vertices: &[DVec2],
    gauge: impl Fn(DVec2) -> f64,
    edges: &[(DVec2, DVec2)],
    allowed: impl Fn(DVec2) -> bool,
) -> (DVec2, f64) {
    let mut lines: Vec<(DVec2, f64, f64)> = edges
        .iter()
        .map(|(a, b)| {
            let n = (*b - *a).perp();
            (n, 0.0, n.dot(*a))
        })
        .collect();
    let mut centres: Vec<DVec2> = edges.iter().flat_map(|(a, b)| [*a, *b]).collect();
    if vertices.is_empty() {
        centres.extend(circle_centres(points));
        for (a, b) in edges {
            for u in points {
                for v in points {
                    let d = *b - *a;
                    let denom = 2.0 * d.dot(*v - *u);
                    if denom != 0.0 {
                        let t = (v.length_squared() - u.length_squared() - 2.0 * a.dot(*v - *u))
                            / denom;
                        centres.push(*a + d * t);
                    }
                }
            }
        }
    } else {
        lines.extend(polygon_planes(points, vertices));
        centres.extend(plane_vertices(&lines));
    }
    centres
        .into_iter()
        .filter(|c| c.is_finite() && allowed(*c))
        .map(|c| (c, kth(points.iter().map(|p| gauge(*p - c)).collect(), 1)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .expect("an allowed candidate")
}
