//! The exact answers behind the pixel candidates of [`super`]: the candidate
//! centres three distance pieces determine, Welzl's algorithm, and a branch and
//! bound for distances without closed-form vertices.

use glam::DVec2;

use super::{candidates, clearing_vertices, kth_gauge, surroundings, Homothet, Unit, Vertex};
use crate::{cancel::Watch, geometry::Frame, Result};

/// Roots of a t² + b t + c = 0 (the one root of the linear equation when a
/// vanishes).
pub(super) fn quadratic_roots(a: f64, b: f64, c: f64) -> Vec<f64> {
    // The coefficients carry different powers of length, so no relative test
    // tells a small `a` from a zero one at every scale: only 0 is linear, and
    // a tiny `a` gives the near root as c / q and a far one that distance
    // filters drop.
    if a == 0.0 {
        return if b != 0.0 {
            Vec::from([-c / b])
        } else {
            Vec::new()
        };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < -1e-12 * b * b {
        return Vec::new();
    }
    let root = disc.max(0.0).sqrt();
    // The stable pair: no cancellation between b and the root.
    let q = -0.5 * (b + b.signum() * root);
    if q == 0.0 {
        return Vec::from([0.0]);
    }
    Vec::from([q / a, c / q])
}

/// Cells a branch and bound may evaluate before it stops with its gap.
const MAX_CELLS: usize = 200_000;

/// The largest value of `exact` over the allowed points of the square of
/// half-side `reach` around `around`, by branch and bound: `bound(c, h)` bounds
/// `exact` from above on the square of half-side h around c, allowed centres
/// give true values, and squares that
/// cannot beat the best or miss the allowed set (`meets(c, r)`: the disc of
/// radius r around c meets it) are dropped, until the gap between the best
/// upper bound and the best value is at most `resolved(best)`. `seed`, an
/// allowed centre and its value, starts the search. Returns the centre, its
/// value, the gap left and the cells evaluated; [`crate::Error::Cancelled`] once the
/// cancel flag ([`crate::cancel`]) is set.
pub(super) fn branch_and_bound(
    around: DVec2,
    reach: f64,
    bound: impl Fn(DVec2, f64) -> f64,
    exact: impl Fn(DVec2) -> f64,
    allowed: impl Fn(DVec2) -> bool,
    meets: impl Fn(DVec2, f64) -> bool,
    (seed, resolved): (Option<(DVec2, f64)>, impl Fn(f64) -> f64),
) -> Result<Option<(DVec2, f64, f64, usize)>> {
    use std::collections::BinaryHeap;
    let watch = Watch::current();
    #[derive(PartialEq)]
    struct Cell(f64, DVec2, f64);
    impl Eq for Cell {}
    impl PartialOrd for Cell {
        fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
            Some(self.cmp(other))
        }
    }
    impl Ord for Cell {
        fn cmp(&self, other: &Self) -> std::cmp::Ordering {
            self.0.total_cmp(&other.0)
        }
    }
    let root2 = std::f64::consts::SQRT_2;
    let mut best: Option<(DVec2, f64)> = seed;
    let mut heap = BinaryHeap::new();
    let mut cells = 0;
    let push = |heap: &mut BinaryHeap<Cell>,
                best: &mut Option<(DVec2, f64)>,
                cells: &mut usize,
                c: DVec2,
                h: f64| {
        *cells += 1;
        if !meets(c, h * root2) {
            return;
        }
        if allowed(c) {
            let v = exact(c);
            if best.is_none_or(|b| v > b.1) {
                *best = Some((c, v));
            }
        }
        heap.push(Cell(bound(c, h), c, h));
    };
    push(&mut heap, &mut best, &mut cells, around, reach);
    while let Some(Cell(upper, c, h)) = heap.pop() {
        if cells % 1024 < 4 {
            watch.check()?;
        }
        let floor = best.map_or(f64::NEG_INFINITY, |b| b.1);
        let gap = upper - floor;
        if gap <= resolved(floor) || cells >= MAX_CELLS {
            return Ok(best.map(|(c, v)| (c, v, gap.max(0.0), cells)));
        }
        let q = h / 2.0;
        for d in [
            DVec2::new(-q, -q),
            DVec2::new(q, -q),
            DVec2::new(-q, q),
            DVec2::new(q, q),
        ] {
            push(&mut heap, &mut best, &mut cells, c + d, q);
        }
    }
    Ok(best.map(|(c, v)| (c, v, 0.0, cells)))
}

