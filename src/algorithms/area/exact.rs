//! The exact search among the sites the pixels propose: candidates, the
//! degenerate answers, and the neighbours' first guess.

use super::*;

/// The sites a quadrangle's vertices are searched among (the distinct ones;
/// for the largest, the hull's vertices where there are four), and the hull; an
/// error for fewer than four distinct sites or all on a line. The sites are
/// those [`super::in_range`] checked.
pub(crate) fn quadrangle_candidates(
    sites: &[DVec2],
    extreme: Extreme,
) -> Result<(Vec<u32>, Vec<u32>)> {
    let distinct = first_of_each(sites);
    let hull = convex_hull(sites);
    if distinct.len() < 4 {
        return Err(Error::too_few(
            4,
            distinct.len(),
            format!(
                "a quadrangle needs four distinct sites, not all on a line; there are {} distinct",
                distinct.len()
            ),
        ));
    }
    if hull.len() < 3 {
        return Err(Error::degenerate(
            "a quadrangle needs four distinct sites, not all on a line; these lie on one line"
                .into(),
        ));
    }
    let chosen = match extreme {
        Extreme::Largest if hull.len() >= 4 => hull.clone(),
        _ => distinct,
    };
    Ok((chosen, hull))
}

/// The answer when two sites coincide (the smallest triangle) or all sites lie
/// on a line: area 0 either way; an error for fewer than three. The sites are
/// those [`super::in_range`] checked.
pub(crate) fn degenerate_triangle(sites: &[DVec2], extreme: Extreme) -> Result<Option<AreaAnswer>> {
    if sites.len() < 3 {
        return Err(Error::too_few(
            3,
            sites.len(),
            format!("a triangle needs three sites; there are {}", sites.len()),
        ));
    }
    if extreme == Extreme::Smallest {
        if let Some((a, b)) = duplicate_pair(sites, &first_of_each(sites)) {
            let c = (0..sites.len() as u32)
                .find(|&c| c != a && c != b)
                .expect("n >= 3");
            return Ok(Some(decided(
                extreme,
                Vec::from([a, b, c]),
                0.0,
                Decided::Duplicates,
            )));
        }
    }
    let hull = convex_hull(sites);
    if hull.len() < 3 {
        let mut v = hull.clone();
        v.extend(
            (0..sites.len() as u32)
                .filter(|c| !hull.contains(c))
                .take(3 - v.len()),
        );
        return Ok(Some(decided(extreme, v, 0.0, Decided::Collinear)));
    }
    Ok(None)
}

pub(crate) fn decided(extreme: Extreme, sites: Vec<u32>, area: f64, by: Decided) -> AreaAnswer {
    AreaAnswer {
        extreme,
        sites,
        area,
        pixel_area: None,
        roofs: 0,
        bound: None,
        checked: 0,
        shared: 0,
        width: 0,
        height: 0,
        frame: None,
        decided_by: by,
        prepare_ms: 0.0,
        draw_ms: 0.0,
        reduce_ms: 0.0,
        exact_ms: 0.0,
    }
}

/// Two sites at one position, if any.
pub(super) fn duplicate_pair(sites: &[DVec2], distinct: &[u32]) -> Option<(u32, u32)> {
    if distinct.len() == sites.len() {
        return None;
    }
    let mut seen = std::collections::HashMap::new();
    for (i, p) in sites.iter().enumerate() {
        if let Some(&j) = seen.get(&(p.x.to_bits(), p.y.to_bits())) {
            return Some((j, i as u32));
        }
        seen.insert((p.x.to_bits(), p.y.to_bits()), i as u32);
    }
    None
}

