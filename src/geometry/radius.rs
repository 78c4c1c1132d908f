//! How far each cone must reach: the width bounds of thesis §3.5 from a quadtree,
//! and pixgeo's per-site bound from a grid of buckets.
//!
//! All coordinates here are pixel coordinates; pixel centres are the integer points
//! of `[0, w-1] x [0, h-1]`.

use glam::DVec2;
use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

use super::{
    frame::{distance2_to_rect, farthest2_in_rect},
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
        if nx * ny > inside.len().max(1) || cell < 1.0 {
            break;
        }
        let mut marked = vec![false; nx * ny];
        for p in &inside {
            let ix = ((p.x / cell) as usize).min(nx - 1);
            let iy = ((p.y / cell) as usize).min(ny - 1);
            marked[iy * nx + ix] = true;
        }
        if marked.iter().all(|m| *m) {
            full_level = Some(level);
            level += 1;
        } else {
            break;
        }
    }
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

/// A radius per site that its cone must reach: every pixel centre owned by site s
/// is within `radii[s]` of it (a site that owns no pixel may get 0).
///
/// The picture is cut into square cells of side `cell` (rounded to whole pixels).
/// For a cell B, U(B) is the
/// smallest over sites of the distance to B's farthest point: every point of B has
/// a site within U(B), so its owner s is within U(B) and has `mindist(s, B) <= U(B)`.
/// Each such candidate needs `min(U(B), maxdist(s, B))`. As cells shrink, the radius
/// tends to the width of the site's own region (thesis Def. 3.2); where sites are
/// dense the radii shrink to the local spacing, while a site next to an empty
/// quarter still reaches across it: the thesis's worst case costs only the cones
/// that need the reach.
///
/// Sites are found through square bins of side `bin` (about one site each), those
/// outside the picture in the nearest border bin: projecting onto the picture never
/// moves a site closer to a point of the picture, so ring distances stay lower
/// bounds.
pub fn local_radii(sites: &[DVec2], frame: &Frame, cell: f64, bin: f64) -> Vec<f64> {
    // Whole pixels: then [lo, hi] below holds exactly the cell's pixel centres.
    let cell = cell.round().max(1.0);
    let bins = Grid::new(sites, frame, bin.max(cell));
    let nx = (frame.width as f64 / cell).ceil() as usize;
    let ny = (frame.height as f64 / cell).ceil() as usize;
    let (w, h) = ((frame.width - 1) as f64, (frame.height - 1) as f64);
    // Squared radii: non-negative floats order like their bit patterns, so
    // `fetch_max` on the bits is a maximum.
    let radii: Vec<AtomicU64> = (0..sites.len()).map(|_| AtomicU64::new(0)).collect();
    (0..ny).into_par_iter().for_each_init(Vec::new, |seen, cy| {
        for cx in 0..nx {
            // The cell's pixel centres span [lo, hi].
            let lo = DVec2::new(cx as f64, cy as f64) * cell;
            let hi = (lo + cell - 1.0).min(DVec2::new(w, h)).max(lo);
            let maxdist2 = |p: DVec2| farthest2_in_rect(p, lo, hi);
            let mindist2 = |p: DVec2| distance2_to_rect(p, lo, hi);
            let rect = bins.bins_of(lo, hi);
            // U(B)²: rings of bins until no farther ring can hold a closer site (a
            // site in ring k is at least k - 1 bins away). The sites seen on the way
            // are the first candidates.
            seen.clear();
            let mut cover2 = f64::INFINITY;
            let mut ring = 0;
            while ring <= bins.max_ring() && ring_gap2(ring, bins.cell) < cover2 {
                bins.for_ring(rect, ring, |i, p| {
                    cover2 = cover2.min(maxdist2(p));
                    seen.push((i, p));
                });
                ring += 1;
            }
            // Candidates: every site within U(B) of the cell.
            let mut raise = |i: u32, p: DVec2| {
                if mindist2(p) <= cover2 {
                    let need = cover2.min(maxdist2(p)).to_bits();
                    // Read first: most candidates do not raise the radius, and a
                    // plain load is far cheaper than fetch_max's CAS loop.
                    let r = &radii[i as usize];
                    if r.load(Ordering::Relaxed) < need {
                        r.fetch_max(need, Ordering::Relaxed);
                    }
                }
            };
            for &(i, p) in seen.iter() {
                raise(i, p);
            }
            while ring <= bins.max_ring() && ring_gap2(ring, bins.cell) <= cover2 {
                bins.for_ring(rect, ring, &mut raise);
                ring += 1;
            }
        }
    });
    radii
        .into_iter()
        .map(|r| f64::from_bits(r.into_inner()).sqrt())
        .collect()
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
    fn new(sites: &[DVec2], frame: &Frame, cell: f64) -> Self {
        let cell = cell.max(1.0);
        let nx = (frame.width as f64 / cell).ceil().max(1.0) as usize;
        let ny = (frame.height as f64 / cell).ceil().max(1.0) as usize;
        let index = |p: DVec2| {
            let ix = ((p.x + 0.5) / cell).floor().clamp(0.0, (nx - 1) as f64) as usize;
            let iy = ((p.y + 0.5) / cell).floor().clamp(0.0, (ny - 1) as f64) as usize;
            iy * nx + ix
        };
        let mut start = vec![0u32; nx * ny + 1];
        for p in sites {
            start[index(*p) + 1] += 1;
        }
        for k in 0..nx * ny {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut order = vec![0u32; sites.len()];
        for (i, p) in sites.iter().enumerate() {
            let k = index(*p);
            order[fill[k] as usize] = i as u32;
            fill[k] += 1;
        }
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

    /// Calls `f(index, position)` for every site in the bins at Chebyshev
    /// distance `ring` from the bin rectangle `[x0, y0, x1, y1]`.
    fn for_ring(&self, [x0, y0, x1, y1]: [isize; 4], ring: usize, mut f: impl FnMut(u32, DVec2)) {
        let r = ring as isize;
        let (nx, ny) = (self.nx as isize, self.ny as isize);
        // The bins of row y from x0 to x1 are contiguous in `order`.
        let mut span = |y: isize, a: isize, b: isize| {
            let (a, b) = (a.max(0), b.min(nx - 1));
            if y < 0 || y >= ny || a > b {
                return;
            }
            let row = y as usize * self.nx;
            let (from, to) = (
                self.start[row + a as usize] as usize,
                self.start[row + b as usize + 1] as usize,
            );
            for (&i, &p) in self.order[from..to].iter().zip(&self.position[from..to]) {
                f(i, p);
            }
        };
        if r == 0 {
            for y in y0..=y1 {
                span(y, x0, x1);
            }
            return;
        }
        span(y0 - r, x0 - r, x1 + r);
        span(y1 + r, x0 - r, x1 + r);
        for y in y0 - r + 1..y1 + r {
            span(y, x0 - r, x0 - r);
            span(y, x1 + r, x1 + r);
        }
    }
}

/// The cell and bin sides for [`local_radii`]: cells a third of the mean site
/// spacing (2 to 64 pixels), bins the spacing itself. Smaller cells give tighter
/// radii for more CPU work.
pub fn default_cell_and_bin(frame: &Frame, sites: usize) -> (f64, f64) {
    let spacing = (frame.len() as f64 / sites.max(1) as f64).sqrt();
    // At most about 4 million cells and bins, whatever the picture's size.
    let least = (frame.len() as f64 / (1u64 << 22) as f64).sqrt();
    (
        (spacing / 3.0).clamp(2.0, 64.0).max(least),
        spacing.clamp(2.0, 256.0).max(least),
    )
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
    fn local_radii_reach_every_owned_pixel() {
        let frame = Frame::pixels(61, 47).unwrap();
        // Clustered in one quarter, a regular row, and sites outside the picture.
        let mut sites: Vec<DVec2> = (0..40)
            .map(|i| DVec2::new((i * 7 % 23) as f64 * 0.9, (i * 11 % 19) as f64 * 1.1))
            .collect();
        sites.extend((0..6).map(|i| DVec2::new(10.0 * i as f64, 40.0)));
        sites.extend([
            DVec2::new(80.0, -10.0),
            DVec2::new(-3.0, 30.0),
            DVec2::new(30.0, 47.2),
        ]);
        for (cell, bin) in [(1.0, 1.0), (3.0, 7.0), (2.5, 10.0), (6.0, 6.0), (4.0, 64.0)] {
            let radii = local_radii(&sites, &frame, cell, bin);
            for y in 0..47 {
                for x in 0..61 {
                    let q = DVec2::new(x as f64, y as f64);
                    let d = nearest(&sites, q);
                    for (i, s) in sites.iter().enumerate() {
                        if ((*s - q).length() - d).abs() < 1e-12 {
                            assert!(
                                d <= radii[i] + 1e-9,
                                "cell {cell} bin {bin}: pixel {q} site {i} at {d} > {}",
                                radii[i]
                            );
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
