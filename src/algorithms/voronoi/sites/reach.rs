//! How far each site can win: bounds from the cells of the sites that reach a
//! box, culling, and the range of a site's distances over a box.

use super::*;
use crate::memory::Gather;

/// A site's rectangle (pixel coordinates) and the largest shape distance (pixels)
/// it may have where it wins.
type Reach = ([f32; 4], f64);

/// Side of the site cull's blocks, in cells (see `cull`): blocks of 4 shorten
/// the site pass most for weighted points, whose reach varies with their
/// weights (docs/tuning.md, "Measured choices").
const CULL_BLOCK: usize = 4;

/// Each site's [`Reach`], `None` where it wins nowhere, and an upper bound on the
/// envelope over the picture.
///
/// Cells of about half the sites' spacing ([`CellBounds`]); a site's rectangle
/// holds the cells it may own a pixel of, each cut to where the site can reach.
pub(super) fn cull(
    sites: &[Site],
    width: u32,
    height: u32,
    metric: Metric,
    scale: f64,
) -> Result<(Vec<Option<Reach>>, f64)> {
    let spacing = (width as f64 * height as f64 / sites.len() as f64).sqrt();
    // Cells of half the spacing bound faster than a third, with rectangles
    // only a little larger. Few sites have few cells to walk: down to 16
    // pixels, but no less than an eighth of the spacing (a cell's walk to its
    // nearest site stays short), keeps their rectangles near their regions.
    // The measurements are in docs/tuning.md, "Measured choices".
    let side = (spacing / 2.0)
        .min(16.0)
        .max(spacing / 8.0)
        .clamp(3.0, 64.0)
        .floor();
    let cells = CellBounds::new(sites, width, height, metric, scale, side)?;
    let reaches = (0..sites.len())
        .into_par_iter()
        .map(|k| {
            let mut rect: Option<(DVec2, DVec2)> = None;
            let mut far = 0.0f64;
            cells.owned_cells(k, |owned| {
                far = far.max(owned.distance);
                let (p, q) = owned.rect;
                rect = Some(match rect {
                    None => (p, q),
                    Some((rp, rq)) => (rp.min(p), rq.max(q)),
                });
            });
            // Half a pixel around the centres, so rasterization keeps the rim; a
            // pixel more of reach for the same reason.
            rect.map(|(p, q)| {
                let rect = [
                    (p.x - 0.5) as f32,
                    (p.y - 0.5) as f32,
                    (q.x + 0.5) as f32,
                    (q.y + 0.5) as f32,
                ];
                (rect, far + 1.0)
            })
        })
        .collect();
    Ok((reaches, cells.reach))
}

/// The picture in square cells, each with an upper bound on the weighted
/// envelope over it: the smallest largest-distance of the sites binned near it
/// (any subset of the sites bounds the envelope from above).
pub(super) struct CellBounds<'a> {
    sites: &'a [Site],
    metric: Metric,
    scale: f64,
    /// Cell (i, j) holds the pixel centres [i side, (i + 1) side) (clipped).
    side: f64,
    pub(super) across: usize,
    pub(super) down: usize,
    corner: DVec2,
    /// Arcs are measured (in L2, see `spread`) many times each: their wedges
    /// once.
    wedges: Vec<Option<ArcWedge>>,
    upper: Vec<f64>,
    /// The largest bound in each block of CULL_BLOCK x CULL_BLOCK cells: a site
    /// skips a block beyond its reach there without visiting the cells.
    block_bounds: Vec<f64>,
    /// The largest bound of all.
    pub(super) reach: f64,
}

/// A cell a site may own a pixel of (see [`CellBounds::owned_cells`]).
pub(super) struct OwnedCell {
    /// Column and row.
    pub(super) cell: (usize, usize),
    /// The site's smallest weighted distance there.
    pub(super) least: f64,
    /// Its largest shape distance (pixels) where it may win there.
    pub(super) distance: f64,
    /// The cell's pixel centres cut to where the site can reach.
    rect: (DVec2, DVec2),
}

