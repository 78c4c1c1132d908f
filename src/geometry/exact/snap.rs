//! Rings of rounded corners kept valid: snap rounding on the doubles. Each
//! corner of a cell is the double nearest its exact corner, so cells that
//! share a corner share its double; but exact corners within a few units in
//! the last place of each other (a vertex of many nearly co-circular sites,
//! found once per triple), or a thin cell between sites a grid step apart,
//! can round into a ring that crosses itself or turns clockwise. Where a ring
//! does (each test exact on the doubles), every corner's hot pixel (the
//! points that round to it) that an edge passes through becomes a corner of
//! that edge, again until none is passed (iterated snap rounding, Halperin
//! and Packer 2002): edges then cross nowhere, and what rounding collapsed
//! (a loop through one corner, a spike, a ring of no area) is cut away. The
//! rule reads only the rounded corners, and an edge gets the same corners in
//! both cells it bounds, so the cells still share their corners bit for bit.

use std::cmp::Ordering;

use glam::DVec2;
use num_rational::BigRational;
use rayon::prelude::*;

use super::predicates::{orient, ring_turn};
use super::{next_toward, rational};
use crate::geometry::frame::lexicographic;
use crate::{error::Result, memory::Gather};

/// Rounds in which edges take the hot pixels they pass: each adds corners
/// already there, so a few suffice; past these the rings are left as the
/// last round made them.
const MOST_ROUNDS: usize = 64;

/// Makes every ring of `cells` simple and counter-clockwise (or empty, where
/// rounding collapsed it), snapping edges to the corners they pass.
pub(crate) fn keep_rings_simple(cells: &mut [Vec<DVec2>]) -> Result<()> {
    if cells.par_iter().all(|ring| is_simple(ring)) {
        return Ok(());
    }
    let mut corners = cells
        .iter()
        .flatten()
        .copied()
        .gather::<Vec<_>>("cell corners")?;
    corners.sort_by_key(|&c| lexicographic(c));
    corners.dedup_by_key(|c| lexicographic(*c));
    for _ in 0..MOST_ROUNDS {
        let mut snapped = false;
        for ring in cells.iter_mut() {
            snapped |= snap_ring(ring, &corners);
        }
        if !snapped {
            break;
        }
    }
    for ring in cells.iter_mut() {
        clean(ring);
    }
    Ok(())
}

/// Routes each edge of `ring` through the hot pixels of `corners` it passes,
/// in their order along it; whether any was.
#[expect(clippy::disallowed_methods, reason = "one ring's corners")]
fn snap_ring(ring: &mut Vec<DVec2>, corners: &[DVec2]) -> bool {
    let n = ring.len();
    let mut out = Vec::with_capacity(n);
    let mut snapped = false;
    for k in 0..n {
        let (a, b) = (ring[k], ring[(k + 1) % n]);
        out.push(a);
        let mut passed: Vec<DVec2> = passed_pixels(a, b, corners);
        snapped |= !passed.is_empty();
        // Along the edge by its longer axis, then the other, each signed by
        // the edge's direction: the reversed edge gets the reversed order.
        let d = b - a;
        let sign = |v: f64| if v < 0.0 { -1.0 } else { 1.0 };
        let key = |p: &DVec2| match d.x.abs() >= d.y.abs() {
            true => (sign(d.x) * p.x, sign(d.y) * p.y),
            false => (sign(d.y) * p.y, sign(d.x) * p.x),
        };
        passed.sort_by(|p, q| {
            let (kp, kq) = (key(p), key(q));
            kp.0.total_cmp(&kq.0).then(kp.1.total_cmp(&kq.1))
        });
        out.extend(passed);
    }
    *ring = out;
    snapped
}

/// The corners other than `a` and `b` whose hot pixels the segment `a b`
/// passes through (their closed boxes of the points that round to them).
#[expect(clippy::disallowed_methods, reason = "the corners near one edge")]
fn passed_pixels(a: DVec2, b: DVec2, corners: &[DVec2]) -> Vec<DVec2> {
    let (a, b) = ordered(a, b);
    let (lo, hi) = (a.min(b), a.max(b));
    // A double's box reaches past the segment's doubles only if the double
    // itself lies within their range.
    let first = corners.partition_point(|c| c.x < lo.x);
    corners[first..]
        .iter()
        .take_while(|c| c.x <= hi.x)
        .filter(|c| c.y >= lo.y && c.y <= hi.y && **c != a && **c != b)
        .filter(|&&c| near_line(a, b, c) && crosses_pixel(a, b, c))
        .copied()
        .collect()
}