/// The vertices sorted counter-clockwise around their centroid, starting at the
/// smallest index.
pub(crate) fn counter_clockwise(sites: &[DVec2], mut v: Vec<u32>) -> Vec<u32> {
    if v.len() == 3 {
        // By the exact orientation: angles round near-collinear triangles.
        let p = |k: usize| sites[v[k] as usize];
        if orient(p(0), p(1), p(2)) < 0.0 {
            v.swap(1, 2);
        }
        let first = (0..3).min_by_key(|&k| v[k]).expect("vertices");
        v.rotate_left(first);
        return v;
    }
    let c = v.iter().map(|&i| sites[i as usize]).sum::<DVec2>() / v.len() as f64;
    v.sort_by(|&a, &b| {
        let angle = |i: u32| {
            let d = sites[i as usize] - c;
            d.y.atan2(d.x)
        };
        angle(a).total_cmp(&angle(b))
    });
    let first = (0..v.len()).min_by_key(|&k| v[k]).expect("vertices");
    v.rotate_left(first);
    v
}

/// Neighbouring sites along rows of square cells (boustrophedon), whose
/// consecutive triples and quadruples are small shapes: the sample of §7.3.3.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(super) fn neighbour_order(points: &[DVec2]) -> Vec<usize> {
    let lo = points.iter().fold(DVec2::INFINITY, |a, p| a.min(*p));
    let hi = points.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
    let extent = (hi - lo).max_element().max(f64::MIN_POSITIVE);
    let cell = extent / (points.len() as f64).sqrt().max(1.0);
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by_cached_key(|&k| {
        let p = points[k] - lo;
        let row = (p.y / cell) as i64;
        let x = (p.x / cell * 1024.0) as i64;
        (row, if row % 2 == 0 { x } else { -x })
    });
    order
}

/// The smallest triangle of consecutive neighbours and its area, and an upper
/// bound on the smallest triangle: that area or the pigeonhole bound (the
/// hull's area over the 2n - h - 2 triangles of any triangulation, at least
/// n - 2), whichever is smaller.
#[expect(clippy::disallowed_methods, reason = "a triangle's three corners")]
pub(super) fn neighbour_triangle(
    sites: &[DVec2],
    chosen: &[u32],
    hull: usize,
) -> ([u32; 3], f64, f64) {
    let points: Vec<DVec2> = chosen.iter().map(|&i| sites[i as usize]).collect();
    let order = neighbour_order(&points);
    let mut best = ([0, 1, 2].map(|k| chosen[order[k]]), f64::INFINITY);
    for w in order.windows(4) {
        for t in [[w[0], w[1], w[2]], [w[0], w[1], w[3]], [w[0], w[2], w[3]]] {
            let area = exact_area(&points, &t.map(|k| k as u32));
            if area < best.1 {
                best = (t.map(|k| chosen[k]), area);
            }
        }
    }
    if order.len() == 3 {
        let t = [order[0], order[1], order[2]];
        best = (
            t.map(|k| chosen[k]),
            exact_area(&points, &t.map(|k| k as u32)),
        );
    }
    let hull_ring = convex_hull(&points);
    let triangles = (2 * points.len()).saturating_sub(hull + 2).max(1);
    let pigeonhole = convex_ring_area(&points, &hull_ring) / triangles as f64;
    // Both rounded to nearest: a bound half an ulp up holds.
    let bound = best.1.min(pigeonhole) * (1.0 + f64::EPSILON);
    (best.0, best.1, bound)
}

/// The smallest quadrangle of four consecutive neighbours, if any is one.
pub(super) fn neighbour_quadrangle(points: &[DVec2]) -> Option<f64> {
    let order = neighbour_order(points);
    let mut best: Option<f64> = None;
    for w in order.windows(4) {
        // The three ways to choose a diagonal among four points.
        for (p, q, a, b) in [(0, 1, 2, 3), (0, 2, 1, 3), (0, 3, 1, 2)] {
            let (p, q) = (points[w[p]], points[w[q]]);
            let (ca, cb) = (orient(p, q, points[w[a]]), orient(p, q, points[w[b]]));
            if ca * cb < 0.0 {
                let area = 0.5 * (ca.abs() + cb.abs());
                if best.is_none_or(|x| area < x) {
                    best = Some(area);
                }
            }
        }
    }
    best
}
