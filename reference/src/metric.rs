//! Distances by their definitions, in doubles: the oracles' own, written
//! apart from pixgeo's metrics and sites (which they check). pixgeo's types
//! are read as data only.

use std::f64::consts::{PI, TAU};

use glam::DVec2;
use pixgeo::geometry::{
    metric::Metric,
    site::{Shape, Site},
    Frame,
};

/// The `metric` length of offset `d`.
pub fn distance(metric: Metric, d: DVec2) -> f64 {
    let (x, y) = (d.x.abs(), d.y.abs());
    match metric {
        Metric::L2 => x.hypot(y),
        Metric::L1 => x + y,
        Metric::LInf => x.max(y),
        // (x^p + y^p)^(1/p), the larger coordinate taken out so that no
        // power overflows.
        Metric::Lp(p) => match x.max(y) {
            0.0 => 0.0,
            m => m * (1.0 + (x.min(y) / m).powf(p)).powf(p.recip()),
        },
        Metric::Polygon(g) => gauge(&g.vertices, d),
    }
}

/// A monotone function of [`distance`] that ties where it ties: the squared
/// length for L2, the length otherwise.
pub fn key(metric: Metric, d: DVec2) -> f64 {
    match metric {
        Metric::L2 => d.length_squared(),
        _ => distance(metric, d),
    }
}

/// The gauge of `d` for the polygon of `vertices` (counter-clockwise,
/// star-shaped around the origin): `d`'s ray meets the boundary at `d / λ`.
fn gauge(vertices: &[DVec2], d: DVec2) -> f64 {
    if d == DVec2::ZERO {
        return 0.0;
    }
    let n = vertices.len();
    (0..n)
        .filter_map(|k| {
            let (p, q) = (vertices[k], vertices[(k + 1) % n]);
            // The edge p q holds the point t d: t (d × e) = p × e for e = q − p.
            let e = q - p;
            let t = p.perp_dot(e) / d.perp_dot(e);
            let on = (t * d - p).dot(e) / e.length_squared();
            (t > 0.0 && (-1e-12..=1.0 + 1e-12).contains(&on)).then(|| t.recip())
        })
        .fold(f64::NAN, f64::min)
}

/// Bounds `(a, b)` with `a |d| <= distance(d) <= b |d|` (Euclidean |d|).
pub fn euclidean_bounds(metric: Metric) -> (f64, f64) {
    let sqrt2 = 2f64.sqrt();
    match metric {
        Metric::L2 => (1.0, 1.0),
        Metric::L1 => (1.0, sqrt2),
        Metric::LInf => (sqrt2.recip(), 1.0),
        // Between the diagonal's 2^(1/p − 1/2) and the axes' 1.
        Metric::Lp(p) => {
            let diagonal = 2f64.powf(p.recip() - 0.5);
            (diagonal.min(1.0), diagonal.max(1.0))
        }
        // The boundary lies between the nearest edge and the farthest vertex.
        Metric::Polygon(g) => {
            let v = &g.vertices;
            let far = v.iter().map(|p| p.length()).fold(0.0, f64::max);
            let near = (0..v.len())
                .map(|k| segment_distance(DVec2::ZERO, v[k], v[(k + 1) % v.len()]))
                .fold(f64::INFINITY, f64::min);
            (far.recip(), near.recip())
        }
    }
}

/// The centre of pixel `p` of `frame`, in world coordinates.
pub fn to_world(frame: &Frame, p: DVec2) -> DVec2 {
    frame.origin + (p + 0.5) / frame.scale
}

/// The number of pixels of `frame`.
pub fn pixels(frame: &Frame) -> usize {
    frame.width as usize * frame.height as usize
}

/// The Euclidean distance from `q` to the segment `a b`.
fn segment_distance(q: DVec2, a: DVec2, b: DVec2) -> f64 {
    let e = b - a;
    let t = match e.length_squared() {
        0.0 => 0.0,
        l => ((q - a).dot(e) / l).clamp(0.0, 1.0),
    };
    (q - (a + t * e)).length()
}

/// The directions along which the unit ball has a corner: where the distance
/// to a curve can have a cusp.
fn corners(metric: Metric) -> Vec<DVec2> {
    match metric {
        Metric::L1 => vec![DVec2::X, DVec2::Y, -DVec2::X, -DVec2::Y],
        Metric::LInf => vec![
            DVec2::ONE,
            DVec2::new(-1.0, 1.0),
            -DVec2::ONE,
            DVec2::new(1.0, -1.0),
        ],
        Metric::Polygon(g) => g.vertices.clone(),
        Metric::L2 | Metric::Lp(_) => Vec::new(),
    }
}