/// The segment's ends in one order whichever way it is given, so that both
/// cells along an edge take the same corners.
fn ordered(a: DVec2, b: DVec2) -> (DVec2, DVec2) {
    match lexicographic(a) > lexicographic(b) {
        true => (b, a),
        false => (a, b),
    }
}

/// A float filter: whether `c` may lie within a few units in the last place
/// of the line through `a` and `b`. The differences round by a unit of the
/// largest coordinate, the products and their difference by a few ε more;
/// the pixel reaches a unit from `c`.
fn near_line(a: DVec2, b: DVec2, c: DVec2) -> bool {
    let (d, e) = (b - a, c - a);
    let cross = d.perp_dot(e);
    let largest = [a, b, c]
        .map(|p| p.abs().max_element())
        .into_iter()
        .fold(0.0, f64::max);
    let ulp = f64::from_bits(largest.to_bits() + 1) - largest;
    let reach = 4.0 * ulp * (d.length() + e.length())
        + 8.0 * f64::EPSILON * (d.x.abs() * e.y.abs() + d.y.abs() * e.x.abs());
    cross.abs() <= reach || !cross.is_finite()
}

/// Whether the line through `a` and `b` meets the hot pixel of `c`: not all
/// four of its corners strictly on one side, decided in rationals.
fn crosses_pixel(a: DVec2, b: DVec2, c: DVec2) -> bool {
    // Halfway to each neighbouring double (past the largest, the double).
    let half = |v: f64, toward: f64| {
        let next = Some(next_toward(v, toward))
            .filter(|n| n.is_finite())
            .unwrap_or(v);
        (rational(v) + rational(next)) / BigRational::from_integer(2.into())
    };
    let xs = [half(c.x, f64::NEG_INFINITY), half(c.x, f64::INFINITY)];
    let ys = [half(c.y, f64::NEG_INFINITY), half(c.y, f64::INFINITY)];
    let (ax, ay) = (rational(a.x), rational(a.y));
    let (dx, dy) = (rational(b.x) - &ax, rational(b.y) - &ay);
    let zero = BigRational::from_integer(0.into());
    let side = |x: &BigRational, y: &BigRational| (&dx * (y - &ay) - &dy * (x - &ax)).cmp(&zero);
    let sides = [
        side(&xs[0], &ys[0]),
        side(&xs[0], &ys[1]),
        side(&xs[1], &ys[0]),
        side(&xs[1], &ys[1]),
    ];
    !(sides.iter().all(|s| s.is_gt()) || sides.iter().all(|s| s.is_lt()))
}

/// Cuts from `ring` what rounding collapsed: repeated corners, spikes (an
/// edge and its reverse), loops through one corner (the smaller kept off),
/// and the whole ring where what is left has fewer than three corners or is
/// not simple and counter-clockwise.
fn clean(ring: &mut Vec<DVec2>) {
    loop {
        let before = ring.len();
        ring.dedup();
        while ring.len() > 1 && ring.first() == ring.last() {
            ring.pop();
        }
        let n = ring.len();
        if let Some(k) = (0..n).find(|&k| n >= 3 && ring[k] == ring[(k + 2) % n]) {
            ring.remove((k + 1) % n);
        }
        cut_loops(ring);
        if ring.len() == before {
            break;
        }
    }
    if !is_simple(ring) {
        ring.clear();
    }
}

/// Whether `ring` (not closed) is simple and counter-clockwise: at least
/// three corners, none twice, no two edges meeting but consecutive ones at
/// their shared corner, and a left turn at its least corner, each test exact
/// on the doubles. An empty ring is.
fn is_simple(ring: &[DVec2]) -> bool {
    let n = ring.len();
    if n == 0 {
        return true;
    }
    if n < 3 {
        return false;
    }
    if ring_turn(ring) <= 0.0 {
        return false;
    }
    let edge = |k: usize| (ring[k], ring[(k + 1) % n]);
    (0..n).all(|i| {
        (i + 1..n).all(|j| match j == i + 1 || (i == 0 && j == n - 1) {
            true => ring[i] != ring[j] && !folds_back(edge(i), edge(j)),
            false => !edges_meet(edge(i), edge(j)),
        })
    })
}

/// Whether consecutive edges overlap along a line (the ring turns back on
/// itself at their shared corner).
fn folds_back(e: (DVec2, DVec2), f: (DVec2, DVec2)) -> bool {
    let (shared, a, b) = match (e.1 == f.0, f.1 == e.0) {
        (true, _) => (e.1, e.0, f.1),
        (_, true) => (e.0, e.1, f.0),
        _ => return false,
    };
    orient(shared, a, b) == 0.0 && (a - shared).dot(b - shared) > 0.0
}

