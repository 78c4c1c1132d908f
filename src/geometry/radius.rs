//! How far each cone must reach: the width bounds of thesis §3.5 from a quadtree,
//! and pixgeo's per-site bound, the width of a polygon that contains the site's
//! region.
//!
//! All coordinates here are pixel coordinates; pixel centres are the integer points
//! of `[0, w-1] x [0, h-1]`.
//!
//! The file is long (about 1,350 lines and 440 of tests) because every bound that
//! limits a cone lives here and shares these conventions: the quadtree bound, the
//! Delaunay cell bounds, the L_p tile candidates, the k-nearest tile lists and the
//! grid.

use glam::DVec2;

use rayon::prelude::*;

use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};

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
pub struct WidthBounds {
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
pub fn quadtree_width_bounds(sites: &[DVec2], frame: &Frame) -> WidthBounds {
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
pub fn quadtree_k_radius(sites: &[DVec2], frame: &Frame, k: usize) -> Option<f64> {
    let (side, full_level) = deepest_full_level(sites, frame, k.max(1));
    full_level.map(|l| side / (1u64 << l) as f64 * 2f64.sqrt())
}

/// The root side of the picture's quadtree and its deepest level whose cells
/// (those meeting the picture) all hold at least `k` sites of the picture.
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
pub fn region_boxes(
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
pub fn retry_radii(bounds: &WidthBounds, picture_wide: f64) -> Vec<f64> {
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

/// Where a site's region lies within the picture (see [`cell_bounds`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellBound {
    pub radius: f64,
    pub lo: DVec2,
    pub hi: DVec2,
}

/// Where each site's region lies within the picture: every pixel centre that
/// site s owns lies within `radius` of it and inside the box `[lo, hi]`; a site
/// whose region misses the picture gets radius 0 and an empty box at the site.
///
/// The region of s within a Delaunay triangulation of any sites including s
/// (a strip of them, see `delaunay_strips`) contains its region among all
/// sites. Where s is inside the triangulation, that region is the polygon of
/// the circumcentres of its triangles: where they lie in the picture, their
/// box is the site's box, and their largest circumradius a radius. Both are
/// the region's exact box and width (thesis Def. 3.2) when the strip holds its
/// Voronoi neighbours; the box is often half the radius's square, since a site
/// is rarely at the centre of its region. Circumcentres are widened by a
/// relative 1e-9 of their conditioning, so that rounding can only enlarge a
/// bound, and a strip whose triangulation is not Delaunay within that margin
/// is not trusted (see `strip_cell_bounds`).
///
/// The region of a site on the strip's hull is unbounded, and others cross the
/// picture's edge: the picture is clipped instead by the half-planes nearer to
/// s than to each of its neighbours, which leaves a polygon that contains the
/// region whichever sites cut. A site the triangulation leaves out (a
/// duplicate, every site of a collinear set) searches for its cutters ring by
/// ring of square bins of side `bin` (`searched_bound`).
///
/// Where sites are dense the radii shrink to the local spacing, while a site next
/// to an empty quarter still reaches across it: the thesis's worst case costs only
/// the cones that need the reach.
pub fn cell_bounds(sites: &[DVec2], frame: &Frame, bin: f64) -> Vec<CellBound> {
    let picture = picture_corners(frame);
    let mut bounds: Vec<Option<CellBound>> = vec![None; sites.len()];
    for strip in delaunay_strips(sites, frame, |strip| {
        strip_cell_bounds(sites, strip, &picture)
    }) {
        for (s, b) in strip {
            bounds[s as usize] = Some(b);
        }
    }
    let left_out: Vec<usize> = (0..sites.len()).filter(|&s| bounds[s].is_none()).collect();
    if !left_out.is_empty() {
        let bins = Grid::new(sites, frame, bin);
        let searched: Vec<CellBound> = left_out
            .par_iter()
            .map(|&s| searched_bound(&bins, sites[s], &picture))
            .collect();
        for (s, b) in left_out.into_iter().zip(searched) {
            bounds[s] = Some(b);
        }
    }
    bounds.into_iter().flatten().collect()
}

/// The bounds of [`cell_bounds`] for the sites a strip owns and triangulates.
///
/// The circumcentres describe the regions only if the triangulation is
/// Delaunay: every edge is checked (each triangle's circle holds neither
/// opposite corner, within the margin), and a strip that fails clips every
/// site by its neighbours instead, as it does the sites on its hull.
fn strip_cell_bounds(
    sites: &[DVec2],
    strip: &Strip<'_>,
    picture: &[DVec2; 4],
) -> Vec<(u32, CellBound)> {
    let (corners, twins) = (
        &strip.triangulation.triangles,
        &strip.triangulation.halfedges,
    );
    let points: Vec<DVec2> = strip.members.iter().map(|&i| sites[i as usize]).collect();
    let circles: Vec<Circumcircle> = corners
        .chunks_exact(3)
        .map(|t| Circumcircle::of(points[t[0]], points[t[1]], points[t[2]]))
        .collect();
    // Per member: the box of its triangles' circumcentres and their largest
    // circumradius (widened), whether it is in a triangle, and whether its
    // region is unbounded, crosses the picture's edge or is not to be trusted.
    let mut boxes = vec![(DVec2::INFINITY, DVec2::NEG_INFINITY, 0.0f64); points.len()];
    let mut in_triangle = vec![false; points.len()];
    let mut open = vec![false; points.len()];
    for (t, circle) in corners.chunks_exact(3).zip(&circles) {
        for &c in t {
            in_triangle[c] = true;
            let (lo, hi, r) = &mut boxes[c];
            *lo = lo.min(circle.centre - circle.error);
            *hi = hi.max(circle.centre + circle.error);
            *r = r.max(circle.radius + circle.error);
        }
    }
    let mut delaunay = circles.iter().all(|c| c.error.is_finite());
    for e in 0..corners.len() {
        let twin = twins[e];
        if twin == delaunator::EMPTY {
            open[corners[e]] = true;
            open[corners[delaunator::next_halfedge(e)]] = true;
        } else if e < twin {
            // One side's test answers for both.
            delaunay &= !circles[e / 3].holds(points[corners[delaunator::prev_halfedge(twin)]]);
        }
    }
    let (first, last) = (picture[0], picture[2]);
    for (open, (lo, hi, _)) in open.iter_mut().zip(&boxes) {
        *open |= !(delaunay && lo.cmpge(first).all() && hi.cmple(last).all());
    }
    // The cutters of the open members: their neighbours in the triangulation.
    let mut cutters: Vec<(usize, usize)> = Vec::new();
    for e in 0..corners.len() {
        let (a, b) = (corners[e], corners[delaunator::next_halfedge(e)]);
        if open[a] {
            cutters.push((a, b));
        }
        if open[b] && twins[e] == delaunator::EMPTY {
            cutters.push((b, a));
        }
    }
    cutters.sort_unstable();
    let mut bounds: Vec<(u32, CellBound)> = cutters
        .chunk_by(|x, y| x.0 == y.0)
        .filter(|run| strip.owns(strip.members[run[0].0]))
        .map(|run| {
            let site = points[run[0].0];
            let bound = clipped_bound(site, run.iter().map(|&(_, c)| points[c]), picture);
            (strip.members[run[0].0], bound)
        })
        .collect();
    bounds.extend(
        (0..points.len())
            .filter(|&m| in_triangle[m] && !open[m] && strip.owns(strip.members[m]))
            .map(|m| {
                let (lo, hi, radius) = boxes[m];
                (strip.members[m], CellBound { radius, lo, hi })
            }),
    );
    bounds
}

/// A triangle's circumcircle with a bound on its rounding error (infinite for
/// a degenerate triangle).
struct Circumcircle {
    centre: DVec2,
    radius: f64,
    error: f64,
}

impl Circumcircle {
    fn of(a: DVec2, b: DVec2, c: DVec2) -> Self {
        let (u, v) = (b - a, c - a);
        let d = 2.0 * u.perp_dot(v);
        let (uu, vv) = (u.length_squared(), v.length_squared());
        let inverse = 1.0 / d;
        let offset = DVec2::new(v.y * uu - u.y * vv, u.x * vv - v.x * uu) * inverse;
        // The offset divides terms of size |v| uu + |u| vv by d: its error grows
        // with that ratio (a flat triangle's is large), and with the coordinates.
        let spread = u.abs().max(v.abs()).max_element();
        let conditioning = 2.0 * spread * (uu + vv) * inverse.abs();
        let error = 1e-9 * (conditioning + a.abs().max_element() + 1.0);
        if offset.is_finite() && error.is_finite() {
            Self {
                centre: a + offset,
                radius: offset.length(),
                error,
            }
        } else {
            Self {
                centre: a,
                radius: 0.0,
                error: f64::INFINITY,
            }
        }
    }

    /// Whether `p` lies inside the circle by more than its error.
    fn holds(&self, p: DVec2) -> bool {
        let inner = self.radius - 2.0 * self.error;
        inner > 0.0 && (p - self.centre).length_squared() < inner * inner
    }
}

/// The bound of a polygon from the picture's corners (relative to `site`)
/// clipped by the half-planes nearer to `site` than to each of `cutters`.
fn clipped_bound(
    site: DVec2,
    cutters: impl Iterator<Item = DVec2>,
    picture: &[DVec2; 4],
) -> CellBound {
    let mut polygon = Polygon::new(picture.map(|v| v - site));
    for t in cutters {
        let d = t - site;
        if d != DVec2::ZERO {
            polygon.clip(d, half_plane_limit(d));
        }
    }
    polygon.bound(site)
}

/// The bound of [`cell_bounds`] for site `s`, its cutters searched ring by ring
/// of square `bins` (about one site each; sites outside the picture sit in the
/// nearest border bin: projecting onto the picture never brings two points
/// closer, so ring distances stay lower bounds). The search ends once every site
/// not yet seen is at least twice the radius away: its bisector lies beyond the
/// polygon.
fn searched_bound(bins: &Grid, s: DVec2, picture: &[DVec2; 4]) -> CellBound {
    let mut polygon = Polygon::new(picture.map(|v| v - s));
    let mut reach2 = polygon.farthest2();
    let [bx, by, _, _] = bins.bins_of(s, s);
    let mut ring = 0;
    while ring <= bins.max_ring() && ring_gap2(ring, bins.cell) < 4.0 * reach2 {
        bins.for_ring_bins([bx, by, bx, by], ring, |lo, hi, _, members| {
            // A bin wholly at twice the radius or more cannot cut.
            if reach2 == 0.0 || distance2_to_rect(s, lo, hi) >= 4.0 * reach2 {
                return;
            }
            for &t in members {
                let d = t - s;
                let dd = d.length_squared();
                if dd == 0.0 || dd >= 4.0 * reach2 {
                    continue;
                }
                if polygon.clip(d, half_plane_limit(d)) {
                    reach2 = polygon.farthest2();
                }
            }
        });
        ring += 1;
    }
    polygon.bound(s)
}

/// The picture's corner pixel centres.
fn picture_corners(frame: &Frame) -> [DVec2; 4] {
    let corner = DVec2::new((frame.width - 1) as f64, (frame.height - 1) as f64);
    [
        DVec2::ZERO,
        DVec2::new(corner.x, 0.0),
        corner,
        DVec2::new(0.0, corner.y),
    ]
}

/// The half-plane nearer to a site than to a site `d` away from it, relative to
/// the first: `v.d <= |d|² / 2`, widened so that rounding only enlarges it.
fn half_plane_limit(d: DVec2) -> f64 {
    0.5 * d.length_squared() * (1.0 + 1e-9) + 1e-9
}

/// Every site's Delaunay neighbours (delaunator, in strips: see
/// [`delaunay_strips`]), in compressed rows: those of site s are
/// `list[start[s]..start[s + 1]]`. Sites the triangulation leaves out
/// (duplicates, collinear sets) have none.
struct DelaunayNeighbours {
    start: Vec<u32>,
    list: Vec<u32>,
}

impl DelaunayNeighbours {
    fn of(sites: &[DVec2], frame: &Frame) -> Self {
        let edges = delaunay_strips(sites, frame, strip_edges);
        let (start, list) = group_by_bucket(
            sites.len(),
            edges.iter().flatten().map(|&(a, b)| (a as usize, b)),
        );
        Self { start, list }
    }

    fn of_site(&self, s: usize) -> &[u32] {
        &self.list[self.start[s] as usize..self.start[s + 1] as usize]
    }
}

/// A horizontal strip of the sites, triangulated: the sites it owns and those
/// within a few spacings beyond its edges (`members`, indices into the sites).
struct Strip<'a> {
    index: usize,
    /// Each site's strip.
    strip_of: &'a [usize],
    members: Vec<u32>,
    /// Of the members (`triangles` index `members`).
    triangulation: delaunator::Triangulation,
}

impl Strip<'_> {
    fn owns(&self, site: u32) -> bool {
        self.strip_of[site as usize] == self.index
    }
}

/// Sites per strip below which one triangulation is quicker.
const STRIP_SITES: usize = 1500;

/// `each` of the strips many sites are triangulated in, one per thread, at
/// once. A site takes what it needs from its own strip: near an edge its
/// triangles may miss a site beyond the margin, which can only leave its region
/// in the strip larger than among all sites.
fn delaunay_strips<T: Send>(
    sites: &[DVec2],
    frame: &Frame,
    each: impl Fn(&Strip<'_>) -> T + Sync,
) -> Vec<T> {
    let strips = (sites.len() / STRIP_SITES).clamp(1, rayon::current_num_threads().max(1));
    let height = frame.height as f64 / strips as f64;
    let margin = 4.0 * (frame.len() as f64 / sites.len().max(1) as f64).sqrt();
    let strip_of: Vec<usize> = sites
        .iter()
        .map(|p| ((p.y / height).floor().max(0.0) as usize).min(strips - 1))
        .collect();
    (0..strips)
        .into_par_iter()
        .map(|k| {
            let (top, bottom) = (k as f64 * height, (k + 1) as f64 * height);
            let members: Vec<u32> = (0..sites.len() as u32)
                .filter(|&i| {
                    let y = sites[i as usize].y;
                    strip_of[i as usize] == k
                        || (k > 0 && y >= top - margin && y < top)
                        || (k + 1 < strips && y >= bottom && y < bottom + margin)
                })
                .collect();
            let points: Vec<delaunator::Point> = members
                .iter()
                .map(|&i| {
                    let p = sites[i as usize];
                    delaunator::Point { x: p.x, y: p.y }
                })
                .collect();
            each(&Strip {
                index: k,
                strip_of: &strip_of,
                triangulation: delaunator::triangulate(&points),
                members,
            })
        })
        .collect()
}

/// The directed edges (a, b) of a strip's triangulation (site indices) whose
/// first end the strip owns.
fn strip_edges(strip: &Strip<'_>) -> Vec<(u32, u32)> {
    let (corners, twins) = (
        &strip.triangulation.triangles,
        &strip.triangulation.halfedges,
    );
    let mut edges = Vec::with_capacity(corners.len() + 64);
    let mut keep = |a: usize, b: usize| {
        let (a, b) = (strip.members[a], strip.members[b]);
        if strip.owns(a) {
            edges.push((a, b));
        }
    };
    // Half-edge e runs from corners[e] to the next corner of its triangle; an
    // edge of the hull has no twin, so its other direction is added here.
    for e in 0..corners.len() {
        let (a, b) = (corners[e], corners[delaunator::next_halfedge(e)]);
        keep(a, b);
        if twins[e] == delaunator::EMPTY {
            keep(b, a);
        }
    }
    edges
}

/// A radius per site for the k lowest layers of the arrangement (degree 1..k
/// diagrams): every pixel centre that has site s among its k nearest lies within
/// `radii[s]` of it.
///
/// The picture is cut into square cells of side `cell`. For a cell B, U(B) is the
/// k-th smallest over sites of the distance to B's farthest point: every point of
/// B has k sites within U(B), so a site among its k nearest is within U(B) of it
/// and has `mindist(s, B) <= U(B)`. Each such candidate needs
/// `min(U(B), maxdist(s, B))`. Sites are found through square bins of side `bin`.
///
/// With `stretch` > 1 the bound holds for a metric whose distances lie within
/// a factor `stretch` of each other relative to the Euclidean ones (the ratio of
/// its Euclidean bounds, `Metric::stretch`): a point whose k-th nearest site is
/// within Euclidean U has its k metric-nearest within Euclidean `stretch * U`.
pub fn k_local_radii(
    sites: &[DVec2],
    frame: &Frame,
    k: usize,
    cell: f64,
    bin: f64,
    stretch: f64,
) -> Vec<f64> {
    local_regions_by(sites, frame, k, cell, bin, Measure::euclidean(stretch))
        .into_iter()
        .map(|r| r.reach)
        .collect()
}

/// Where a site's region lies: every pixel centre the site owns is within
/// `reach` of it (in the metric measured) and inside the box `[lo, hi]` of
/// pixel centres (empty, `lo > hi`, for a site that owns none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    pub reach: f64,
    pub lo: DVec2,
    pub hi: DVec2,
}

/// [`k_local_radii`] for the nearest site under `metric`, as distances in the
/// metric itself, with the box of the cells where each site may own a pixel.
/// Measured directly, which for p far from 2 is much tighter than stretching
/// Euclidean bounds (L0.5 stretches them by 2.83). `None` for polygon gauges,
/// which need not grow with each coordinate.
pub fn local_metric_regions(sites: &[DVec2], frame: &Frame, metric: Metric) -> Option<Vec<Region>> {
    // Cells twice as wide as for the Euclidean cover: at 16000 sites a quarter
    // of the cells halved the time of L_p bounds and of the whole L3 fan diagram
    // (radii 15% longer), and changed nothing at 2000.
    let (cell, bin) = k_cell_and_bin(frame, sites.len(), 1);
    let cell = 2.0 * cell;
    let keys = LpKeys::of(metric);
    Measure::native(metric, keys.as_ref())
        .map(|measure| local_regions_by(sites, frame, 1, cell, bin, measure))
}

/// The sites that the square screen tiles of a picture must consider for their
/// pixels' nearest site: every site within U(T) of tile T, where U(T) is the
/// smallest distance within which some site holds the whole tile. Tile `t`
/// covers the pixel centres from `(t % across, t / across) * side`, `side` on
/// each side (fewer at the right and bottom edges).
#[derive(Clone, Debug)]
pub struct TileCandidates {
    pub across: usize,
    pub side: u32,
    /// Tile `t`'s sites are `items[start[t]..start[t + 1]]`.
    pub start: Vec<u32>,
    pub items: Vec<u32>,
    /// Per site, the farthest (in the metric) it may own a pixel: 0 where it
    /// owns none.
    pub reaches: Vec<f64>,
}

/// [`TileCandidates`] under `metric` (any but polygon gauges, `None` then), the
/// sites in pixel coordinates: a tile's candidates are found as a cover cell's
/// are (`Grid::k_candidates`), with no region bounded per site.
pub fn tile_candidates(
    sites: &[DVec2],
    frame: &Frame,
    side: u32,
    metric: Metric,
) -> Option<TileCandidates> {
    let keys = LpKeys::of(metric);
    let measure = Measure::native(metric, keys.as_ref())?;
    let side = side.max(1);
    let across = frame.width.div_ceil(side) as usize;
    let down = frame.height.div_ceil(side) as usize;
    let (_, bin) = k_cell_and_bin(frame, sites.len(), 1);
    let bins = Grid::new(sites, frame, bin.max(side as f64));
    let corner = DVec2::new((frame.width - 1) as f64, (frame.height - 1) as f64);
    let radii = Radii::new(sites.len());
    // Blocks of BLOCK x BLOCK tiles search the grid once; each tile then takes
    // its own U(T) and list from the block's candidates (a site that can own a
    // pixel of the tile, or that holds the whole tile nearest, is one of them:
    // U(T) <= U(B)). One row of blocks per task: per tile row, the lists'
    // lengths and items.
    const BLOCK: usize = 2;
    let rows: Vec<Vec<(Vec<u32>, Vec<u32>)>> = (0..down.div_ceil(BLOCK))
        .into_par_iter()
        .map_init(
            || (Vec::new(), Vec::new()),
            |(candidates, nearest), by| {
                let rows = (BLOCK * by..(BLOCK * (by + 1)).min(down)).len();
                let mut out = vec![(Vec::with_capacity(across), Vec::new()); rows];
                for bx in 0..across.div_ceil(BLOCK) {
                    let tile_lo =
                        |t: [usize; 2]| DVec2::new(t[0] as f64, t[1] as f64) * side as f64;
                    let lo = tile_lo([BLOCK * bx, BLOCK * by]);
                    let hi = (lo + (BLOCK as u32 * side - 1) as f64).min(corner);
                    bins.k_candidates(lo, hi, 1, measure, candidates, nearest);
                    for (r, (counts, items)) in out.iter_mut().enumerate() {
                        for tx in BLOCK * bx..(BLOCK * (bx + 1)).min(across) {
                            let lo = tile_lo([tx, BLOCK * by + r]);
                            let hi = (lo + (side - 1) as f64).min(corner);
                            let cover = candidates
                                .iter()
                                .map(|&(_, p)| measure.farthest_below(p, lo, hi, f64::INFINITY))
                                .fold(f64::INFINITY, f64::min);
                            let before = items.len();
                            for &(i, p) in candidates.iter() {
                                if measure.nearest_within(p, lo, hi, cover) {
                                    radii.raise(i, measure.farthest_below(p, lo, hi, cover));
                                    items.push(i);
                                }
                            }
                            counts.push((items.len() - before) as u32);
                        }
                    }
                }
                out
            },
        )
        .collect();
    let mut start = Vec::with_capacity(across * down + 1);
    start.push(0u32);
    let mut items = Vec::with_capacity(rows.iter().flatten().map(|r| r.1.len()).sum());
    for (counts, row) in rows.into_iter().flatten() {
        for c in counts {
            start.push(start[start.len() - 1] + c);
        }
        items.extend(row);
    }
    Some(TileCandidates {
        across,
        side,
        start,
        items,
        reaches: radii.into_radii(measure),
    })
}

fn local_regions_by(
    sites: &[DVec2],
    frame: &Frame,
    k: usize,
    cell: f64,
    bin: f64,
    measure: Measure,
) -> Vec<Region> {
    // Whole pixels: then [lo, hi] below holds exactly the cell's pixel centres.
    let cell = cell.round().max(1.0);
    let bins = Grid::new(sites, frame, bin.max(cell));
    let nx = (frame.width as f64 / cell).ceil() as usize;
    let ny = (frame.height as f64 / cell).ceil() as usize;
    let corner = DVec2::new((frame.width - 1) as f64, (frame.height - 1) as f64);
    let radii = Radii::new(sites.len());
    let boxes = CellBoxes::new(sites.len());
    (0..ny).into_par_iter().for_each_init(
        || (Vec::new(), Vec::new()),
        |(candidates, nearest), cy| {
            for cx in 0..nx {
                let lo = DVec2::new(cx as f64, cy as f64) * cell;
                let hi = (lo + cell - 1.0).min(corner).max(lo);
                let cover = bins.k_candidates(lo, hi, k, measure, candidates, nearest);
                for &(i, p) in candidates.iter() {
                    radii.raise(i, measure.farthest_below(p, lo, hi, cover));
                    boxes.include(i, cx as u32, cy as u32);
                }
            }
        },
    );
    radii
        .into_radii(measure)
        .into_iter()
        .zip(boxes.into_boxes(cell, corner))
        .map(|(reach, (lo, hi))| Region { reach, lo, hi })
        .collect()
}

/// How [`Grid::k_candidates`] measures sites against rectangles: by the keys of
/// a metric that grows with the size of each coordinate and is 1 on the axes
/// (L1, L2, L∞, L_p), so that a rectangle's nearest and farthest points are found
/// coordinate by coordinate, and a site `g` cells away along an axis is at least
/// `g` away. U(B) is then widened by `stretch`, a factor on distances (1 when the
/// metric is the diagram's own). L_p keys come as bounds ([`LpKeys`]): farthest
/// points from above, nearest from below, so that every bound only widens.
#[derive(Clone, Copy, Debug)]
struct Measure<'a> {
    metric: Metric,
    stretch: f64,
    lp: Option<&'a LpKeys>,
}

