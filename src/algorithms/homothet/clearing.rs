//! The candidate centres of the largest circle clearing points and segments:
//! the vertices of their Voronoi diagram and its crossings with the region's
//! edges, each with the three pieces that determine it, so that
//! the exact kernel (`geometry::exact::clearing`) can decide the best of them
//! exactly.

use glam::DVec2;

use super::quadratic_roots;
use crate::geometry::exact::clearing::{Piece, Vertex};

/// Every centre equidistant (Euclidean) from three of the points and the
/// lines through `lines`, and every point of a `walls` segment equidistant
/// from two of them: with the points themselves and the walls' ends, the
/// candidates for the largest circle clearing points and segments (whose ends
/// are among `points`). Circles through three points are kept when `keep`
/// accepts their radius.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(super) fn clearing_vertices(
    points: &[DVec2],
    lines: &[(DVec2, DVec2)],
    walls: &[(DVec2, DVec2)],
    keep: impl Fn(f64) -> bool,
) -> Vec<Vertex> {
    // A line as unit normal n and offset e: signed distance n·c − e.
    let normal = |(a, b): (DVec2, DVec2)| {
        let n = (b - a).perp().normalize();
        (n, n.dot(a))
    };
    let ls: Vec<(DVec2, f64)> = lines.iter().map(|l| normal(*l)).collect();
    let line = |x: usize, side: f64| Piece::Line(lines[x].0, lines[x].1, side);
    let signs = [1.0, -1.0];
    let mut out = Vec::new();
    // Centres on a line c = c0 + t u with clearance r = r0 + t k that are also at
    // distance r from p.
    let on_line_from_point = |out: &mut Vec<Vertex>,
                              (c0, u): (DVec2, DVec2),
                              (r0, k): (f64, f64),
                              p: DVec2,
                              pieces: [Piece; 3]| {
        let w = c0 - p;
        for t in quadratic_roots(
            u.length_squared() - k * k,
            2.0 * (u.dot(w) - r0 * k),
            w.length_squared() - r0 * r0,
        ) {
            if r0 + t * k >= 0.0 {
                out.push(Vertex::meeting(c0 + u * t, pieces));
            }
        }
    };
    let np = points.len();
    let nl = ls.len();
    for x in 0..np {
        for y in x + 1..np {
            let (p, q) = (points[x], points[y]);
            if p == q {
                continue;
            }
            for &r in &points[y + 1..] {
                if let Some(c) = super::refine::circumcentre(p, q, r) {
                    if keep(c.distance(p)) {
                        let pieces = [Piece::Point(p), Piece::Point(q), Piece::Point(r)];
                        out.push(Vertex::meeting(c, pieces));
                    }
                }
            }
            // Two points and a line: along their bisector.
            let m = (p + q) / 2.0;
            let u = (q - p).perp().normalize();
            for (z, &(n, e)) in ls.iter().enumerate() {
                for s in signs {
                    let pieces = [Piece::Point(p), Piece::Point(q), line(z, s)];
                    let r = (s * (n.dot(m) - e), s * n.dot(u));
                    on_line_from_point(&mut out, (m, u), r, p, pieces);
                }
            }
        }
    }
    for x in 0..nl {
        for y in x + 1..nl {
            let ((n1, e1), (n2, e2)) = (ls[x], ls[y]);
            for s1 in signs {
                for s2 in signs {
                    // s1 (n1·c − e1) = s2 (n2·c − e2): the line A·c = B.
                    let a = s1 * n1 - s2 * n2;
                    let b = s1 * e1 - s2 * e2;
                    if a.length_squared() < 1e-24 {
                        continue;
                    }
                    let c0 = a * (b / a.length_squared());
                    let u = a.perp().normalize();
                    let (r0, k) = (s1 * (n1.dot(c0) - e1), s1 * n1.dot(u));
                    let two = |third: Piece| [line(x, s1), line(y, s2), third];
                    // A point and two lines.
                    for &p in points {
                        on_line_from_point(&mut out, (c0, u), (r0, k), p, two(Piece::Point(p)));
                    }
                    // Three lines: the third equation fixes t.
                    for (z, &(n3, e3)) in ls.iter().enumerate().skip(y + 1) {
                        for s3 in signs {
                            // s3 (n3·(c0 + t u) − e3) = r0 + t k.
                            let slope = s3 * n3.dot(u) - k;
                            if slope.abs() > 1e-12 {
                                let t = (r0 - s3 * (n3.dot(c0) - e3)) / slope;
                                if r0 + t * k >= 0.0 {
                                    out.push(Vertex::meeting(c0 + u * t, two(line(z, s3))));
                                }
                            }
                        }
                    }
                    // Two lines and a wall.
                    for &(wa, wb) in walls {
                        let (nw, ew) = normal((wa, wb));
                        let d = nw.dot(u);
                        if d.abs() > 1e-12 {
                            let c = c0 + u * ((ew - nw.dot(c0)) / d);
                            out.push(Vertex::meeting(c, two(Piece::Wall(wa, wb))));
                        }
                    }
                }
            }
        }
    }
    // On a wall c = a + t (b − a), t in [0, 1]: equidistant from two points, a
    // point and a line, or two lines; and the wall's ends.
    for &(a, b) in walls {
        let d = b - a;
        let wall = Piece::Wall(a, b);
        let inside = |t: f64| (-1e-12..=1.0 + 1e-12).contains(&t);
        let mut on_wall = |t: f64, pieces: [Piece; 3]| {
            if inside(t) {
                out.push(Vertex::meeting(a + d * t, pieces));
            }
        };
        for x in 0..np {
            let u = points[x];
            for &v in &points[x + 1..] {
                let denom = 2.0 * d.dot(v - u);
                if denom != 0.0 {
                    let t = (v.length_squared() - u.length_squared() - 2.0 * a.dot(v - u)) / denom;
                    on_wall(t, [wall, Piece::Point(u), Piece::Point(v)]);
                }
            }
            for (z, &(n, e)) in ls.iter().enumerate() {
                for s in signs {
                    // |a + t d − p|² = (s (n·a − e) + t s n·d)².
                    let (r0, k) = (s * (n.dot(a) - e), s * n.dot(d));
                    let w = a - u;
                    for t in quadratic_roots(
                        d.length_squared() - k * k,
                        2.0 * (d.dot(w) - r0 * k),
                        w.length_squared() - r0 * r0,
                    ) {
                        on_wall(t, [wall, Piece::Point(u), line(z, s)]);
                    }
                }
            }
        }
        for x in 0..nl {
            for y in x + 1..nl {
                let ((n1, e1), (n2, e2)) = (ls[x], ls[y]);
                for s in signs {
                    // n1·(a + t d) − e1 = s (n2·(a + t d) − e2).
                    let slope = n1.dot(d) - s * n2.dot(d);
                    if slope.abs() > 1e-12 {
                        let t = (s * (n2.dot(a) - e2) - (n1.dot(a) - e1)) / slope;
                        on_wall(t, [wall, line(x, 1.0), line(y, s)]);
                    }
                }
            }
        }
    }
    out
}