/// Groups pixels (row-major indices) into clusters of 8-connected pixels.
#[expect(
    clippy::disallowed_methods,
    reason = "per-pixel values of a picture whose room was reserved where it was placed"
)]
pub(super) fn clusters(frame: &Frame, pixels: &[usize]) -> Vec<Vec<usize>> {
    use std::collections::HashMap;
    let w = frame.width as i64;
    let slot: HashMap<usize, usize> = pixels.iter().enumerate().map(|(k, &p)| (p, k)).collect();
    let mut parent: Vec<usize> = (0..pixels.len()).collect();
    fn root(parent: &mut [usize], mut k: usize) -> usize {
        while parent[k] != k {
            parent[k] = parent[parent[k]];
            k = parent[k];
        }
        k
    }
    for (k, &p) in pixels.iter().enumerate() {
        let (i, j) = (p as i64 % w, p as i64 / w);
        for (di, dj) in [(1, 0), (-1, 1), (0, 1), (1, 1)] {
            let (x, y) = (i + di, j + dj);
            if x < 0 || x >= w || y >= frame.height as i64 {
                continue;
            }
            if let Some(&other) = slot.get(&((y * w + x) as usize)) {
                let (a, b) = (root(&mut parent, k), root(&mut parent, other));
                parent[a] = b;
            }
        }
    }
    let mut groups: HashMap<usize, Vec<usize>> = HashMap::new();
    for (k, &p) in pixels.iter().enumerate() {
        let r = root(&mut parent, k);
        groups.entry(r).or_default().push(p);
    }
    groups.into_values().collect()
}

/// Refines around every cluster of near-extreme pixels and keeps the best.
pub(super) fn best_of_clusters(
    frame: &Frame,
    pixels: &[usize],
    goal: Goal,
    refine: impl Fn(DVec2, f64) -> Option<(DVec2, f64, usize)>,
) -> Option<(DVec2, f64, usize)> {
    let mut best: Option<(DVec2, f64)> = None;
    let mut checked = 0;
    for cluster in clusters(frame, pixels) {
        let (around, reach) = surroundings(frame, &cluster);
        if let Some((c, v, n)) = refine(around, reach) {
            checked += n;
            if goal.improves(v, best.map(|b| b.1)) {
                best = Some((c, v));
            }
        }
    }
    best.map(|(c, v)| (c, v, checked))
}

/// The smallest enclosing circle, exact: Welzl's algorithm on the sites the
/// picture names as far from its centre, repeated with every site it left out
/// until none is.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(super) fn smallest_circle(
    sites: &[DVec2],
    centre: DVec2,
    radius: f64,
    slack: f64,
) -> (Homothet, usize) {
    let mut chosen: Vec<u32> = candidates(sites, |s| s.distance(centre) >= radius - slack);
    let mut rounds = 0;
    loop {
        rounds += 1;
        let points: Vec<DVec2> = chosen.iter().map(|&i| sites[i as usize]).collect();
        let circle = crate::geometry::exact::circle::welzl(&points);
        let missed: Vec<u32> = (0..sites.len() as u32)
            .filter(|&i| !circle.holds(&points, sites[i as usize]))
            .collect();
        if missed.is_empty() {
            let on: Vec<u32> = circle.support.iter().map(|&s| chosen[s]).collect();
            return (
                Homothet {
                    centre: circle.centre.to_array(),
                    scale: circle.radius,
                    sites: on,
                },
                rounds,
            );
        }
        chosen.extend(missed);
    }
}

#[derive(Clone, Copy, PartialEq)]
pub(super) enum Goal {
    Smallest,
    Largest,
}

impl Goal {
    /// Whether `v` beats the best so far.
    fn improves(self, v: f64, best: Option<f64>) -> bool {
        match (best, self) {
            (None, _) => true,
            (Some(b), Goal::Smallest) => v < b,
            (Some(b), Goal::Largest) => v > b,
        }
    }
}