impl<'a> Measure<'a> {
    fn euclidean(stretch: f64) -> Self {
        Self {
            metric: Metric::L2,
            stretch,
            lp: None,
        }
    }

    /// The metric measured directly (L_p through `lp`); `None` for polygon
    /// gauges, which need not grow with each coordinate.
    fn native(metric: Metric, lp: Option<&'a LpKeys>) -> Option<Self> {
        match metric {
            Metric::Polygon(_) => None,
            _ => Some(Self {
                metric,
                stretch: 1.0,
                lp,
            }),
        }
    }

    /// A key at most, or at least (`above`), that of offset `d`.
    fn key(self, d: DVec2, above: bool) -> f64 {
        match self.lp {
            Some(LpKeys::Table(table)) => table.bound(d, above),
            Some(&LpKeys::PowerSum(doubled)) => power_sum(d, doubled, above),
            None => self.metric.key(d),
        }
    }

    /// The distance of `key` (at least).
    fn distance_of_key(self, key: f64) -> f64 {
        match self.lp {
            Some(&LpKeys::PowerSum(doubled)) => key.powf(2.0 / doubled as f64) * (1.0 + 1e-12),
            _ => self.metric.distance_of_key(key),
        }
    }

    /// Whether the nearest point of `[lo, hi]` is within key `cover` of `p`.
    fn nearest_within(self, p: DVec2, lo: DVec2, hi: DVec2, cover: f64) -> bool {
        self.key(p.clamp(lo, hi) - p, false) <= cover
    }