impl<'a> CellBounds<'a> {
    pub(super) fn new(
        sites: &'a [Site],
        width: u32,
        height: u32,
        metric: Metric,
        scale: f64,
        side: f64,
    ) -> Result<Self> {
        let (across, down) = (
            (width as f64 / side).ceil() as usize,
            (height as f64 / side).ceil() as usize,
        );
        let wedges = sites.iter().map(Site::wedge).gather("wedges")?;
        let mut cells = Self {
            sites,
            metric,
            scale,
            side,
            across,
            down,
            corner: DVec2::new(width as f64 - 1.0, height as f64 - 1.0),
            wedges,
            upper: Vec::new(),
            block_bounds: Vec::new(),
            reach: 0.0,
        };
        // Sites binned by their box's centre, in bins of about their spacing
        // (no smaller than the cells): a cell's search then visits few empty
        // bins.
        let spacing = (width as f64 * height as f64 / sites.len() as f64).sqrt();
        let bin_side = side.max(spacing);
        let (bins_across, bins_down) = (
            (width as f64 / bin_side).ceil() as usize,
            (height as f64 / bin_side).ceil() as usize,
        );
        let bin_of = |v: f64, n: usize| ((v / bin_side).floor().max(0.0) as usize).min(n - 1);
        let (bin_start, binned) = group_by_bucket(
            bins_across * bins_down,
            sites.iter().enumerate().map(|(k, s)| {
                let (lo, hi) = s.bounds();
                let c = 0.5 * (lo + hi);
                (
                    bin_of(c.y, bins_down) * bins_across + bin_of(c.x, bins_across),
                    k as u32,
                )
            }),
        );
        let bin = |x: usize, y: usize| {
            let b = y * bins_across + x;
            &binned[bin_start[b] as usize..bin_start[b + 1] as usize]
        };
        let (a, _) = metric.euclidean_bounds();
        // Upper bounds from the sites of the nearest non-empty rings of bins,
        // row by row: each cell starts from its left neighbour's best site,
        // whose bound is usually near its own, so that the gap test skips most
        // of the others.
        let cells_ref = &cells;
        let mut upper = crate::memory::filled(across * down, 0.0, "the cells' bounds")?;
        upper
            .par_chunks_mut(across)
            .enumerate()
            .for_each(|(j, row)| {
                let mut hint: Option<usize> = None;
                for (i, bound) in row.iter_mut().enumerate() {
                    let (lo, hi) = cells_ref.bounds_of(i, j);
                    let block = [
                        bin_of(lo.x, bins_across),
                        bin_of(lo.y, bins_down),
                        bin_of(hi.x, bins_across),
                        bin_of(hi.y, bins_down),
                    ]
                    .map(|b| b as isize);
                    let centre = 0.5 * (lo + hi);
                    let (mut best, mut best_site) = match hint {
                        Some(k) => (cells_ref.range(k, i, j, false).1, k),
                        None => (f64::INFINITY, 0),
                    };
                    let mut found = false;
                    for ring in 0..bins_across.max(bins_down) {
                        for_ring_cells((bins_across, bins_down), block, ring, |x, y| {
                            for &k in bin(x, y) {
                                found = true;
                                // A site whose box is already too far cannot lower the
                                // bound: its largest distance exceeds a times that gap.
                                let s = &sites[k as usize];
                                let (blo, bhi) = s.bounds();
                                let gap = distance2_to_rect(centre, blo, bhi).sqrt();
                                if cells_ref.weighted(s, a * gap) < best {
                                    let (_, largest, _) = cells_ref.range(k as usize, i, j, false);
                                    if largest < best {
                                        (best, best_site) = (largest, k as usize);
                                    }
                                }
                            }
                        });
                        // One more ring after the first find tightens the bound
                        // cheaply (the hint is no find: it may lie far off).
                        if found && ring >= 1 {
                            break;
                        }
                    }
                    hint = best.is_finite().then_some(best_site);
                    *bound = best;
                }
            });
        let blocks_across = across.div_ceil(CULL_BLOCK);
        let blocks = blocks_across * down.div_ceil(CULL_BLOCK);
        let mut block_bounds = crate::memory::filled(blocks, f64::NEG_INFINITY, "blocks' bounds")?;
        for (c, &bound) in upper.iter().enumerate() {
            let b = c / across / CULL_BLOCK * blocks_across + c % across / CULL_BLOCK;
            block_bounds[b] = block_bounds[b].max(bound);
        }
        cells.reach = upper.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        cells.upper = upper;
        cells.block_bounds = block_bounds;
        Ok(cells)
    }