/// The outward normals of the unit ball's flat sides.
fn faces(metric: Metric) -> Vec<DVec2> {
    match metric {
        Metric::L1 => corners(Metric::LInf),
        Metric::LInf => corners(Metric::L1),
        Metric::Polygon(g) => {
            let v = &g.vertices;
            (0..v.len())
                .map(|k| {
                    let e = v[(k + 1) % v.len()] - v[k];
                    DVec2::new(e.y, -e.x)
                })
                .collect()
        }
        Metric::L2 | Metric::Lp(_) => Vec::new(),
    }
}

/// The angles at which the circle of `radius` around the origin meets a line
/// through `d` along a corner direction of the ball: where `d − x` lies along
/// a corner, the distance from `d` to the circle may have a cusp.
pub fn corner_crossings(metric: Metric, d: DVec2, radius: f64) -> Vec<f64> {
    let mut out = Vec::new();
    for v in corners(metric) {
        // x = r u(a) on the line d + t v: v × (d − x) = 0, so
        // sin(a − φ) = (v × d) / (r |v|) for φ the angle of v.
        let s = v.perp_dot(d) / (radius * v.length());
        if s.abs() <= 1.0 {
            let phi = v.y.atan2(v.x);
            out.extend([phi + s.asin(), phi + PI - s.asin()]);
        }
    }
    out
}

/// Whether angle `a` lies on the arc from `start` counter-clockwise by `span`.
fn on_arc(a: f64, start: f64, span: f64) -> bool {
    span >= TAU || (a - start).rem_euclid(TAU) <= span
}

/// The least `metric` distance from `q` to the segment `a b`: under a
/// polygonal metric, at an end or where `q − x` lies along a corner of the
/// ball (between those the distance is linear); under L_p, convex along the
/// segment, by golden-section search.
fn segment_least(metric: Metric, q: DVec2, a: DVec2, b: DVec2) -> f64 {
    let at = |t: f64| distance(metric, q - (a + t * (b - a)));
    let ends = at(0.0).min(at(1.0));
    if let Metric::Lp(_) = metric {
        let r = (5f64.sqrt() - 1.0) / 2.0;
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..160 {
            let (u, v) = (hi - r * (hi - lo), lo + r * (hi - lo));
            if at(u) <= at(v) {
                hi = v;
            } else {
                lo = u;
            }
        }
        return ends.min(at((lo + hi) / 2.0));
    }
    corners(metric)
        .into_iter()
        .filter_map(|v| {
            // a + t (b − a) on the line q + s v.
            let t = -(a - q).perp_dot(v) / (b - a).perp_dot(v);
            (0.0..=1.0).contains(&t).then(|| at(t))
        })
        .fold(ends, f64::min)
}

/// The `metric` distance from `q` to a site's shape, by its definition:
/// closed forms for points and Euclidean segments and curves; under a
/// polygonal metric, the least over the points where the distance can be
/// least (the ends, the cusps, where a side of the ball touches a curve);
/// under L_p, a golden-section search along segments and `samples` points per
/// turn along curves.
pub fn shape_distance(metric: Metric, shape: Shape, q: DVec2, samples: usize) -> f64 {
    let curve = |center: DVec2, radius: f64, start: f64, span: f64| {
        let v = q - center;
        if metric == Metric::L2 {
            let a = v.y.atan2(v.x);
            if v == DVec2::ZERO || on_arc(a, start, span) {
                return (v.length() - radius).abs();
            }
        }
        let at = |a: f64| distance(metric, v - radius * DVec2::new(a.cos(), a.sin()));
        let touching = faces(metric).into_iter().map(|n| n.y.atan2(n.x));
        let n = match metric {
            Metric::Lp(_) => (samples as f64 * span / TAU).ceil() as usize,
            _ => 0,
        };
        let sampled = (0..=n).map(|k| start + span * k as f64 / n.max(1) as f64);
        touching
            .chain(corner_crossings(metric, v, radius))
            .filter(|&a| on_arc(a, start, span))
            .chain(sampled)
            .chain([start, start + span.min(TAU)])
            .map(at)
            .fold(f64::INFINITY, f64::min)
    };
    match shape {
        Shape::Point(p) => distance(metric, q - p),
        Shape::Segment(a, b) if metric == Metric::L2 => segment_distance(q, a, b),
        Shape::Segment(a, b) => segment_least(metric, q, a, b),
        Shape::Circle { center, radius } => curve(center, radius, 0.0, TAU),
        Shape::Arc {
            center,
            radius,
            start,
            end,
        } => curve(center, radius, start, (end - start).min(TAU)),
    }
}

/// A site's weighted distance from `q`: its shape's distance over its
/// multiplicative weight, plus its additive weight.
pub fn site_distance(metric: Metric, site: &Site, q: DVec2, samples: usize) -> f64 {
    shape_distance(metric, site.shape, q, samples) / site.multiplicative + site.additive
}
