//! The smallest and largest triangles and quadrangles on the CPU, by the
//! rotational sweep: when a turning line becomes parallel to a pair of sites,
//! the sites next to the pair in the order of distance to the line are the
//! nearest on either side, and the first and last the farthest. A triangle is a
//! pair and one such site, a quadrangle a diagonal pair and one site on each
//! side. O(n² log n) whatever the sites' spacing, where the roofs' pixels
//! (thesis ch. 7, [`super`]) leave sites that share a pixel
//! to an exhaustive search.

use crate::geometry::exact::predicates::convex_hull;
use crate::memory::Gather;
use std::{ops::Range, time::Instant};

use glam::DVec2;

use crate::{
    algorithms::area::{
        counter_clockwise, decided, degenerate_triangle, in_range, quadrangle_candidates,
        AreaAnswer, BestRing, Decided, Extreme,
    },
    error::{Error, Result},
    geometry::{frame::first_of_each, sweep::for_each_line},
};

/// The smallest or largest triangle with three of `sites` as vertices.
pub(crate) fn extremal_triangle_sweep(
    sites: &[DVec2],
    extreme: Extreme,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<AreaAnswer> {
    in_range(sites, |sites| {
        if let Some(answer) = degenerate_triangle(sites, extreme)? {
            return Ok(answer);
        }
        let chosen = match extreme {
            Extreme::Smallest => first_of_each(sites),
            Extreme::Largest => convex_hull(sites),
        };
        sweep(sites, &chosen, extreme, progress, |order, line, offer| {
            let n = order.len();
            let third = |k: usize| order[k];
            match extreme {
                // Three sites on a line: area 0.
                Extreme::Smallest if line.len() >= 3 => {
                    offer(&order[line.start..line.start + 3]);
                }
                Extreme::Smallest => {
                    let (a, b) = (order[line.start], order[line.start + 1]);
                    if line.start > 0 {
                        offer(&[a, b, third(line.start - 1)]);
                    }
                    if line.end < n {
                        offer(&[a, b, third(line.end)]);
                    }
                }
                Extreme::Largest => {
                    let (a, b) = (order[line.start], order[line.end - 1]);
                    if line.start > 0 {
                        offer(&[a, b, third(0)]);
                    }
                    if line.end < n {
                        offer(&[a, b, third(n - 1)]);
                    }
                }
            }
        })
    })
}

/// The smallest or largest quadrangle with four of `sites` as vertices: a
/// diagonal with one vertex strictly on each side.
pub(crate) fn extremal_quadrangle_sweep(
    sites: &[DVec2],
    extreme: Extreme,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<AreaAnswer> {
    in_range(sites, |sites| {
        let (chosen, _) = quadrangle_candidates(sites, extreme)?;
        sweep(sites, &chosen, extreme, progress, |order, line, offer| {
            let n = order.len();
            if line.start == 0 || line.end == n {
                return; // no site on one side
            }
            // Counter-clockwise: along the diagonal, the right side comes first
            // in the order.
            let (right, left) = match extreme {
                Extreme::Smallest => (order[line.start - 1], order[line.end]),
                Extreme::Largest => (order[0], order[n - 1]),
            };
            match extreme {
                Extreme::Smallest => {
                    for pair in order[line.clone()].windows(2) {
                        offer(&[pair[0], right, pair[1], left]);
                    }
                }
                Extreme::Largest => {
                    offer(&[order[line.start], right, order[line.end - 1], left]);
                }
            }
        })
    })
}

/// Runs the sweep over `chosen` sites, offering the candidates `visit` names
/// (indices into `chosen`) and keeping the best by exact area.
fn sweep(
    sites: &[DVec2],
    chosen: &[u32],
    extreme: Extreme,
    progress: &mut dyn FnMut(u64, u64),
    mut visit: impl FnMut(&[u32], Range<usize>, &mut dyn FnMut(&[u32])),
) -> Result<AreaAnswer> {
    let started = Instant::now();
    let points: Vec<DVec2> = chosen.iter().map(|&i| sites[i as usize]).gather("points")?;
    let mut best = BestRing::new(extreme);
    let mut lines = 0;
    for_each_line(&points, progress, |order, line| {
        lines += 1;
        visit(order, line, &mut |v: &[u32]| best.offer(&points, v));
    })?;
    let (vertices, area) = best
        .exact(&points)
        .ok_or_else(|| Error::Internal("the sweep found no candidate".into()))?;
    let vertices: Vec<u32> = vertices
        .iter()
        .map(|&k| chosen[k as usize])
        .gather("vertices")?;
    let vertices = match vertices.len() {
        3 => counter_clockwise(sites, vertices),
        _ => vertices,
    };
    let mut answer = decided(extreme, vertices, area, Decided::Sweep);
    answer.checked = lines;
    answer.exact_ms = started.elapsed().as_secs_f64() * 1e3;
    Ok(answer)
}
