//! Triangle areas with exact signs.

use std::cmp::Ordering;

use glam::DVec2;
use num_rational::BigRational;
use num_traits::Signed;

use super::filter::Bound;
use super::predicates::orient;
use super::{nearest_double, orient_exact};

/// The best site strictly on each side of the line p → q (left, right): the
/// nearest (`largest` false) or farthest, by exact area (the first on a tie),
/// with its triangle's area as a float.
pub(crate) fn sides_of(
    sites: &[DVec2],
    p: usize,
    q: usize,
    largest: bool,
) -> [Option<(u32, f64)>; 2] {
    // Per side: the triangle and its area's float bounds.
    type Best = Option<([u32; 3], (f64, f64))>;
    let mut best: [Best; 2] = [None, None];
    let wanted = if largest {
        Ordering::Greater
    } else {
        Ordering::Less
    };
    for s in 0..sites.len() {
        let c = orient(sites[p], sites[q], sites[s]);
        if c == 0.0 {
            continue;
        }
        let side = usize::from(c < 0.0);
        let ring = [p as u32, q as u32, s as u32];
        let bounds = area_bounds(sites, &ring);
        let better = best[side]
            .as_ref()
            .is_none_or(|(b, bb)| compare_areas(sites, (&ring, bounds), (b, *bb)) == wanted);
        if better {
            best[side] = Some((ring, bounds));
        }
    }
    best.map(|b| b.map(|(ring, (area, _))| (ring[2], area)))
}

/// The area of the ring of `sites` named by `ring` (a triangle, or a
/// quadrangle as two triangles on its diagonal from the first vertex to the
/// third), as a float and a bound on its error: Shewchuk's bound on a float
/// orientation, doubled.
pub(crate) fn area_bounds(sites: &[DVec2], ring: &[u32]) -> (f64, f64) {
    area_bounds_within(Bound::AREA, sites, ring)
}

pub(super) fn area_bounds_within(bound: Bound, sites: &[DVec2], ring: &[u32]) -> (f64, f64) {
    let p = |k: usize| sites[ring[k] as usize];
    let half = |a: DVec2, b: DVec2, c: DVec2| {
        let (l, r) = ((b.x - a.x) * (c.y - a.y), (b.y - a.y) * (c.x - a.x));
        let error = bound.error(l.abs() + r.abs());
        ((l - r).abs() / 2.0, error + f64::MIN_POSITIVE)
    };
    let (a, ea) = half(p(0), p(1), p(2));
    if ring.len() == 3 {
        return (a, ea);
    }
    let (b, eb) = half(p(2), p(3), p(0));
    (
        a + b,
        (ea + eb) * (1.0 + f64::EPSILON) + (a + b) * f64::EPSILON,
    )
}

/// Twice the exact area of the ring (as [`area_bounds`] measures it).
pub(crate) fn exact_double_area(sites: &[DVec2], ring: &[u32]) -> BigRational {
    let p = |k: usize| sites[ring[k] as usize];
    let twice = orient_exact(p(0), p(1), p(2)).abs();
    if ring.len() == 3 {
        return twice;
    }
    twice + orient_exact(p(2), p(3), p(0)).abs()
}

/// The exact area of the ring, rounded to the nearest double.
pub(crate) fn exact_area(sites: &[DVec2], ring: &[u32]) -> f64 {
    nearest_double(&(exact_double_area(sites, ring) / BigRational::from_integer(2.into())))
}

/// The area of a convex ring, exactly (a fan of triangles from its first
/// vertex), rounded to the nearest double.
pub(crate) fn convex_ring_area(sites: &[DVec2], ring: &[u32]) -> f64 {
    let twice = (1..ring.len().saturating_sub(1))
        .map(|k| exact_double_area(sites, &[ring[0], ring[k], ring[k + 1]]))
        .fold(BigRational::from_integer(0.into()), |a, b| a + b);
    nearest_double(&(twice / BigRational::from_integer(2.into())))
}

/// The order of two rings' areas, exactly: floats where their bounds keep
/// them apart, rationals where not.
pub(crate) fn compare_areas(
    sites: &[DVec2],
    a: (&[u32], (f64, f64)),
    b: (&[u32], (f64, f64)),
) -> Ordering {
    let ((ra, (va, ea)), (rb, (vb, eb))) = (a, b);
    if va + ea < vb - eb {
        return Ordering::Less;
    }
    if vb + eb < va - ea {
        return Ordering::Greater;
    }
    exact_double_area(sites, ra).cmp(&exact_double_area(sites, rb))
}