    fn cell_of(&self, v: f64, n: usize) -> usize {
        ((v / self.side).floor().max(0.0) as usize).min(n - 1)
    }

    /// Cell (i, j)'s first and last pixel centres.
    fn bounds_of(&self, i: usize, j: usize) -> (DVec2, DVec2) {
        let lo = DVec2::new(i as f64 * self.side, j as f64 * self.side);
        (lo, (lo + self.side - 1.0).min(self.corner))
    }

    fn weighted(&self, s: &Site, d: f64) -> f64 {
        d / (self.scale * s.multiplicative) + s.additive
    }

    /// Site k's smallest and largest weighted distance over cell (i, j), and
    /// its largest shape distance there; exact where `spread` can be.
    fn range(&self, k: usize, i: usize, j: usize, exact: bool) -> (f64, f64, f64) {
        let (lo, hi) = self.bounds_of(i, j);
        let s = &self.sites[k];
        // Only arcs read their wedge (the others' would cost a cache miss).
        let wedge = match s.shape {
            Shape::Arc { .. } => self.wedges[k].as_ref(),
            _ => None,
        };
        let (dlo, dhi) = spread(
            s,
            wedge,
            self.metric,
            0.5 * (lo + hi),
            0.5 * (hi - lo),
            exact,
        );
        (self.weighted(s, dlo), self.weighted(s, dhi), dhi)
    }

    /// Visits each cell that site k may own a pixel of: the cells the largest
    /// upper bound reaches from its box, skipping blocks of cells whose largest
    /// bound it cannot reach, where its smallest distance can reach the cell's
    /// bound.
    pub(super) fn owned_cells(&self, k: usize, mut visit: impl FnMut(OwnedCell)) {
        let s = &self.sites[k];
        let (a, _) = self.metric.euclidean_bounds();
        let (blo, bhi) = s.bounds();
        let refine = self.metric == Metric::L2 && matches!(s.shape, Shape::Segment(..));
        // Where the cell's bound is its weighted distance, the shape distance.
        let limit_of = |bound: f64| (bound - s.additive) * self.scale * s.multiplicative;
        // No cell's bound is above the largest: the site owns no pixel
        // farther than this (Euclidean) from its box.
        let widest = limit_of(self.reach) / a * (1.0 + 1e-9);
        if widest.is_nan() || widest < 0.0 {
            return;
        }
        // Whether the pixel centres [p, q] lie beyond a shape distance of
        // `limit` from the site: a Euclidean 1 / a times that from its box.
        let beyond = |limit: f64, p: DVec2, q: DVec2| {
            let gap = (p - bhi).max(blo - q).max(DVec2::ZERO);
            limit < 0.0 || a * a * gap.length_squared() > limit * limit * (1.0 + 1e-9)
        };
        let mut cell = |x: usize, y: usize| {
            let bound = self.upper[y * self.across + x];
            let limit = limit_of(bound);
            // Most cells fail on the gap between them and the site's box.
            let (p, q) = self.bounds_of(x, y);
            if beyond(limit, p, q) {
                return;
            }
            // Where the exact range costs more, the quick one first: most
            // cells it rules out.
            let quick = self.range(k, x, y, false);
            let (least, _, d) = match refine {
                true if quick.0 > bound => return,
                true => self.range(k, x, y, true),
                false => quick,
            };
            if least <= bound {
                // The site owns a pixel of the cell only where its weighted
                // distance is at most the cell's bound: within that shape
                // distance of the shape, and a Euclidean 1 / a times that of
                // its box.
                let distance = d.min(limit);
                let grow = distance / a * (1.0 + 1e-9);
                let rect = (p.max(blo - grow), q.min(bhi + grow));
                if rect.0.cmple(rect.1).all() {
                    visit(OwnedCell {
                        cell: (x, y),
                        least,
                        distance,
                        rect,
                    });
                }
            }
        };
        let (x0, x1) = (
            self.cell_of(blo.x - widest, self.across),
            self.cell_of(bhi.x + widest, self.across),
        );
        let (y0, y1) = (
            self.cell_of(blo.y - widest, self.down),
            self.cell_of(bhi.y + widest, self.down),
        );
        let blocks_across = self.across.div_ceil(CULL_BLOCK);
        for j in y0 / CULL_BLOCK..=y1 / CULL_BLOCK {
            for i in x0 / CULL_BLOCK..=x1 / CULL_BLOCK {
                let (columns, rows) = (
                    CULL_BLOCK * i..(CULL_BLOCK * (i + 1)).min(self.across),
                    CULL_BLOCK * j..(CULL_BLOCK * (j + 1)).min(self.down),
                );
                let (p, _) = self.bounds_of(columns.start, rows.start);
                let (_, q) = self.bounds_of(columns.end - 1, rows.end - 1);
                if beyond(limit_of(self.block_bounds[j * blocks_across + i]), p, q) {
                    continue;
                }
                for y in rows.start.max(y0)..rows.end.min(y1 + 1) {
                    for x in columns.start.max(x0)..columns.end.min(x1 + 1) {
                        cell(x, y);
                    }
                }
            }
        }
    }
}