/// A linear equation `a · c + b λ = r` in the centre c and the scale λ.
#[derive(Clone, Copy)]
struct Plane {
    a: DVec2,
    b: f64,
    r: f64,
}

/// The best of the points where three of the distance pieces of the
/// `generators` and the `edges` meet (the pieces a centre within `reach` of
/// `around` can see), with a scale in `window` and `allowed`: bounded by the
/// `near` sites (a superset of the generators: every site that can matter
/// within the reach), then evaluated with `full` over all sites.
#[allow(clippy::too_many_arguments)]
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(super) fn best_vertex(
    sites: &[DVec2],
    unit: Unit,
    around: DVec2,
    reach: f64,
    (near, generators): (&[u32], &[u32]),
    edges: &[(DVec2, DVec2)],
    goal: Goal,
    k: usize,
    window: (f64, f64),
    allowed: impl Fn(DVec2) -> bool,
    full: impl Fn(DVec2) -> f64,
    kept: Option<&mut Vec<(Vertex, f64)>>,
) -> Option<(DVec2, f64, usize)> {
    let in_window = |scale: f64| scale >= window.0 && scale <= window.1;
    let mut planes: Vec<Plane> = Vec::new();
    if let Unit::Polygon(g) = unit {
        // Where the gauge of s − c changes its linear piece matters wherever the
        // objective is not one convex piece-wise maximum: always for the largest
        // empty homothet, and for polygons that are not convex.
        let rays = goal == Goal::Largest || !g.is_convex();
        let n = g.vertices.len();
        for &i in generators {
            let s = sites[i as usize];
            let (from, to) = directions_seen(s, around, reach);
            for k in 0..n {
                let (p, q) = (g.vertices[k], g.vertices[(k + 1) % n]);
                if !sector_meets(p, q, from, to) {
                    continue;
                }
                // In sector k the gauge of v = s − c is (v × e) / (p × q), e = q − p:
                // c · (e.y, −e.x) + (p × q) λ = s × e.
                let e = q - p;
                planes.push(Plane {
                    a: DVec2::new(e.y, -e.x),
                    b: p.perp_dot(q),
                    r: s.perp_dot(e),
                });
                if rays {
                    // The ray s − t p where the piece begins: p × c = p × s.
                    planes.push(Plane {
                        a: DVec2::new(-p.y, p.x),
                        b: 0.0,
                        r: p.perp_dot(s),
                    });
                }
            }
        }
    }
    for (a, b) in edges {
        let n = (*b - *a).perp();
        planes.push(Plane {
            a: n,
            b: 0.0,
            r: n.dot(*a),
        });
    }
    let mut points: Vec<Vertex> = Vec::new();
    match unit {
        Unit::Polygon(_) => {
            let m = planes.len();
            for x in 0..m {
                for y in x + 1..m {
                    for z in y + 1..m {
                        if let Some((c, scale)) = solve3(planes[x], planes[y], planes[z]) {
                            if in_window(scale) {
                                points.push(Vertex::at(c));
                            }
                        }
                    }
                }
                // Two lines meet in a point whose scale is evaluated.
                for y in x + 1..m {
                    if planes[x].b == 0.0 && planes[y].b == 0.0 {
                        if let Some(c) = solve2(planes[x], planes[y]) {
                            points.push(Vertex::at(c));
                        }
                    }
                }
            }
        }
        Unit::Circle => {
            let at: Vec<DVec2> = generators.iter().map(|&i| sites[i as usize]).collect();
            // Circles on two points' diameter (the k-th level's), then every
            // vertex of the points' diagram and its crossings with the edges.
            for (x, p) in at.iter().enumerate() {
                for q in &at[x + 1..] {
                    if in_window(p.distance(*q) / 2.0) {
                        points.push(Vertex::at((*p + *q) / 2.0));
                    }
                }
            }
            points.extend(clearing_vertices(&at, &[], edges, in_window));
        }
    }
    // Sites themselves (the one-site homothet of scale 0) and region corners
    // count as candidate centres.
    points.extend(generators.iter().map(|&i| Vertex::at(sites[i as usize])));
    points.extend(
        edges
            .iter()
            .flat_map(|(a, b)| [Vertex::at(*a), Vertex::at(*b)]),
    );
    // Only centres near the candidate pixels, where the near sites decide.
    points.retain(|v| {
        let c = v.centre;
        c.is_finite() && c.distance(around) <= reach * (1.0 + 1e-9) && allowed(c)
    });
    let checked = points.len();
    let near_points: Vec<DVec2> = near.iter().map(|&i| sites[i as usize]).collect();
    let mut bounded: Vec<(Vertex, f64)> = points
        .into_iter()
        .filter_map(|v| {
            kth_gauge(&near_points, unit, v.centre, k.min(near_points.len())).map(|g| (v, g))
        })
        .collect();
    // The near sites' value bounds the true one: from below for the furthest
    // (all sites), from above for the nearest; for other levels it is the true
    // value near the candidate pixels.
    let exact_k = goal == Goal::Smallest && k < sites.len();
    match goal {
        Goal::Smallest => bounded.sort_by(|a, b| a.1.total_cmp(&b.1)),
        Goal::Largest => bounded.sort_by(|a, b| b.1.total_cmp(&a.1)),
    }
    if let Some(kept) = kept {
        kept.extend(bounded.iter().filter(|b| in_window(b.1)).copied());
    }
    let mut best: Option<(DVec2, f64)> = None;
    for (vertex, bound) in bounded {
        let c = vertex.centre;
        if let Some((_, b)) = best {
            let hopeless = match goal {
                Goal::Smallest => bound >= b,
                Goal::Largest => bound <= b,
            };
            if hopeless {
                break;
            }
        }
        let v = if exact_k { bound } else { full(c) };
        if goal.improves(v, best.map(|b| b.1)) {
            best = Some((c, v));
        }
    }
    best.map(|(c, v)| (c, v, checked))
}

