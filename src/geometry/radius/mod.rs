//! How far each cone must reach: the width bounds of thesis §3.5 from a quadtree,
//! and pixgeo's per-site bound, the width of a polygon that contains the site's
//! region.
//!
//! All coordinates here are pixel coordinates; pixel centres are the integer points
//! of `[0, w-1] x [0, h-1]`.
//!
//! The quadtree bound is here; the Delaunay cell bounds in `cells`, the local
//! reaches and tile lists in `local`, the bins they search in `grid`.

use glam::DVec2;

use rayon::prelude::*;

use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};

mod cells;
mod grid;
mod local;
#[cfg(test)]
mod tests;

pub(crate) use cells::*;
use grid::*;
pub(crate) use local::*;

use super::{
    buckets::{for_ring_cells, group_by_bucket},
    cell::clip_convex,
    frame::{distance2_to_rect, farthest2_in_rect},
    metric::{DepthKey, Metric},
    Frame,
};

/// Bounds on the width of the Voronoi diagram restricted to the picture
/// (thesis Def. 3.3, Lemma 3.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct WidthBounds {
    /// Side of a cell at the first level with an empty cell: some point is at least
    /// about this far from every site.
    pub lower: f64,
    /// Diagonal of a cell at the deepest level whose cells all hold a site; `None`
    /// when not even the root holds a site of the picture.
    pub upper: Option<f64>,
    /// The deepest level whose cells are all occupied (0 = the root).
    pub full_level: Option<u32>,
}

/// The quadtree of thesis §3.5 over the picture: the root is the smallest
/// power-of-two square holding it, a level-`l` cell has side `S / 2^l`. A cell is
/// marked when a site lies in it; the deepest level where every cell meeting the
/// picture is marked gives the upper bound. Levels stop once they have more cells
/// than there are sites, since those cannot all be marked.
pub(crate) fn quadtree_width_bounds(sites: &[DVec2], frame: &Frame) -> WidthBounds {
    let (side, full_level) = deepest_full_level(sites, frame, 1);
    let cell_at = |l: u32| side / (1u64 << l) as f64;
    match full_level {
        Some(l) => WidthBounds {
            lower: cell_at(l + 1),
            upper: Some(cell_at(l) * 2f64.sqrt()),
            full_level,
        },
        None => WidthBounds {
            lower: side,
            upper: None,
            full_level,
        },
    }
}

/// Thesis Theorem 3.3: if every cell of a covering of the picture holds at least
/// `k` sites, cones truncated at the largest cell diagonal keep the `k` lowest
/// layers of the arrangement. The diagonal of the quadtree's deepest such level;
/// `None` when not even the root holds `k` sites of the picture.
pub(crate) fn quadtree_k_radius(sites: &[DVec2], frame: &Frame, k: usize) -> Option<f64> {
    let (side, full_level) = deepest_full_level(sites, frame, k.max(1));
    full_level.map(|l| side / (1u64 << l) as f64 * 2f64.sqrt())
}

/// The root side of the picture's quadtree and its deepest level whose cells
/// (those meeting the picture) all hold at least `k` sites of the picture.
#[expect(
    clippy::disallowed_macros,
    reason = "a count a quadtree cell, fewer than the sites"
)]
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
fn deepest_full_level(sites: &[DVec2], frame: &Frame, k: usize) -> (f64, Option<u32>) {
    let (w, h) = (frame.width as f64, frame.height as f64);
    let side = (frame.width.max(frame.height) as f64)
        .log2()
        .ceil()
        .exp2()
        .max(1.0);
    let inside: Vec<DVec2> = sites
        .iter()
        .map(|p| *p + 0.5) // picture corner at the origin
        .filter(|p| p.x >= 0.0 && p.y >= 0.0 && p.x < w && p.y < h)
        .collect();
    let mut full_level = None;
    let mut level = 0u32;
    loop {
        let cell = side / (1u64 << level) as f64;
        let nx = (w / cell).ceil() as usize;
        let ny = (h / cell).ceil() as usize;
        if nx * ny * k > inside.len().max(1) || cell < 1.0 {
            break;
        }
        let mut count = vec![0usize; nx * ny];
        for p in &inside {
            let ix = ((p.x / cell) as usize).min(nx - 1);
            let iy = ((p.y / cell) as usize).min(ny - 1);
            count[iy * nx + ix] += 1;
        }
        if count.iter().all(|c| *c >= k) {
            full_level = Some(level);
            level += 1;
        } else {
            break;
        }
    }
    (side, full_level)
}

