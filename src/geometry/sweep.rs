//! The rotational sweep (Edelsbrunner and Guibas' idea, with a sort in place of
//! the topological sweep): points ordered by their distance to a line that
//! turns through half a circle. Two points swap places exactly when the line
//! becomes parallel to them; at that moment the points next to them in the
//! order are the nearest to their line on either side, and the first and last
//! the farthest. O(n² log n) time, O(n²) memory.
//!
//! Exact for any distinct points: directions are compared by an exact sign,
//! and the points on one line, which all swap at one moment, reverse as a block.

use crate::memory::Gather;
use std::{
    cmp::Ordering,
    ops::Range,
    sync::atomic::{AtomicBool, Ordering as AtomicOrdering},
};

use glam::DVec2;
use rayon::slice::ParallelSliceMut;

use super::exact::{two_difference, two_product, two_sum};
use crate::error::{Error, Result};

/// Calls `visit(order, block)` for every line through two or more of the
/// distinct `points`, in the order of the lines' directions over half a turn.
/// `order` holds the point indices ordered by signed distance to the line,
/// right side first; `order[block]` are the line's points, ordered along its
/// direction. `progress(done, total)` counts point pairs.
pub(crate) fn for_each_line(
    points: &[DVec2],
    progress: &mut dyn FnMut(u64, u64),
    mut visit: impl FnMut(&[u32], Range<usize>),
) -> Result<()> {
    let n = points.len();
    let pairs = n * n.saturating_sub(1) / 2;
    let mut events: Vec<Event> = Vec::new();
    events
        .try_reserve_exact(pairs)
        .map_err(|_| Error::HostMemory {
            what: format!("the sweep over {n} points ({pairs} point pairs)"),
            bytes: (pairs as u64).saturating_mul(std::mem::size_of::<Event>() as u64),
        })?;
    for i in 0..n as u32 {
        for j in i + 1..n as u32 {
            let d = points[j as usize] - points[i as usize];
            if d == DVec2::ZERO {
                return Err(Error::malformed(format!(
                    "points {i} and {j} coincide; the sweep takes distinct points"
                )));
            }
            // Each pair from, to with to - from in the upper half-plane, the
            // direction's angle in [0, pi). Signs of differences are exact.
            let (from, to, d) = if upper(d) { (i, j, d) } else { (j, i, -d) };
            events.push(Event { d, from, to });
        }
    }
    let inexact = AtomicBool::new(false);
    let compare = |a: &Event, b: &Event| {
        compare_directions(points, a, b).unwrap_or_else(|| {
            inexact.store(true, AtomicOrdering::Relaxed);
            Ordering::Equal
        })
    };
    events.par_sort_unstable_by(compare);
    if inexact.load(AtomicOrdering::Relaxed) {
        return Err(Error::out_of_range(
            "two of the points' directions differ by less than floats can resolve beside their \
             coordinates (about 1e-290 in ratio); scale or round the coordinates"
                .into(),
        ));
    }

    // Just before angle 0 the distance to the line ranks by y, then x.
    let mut order: Vec<u32> = (0..n as u32).gather("order")?;
    order.sort_unstable_by(|&a, &b| {
        let (p, q) = (points[a as usize], points[b as usize]);
        p.y.total_cmp(&q.y).then(p.x.total_cmp(&q.x))
    });
    let mut position = crate::memory::filled(n, 0usize, "the points' sweep positions")?;
    for (k, &s) in order.iter().enumerate() {
        position[s as usize] = k;
    }
    // Per point, the first position of its line and its partners at the
    // current direction.
    let mut first = crate::memory::filled(n, usize::MAX, "the points' first partners")?;
    let mut partners = crate::memory::filled(n, 0usize, "the points' partners")?;
    let mut start = 0;
    let watch = crate::cancel::Watch::current();
    while start < events.len() {
        watch.check()?;
        let end = start
            + 1
            + events[start + 1..]
                .iter()
                .position(|e| compare(&events[start], e) != Ordering::Equal)
                .unwrap_or(events.len() - start - 1);
        let class = &events[start..end];
        for &Event { from: f, to: t, .. } in class {
            let low = position[f as usize].min(position[t as usize]);
            for p in [f, t] {
                first[p as usize] = first[p as usize].min(low);
                partners[p as usize] += 1;
            }
        }
        for &Event { from: f, .. } in class {
            let lo = first[f as usize];
            if lo == usize::MAX {
                continue; // this line is done
            }
            let block = lo..lo + partners[f as usize] + 1;
            let line = &order[block.clone()];
            if block.end > n
                || line
                    .iter()
                    .any(|&p| first[p as usize] != lo || partners[p as usize] + 1 != line.len())
            {
                return Err(Error::Internal(
                    "the sweep's order lost a line's points".into(),
                ));
            }
            visit(&order, block.clone());
            for &p in line {
                first[p as usize] = usize::MAX;
                partners[p as usize] = 0;
            }
            order[block.clone()].reverse();
            for k in block {
                position[order[k] as usize] = k;
            }
        }
        if end * 64 / events.len().max(1) != start * 64 / events.len().max(1) {
            progress(end as u64, events.len() as u64);
        }
        start = end;
    }
    Ok(())
}

/// A pair of points, `to - from` (rounded) pointing into the upper half-plane.
struct Event {
    d: DVec2,
    from: u32,
    to: u32,
}

