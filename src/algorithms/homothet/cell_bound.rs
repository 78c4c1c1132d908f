//! An upper bound on the Euclidean clearance to points and segments over a
//! square, tight where the clearance is a plateau between parallel walls
//! (where a Lipschitz bound can only shrink with the square).

use glam::DVec2;

/// The largest clearance `min_i d_i(x)` to the `points` and `segments` over the
/// square of half-side `h` around `c`, from above (in exact arithmetic; the
/// caller adds rounding). Each distance is convex, so its largest value on the
/// square is at a corner; a segment whose line the square does not cross and
/// whose slab holds the square is an affine distance there, and the least of
/// those affine pieces is concave: its largest value over the square is at a
/// corner, where two pieces cross an edge, or where three meet.
pub(super) fn clearance_over_square(
    points: &[DVec2],
    segments: &[(DVec2, DVec2)],
    c: DVec2,
    h: f64,
) -> f64 {
    let corners = [
        c + DVec2::new(-h, -h),
        c + DVec2::new(h, -h),
        c + DVec2::new(h, h),
        c + DVec2::new(-h, h),
    ];
    let farthest = |d: &dyn Fn(DVec2) -> f64| corners.iter().map(|&x| d(x)).fold(0.0, f64::max);
    let mut bound = points
        .iter()
        .map(|p| farthest(&|x| x.distance(*p)))
        .fold(f64::INFINITY, f64::min);
    // Affine pieces n·x + e.
    let mut planes: Vec<(DVec2, f64)> = Vec::new();
    for &(a, b) in segments {
        let e = b - a;
        let length2 = e.length_squared();
        let affine = (length2 > 0.0)
            .then(|| {
                let n = e.perp() / length2.sqrt();
                let sides = corners.map(|x| n.dot(x - a));
                let along = corners.map(|x| (x - a).dot(e) / length2);
                let one_side = sides.iter().all(|&s| s > 0.0) || sides.iter().all(|&s| s < 0.0);
                let in_slab = along.iter().all(|t| (0.0..=1.0).contains(t));
                (one_side && in_slab).then(|| {
                    let n = if sides[0] > 0.0 { n } else { -n };
                    (n, -n.dot(a))
                })
            })
            .flatten();
        match affine {
            Some(plane) => planes.push(plane),
            None => {
                bound = bound.min(farthest(&|x| {
                    crate::geometry::metric::segment_distance(x, a, b)
                }))
            }
        }
    }
    if planes.is_empty() {
        return bound;
    }
    let lowest = |x: DVec2| {
        planes
            .iter()
            .map(|(n, e)| n.dot(x) + e)
            .fold(f64::INFINITY, f64::min)
    };
    let (lo, hi) = (corners[0], corners[2]);
    let mut best = corners.iter().map(|&x| lowest(x)).fold(f64::MIN, f64::max);
    let mut consider = |x: DVec2| {
        if x.is_finite() && x.cmpge(lo).all() && x.cmple(hi).all() {
            best = best.max(lowest(x));
        }
    };
    for (i, &(n1, e1)) in planes.iter().enumerate() {
        for &(n2, e2) in &planes[i + 1..] {
            // Where the two pieces are equal: m·x = f.
            let (m, f) = (n1 - n2, e2 - e1);
            // Crossing the square's edges.
            if m.x != 0.0 {
                for y in [lo.y, hi.y] {
                    consider(DVec2::new((f - m.y * y) / m.x, y));
                }
            }
            if m.y != 0.0 {
                for x in [lo.x, hi.x] {
                    consider(DVec2::new(x, (f - m.x * x) / m.y));
                }
            }
            // Meeting a third piece.
            for &(n3, e3) in &planes {
                let (m2, f2) = (n1 - n3, e3 - e1);
                let det = m.perp_dot(m2);
                if det != 0.0 {
                    consider(DVec2::new(f * m2.y - m.y * f2, m.x * f2 - f * m2.x) / det);
                }
            }
        }
    }
    bound.min(best)
}