    /// The key of the farthest point of `[lo, hi]` from `p`, or `cap` if that is
    /// smaller.
    fn farthest_below(self, p: DVec2, lo: DVec2, hi: DVec2, cap: f64) -> f64 {
        let offset = (p - (lo + hi) * 0.5).abs() + (hi - lo) * 0.5;
        self.key(offset, true).min(cap)
    }

    /// The key of U(B), widened by the stretch (and by a hair, so that the
    /// rounding of the widening only enlarges it).
    fn widen(self, cover: f64) -> f64 {
        if self.stretch == 1.0 {
            cover
        } else {
            let distance = self.metric.distance_of_key(cover) * self.stretch;
            self.metric.key_of_distance(distance) * (1.0 + 1e-12)
        }
    }

    /// A lower bound on the keys of the sites `ring` cells of side `cell` away
    /// (at least `ring - 1` cells along one axis).
    fn ring_gap(self, ring: usize, cell: f64) -> f64 {
        if ring == 0 {
            f64::NEG_INFINITY
        } else {
            let gap = (ring as f64 - 1.0).max(0.0) * cell;
            self.key(DVec2::new(gap, 0.0), false)
        }
    }
}

/// The sites that square screen tiles must consider for the k lowest layers,
/// and the radii [`k_local_radii`] gives with cells of a quarter tile's side.
#[derive(Clone, Debug, Default)]
pub struct TileLists {
    /// Tiles per row; tile `t` covers the pixel centres from
    /// `(t % across, t / across) * side`, `side` pixels on each side (fewer at
    /// the picture's right and bottom edges).
    pub across: usize,
    pub side: u32,
    /// Per tile, the sites among the k nearest of one of its pixels (and maybe
    /// others), nearest to the tile's centre first; ties by index.
    pub lists: Vec<Vec<u32>>,
    pub radii: Vec<f64>,
}