/// The directions (angles, `from` ≤ `to`) in which `s` is seen from the disc of
/// radius `reach` around `c`.
fn directions_seen(s: DVec2, c: DVec2, reach: f64) -> (f64, f64) {
    let v = s - c;
    let d = v.length();
    if d <= reach {
        return (-std::f64::consts::PI, std::f64::consts::PI);
    }
    let mid = v.y.atan2(v.x);
    let half = (reach / d).asin();
    (mid - half, mid + half)
}

/// Whether the sector from direction `p` counter-clockwise to `q` meets the
/// directions `from..=to`.
fn sector_meets(p: DVec2, q: DVec2, from: f64, to: f64) -> bool {
    use std::f64::consts::TAU;
    if to - from >= TAU - 1e-12 {
        return true;
    }
    let a = p.y.atan2(p.x);
    let span = (q.y.atan2(q.x) - a).rem_euclid(TAU);
    // Shift the interval so that it starts within one turn after a.
    let start = (from - a).rem_euclid(TAU);
    let end = start + (to - from);
    start <= span || end >= TAU
}

/// The centre and scale where three planes meet.
fn solve3(p: Plane, q: Plane, r: Plane) -> Option<(DVec2, f64)> {
    let m = glam::DMat3::from_cols(
        glam::DVec3::new(p.a.x, q.a.x, r.a.x),
        glam::DVec3::new(p.a.y, q.a.y, r.a.y),
        glam::DVec3::new(p.b, q.b, r.b),
    );
    let det = m.determinant();
    let size = m
        .x_axis
        .abs()
        .max_element()
        .max(m.y_axis.abs().max_element())
        .max(m.z_axis.abs().max_element());
    if det.abs() <= 1e-12 * size * size * size {
        return None;
    }
    let x = m.inverse() * glam::DVec3::new(p.r, q.r, r.r);
    Some((DVec2::new(x.x, x.y), x.z))
}

fn solve2(p: Plane, q: Plane) -> Option<DVec2> {
    let det = p.a.perp_dot(q.a);
    if det.abs() <= 1e-12 * p.a.length() * q.a.length() {
        return None;
    }
    Some(DVec2::new(
        (p.r * q.a.y - q.r * p.a.y) / det,
        (p.a.x * q.r - q.a.x * p.r) / det,
    ))
}

