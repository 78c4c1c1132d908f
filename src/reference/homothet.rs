//! Smallest enclosing and largest empty circles and polygon homothets on the CPU:
//! Welzl's algorithm, and exhaustive searches over every candidate centre that
//! two or three sites (or region edges) determine.

use glam::DVec2;
use rand::seq::SliceRandom;
use rand_chacha::{rand_core::SeedableRng, ChaCha8Rng};

/// A circle and the indices (into the points given) of the points on it that
/// determine it.
#[derive(Clone, Debug, PartialEq)]
pub struct Circle {
    pub centre: DVec2,
    pub radius: f64,
    pub support: Vec<usize>,
}

impl Circle {
    fn holds(&self, p: DVec2) -> bool {
        p.distance(self.centre) <= self.radius * (1.0 + 1e-12) + 1e-300
    }
}

fn through_two(a: DVec2, b: DVec2, ia: usize, ib: usize) -> Circle {
    let centre = (a + b) / 2.0;
    Circle {
        centre,
        radius: a.distance(centre).max(b.distance(centre)),
        support: vec![ia, ib],
    }
}

fn through_three(p: [DVec2; 3], i: [usize; 3]) -> Circle {
    let (a, b, c) = (p[0], p[1] - p[0], p[2] - p[0]);
    let d = 2.0 * b.perp_dot(c);
    if d == 0.0 {
        // Collinear: the circle on the two farthest apart.
        let pairs = [(0, 1), (0, 2), (1, 2)];
        let (x, y) = pairs
            .into_iter()
            .max_by(|u, v| p[u.0].distance(p[u.1]).total_cmp(&p[v.0].distance(p[v.1])))
            .expect("three pairs");
        return through_two(p[x], p[y], i[x], i[y]);
    }
    let (b2, c2) = (b.length_squared(), c.length_squared());
    let centre = a + DVec2::new(c.y * b2 - b.y * c2, b.x * c2 - c.x * b2) / d;
    let radius = p.iter().map(|q| q.distance(centre)).fold(0.0, f64::max);
    Circle {
        centre,
        radius,
        support: i.to_vec(),
    }
}

/// The smallest circle holding every point (Welzl 1991, iterative
/// move-to-front form, in a fixed random order). Empty input gives radius 0 at
/// the origin.
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
            support: vec![i],
        },
    };
    for i in 1..order.len() {
        if c.holds(p(i)) {
            continue;
        }
        c = Circle {
            centre: p(i),
            radius: 0.0,
            support: vec![order[i]],
        };
        for j in 0..i {
            if c.holds(p(j)) {
                continue;
            }
            c = through_two(p(i), p(j), order[i], order[j]);
            for k in 0..j {
                if !c.holds(p(k)) {
                    c = through_three([p(i), p(j), p(k)], [order[i], order[j], order[k]]);
                }
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
                let t = through_three([points[a], points[b], points[c]], [a, b, c]);
                out.push(t.centre);
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