impl TileLists {
    /// The first and last pixel centre of tile `t`.
    pub fn rect(&self, t: usize, frame: &Frame) -> (DVec2, DVec2) {
        let corner = DVec2::new((frame.width - 1) as f64, (frame.height - 1) as f64);
        let lo = DVec2::new((t % self.across) as f64, (t / self.across) as f64) * self.side as f64;
        (lo, (lo + (self.side - 1) as f64).min(corner))
    }
}

/// [`k_local_radii`] computed tile by tile, which also gives each tile's list
/// of sites directly. A tile's candidates are found once, by the same bound
/// U(T) the cells use; every cell B inside the tile then takes its own U(B)
/// from them: `maxdist(s, B) <= maxdist(s, T)` makes U(B) <= U(T) and puts every
/// site with `mindist(s, B) <= U(B)` among the tile's candidates. A tile's list
/// holds the candidates of its cells.
pub fn k_tile_lists(
    sites: &[DVec2],
    frame: &Frame,
    k: usize,
    side: u32,
    stretch: f64,
) -> TileLists {
    let stretch2 = stretch * stretch;
    let k = k.max(1);
    let side = side.max(1);
    let across = frame.width.div_ceil(side) as usize;
    let down = frame.height.div_ceil(side) as usize;
    let (_, bin) = k_cell_and_bin(frame, sites.len(), k);
    let bins = Grid::new(sites, frame, bin.max(side as f64));
    let radii = Radii::new(sites.len());
    let mut tiles = TileLists {
        across,
        side,
        ..Default::default()
    };
    let cell = side.div_ceil(4).max(1) as f64;
    tiles.lists = (0..across * down)
        .into_par_iter()
        .map_init(
            || (Vec::new(), Vec::new(), Vec::new()),
            |(candidates, nearest, keep), t| {
                let (lo, hi) = tiles.rect(t, frame);
                bins.k_candidates(lo, hi, k, Measure::euclidean(stretch), candidates, nearest);
                keep.clear();
                keep.resize(candidates.len(), false);
                let mut y = lo.y;
                while y <= hi.y {
                    let mut x = lo.x;
                    while x <= hi.x {
                        let a = DVec2::new(x, y);
                        let b = (a + cell - 1.0).min(hi);
                        nearest.clear();
                        nearest.extend(candidates.iter().map(|&(_, p)| farthest2_in_rect(p, a, b)));
                        let cover2 = if nearest.len() >= k {
                            *nearest.select_nth_unstable_by(k - 1, f64::total_cmp).1
                        } else {
                            f64::INFINITY
                        } * stretch2;
                        for (c, &(i, p)) in candidates.iter().enumerate() {
                            if distance2_to_rect(p, a, b) <= cover2 {
                                keep[c] = true;
                                radii.raise(i, cover2.min(farthest2_in_rect(p, a, b)));
                            }
                        }
                        x += cell;
                    }
                    y += cell;
                }
                let centre = (lo + hi) * 0.5;
                let mut list: Vec<(f64, u32)> = candidates
                    .iter()
                    .zip(keep.iter())
                    .filter(|(_, &keep)| keep)
                    .map(|(&(i, p), _)| (p.distance_squared(centre), i))
                    .collect();
                list.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                list.into_iter().map(|(_, i)| i).collect()
            },
        )
        .collect();
    tiles.radii = radii.into_radii(Measure::euclidean(1.0));
    tiles
}

/// How L_p keys are bounded: where 2p is whole (up to
/// [`DepthKey::MAX_DOUBLED_P`], as the shaders' power-sum keys), as the sum of
/// the coordinates' p-th powers, from products and a square root; else as
/// distances from an [`LpTable`]. The sums build no table, and bound faster
/// (docs/tuning.md, "Measured choices").
#[derive(Debug)]
enum LpKeys {
    Table(LpTable),
    /// Twice p.
    PowerSum(u32),
}

impl LpKeys {
    fn of(metric: Metric) -> Option<Self> {
        match metric {
            Metric::Lp(p)
                if (2.0 * p).fract() == 0.0 && 2.0 * p <= DepthKey::MAX_DOUBLED_P as f64 =>
            {
                Some(Self::PowerSum((2.0 * p) as u32))
            }
            Metric::Lp(p) => Some(Self::Table(LpTable::new(p))),
            _ => None,
        }
    }
}

