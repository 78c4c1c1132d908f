//! Extremal area triangles and quadrangles by exhaustive search, and the
//! rotational sweep that finds the triangles in O(n² log n).
//!
//! A quadrangle is four sites p, r, q, l (counter-clockwise) whose diagonal pq
//! has l strictly on its left and r strictly on its right: every simple
//! quadrangle has such a diagonal, and its area is the two triangles' sum.

use std::cmp::Ordering;

use glam::DVec2;
use num_rational::BigRational;
use num_traits::{Signed, ToPrimitive, Zero};

use crate::exact::signed_double_area;

/// The sign of a, b, c's exact orientation: 1 counter-clockwise, -1
/// clockwise, 0 on a line.
pub fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    match side_of(a, b, c) {
        Ordering::Greater => 1.0,
        Ordering::Less => -1.0,
        Ordering::Equal => 0.0,
    }
}

/// The area of triangle a, b, c: the exact area, rounded to the nearest
/// double.
pub fn triangle_area(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    let half = BigRational::new(1.into(), 2.into());
    (signed_double_area(a, b, c).abs() * half)
        .to_f64()
        .expect("a finite area")
}

/// Twice the signed area of a, b, c in doubles and a bound on its error
/// (Shewchuk's orientation filter); `None` where the products leave the
/// range the bound holds in.
fn signed_estimate(a: DVec2, b: DVec2, c: DVec2) -> Option<(f64, f64)> {
    let (l, r) = ((b.x - a.x) * (c.y - a.y), (b.y - a.y) * (c.x - a.x));
    let size = l.abs() + r.abs();
    let normal = size == 0.0 || (1e-250..1e250).contains(&size);
    normal.then_some((l - r, 3.4e-16 * size))
}

/// Twice the area of a, b, c in doubles and a bound on its error.
fn estimate(a: DVec2, b: DVec2, c: DVec2) -> Option<(f64, f64)> {
    signed_estimate(a, b, c).map(|(d, e)| (d.abs(), e))
}

/// The side of a → b that c lies on: by the estimate where it tells,
/// exactly where not.
fn side_of(a: DVec2, b: DVec2, c: DVec2) -> Ordering {
    match signed_estimate(a, b, c) {
        Some((d, e)) if d.abs() > e => d.total_cmp(&0.0),
        _ => signed_double_area(a, b, c).cmp(&BigRational::zero()),
    }
}

/// How twice the area of triangle `x` compares with triangle `y`'s: by their
/// estimates where those tell, exactly where not.
fn compare_areas(x: [DVec2; 3], y: [DVec2; 3]) -> Ordering {
    if let (Some((dx, ex)), Some((dy, ey))) =
        (estimate(x[0], x[1], x[2]), estimate(y[0], y[1], y[2]))
    {
        if dx - ex > dy + ey {
            return Ordering::Greater;
        }
        if dx + ex < dy - ey {
            return Ordering::Less;
        }
    }
    let twice = |t: [DVec2; 3]| signed_double_area(t[0], t[1], t[2]).abs();
    twice(x).cmp(&twice(y))
}

/// The best site strictly on each side of the line p → q (left, right): the
/// nearest (`largest` false) or farthest by exact area, the first on a tie,
/// with its triangle's area rounded to the nearest double.
pub fn sides_of(sites: &[DVec2], p: usize, q: usize, largest: bool) -> [Option<(u32, f64)>; 2] {
    let (a, b) = (sites[p], sites[q]);
    let wanted = if largest {
        Ordering::Greater
    } else {
        Ordering::Less
    };
    let mut best: [Option<u32>; 2] = [None, None];
    for (s, &site) in sites.iter().enumerate() {
        let side = match side_of(a, b, site) {
            Ordering::Equal => continue,
            Ordering::Greater => 0,
            Ordering::Less => 1,
        };
        let better = best[side]
            .is_none_or(|t| compare_areas([a, b, site], [a, b, sites[t as usize]]) == wanted);
        if better {
            best[side] = Some(s as u32);
        }
    }
    best.map(|t| t.map(|t| (t, triangle_area(a, b, sites[t as usize]))))
}

