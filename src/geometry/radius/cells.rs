//! Per-site bounds from the Delaunay triangulation: each site's region lies in
//! its Voronoi cell clipped to the picture, whose farthest corner bounds its cone.

use super::*;

/// Where a site's region lies within the picture (see [`cell_bounds`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CellBound {
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
#[expect(
    clippy::disallowed_macros,
    reason = "a bound a site, within the budget the caller reserved"
)]
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(crate) fn cell_bounds(sites: &[DVec2], frame: &Frame, bin: f64) -> Vec<CellBound> {
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
#[expect(clippy::disallowed_macros, reason = "a flag a point of one strip")]
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(super) fn strip_cell_bounds(
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
pub(super) struct Circumcircle {
    centre: DVec2,
    radius: f64,
    error: f64,
}

impl Circumcircle {
    pub(super) fn of(a: DVec2, b: DVec2, c: DVec2) -> Self {
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
    pub(super) fn holds(&self, p: DVec2) -> bool {
        let inner = self.radius - 2.0 * self.error;
        inner > 0.0 && (p - self.centre).length_squared() < inner * inner
    }
}

/// The bound of a polygon from the picture's corners (relative to `site`)
/// clipped by the half-planes nearer to `site` than to each of `cutters`.
pub(super) fn clipped_bound(
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
pub(super) fn searched_bound(bins: &Grid, s: DVec2, picture: &[DVec2; 4]) -> CellBound {
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
pub(super) fn picture_corners(frame: &Frame) -> [DVec2; 4] {
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
pub(super) fn half_plane_limit(d: DVec2) -> f64 {
    0.5 * d.length_squared() * (1.0 + 1e-9) + 1e-9
}

/// Every site's Delaunay neighbours (delaunator, in strips: see
/// [`delaunay_strips`]), in compressed rows: those of site s are
/// `list[start[s]..start[s + 1]]`. Sites the triangulation leaves out
/// (duplicates, collinear sets) have none.
pub(super) struct DelaunayNeighbours {
    start: Vec<u32>,
    list: Vec<u32>,
}

impl DelaunayNeighbours {
    pub(super) fn of(sites: &[DVec2], frame: &Frame) -> Self {
        let edges = delaunay_strips(sites, frame, strip_edges);
        let (start, list) = group_by_bucket(
            sites.len(),
            edges.iter().flatten().map(|&(a, b)| (a as usize, b)),
        );
        Self { start, list }
    }

    pub(super) fn of_site(&self, s: usize) -> &[u32] {
        &self.list[self.start[s] as usize..self.start[s + 1] as usize]
    }
}

/// A horizontal strip of the sites, triangulated: the sites it owns and those
/// within a few spacings beyond its edges (`members`, indices into the sites).
pub(super) struct Strip<'a> {
    pub(super) index: usize,
    /// Each site's strip.
    pub(super) strip_of: &'a [usize],
    pub(super) members: Vec<u32>,
    /// Of the members (`triangles` index `members`).
    pub(super) triangulation: delaunator::Triangulation,
}

impl Strip<'_> {
    pub(super) fn owns(&self, site: u32) -> bool {
        self.strip_of[site as usize] == self.index
    }
}

/// Sites per strip below which one triangulation is quicker.
pub(super) const STRIP_SITES: usize = 1500;

/// `each` of the strips many sites are triangulated in, one per thread, at
/// once. A site takes what it needs from its own strip: near an edge its
/// triangles may miss a site beyond the margin, which can only leave its region
/// in the strip larger than among all sites.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(super) fn delaunay_strips<T: Send>(
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
#[expect(clippy::disallowed_methods, reason = "one strip's edges")]
pub(super) fn strip_edges(strip: &Strip<'_>) -> Vec<(u32, u32)> {
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

/// The bin side for [`cell_bounds`]: the mean site spacing, so that a bin holds
/// about one site (at least 2 pixels, and at most about 4 million bins).
pub(crate) fn default_bin(frame: &Frame, sites: usize) -> f64 {
    let spacing = (frame.len() as f64 / sites.max(1) as f64).sqrt();
    let least = (frame.len() as f64 / (1u64 << 22) as f64).sqrt();
    spacing.max(2.0).max(least)
}