/// Every site over the whole picture (no speedup), reaching the farthest pixel:
/// the Euclidean distance to the far corner of its box, stretched by the metric.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(super) fn picture_wide(
    sites: &[Site],
    width: u32,
    height: u32,
    metric: Metric,
    scale: f64,
) -> (Vec<Option<Reach>>, f64) {
    let (lo, hi) = (
        DVec2::splat(0.0),
        DVec2::new(width as f64 - 1.0, height as f64 - 1.0),
    );
    let rect = [-0.5, -0.5, width as f32 - 0.5, height as f32 - 0.5];
    let b = metric.euclidean_bounds().1;
    let reaches: Vec<Option<Reach>> = sites
        .iter()
        .map(|s| {
            let (a, z) = s.bounds();
            let far = (hi - a).max(z - lo).length();
            Some((rect, b * far + 1.0))
        })
        .collect();
    // The envelope is at most any one site's largest weighted distance.
    let envelope = sites
        .iter()
        .zip(&reaches)
        .map(|(s, r)| {
            r.map_or(f64::INFINITY, |r| {
                r.1 / (scale * s.multiplicative) + s.additive
            })
        })
        .fold(f64::INFINITY, f64::min);
    (reaches, envelope)
}

/// The range of the Euclidean distance to the segment `a b` over the box
/// `[lo, hi]`: the distance is convex, so largest at a corner; the smallest is 0
/// where the segment meets the box, else at an end of the segment or a corner
/// of the box (the nearest points of two convex polygons include a vertex).
fn segment_spread(a: DVec2, b: DVec2, lo: DVec2, hi: DVec2) -> (f64, f64) {
    let corners = [lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)];
    let to_corners = corners.map(|c| segment_distance(c, a, b));
    let largest = to_corners.into_iter().fold(0.0, f64::max);
    // Liang-Barsky: the part of the segment inside the box.
    let e = b - a;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (q, p) in [(a - lo, -e), (hi - a, e)] {
        for axis in 0..2 {
            if p[axis] == 0.0 {
                if q[axis] < 0.0 {
                    t0 = 2.0;
                }
            } else {
                let t = q[axis] / p[axis];
                if p[axis] < 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
            }
        }
    }
    if t0 <= t1 {
        return widened(0.0, largest);
    }
    let to_box = |p: DVec2| (p - p.clamp(lo, hi)).length();
    let least = to_corners
        .into_iter()
        .chain([to_box(a), to_box(b)])
        .fold(f64::INFINITY, f64::min);
    widened(least, largest)
}

/// A range widened past the rounding of the distances that found it.
fn widened(least: f64, largest: f64) -> (f64, f64) {
    (least * (1.0 - 1e-12), largest * (1.0 + 1e-12))
}