/// Whether two segments share a point, exactly.
fn edges_meet((a, b): (DVec2, DVec2), (c, d): (DVec2, DVec2)) -> bool {
    let side = |p: DVec2, q: DVec2, r: DVec2| orient(p, q, r).total_cmp(&0.0);
    let (abc, abd) = (side(a, b, c), side(a, b, d));
    let (cda, cdb) = (side(c, d, a), side(c, d, b));
    let outside = |p: DVec2, q: DVec2, r: DVec2| {
        let (lo, hi) = (p.min(q), p.max(q));
        r.cmplt(lo).any() || r.cmpgt(hi).any()
    };
    let crossing = abc != abd && cda != cdb;
    let zero = Ordering::Equal;
    let touching = (abc == zero && !outside(a, b, c))
        || (abd == zero && !outside(a, b, d))
        || (cda == zero && !outside(c, d, a))
        || (cdb == zero && !outside(c, d, b));
    (crossing && ![abc, abd, cda, cdb].contains(&zero)) || touching
}

/// Twice the signed area of `ring`, about its first corner.
fn twice_area(ring: &[DVec2]) -> f64 {
    let Some(&o) = ring.first() else { return 0.0 };
    (1..ring.len().saturating_sub(1))
        .map(|k| (ring[k] - o).perp_dot(ring[k + 1] - o))
        .sum()
}

/// Where a corner repeats, the ring splits into two loops through it: the
/// one of smaller area is cut off.
#[expect(clippy::disallowed_methods, reason = "one ring's corners")]
fn cut_loops(ring: &mut Vec<DVec2>) {
    'again: loop {
        for i in 0..ring.len() {
            if let Some(k) = ring[i + 1..].iter().position(|p| *p == ring[i]) {
                let j = i + 1 + k;
                let inner = &ring[i..j];
                let outer: Vec<DVec2> = ring[j..].iter().chain(&ring[..i]).copied().collect();
                if twice_area(inner).abs() > twice_area(&outer).abs() {
                    *ring = inner.to_vec();
                } else {
                    *ring = outer;
                }
                continue 'again;
            }
        }
        return;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ring_doubling_back_through_rounded_corners_is_snapped() {
        // Corners a few ulps apart on one line, rounded into a zigzag: the
        // edges take the corners they pass, the spike is cut, and the rings
        // left are simple (the sliver between them had no area).
        let ulp = next_toward(110.0, f64::INFINITY) - 110.0;
        let at = |k: f64| DVec2::new(110.0 - k * ulp, 170.0);
        let (low, high) = (DVec2::new(0.0, 0.0), DVec2::new(0.0, 200.0));
        let mut cells = Vec::from([
            Vec::from([low, at(3.0), at(1.0), at(4.0), high]),
            Vec::from([at(4.0), at(1.0), at(3.0), DVec2::new(200.0, 0.0)]),
        ]);
        assert!(!is_simple(&cells[0]));
        keep_rings_simple(&mut cells).unwrap();
        assert!(cells.iter().all(|ring| is_simple(ring)), "{cells:?}");
        assert!(
            cells[0].contains(&low) && cells[0].contains(&high),
            "{cells:?}"
        );
    }

    #[test]
    fn simple_rings_stay_as_they_are() {
        let mut cells = Vec::from([Vec::from([DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y])]);
        let before = cells.clone();
        keep_rings_simple(&mut cells).unwrap();
        assert_eq!(cells, before);
    }

    #[test]
    fn crossing_and_touching_edges_are_found_exactly() {
        let p = |x: f64, y: f64| DVec2::new(x, y);
        // A bow tie, and a ring through one corner twice.
        assert!(!is_simple(&[
            p(0.0, 0.0),
            p(1.0, 1.0),
            p(1.0, 0.0),
            p(0.0, 1.0)
        ]));
        assert!(!is_simple(&[
            p(0.0, 0.0),
            p(2.0, 0.0),
            p(1.0, 0.0),
            p(1.0, 1.0)
        ]));
        // One ulp keeps a corner off an edge.
        let off = next_toward(1.0, 2.0);
        assert!(is_simple(&[
            p(0.0, 0.0),
            p(2.0, 0.0),
            p(2.0, 2.0),
            p(1.0, off),
            p(0.0, 2.0)
        ]));
        assert!(!is_simple(&[
            p(0.0, 0.0),
            p(2.0, 0.0),
            p(2.0, 2.0),
            p(1.0, 0.0),
            p(0.0, 2.0)
        ]));
    }
}