/// |d.x|^p + |d.y|^p for p = `doubled` / 2, widened by a hair below or
/// (`above`) above its rounding.
fn power_sum(d: DVec2, doubled: u32, above: bool) -> f64 {
    let power = |x: f64| {
        let root = if doubled % 2 == 1 { x.sqrt() } else { 1.0 };
        (0..doubled / 2).fold(root, |r, _| r * x)
    };
    let sum = power(d.x.abs()) + power(d.y.abs());
    sum * if above { 1.0 + 1e-12 } else { 1.0 - 1e-12 }
}

/// Bounds on L_p distances without powers: the distance of an offset is m g(t)
/// for its larger and smaller coordinate sizes m and n, t = n / m, with
/// g(t) = (1 + t^p)^(1/p) increasing on [0, 1]. The table holds g at every
/// float32 t whose 16 low bits are zero: above the smallest normal float32,
/// neighbouring entries are under 0.8% apart in t and, as
/// d ln g / d ln t = t^p / (1 + t^p) <= 1, in g, for every p. Below it (but for
/// t = 0, where the distance is m) the distance is computed. Costs a few
/// nanoseconds where two powers cost about a hundred.
#[derive(Debug)]
struct LpTable {
    p: f64,
    g: Vec<f64>,
}

impl LpTable {
    /// Entries up to just past t = 1 (float32 bits 0x3F80_0000).
    const LEN: u32 = 0x3F82;
    /// Ratios below this are computed (twice the smallest normal float32, so
    /// that the rounding margins keep them normal).
    const SMALLEST: f64 = 2.0 * f32::MIN_POSITIVE as f64;

    fn new(p: f64) -> Self {
        let g = (0..Self::LEN)
            .map(|i| Self::exact(p, f64::from(f32::from_bits(i << 16))))
            .collect();
        Self { p, g }
    }

    fn exact(p: f64, t: f64) -> f64 {
        (1.0 + t.powf(p)).powf(1.0 / p)
    }

    /// The distance of `d`, bounded from below or (`above`) from above: the
    /// larger coordinate size times g at the table entries around t.
    fn bound(&self, d: DVec2, above: bool) -> f64 {
        let a = d.abs();
        let m = a.x.max(a.y);
        let t = if m > 0.0 { a.x.min(a.y) / m } else { 0.0 };
        if t == 0.0 {
            return m;
        }
        if t < Self::SMALLEST {
            return m * Self::exact(self.p, t);
        }
        // Rounding margins move t outwards first; float32 bits order like the
        // values for t >= 0, so cutting the low bits takes the bin's lower end.
        let (margin, next, guard) = if above {
            (1.0 + 1e-6, 1, 1.0 + 1e-12)
        } else {
            (1.0 - 1e-6, 0, 1.0 - 1e-12)
        };
        let bin = (((t * margin).min(1.0) as f32).to_bits() >> 16) as usize;
        m * self.g[bin + next] * guard
    }
}

/// Radii raised from many threads: their metric's keys (squared radii for L2) as
/// bits, since non-negative floats order like their bit patterns, so `fetch_max`
/// on them is a maximum.
struct Radii(Vec<AtomicU64>);

impl Radii {
    fn new(n: usize) -> Self {
        Self((0..n).map(|_| AtomicU64::new(0)).collect())
    }

    fn raise(&self, i: u32, key: f64) {
        let need = key.to_bits();
        // Most candidates do not raise the radius; a plain load is far cheaper
        // than fetch_max.
        let r = &self.0[i as usize];
        if r.load(Ordering::Relaxed) < need {
            r.fetch_max(need, Ordering::Relaxed);
        }
    }

    fn into_radii(self, measure: Measure) -> Vec<f64> {
        self.0
            .into_iter()
            .map(|r| measure.distance_of_key(f64::from_bits(r.into_inner())))
            .collect()
    }
}

/// Per site, the smallest and largest column and row of the cells it may own a
/// pixel of, raised from many threads.
struct CellBoxes(Vec<[AtomicU32; 4]>);

impl CellBoxes {
    fn new(n: usize) -> Self {
        Self(
            (0..n)
                .map(|_| [u32::MAX, u32::MAX, 0, 0].map(AtomicU32::new))
                .collect(),
        )
    }

    fn include(&self, i: u32, cx: u32, cy: u32) {
        let [x0, y0, x1, y1] = &self.0[i as usize];
        // As in `Radii::raise`: plain loads first, most cells change nothing.
        for (bound, v, lower) in [
            (x0, cx, true),
            (y0, cy, true),
            (x1, cx, false),
            (y1, cy, false),
        ] {
            let b = bound.load(Ordering::Relaxed);
            if lower && v < b {
                bound.fetch_min(v, Ordering::Relaxed);
            } else if !lower && v > b {
                bound.fetch_max(v, Ordering::Relaxed);
            }
        }
    }

    /// The boxes' pixel centres, for cells of side `cell` and the picture's last
    /// pixel centre `corner`; `lo > hi` for a site in no cell.
    fn into_boxes(self, cell: f64, corner: DVec2) -> impl Iterator<Item = (DVec2, DVec2)> {
        self.0.into_iter().map(move |b| {
            let [x0, y0, x1, y1] = b.map(|v| v.into_inner() as f64);
            if x0 > x1 {
                return (DVec2::ONE, DVec2::ZERO);
            }
            (
                DVec2::new(x0, y0) * cell,
                (DVec2::new(x1, y1) * cell + cell - 1.0).min(corner),
            )
        })
    }
}

/// Cell and bin sides for [`k_local_radii`]: the k-th neighbour is about
/// `sqrt k` spacings away, so cells are a sixth of that and bins that wide
/// (at least 2 pixels; at most about 4 million cells).
pub fn k_cell_and_bin(frame: &Frame, sites: usize, k: usize) -> (f64, f64) {
    let reach = (frame.len() as f64 * k.max(1) as f64 / sites.max(1) as f64).sqrt();
    let least = (frame.len() as f64 / (1u64 << 22) as f64).sqrt();
    ((reach / 6.0).max(2.0).max(least), reach.max(2.0).max(least))
}

/// A convex polygon of bounded size on the stack, with room for one clip.
struct Polygon {
    len: usize,
    /// The corners are `buffers[current][..len]`; a clip writes the other buffer
    /// and flips (no copy back).
    current: usize,
    buffers: [[DVec2; Polygon::CAPACITY]; 2],
}

impl Polygon {
    const CAPACITY: usize = 32;

    fn new(corners: [DVec2; 4]) -> Self {
        let mut polygon = Self {
            len: 4,
            current: 0,
            buffers: [[DVec2::ZERO; Self::CAPACITY]; 2],
        };
        polygon.buffers[0][..4].copy_from_slice(&corners);
        polygon
    }

    fn corners(&self) -> &[DVec2] {
        &self.buffers[self.current][..self.len]
    }

    /// The smallest and largest coordinates of the corners; both 0 when empty.
    fn bounding_box(&self) -> (DVec2, DVec2) {
        let corners = self.corners();
        if corners.is_empty() {
            return (DVec2::ZERO, DVec2::ZERO);
        }
        corners
            .iter()
            .fold((DVec2::MAX, DVec2::MIN), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            })
    }

    /// The radius and box of a polygon around `site` (corners relative to it).
    fn bound(&self, site: DVec2) -> CellBound {
        let (lo, hi) = self.bounding_box();
        CellBound {
            radius: self.farthest2().sqrt(),
            lo: site + lo,
            hi: site + hi,
        }
    }

    /// Squared distance of the farthest corner from the origin; 0 when empty.
    fn farthest2(&self) -> f64 {
        self.corners()
            .iter()
            .map(|v| v.length_squared())
            .fold(0.0, f64::max)
    }

    /// Clips to `v.normal <= limit` (Sutherland–Hodgman); returns whether anything
    /// was cut. A clip that would overflow the capacity is skipped, which only
    /// leaves the polygon larger.
    fn clip(&mut self, normal: DVec2, limit: f64) -> bool {
        if self.len == Self::CAPACITY || self.corners().iter().all(|v| v.dot(normal) <= limit) {
            return false;
        }
        let [first, second] = &mut self.buffers;
        let (from, to) = if self.current == 0 {
            (&first[..self.len], second)
        } else {
            (&second[..self.len], first)
        };
        let mut n = 0;
        clip_convex(from, normal, limit, |v| {
            to[n] = v;
            n += 1;
        });
        self.current = 1 - self.current;
        self.len = n;
        true
    }
}