/// The smallest (`largest` false) or largest triangle over all triples of
/// sites: its sites and area. `None` for fewer than three sites.
pub fn extremal_triangle(sites: &[DVec2], largest: bool) -> Option<([u32; 3], f64)> {
    let n = sites.len();
    let wanted = if largest {
        Ordering::Greater
    } else {
        Ordering::Less
    };
    let corners = |t: [u32; 3]| t.map(|i| sites[i as usize]);
    let mut best: Option<[u32; 3]> = None;
    for i in 0..n as u32 {
        for j in i + 1..n as u32 {
            for k in j + 1..n as u32 {
                let t = [i, j, k];
                if best.is_none_or(|b| compare_areas(corners(t), corners(b)) == wanted) {
                    best = Some(t);
                }
            }
        }
    }
    best.map(|t| {
        (
            t,
            triangle_area(
                sites[t[0] as usize],
                sites[t[1] as usize],
                sites[t[2] as usize],
            ),
        )
    })
}

/// The smallest or largest quadrangle over all diagonals and sides: its sites
/// counter-clockwise (p, r, q, l) and area. `None` when no diagonal has sites
/// on both sides (all sites on a line).
pub fn extremal_quadrangle(sites: &[DVec2], largest: bool) -> Option<([u32; 4], f64)> {
    let n = sites.len();
    let mut best: Option<([u32; 4], f64)> = None;
    for p in 0..n {
        for q in p + 1..n {
            if let [Some((l, a)), Some((r, b))] = sides_of(sites, p, q, largest) {
                let area = a + b;
                if best.is_none_or(|x| if largest { area > x.1 } else { area < x.1 }) {
                    best = Some(([p as u32, r, q as u32, l], area));
                }
            }
        }
    }
    best
}

/// The smallest triangle by the rotational sweep (Edelsbrunner and Guibas'
/// idea, with a sort instead of a topological sweep): the sites ordered by
/// their distance to a line turning through half a circle swap neighbours
/// exactly when the line becomes parallel to the pair, and then the sites next
/// to the pair in the order are the nearest to its line. O(n² log n) for sites
/// in general position (no three on a line, no two pairs parallel); the
/// benchmark's peer.
pub fn smallest_triangle_sweep(sites: &[DVec2]) -> Option<([u32; 3], f64)> {
    let n = sites.len();
    if n < 3 {
        return None;
    }
    // Each pair's direction as an angle in [0, pi).
    let mut events: Vec<(f64, u32, u32)> = Vec::with_capacity(n * (n - 1) / 2);
    for i in 0..n {
        for j in i + 1..n {
            let d = sites[j] - sites[i];
            let mut a = d.y.atan2(d.x);
            if a < 0.0 {
                a += std::f64::consts::PI;
            }
            if a >= std::f64::consts::PI {
                a -= std::f64::consts::PI;
            }
            events.push((a, i as u32, j as u32));
        }
    }
    events.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    // The order along the normal of a direction just before the first event:
    // direction angle -epsilon, i.e. sort by the dot product with its normal.
    let start = events[0].0 - 1e-9;
    let normal = DVec2::new(-start.sin(), start.cos());
    let mut order: Vec<u32> = (0..n as u32).collect();
    order.sort_by(|&a, &b| {
        sites[a as usize]
            .dot(normal)
            .total_cmp(&sites[b as usize].dot(normal))
    });
    let mut position = vec![0usize; n];
    for (k, &s) in order.iter().enumerate() {
        position[s as usize] = k;
    }
    let mut best: Option<([u32; 3], f64)> = None;
    for &(_, i, j) in &events {
        let (pi, pj) = (position[i as usize], position[j as usize]);
        let (lo, hi) = (pi.min(pj), pi.max(pj));
        // In general position the pair is adjacent; otherwise skip the swap's
        // neighbours check (the exhaustive search is the oracle).
        if hi == lo + 1 {
            for k in [lo.checked_sub(1), (hi + 1 < n).then_some(hi + 1)]
                .into_iter()
                .flatten()
            {
                let s = order[k];
                let (a, b, c) = (sites[i as usize], sites[j as usize], sites[s as usize]);
                let area = 0.5 * (b - a).perp_dot(c - a).abs();
                if best.is_none_or(|b| area < b.1) {
                    best = Some(([i, j, s], area));
                }
            }
        }
        order.swap(pi, pj);
        position[i as usize] = pj;
        position[j as usize] = pi;
    }
    best
}