/// Boxes `[lo, hi]` that hold each site's region under L1 or L∞ (`None` for the
/// other metrics), from its Delaunay neighbours (`DelaunayNeighbours`).
///
/// Under L1, a site t in the cone above s (|t.x - s.x| < t.y - s.y) is nearer
/// than s to every point higher than (s.y + t.y + |t.x - s.x|) / 2: there the
/// vertical offsets differ by more than the horizontal ones can make up. So that
/// height bounds the region of s from above, the other three cones bound it
/// likewise, and any set of sites gives a valid box (rounding aside, which the
/// callers' half pixel covers). L∞ is L1 of the coordinates ((x + y) / 2,
/// (x - y) / 2), where the same box becomes a diamond. A cone without a
/// neighbour takes the neighbours' neighbours; a side still without one stays
/// unbounded (infinite). A site the triangulation leaves out (a duplicate, every
/// site of a collinear set) gets `None`.
pub(crate) fn region_boxes(
    sites: &[DVec2],
    frame: &Frame,
    metric: Metric,
) -> Option<Vec<Option<(DVec2, DVec2)>>> {
    // Coordinates in which the metric is L1.
    let to: fn(DVec2) -> DVec2 = match metric {
        Metric::L1 => |p| p,
        Metric::LInf => |p| DVec2::new(p.x + p.y, p.x - p.y) * 0.5,
        _ => return None,
    };
    let neighbours = DelaunayNeighbours::of(sites, frame);
    let boxes = (0..sites.len())
        .into_par_iter()
        .map(|i| {
            let s = to(sites[i]);
            let ring = neighbours.of_site(i);
            if ring.is_empty() {
                return None;
            }
            let mut bounds = (DVec2::NEG_INFINITY, DVec2::INFINITY);
            for &t in ring {
                tighten_l1_box(&mut bounds, s, to(sites[t as usize]));
            }
            // A cone the neighbours miss often holds one of theirs.
            if !(bounds.0.is_finite() && bounds.1.is_finite()) {
                for &t in ring {
                    for &u in neighbours.of_site(t as usize) {
                        tighten_l1_box(&mut bounds, s, to(sites[u as usize]));
                    }
                }
            }
            let (lo, hi) = bounds;
            Some(if metric == Metric::L1 {
                (lo, hi)
            } else {
                // The diamond's box: x = u + v, y = u - v.
                (
                    DVec2::new(lo.x + lo.y, lo.x - hi.y),
                    DVec2::new(hi.x + hi.y, hi.x - lo.y),
                )
            })
        })
        .collect();
    Some(boxes)
}

/// Narrows the L1 box `(lo, hi)` of the region of s by a site t (see
/// [`region_boxes`]).
fn tighten_l1_box((lo, hi): &mut (DVec2, DVec2), s: DVec2, t: DVec2) {
    let d = t - s;
    let a = d.abs();
    if a.x < d.y {
        hi.y = hi.y.min(s.y + 0.5 * (d.y + a.x));
    } else if a.x < -d.y {
        lo.y = lo.y.max(s.y - 0.5 * (-d.y + a.x));
    } else if a.y < d.x {
        hi.x = hi.x.min(s.x + 0.5 * (d.x + a.y));
    } else if a.y < -d.x {
        lo.x = lo.x.max(s.x - 0.5 * (-d.x + a.y));
    }
}

/// The radii of the thesis's retry loop: start a little above the lower bound
/// (`lower * sqrt 2`), step by `sqrt 2` and end at the upper bound — or, when the
/// quadtree gives none, at the radius that covers the picture from every site.
/// Steps of `sqrt 2` rather than 2: a pass costs about the square of its radius,
/// so overshooting the needed radius by up to 2x would cost up to 4x.
pub(crate) fn retry_radii(bounds: &WidthBounds, picture_wide: f64) -> Vec<f64> {
    let last = bounds.upper.unwrap_or(picture_wide).min(picture_wide);
    let mut r = (bounds.lower * 2f64.sqrt()).min(last);
    let mut out = Vec::new();
    while r < last * 0.99 {
        out.push(r);
        r *= std::f64::consts::SQRT_2;
    }
    out.push(last);
    out
}