fn upper(d: DVec2) -> bool {
    d.y > 0.0 || (d.y == 0.0 && d.x > 0.0)
}

/// `to - from`, each coordinate as its rounded value and the exact rest.
struct Difference {
    hi: DVec2,
    lo: DVec2,
}

impl Difference {
    fn new(from: DVec2, to: DVec2) -> Self {
        let (x, dx) = two_difference(to.x, from.x);
        let (y, dy) = two_difference(to.y, from.y);
        Difference {
            hi: DVec2::new(x, y),
            lo: DVec2::new(dx, dy),
        }
    }
}

/// Two pairs' directions in [0, pi) by angle: the sign of their cross product,
/// exact; `None` where a part's product would leave the normal range.
fn compare_directions(points: &[DVec2], a: &Event, b: &Event) -> Option<Ordering> {
    let c = a.d.perp_dot(b.d);
    let magnitude = (a.d.x * b.d.y).abs() + (a.d.y * b.d.x).abs();
    // The rounded differences and products are off by a few units in the last
    // place of `magnitude`; the normal-range floor keeps products exact.
    if c.abs() > 8.0 * f64::EPSILON * magnitude && magnitude > 1e-250 {
        return 0.0.partial_cmp(&c);
    }
    let difference = |e: &Event| Difference::new(points[e.from as usize], points[e.to as usize]);
    exact_cross_sign(&difference(a), &difference(b)).map(Ordering::reverse)
}

/// The sign of a.x b.y - a.y b.x, summed exactly from the parts' products.
/// Each vector is first scaled by a power of two (which keeps the sign) so
/// that the products stay far from underflow; `None` where one still would
/// not be exact.
fn exact_cross_sign(a: &Difference, b: &Difference) -> Option<Ordering> {
    let (a, b) = (normalized(a), normalized(b));
    let mut terms = [0.0; 16];
    let mut k = 0;
    for (x, y, sign) in [(a.0, b.1, 1.0), (a.1, b.0, -1.0)] {
        for u in x {
            for v in y {
                let (p, e) = two_product(u, v);
                if p != 0.0 && p.abs() < 1e-290 {
                    return None;
                }
                terms[k] = sign * p;
                terms[k + 1] = sign * e;
                k += 2;
            }
        }
    }
    Some(expansion_sign(&terms))
}

/// A difference's four parts (x's, y's), scaled so the largest is near 1.
fn normalized(d: &Difference) -> ([f64; 2], [f64; 2]) {
    let largest = d.hi.abs().max_element();
    let k = -largest.log2().floor() as i32;
    let s = |v: f64| crate::geometry::scale::times_power_of_two(v, k);
    ([s(d.hi.x), s(d.lo.x)], [s(d.hi.y), s(d.lo.y)])
}

/// The sign of the exact sum of `terms`: Shewchuk's expansion growth, whose
/// components do not overlap, so the largest nonzero one carries the sign.
fn expansion_sign(terms: &[f64; 16]) -> Ordering {
    let mut expansion = [0.0; 16];
    for (k, &t) in terms.iter().enumerate() {
        let mut carry = t;
        for e in expansion[..k].iter_mut() {
            let (sum, rest) = two_sum(carry, *e);
            *e = rest;
            carry = sum;
        }
        expansion[k] = carry;
    }
    let top = expansion.iter().rev().find(|&&e| e != 0.0).copied();
    top.map_or(Ordering::Equal, |t| t.partial_cmp(&0.0).expect("finite"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cross_sign(a: [f64; 4], b: [f64; 4]) -> Ordering {
        let d = |v: [f64; 4]| Difference::new(DVec2::new(v[0], v[1]), DVec2::new(v[2], v[3]));
        exact_cross_sign(&d(a), &d(b)).unwrap()
    }

    #[test]
    fn exact_sign_sees_what_rounding_hides() {
        // 1 - 2^-60 rounds to 1, but the directions differ by 2^-60.
        let tiny = 2f64.powi(-60);
        assert_eq!(
            cross_sign([0.0, 0.0, 1.0, 1.0], [tiny, 0.0, 1.0, 1.0]),
            Ordering::Greater
        );
        assert_eq!(
            cross_sign([0.0, 0.0, 1.0, 1.0], [-tiny, 0.0, 1.0, 1.0]),
            Ordering::Less
        );
        assert_eq!(
            cross_sign([1.0, 1.0, 3.0, 3.0], [-2.0, -2.0, 5.0, 5.0]),
            Ordering::Equal
        );
    }

    #[test]
    fn lines_of_a_lattice_come_as_blocks() {
        let points: Vec<DVec2> = (0..16)
            .map(|k| DVec2::new((k % 4) as f64, (k / 4) as f64))
            .collect();
        let mut lines = 0;
        let mut pairs = 0;
        for_each_line(&points, &mut |_, _| {}, |order, block| {
            lines += 1;
            let m = block.len();
            pairs += m * (m - 1) / 2;
            let line: Vec<DVec2> = order[block].iter().map(|&i| points[i as usize]).collect();
            for w in line.windows(3) {
                assert_eq!((w[1] - w[0]).perp_dot(w[2] - w[0]), 0.0);
            }
        })
        .unwrap();
        assert_eq!(pairs, 16 * 15 / 2);
        // Lines through two or more points of a 4x4 lattice.
        assert_eq!(lines, 62);
    }
}
