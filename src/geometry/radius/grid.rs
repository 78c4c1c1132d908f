//! The bins of sites and the small convex polygons the local bounds search with.

use super::*;

/// A convex polygon of bounded size on the stack, with room for one clip.
pub(super) struct Polygon {
    len: usize,
    /// The corners are `buffers[current][..len]`; a clip writes the other buffer
    /// and flips (no copy back).
    current: usize,
    buffers: [[DVec2; Polygon::CAPACITY]; 2],
}

impl Polygon {
    pub(super) const CAPACITY: usize = 32;

    pub(super) fn new(corners: [DVec2; 4]) -> Self {
        let mut polygon = Self {
            len: 4,
            current: 0,
            buffers: [[DVec2::ZERO; Self::CAPACITY]; 2],
        };
        polygon.buffers[0][..4].copy_from_slice(&corners);
        polygon
    }

    pub(super) fn corners(&self) -> &[DVec2] {
        &self.buffers[self.current][..self.len]
    }

    /// The smallest and largest coordinates of the corners; both 0 when empty.
    pub(super) fn bounding_box(&self) -> (DVec2, DVec2) {
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
    pub(super) fn bound(&self, site: DVec2) -> CellBound {
        let (lo, hi) = self.bounding_box();
        CellBound {
            radius: self.farthest2().sqrt(),
            lo: site + lo,
            hi: site + hi,
        }
    }

    /// Squared distance of the farthest corner from the origin; 0 when empty.
    pub(super) fn farthest2(&self) -> f64 {
        self.corners()
            .iter()
            .map(|v| v.length_squared())
            .fold(0.0, f64::max)
    }

    /// Clips to `v.normal <= limit` (Sutherland–Hodgman); returns whether anything
    /// was cut. A clip that would overflow the capacity is skipped, which only
    /// leaves the polygon larger.
    pub(super) fn clip(&mut self, normal: DVec2, limit: f64) -> bool {
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
pub(super) fn ring_gap2(ring: usize, cell: f64) -> f64 {
    let gap = (ring as f64 - 1.0).max(0.0) * cell;
    if ring == 0 {
        f64::NEG_INFINITY
    } else {
        gap * gap
    }
}

/// Site indices binned into square cells over the picture's pixel centres.
pub(super) struct Grid {
    pub(super) cell: f64,
    pub(super) nx: usize,
    pub(super) ny: usize,
    /// Sites of cell (x, y) are `order[start[y * nx + x]..start[y * nx + x + 1]]`,
    /// their positions at the same indices of `position`.
    pub(super) start: Vec<u32>,
    pub(super) order: Vec<u32>,
    pub(super) position: Vec<DVec2>,
}

impl Grid {
    /// The candidates of the rectangle B = `[lo, hi]` for the k lowest layers
    /// (see [`k_local_radii`]): into `candidates` every site within U(B) of B,
    /// both as `measure` keys; returns U(B)'s key, widened by the measure's
    /// stretch (infinite when there are fewer than k sites). `nearest` is
    /// scratch.
    pub(super) fn k_candidates(
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

    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    pub(super) fn new(sites: &[DVec2], frame: &Frame, cell: f64) -> Self {
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
    pub(super) fn bins_of(&self, lo: DVec2, hi: DVec2) -> [isize; 4] {
        let index =
            |v: f64, n: usize| ((v + 0.5) / self.cell).floor().clamp(0.0, (n - 1) as f64) as isize;
        [
            index(lo.x, self.nx),
            index(lo.y, self.ny),
            index(hi.x, self.nx),
            index(hi.y, self.ny),
        ]
    }

    pub(super) fn max_ring(&self) -> usize {
        self.nx.max(self.ny)
    }

    /// Calls `f(lo, hi, indices, positions)` for every bin at Chebyshev distance
    /// `ring` from the bin rectangle `[x0, y0, x1, y1]`: the bin's corners (pixel
    /// coordinates, widened by half a pixel) and its sites.
    pub(super) fn for_ring_bins(
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