/// The range of the site's shape distance over a box of half-extents `half`
/// around `centre`. A point's is exact under the L_p norms, which grow with
/// each coordinate's size: the box's nearest and farthest offsets from it.
/// Euclidean circles' is exact, and segments' where `exact` (four distances
/// and a clip instead of one).
/// Other shapes' comes from the value d at the centre: d ± |half| for the L_p
/// norms, and (d^p ± |half|^p)^(1/p) for p < 1, whose p-th power is
/// subadditive. A polygon need be neither symmetric nor convex, and segments
/// and curves under L_p are costly to measure: their range comes from the
/// Euclidean one and the bounds a |x| <= |x| <= b |x| of the metric.
fn spread(
    site: &Site,
    wedge: Option<&ArcWedge>,
    metric: Metric,
    centre: DVec2,
    half: DVec2,
    exact: bool,
) -> (f64, f64) {
    if let (Shape::Point(p), Metric::L2 | Metric::L1 | Metric::LInf | Metric::Lp(_)) =
        (site.shape, metric)
    {
        let offset = (p - centre).abs();
        return (
            metric.distance((offset - half).max(DVec2::ZERO)),
            metric.distance(offset + half),
        );
    }
    // Distances to extended shapes under other metrics need a search per
    // evaluation (but under L1 and L∞, a few candidates), and polygon gauges
    // bound nothing by their value at the centre; the Euclidean range is
    // closed-form and, stretched, as rigorous.
    if !matches!(metric, Metric::L2 | Metric::L1 | Metric::LInf) {
        let (a, b) = metric.euclidean_bounds();
        let (lo, hi) = spread(site, wedge, Metric::L2, centre, half, exact);
        return (a * lo, b * hi);
    }
    if metric == Metric::L2 {
        match site.shape {
            Shape::Segment(a, b) if exact => {
                return segment_spread(a, b, centre - half, centre + half)
            }
            Shape::Circle { center, radius } => {
                // The distance to the centre spans [near, far] over the box.
                let offset = (center - centre).abs();
                let near = (offset - half).max(DVec2::ZERO).length();
                let far = (offset + half).length();
                let (a, b) = ((near - radius).abs(), (far - radius).abs());
                let least = if near <= radius && radius <= far {
                    0.0
                } else {
                    a.min(b)
                };
                return widened(least, a.max(b));
            }
            _ => {}
        }
    }
    let d = match wedge {
        Some(wedge) if metric == Metric::L2 => wedge.distance(centre),
        _ => site.distance_to_shape(metric, centre),
    };
    let h = metric.distance(half);
    match metric {
        Metric::Lp(p) if p < 1.0 => {
            let (dp, hp) = (d.powf(p), h.powf(p));
            ((dp - hp).max(0.0).powf(1.0 / p), (dp + hp).powf(1.0 / p))
        }
        _ => ((d - h).max(0.0), d + h),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The exact ranges of Euclidean segments and circles over a box hold every
    /// distance from a fine grid of its points, and reach within a grid step of
    /// the grid's extremes; the quick ranges hold them too.
    #[test]
    fn ranges_over_a_box_hold_its_distances() {
        let frame = crate::geometry::Frame::pixels(64, 64).unwrap();
        let ends = frame.random_points(120, 11).unwrap();
        let (centre, half) = (DVec2::new(30.0, 33.0), DVec2::new(3.5, 3.5));
        let mut sites: Vec<Site> = ends
            .chunks_exact(2)
            .map(|e| Site::new(Shape::Segment(e[0], e[1])))
            .collect();
        // Through the box, along its side, from inside, and a point-like one.
        let segment = |a: [f64; 2], b: [f64; 2]| Site::new(Shape::Segment(a.into(), b.into()));
        sites.extend([
            segment([0.0, 33.0], [60.0, 33.0]),
            segment([26.5, 0.0], [26.5, 60.0]),
            segment([31.0, 34.0], [50.0, 50.0]),
            segment([10.0, 10.0], [10.0, 10.0]),
        ]);
        sites.extend(ends.iter().take(20).enumerate().map(|(i, &c)| {
            Site::new(Shape::Circle {
                center: c,
                radius: 2.0 * i as f64,
            })
        }));
        let steps = 56;
        for site in &sites {
            let (mut near, mut far) = (f64::INFINITY, 0.0f64);
            for i in 0..=steps {
                for j in 0..=steps {
                    let t = DVec2::new(i as f64, j as f64) / steps as f64;
                    let p = centre - half + 2.0 * half * t;
                    let d = site.distance_to_shape(Metric::L2, p);
                    near = near.min(d);
                    far = far.max(d);
                }
            }
            let step = 2.0 * half.length() / steps as f64;
            for exact in [true, false] {
                let (lo, hi) = spread(site, None, Metric::L2, centre, half, exact);
                assert!(
                    lo <= near && hi >= far,
                    "{site:?}: [{lo}, {hi}] against [{near}, {far}]"
                );
                if exact {
                    assert!(near - lo <= step && hi - far <= step, "{site:?}: not tight");
                }
            }
        }
    }
}