pub(super) fn circumcentre(a: DVec2, b: DVec2, c: DVec2) -> Option<DVec2> {
    let (b, c) = (b - a, c - a);
    let d = 2.0 * b.perp_dot(c);
    if d == 0.0 {
        return None;
    }
    let (b2, c2) = (b.length_squared(), c.length_squared());
    Some(a + DVec2::new(c.y * b2 - b.y * c2, b.x * c2 - c.x * b2) / d)
}

/// The smallest circle holding at least `k` of `sites`, exactly, given the
/// float search's radius `radius` and the pixels where its centre may lie:
/// around each cluster of them, every circle on two of the sites nearby as a
/// diameter or through three whose float radius is within rounding of
/// `radius` (smaller ones hold fewer sites) is decided in rationals (its
/// centre and squared radius, and the sites it holds, floats where they are
/// clear of the boundary). The least,
/// as the doubles nearest its centre and radius, with the sites exactly on
/// it; `None` where none holds k sites.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(super) fn exact_k_circle(
    sites: &[DVec2],
    k: usize,
    radius: f64,
    frame: &Frame,
    pixels: &[usize],
) -> Option<Homothet> {
    use crate::geometry::exact::circle::ExactCircle;
    let mut best: Option<(ExactCircle, f64)> = None;
    for cluster in clusters(frame, pixels) {
        let (around, reach) = surroundings(frame, &cluster);
        // The float search's radius is within rounding of the optimum's, which
        // is no circle smaller: only circles within it are decided.
        let tol =
            1e-9 * radius + 64.0 * f64::EPSILON * (around.abs().max_element() + reach + radius);
        let limit = radius + tol;
        // Sites a near-optimal circle centred within reach may hold, and of
        // those the ones that may lie on it.
        let held_by: Vec<u32> = (0..sites.len() as u32)
            .filter(|&i| sites[i as usize].distance(around) <= reach + limit)
            .collect();
        let ring: Vec<u32> = held_by
            .iter()
            .copied()
            .filter(|&i| sites[i as usize].distance(around) >= radius - tol - reach)
            .collect();
        let centred = |c: DVec2, r: f64| {
            (radius - tol..=limit).contains(&r) && c.distance(around) <= reach + tol
        };
        let mut circles: Vec<(f64, [u32; 3])> = Vec::new();
        for (a, &i) in ring.iter().enumerate() {
            for (b, &j) in ring.iter().enumerate().skip(a + 1) {
                let (p, q) = (sites[i as usize], sites[j as usize]);
                if centred((p + q) / 2.0, p.distance(q) / 2.0) {
                    circles.push((p.distance(q) / 2.0, [i, j, j]));
                }
                for &l in &ring[b + 1..] {
                    let u = sites[l as usize];
                    if let Some(c) = circumcentre(p, q, u) {
                        if centred(c, c.distance(p)) {
                            circles.push((c.distance(p), [i, j, l]));
                        }
                    }
                }
            }
        }
        circles.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (r, [i, j, l]) in circles {
            if best.as_ref().is_some_and(|b| r > b.1 * (1.0 + 1e-9)) {
                break;
            }
            let (p, q) = (sites[i as usize], sites[j as usize]);
            let circle = match j == l {
                true => ExactCircle::on_diameter(p, q),
                false => match ExactCircle::through(p, q, sites[l as usize]) {
                    Some(circle) => circle,
                    None => continue,
                },
            };
            if best
                .as_ref()
                .is_some_and(|b| b.0.compare_radius(&circle).is_le())
            {
                continue;
            }
            let held = held_by
                .iter()
                .filter(|&&i| circle.holds(sites[i as usize]))
                .count();
            if held >= k {
                best = Some((circle, r));
            }
        }
    }
    let (circle, _) = best?;
    let (centre, radius) = circle.rounded();
    Some(Homothet {
        centre: centre.into(),
        scale: radius,
        sites: (0..sites.len() as u32)
            .filter(|&i| circle.passes_through(sites[i as usize]))
            .collect(),
    })
}