/// Squared lower bound on the distance from a cell to sites `ring` cells away.
fn ring_gap2(ring: usize, cell: f64) -> f64 {
    let gap = (ring as f64 - 1.0).max(0.0) * cell;
    if ring == 0 {
        f64::NEG_INFINITY
    } else {
        gap * gap
    }
}

/// Site indices binned into square cells over the picture's pixel centres.
struct Grid {
    cell: f64,
    nx: usize,
    ny: usize,
    /// Sites of cell (x, y) are `order[start[y * nx + x]..start[y * nx + x + 1]]`,
    /// their positions at the same indices of `position`.
    start: Vec<u32>,
    order: Vec<u32>,
    position: Vec<DVec2>,
}

impl Grid {
    /// The candidates of the rectangle B = `[lo, hi]` for the k lowest layers
    /// (see [`k_local_radii`]): into `candidates` every site within U(B) of B,
    /// both as `measure` keys; returns U(B)'s key, widened by the measure's
    /// stretch (infinite when there are fewer than k sites). `nearest` is
    /// scratch.
    fn k_candidates(
        &self,
        lo: DVec2,
        hi: DVec2,
        k: usize,
        measure: Measure,
        candidates: &mut Vec<(u32, DVec2)>,
        nearest: &mut Vec<f64>,
    ) -> f64 {
        let k = k.max(1);
        let rect = self.bins_of(lo, hi);
        // U(B): rings of bins until no farther ring can hold one of the k
        // closest (a site in ring r is at least r - 1 bins away).
        candidates.clear();
        nearest.clear();
        let mut cover = f64::INFINITY;
        let mut ring = 0;
        while ring <= self.max_ring() && measure.ring_gap(ring, self.cell) < cover {
            self.for_ring_bins(rect, ring, |_, _, indices, positions| {
                for (&i, &p) in indices.iter().zip(positions) {
                    // Only a site that could be among the k closest needs its key.
                    let kth = if nearest.len() == k {
                        nearest[k - 1]
                    } else {
                        f64::INFINITY
                    };
                    let d = measure.farthest_below(p, lo, hi, kth);
                    candidates.push((i, p));
                    let at = nearest.partition_point(|&x| x < d);
                    if at < k {
                        nearest.insert(at, d);
                        nearest.truncate(k);
                    }
                }
            });
            if nearest.len() == k {
                cover = nearest[k - 1];
            }
            ring += 1;
        }
        let cover = measure.widen(cover);
        candidates.retain(|&(_, p)| measure.nearest_within(p, lo, hi, cover));
        while ring <= self.max_ring() && measure.ring_gap(ring, self.cell) <= cover {
            self.for_ring_bins(rect, ring, |_, _, indices, positions| {
                for (&i, &p) in indices.iter().zip(positions) {
                    if measure.nearest_within(p, lo, hi, cover) {
                        candidates.push((i, p));
                    }
                }
            });
            ring += 1;
        }
        cover
    }

    fn new(sites: &[DVec2], frame: &Frame, cell: f64) -> Self {
        let cell = cell.max(1.0);
        let nx = (frame.width as f64 / cell).ceil().max(1.0) as usize;
        let ny = (frame.height as f64 / cell).ceil().max(1.0) as usize;
        let index = |p: DVec2| {
            let ix = ((p.x + 0.5) / cell).floor().clamp(0.0, (nx - 1) as f64) as usize;
            let iy = ((p.y + 0.5) / cell).floor().clamp(0.0, (ny - 1) as f64) as usize;
            iy * nx + ix
        };
        let (start, order) = group_by_bucket(
            nx * ny,
            sites.iter().enumerate().map(|(i, p)| (index(*p), i as u32)),
        );
        let position = order.iter().map(|&i| sites[i as usize]).collect();
        Self {
            cell,
            nx,
            ny,
            start,
            order,
            position,
        }
    }

    /// The rectangle of bins `[x0, x1] x [y0, y1]` holding the points of `[lo, hi]`.
    fn bins_of(&self, lo: DVec2, hi: DVec2) -> [isize; 4] {
        let index =
            |v: f64, n: usize| ((v + 0.5) / self.cell).floor().clamp(0.0, (n - 1) as f64) as isize;
        [
            index(lo.x, self.nx),
            index(lo.y, self.ny),
            index(hi.x, self.nx),
            index(hi.y, self.ny),
        ]
    }

    fn max_ring(&self) -> usize {
        self.nx.max(self.ny)
    }

    /// Calls `f(lo, hi, indices, positions)` for every bin at Chebyshev distance
    /// `ring` from the bin rectangle `[x0, y0, x1, y1]`: the bin's corners (pixel
    /// coordinates, widened by half a pixel) and its sites.
    fn for_ring_bins(
        &self,
        rect: [isize; 4],
        ring: usize,
        mut f: impl FnMut(DVec2, DVec2, &[u32], &[DVec2]),
    ) {
        for_ring_cells((self.nx, self.ny), rect, ring, |x, y| {
            let k = y * self.nx + x;
            let (from, to) = (self.start[k] as usize, self.start[k + 1] as usize);
            let lo = DVec2::new(x as f64, y as f64) * self.cell - 0.5;
            f(
                lo,
                lo + self.cell,
                &self.order[from..to],
                &self.position[from..to],
            );
        });
    }
}

/// The bin side for [`cell_bounds`]: the mean site spacing, so that a bin holds
/// about one site (at least 2 pixels, and at most about 4 million bins).
pub fn default_bin(frame: &Frame, sites: usize) -> f64 {
    let spacing = (frame.len() as f64 / sites.max(1) as f64).sqrt();
    let least = (frame.len() as f64 / (1u64 << 22) as f64).sqrt();
    spacing.max(2.0).max(least)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nearest(sites: &[DVec2], q: DVec2) -> f64 {
        sites
            .iter()
            .map(|s| (*s - q).length())
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn cell_bounds_hold_every_owned_pixel() {
        let frame = Frame::pixels(61, 47).unwrap();
        // Clustered in one quarter, a regular row, duplicates, a co-circular
        // lattice and sites outside the picture.
        let mut sites: Vec<DVec2> = (0..40)
            .map(|i| DVec2::new((i * 7 % 23) as f64 * 0.9, (i * 11 % 19) as f64 * 1.1))
            .collect();
        sites.extend((0..6).map(|i| DVec2::new(10.0 * i as f64, 40.0)));
        sites.extend(
            (0..9).map(|i| DVec2::new(40.0 + 5.0 * (i % 3) as f64, 20.0 + 5.0 * (i / 3) as f64)),
        );
        sites.extend([
            DVec2::new(80.0, -10.0),
            DVec2::new(-3.0, 30.0),
            DVec2::new(30.0, 47.2),
            DVec2::new(30.0, 47.2),
        ]);
        for bin in [1.0, 2.5, 7.0, 64.0] {
            let bounds = cell_bounds(&sites, &frame, bin);
            assert_bounds_hold_owned_pixels(&sites, &frame, &bounds, &format!("bin {bin}"));
        }
    }

    /// A nearest site of every pixel (under the metric) is in its tile's list,
    /// and reaches the pixel.
    #[test]
    fn tile_candidates_list_every_owner() {
        let (frame, sites) = awkward_sites();
        for metric in [
            Metric::L2,
            Metric::L1,
            Metric::LInf,
            Metric::Lp(0.5),
            Metric::Lp(3.0),
        ] {
            for side in [1, 8, 13] {
                let tiles = tile_candidates(&sites, &frame, side, metric).unwrap();
                for y in 0..frame.height {
                    for x in 0..frame.width {
                        let q = DVec2::new(x as f64, y as f64);
                        let d = sites
                            .iter()
                            .map(|s| metric.distance(*s - q))
                            .fold(f64::INFINITY, f64::min);
                        let t = (y / side) as usize * tiles.across + (x / side) as usize;
                        let list =
                            &tiles.items[tiles.start[t] as usize..tiles.start[t + 1] as usize];
                        // Equal distances may round either way in the
                        // bounds: one of the nearest suffices.
                        let listed = list
                            .iter()
                            .map(|&i| (metric.distance(sites[i as usize] - q), i as usize))
                            .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
                        assert!(
                            listed.0 <= d * (1.0 + 1e-12),
                            "{metric} side {side}: pixel {q}: nearest listed at {}, nearest at {d}",
                            listed.0
                        );
                        assert!(
                            listed.0 <= tiles.reaches[listed.1] * (1.0 + 1e-9),
                            "{metric} side {side}: pixel {q}: site {} at {} beyond {}",
                            listed.1,
                            listed.0,
                            tiles.reaches[listed.1]
                        );
                    }
                }
            }
        }
    }

    /// Every pixel centre lies within the radius and inside the box of each of
    /// its nearest sites.
    fn assert_bounds_hold_owned_pixels(
        sites: &[DVec2],
        frame: &Frame,
        bounds: &[CellBound],
        what: &str,
    ) {
        for y in 0..frame.height {
            for x in 0..frame.width {
                let q = DVec2::new(x as f64, y as f64);
                let d = nearest(sites, q);
                for (i, s) in sites.iter().enumerate() {
                    if ((*s - q).length() - d).abs() < 1e-12 {
                        let b = &bounds[i];
                        assert!(
                            d <= b.radius + 1e-9,
                            "{what}: pixel {q} site {i} at {d} > {}",
                            b.radius
                        );
                        assert!(
                            q.cmpge(b.lo - 1e-9).all() && q.cmple(b.hi + 1e-9).all(),
                            "{what}: pixel {q} of site {i} outside {b:?}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn cell_bounds_from_strips_hold_every_owned_pixel() {
        // Enough sites for one triangulation per thread: a lattice across the
        // strips' edge (co-circular everywhere), random sites, duplicates and
        // a collinear run.
        let frame = Frame::pixels(120, 90).unwrap();
        let mut sites = frame.random_points(1800, 11);
        sites.extend((0..1200).map(|i| DVec2::new((i % 40) as f64 * 3.0, 30.0 + (i / 40) as f64)));
        sites.extend_from_within(..200);
        sites.extend((0..100).map(|i| DVec2::new(i as f64 * 1.2, 45.0)));
        let bounds = cell_bounds(&sites, &frame, default_bin(&frame, sites.len()));
        assert_bounds_hold_owned_pixels(&sites, &frame, &bounds, "strips");
    }

    #[test]
    fn cell_bounds_are_the_region_boxes() {
        // Every site's box is its region's (clipped by every other site) box
        // within the picture, whether from circumcentres or clipping, up to
        // the margins for rounding.
        let frame = Frame::pixels(200, 150).unwrap();
        let sites = frame.random_points(300, 3);
        let bounds = cell_bounds(&sites, &frame, default_bin(&frame, sites.len()));
        let picture = picture_corners(&frame);
        let mut inside = 0;
        for (i, b) in bounds.iter().enumerate() {
            let exact = clipped_bound(sites[i], sites.iter().copied(), &picture);
            assert!(
                (b.lo - exact.lo).abs().max_element() < 1e-4
                    && (b.hi - exact.hi).abs().max_element() < 1e-4,
                "site {i}: {b:?} against {exact:?}"
            );
            inside += usize::from(b.lo.cmpgt(picture[0]).all() && b.hi.cmplt(picture[2]).all());
        }
        assert!(inside > 200, "only {inside} regions inside the picture");
    }

    #[test]
    fn a_triangulation_that_is_not_delaunay_is_not_trusted() {
        // A lattice is co-circular everywhere, so its triangulation takes either
        // diagonal of each square; with its sites moved by up to 8 pixels
        // (of 10 between them), many of those triangles are wrong.
        let frame = Frame::pixels(80, 80).unwrap();
        let lattice: Vec<DVec2> = (0..64)
            .map(|i| DVec2::new((i % 8) as f64 * 10.0 + 4.0, (i / 8) as f64 * 10.0 + 4.0))
            .collect();
        let points: Vec<delaunator::Point> = lattice
            .iter()
            .map(|p| delaunator::Point { x: p.x, y: p.y })
            .collect();
        let jitter = Frame::pixels(2, 2).unwrap().random_points(64, 9);
        let sites: Vec<DVec2> = lattice
            .iter()
            .zip(&jitter)
            .map(|(p, j)| *p + (*j - 0.5) * 8.0)
            .collect();
        let strip_of = vec![0; sites.len()];
        let strip = Strip {
            index: 0,
            strip_of: &strip_of,
            members: (0..sites.len() as u32).collect(),
            triangulation: delaunator::triangulate(&points),
        };
        let mut bounds = vec![
            CellBound {
                radius: 0.0,
                lo: DVec2::ZERO,
                hi: DVec2::ZERO
            };
            sites.len()
        ];
        let strip_bounds = strip_cell_bounds(&sites, &strip, &picture_corners(&frame));
        assert_eq!(strip_bounds.len(), sites.len());
        for (i, b) in strip_bounds {
            bounds[i as usize] = b;
        }
        assert_bounds_hold_owned_pixels(&sites, &frame, &bounds, "jittered lattice");
    }

    /// A small picture with random sites, a lattice, a diagonal run, duplicates
    /// and sites outside the picture.
    fn awkward_sites() -> (Frame, Vec<DVec2>) {
        let frame = Frame::pixels(64, 48).unwrap();
        let mut sites = frame.random_points(60, 5);
        sites
            .extend((0..12).map(|i| DVec2::new(8.0 * (i % 4) as f64, 30.0 + 6.0 * (i / 4) as f64)));
        sites.extend((0..6).map(|i| DVec2::new(40.0 + 3.0 * i as f64, 3.0 * i as f64)));
        sites.extend_from_within(..5);
        sites.extend([DVec2::new(70.0, -6.0), DVec2::new(-4.0, 20.0)]);
        (frame, sites)
    }

    /// Calls `f(q, i, d)` for every pixel centre q and each site i at its
    /// smallest `metric` distance d (every one of them where several tie).
    fn for_each_owner(
        sites: &[DVec2],
        frame: &Frame,
        metric: Metric,
        mut f: impl FnMut(DVec2, usize, f64),
    ) {
        for y in 0..frame.height {
            for x in 0..frame.width {
                let q = DVec2::new(x as f64, y as f64);
                let distances: Vec<f64> = sites.iter().map(|s| metric.distance(*s - q)).collect();
                let d = distances.iter().copied().fold(f64::INFINITY, f64::min);
                for (i, &own) in distances.iter().enumerate() {
                    if own == d {
                        f(q, i, own);
                    }
                }
            }
        }
    }

    #[test]
    fn region_boxes_hold_every_owned_pixel() {
        // Under L1 and L∞ (ties included, which fill whole areas): random sites,
        // a lattice, a diagonal run, duplicates and sites outside the picture.
        let (frame, sites) = awkward_sites();
        for metric in [Metric::L1, Metric::LInf] {
            let boxes = region_boxes(&sites, &frame, metric).unwrap();
            let mut bounded = 0;
            for_each_owner(&sites, &frame, metric, |q, i, _| {
                if let Some((lo, hi)) = boxes[i] {
                    assert!(
                        q.cmpge(lo - 1e-9).all() && q.cmple(hi + 1e-9).all(),
                        "{metric}: pixel {q} of site {i} outside {lo} .. {hi}"
                    );
                }
            });
            for (lo, hi) in boxes.iter().flatten() {
                bounded += (lo.is_finite() && hi.is_finite()) as usize;
            }
            // The duplicates are left out.
            assert!(boxes.iter().filter(|b| b.is_none()).count() >= 5);
            // Sites inside the hull get boxes bounded on all four sides.
            assert!(
                bounded > sites.len() / 4,
                "{metric}: {bounded} bounded boxes"
            );
        }
        assert!(region_boxes(&sites, &frame, Metric::L2).is_none());
    }

    #[test]
    fn lp_table_bounds_the_distance_within_a_percent() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        let mut unit = || rng.gen::<f64>();
        for p in [0.02, 0.3, 0.5, 1.0, 1.5, 3.0, 60.0] {
            let table = LpTable::new(p);
            let metric = Metric::Lp(p);
            let mut offsets: Vec<DVec2> = (0..20000)
                .map(|_| DVec2::new(unit() - 0.5, unit() - 0.5) * 10f64.powf(6.0 * unit() - 2.0))
                .collect();
            // Axes, diagonals, tiny ratios and zero.
            offsets.extend([
                DVec2::new(3.0, 0.0),
                DVec2::new(0.0, -2.5),
                DVec2::new(7.0, 7.0),
                DVec2::new(5.0, 1e-300),
                DVec2::new(1.0, 1e-9),
                DVec2::ZERO,
            ]);
            for d in offsets {
                let key = metric.key(d);
                let (lo, hi) = (table.bound(d, false), table.bound(d, true));
                assert!(
                    lo <= key && key <= hi,
                    "p = {p}, {d}: {lo} <= {key} <= {hi}"
                );
                assert!(hi <= lo * 1.0081 + 1e-300, "p = {p}, {d}: {lo} .. {hi}");
            }
        }
    }

    #[test]
    fn metric_regions_hold_every_owned_pixel() {
        // Every pixel centre lies within its nearest sites' radii (ties included),
        // measured in the metric, and inside their boxes: random sites, a
        // lattice, a diagonal run, duplicates and sites outside the picture.
        let (frame, sites) = awkward_sites();
        let metrics = [
            Metric::L2,
            Metric::L1,
            Metric::LInf,
            Metric::Lp(0.1),
            Metric::Lp(0.5),
            Metric::Lp(3.0),
            Metric::Lp(60.0),
        ];
        for metric in metrics {
            let regions = local_metric_regions(&sites, &frame, metric).unwrap();
            for_each_owner(&sites, &frame, metric, |q, i, own| {
                let Region { reach, lo, hi } = regions[i];
                assert!(
                    own <= reach * (1.0 + 1e-12),
                    "{metric}: pixel {q} of site {i} at {own} beyond {reach}"
                );
                assert!(
                    q.cmpge(lo).all() && q.cmple(hi).all(),
                    "{metric}: pixel {q} of site {i} outside its box {lo}..{hi}"
                );
            });
            // Far tighter than the stretched Euclidean cover where the stretch
            // is large (2.83 for L0.5, 2^9.5 for L0.1).
            let (cell, bin) = k_cell_and_bin(&frame, sites.len(), 1);
            let b = metric.euclidean_bounds().1;
            let stretched: f64 = k_local_radii(&sites, &frame, 1, cell, bin, metric.stretch())
                .iter()
                .map(|r| r * b)
                .sum();
            let native: f64 = regions.iter().map(|r| r.reach).sum();
            if matches!(metric, Metric::Lp(p) if p < 1.0) {
                assert!(
                    native < 0.5 * stretched,
                    "{metric}: {native} vs {stretched}"
                );
            }
        }
        let gauge = Metric::polygon(
            &[
                DVec2::new(1.0, 0.0),
                DVec2::new(0.0, 1.0),
                DVec2::new(-1.0, -1.0),
            ],
            DVec2::ZERO,
        );
        assert!(local_metric_regions(&sites, &frame, gauge.unwrap()).is_none());
    }

    #[test]
    fn cell_bounds_are_the_region_widths() {
        // Uniform sites: the radius is the farthest corner of the exact region, which
        // lies within a pixel diagonal of the farthest owned pixel centre unless
        // the corner sits in a sliver between pixel centres.
        let frame = Frame::pixels(200, 150).unwrap();
        let sites = frame.random_points(300, 7);
        let radii: Vec<f64> = cell_bounds(&sites, &frame, default_bin(&frame, sites.len()))
            .iter()
            .map(|b| b.radius)
            .collect();
        let mut width = vec![0.0f64; sites.len()];
        for y in 0..150 {
            for x in 0..200 {
                let q = DVec2::new(x as f64, y as f64);
                let (i, d) = sites
                    .iter()
                    .map(|s| (*s - q).length())
                    .enumerate()
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .unwrap();
                width[i] = width[i].max(d);
            }
        }
        let excess: f64 = radii.iter().zip(&width).map(|(r, w)| r - w).sum();
        assert!(radii.iter().zip(&width).all(|(r, w)| r + 1e-9 >= *w));
        assert!(
            excess / (sites.len() as f64) < 1.0,
            "mean excess {}",
            excess / 300.0
        );
    }

    #[test]
    fn tile_lists_hold_every_pixels_k_nearest() {
        // Every site among a pixel's k nearest (ties included) is in its tile's
        // list and within its radius; lists run nearest to the centre first.
        let frame = Frame::pixels(75, 52).unwrap();
        let mut sites = frame.random_points(60, 3);
        sites.extend([DVec2::new(-9.0, 20.0), DVec2::new(30.0, 30.0)]);
        sites.extend((0..9).map(|i| DVec2::new(60.0 + (i % 3) as f64, 40.0 + (i / 3) as f64)));
        for (k, side, stretch) in [(1, 16, 1.0), (5, 16, 1.0), (12, 7, 1.0), (3, 16, 1.5)] {
            let tiles = k_tile_lists(&sites, &frame, k, side, stretch);
            for (t, list) in tiles.lists.iter().enumerate() {
                let (lo, hi) = tiles.rect(t, &frame);
                let centre = (lo + hi) * 0.5;
                let d: Vec<f64> = list
                    .iter()
                    .map(|&i| sites[i as usize].distance_squared(centre))
                    .collect();
                assert!(
                    d.windows(2).all(|w| w[0] <= w[1]),
                    "k {k}: tile {t} out of order"
                );
                for y in lo.y as u32..=hi.y as u32 {
                    for x in lo.x as u32..=hi.x as u32 {
                        let q = DVec2::new(x as f64, y as f64);
                        let mut by: Vec<f64> = sites.iter().map(|s| s.distance(q)).collect();
                        by.sort_by(f64::total_cmp);
                        let kth = by[k - 1];
                        for (i, s) in sites.iter().enumerate() {
                            if s.distance(q) <= kth {
                                assert!(
                                    list.contains(&(i as u32)),
                                    "k {k}: pixel {q}: site {i} not in tile {t}"
                                );
                                assert!(s.distance(q) <= tiles.radii[i] + 1e-9);
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn quadtree_bounds_bracket_the_width() {
        let frame = Frame::pixels(64, 64).unwrap();
        let sites: Vec<DVec2> = (0..64)
            .map(|i| DVec2::new((i % 8) as f64 * 8.0 + 3.0, (i / 8) as f64 * 8.0 + 4.0))
            .collect();
        let b = quadtree_width_bounds(&sites, &frame);
        assert_eq!(b.full_level, Some(3));
        assert_eq!(b.upper, Some(8.0 * 2f64.sqrt()));
        let width = (0..64 * 64)
            .map(|k| nearest(&sites, DVec2::new((k % 64) as f64, (k / 64) as f64)))
            .fold(0.0, f64::max);
        assert!(width <= b.upper.unwrap());
        // A quarter empty: no level below the root is full.
        let quarter: Vec<DVec2> = sites
            .iter()
            .copied()
            .filter(|p| p.x < 32.0 || p.y < 32.0)
            .collect();
        assert_eq!(quadtree_width_bounds(&quarter, &frame).full_level, Some(0));
    }
}
