//! Local reaches: how far each site may own a pixel under the k nearest or a
//! metric, measured on a cover of cells, and the screen tiles' candidate lists.

use super::*;

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
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(crate) fn k_local_radii(
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
pub(crate) fn local_metric_regions(
    sites: &[DVec2],
    frame: &Frame,
    metric: Metric,
) -> Option<Vec<Region>> {
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
pub(crate) struct TileCandidates {
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
#[expect(
    clippy::disallowed_macros,
    clippy::disallowed_methods,
    reason = "a list a screen tile, within the picture its caller reserved"
)]
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
    pub(super) const BLOCK: usize = 2;
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

#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(super) fn local_regions_by(
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
pub(super) struct Measure<'a> {
    metric: Metric,
    stretch: f64,
    lp: Option<&'a LpKeys>,
}

impl<'a> Measure<'a> {
    pub(super) fn euclidean(stretch: f64) -> Self {
        Self {
            metric: Metric::L2,
            stretch,
            lp: None,
        }
    }

    /// The metric measured directly (L_p through `lp`); `None` for polygon
    /// gauges, which need not grow with each coordinate.
    pub(super) fn native(metric: Metric, lp: Option<&'a LpKeys>) -> Option<Self> {
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
    pub(super) fn key(self, d: DVec2, above: bool) -> f64 {
        match self.lp {
            Some(LpKeys::Table(table)) => table.bound(d, above),
            Some(&LpKeys::PowerSum(doubled)) => power_sum(d, doubled, above),
            None => self.metric.key(d),
        }
    }

    /// The distance of `key` (at least).
    pub(super) fn distance_of_key(self, key: f64) -> f64 {
        match self.lp {
            Some(&LpKeys::PowerSum(doubled)) => key.powf(2.0 / doubled as f64) * (1.0 + 1e-12),
            _ => self.metric.distance_of_key(key),
        }
    }

    /// Whether the nearest point of `[lo, hi]` is within key `cover` of `p`.
    pub(super) fn nearest_within(self, p: DVec2, lo: DVec2, hi: DVec2, cover: f64) -> bool {
        self.key(p.clamp(lo, hi) - p, false) <= cover
    }

    /// The key of the farthest point of `[lo, hi]` from `p`, or `cap` if that is
    /// smaller.
    pub(super) fn farthest_below(self, p: DVec2, lo: DVec2, hi: DVec2, cap: f64) -> f64 {
        let offset = (p - (lo + hi) * 0.5).abs() + (hi - lo) * 0.5;
        self.key(offset, true).min(cap)
    }

    /// The key of U(B), widened by the stretch (and by a hair, so that the
    /// rounding of the widening only enlarges it).
    pub(super) fn widen(self, cover: f64) -> f64 {
        if self.stretch == 1.0 {
            cover
        } else {
            let distance = self.metric.distance_of_key(cover) * self.stretch;
            self.metric.key_of_distance(distance) * (1.0 + 1e-12)
        }
    }

    /// A lower bound on the keys of the sites `ring` cells of side `cell` away
    /// (at least `ring - 1` cells along one axis).
    pub(super) fn ring_gap(self, ring: usize, cell: f64) -> f64 {
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
pub(crate) struct TileLists {
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
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(crate) fn k_tile_lists(
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
pub(super) enum LpKeys {
    Table(LpTable),
    /// Twice p.
    PowerSum(u32),
}

impl LpKeys {
    pub(super) fn of(metric: Metric) -> Option<Self> {
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
pub(super) fn power_sum(d: DVec2, doubled: u32, above: bool) -> f64 {
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
pub(super) struct LpTable {
    p: f64,
    g: Vec<f64>,
}

impl LpTable {
    /// Entries up to just past t = 1 (float32 bits 0x3F80_0000).
    pub(super) const LEN: u32 = 0x3F82;
    /// Ratios below this are computed (twice the smallest normal float32, so
    /// that the rounding margins keep them normal).
    pub(super) const SMALLEST: f64 = 2.0 * f32::MIN_POSITIVE as f64;

    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    pub(super) fn new(p: f64) -> Self {
        let g = (0..Self::LEN)
            .map(|i| Self::exact(p, f64::from(f32::from_bits(i << 16))))
            .collect();
        Self { p, g }
    }

    pub(super) fn exact(p: f64, t: f64) -> f64 {
        (1.0 + t.powf(p)).powf(1.0 / p)
    }

    /// The distance of `d`, bounded from below or (`above`) from above: the
    /// larger coordinate size times g at the table entries around t.
    pub(super) fn bound(&self, d: DVec2, above: bool) -> f64 {
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
pub(super) struct Radii(Vec<AtomicU64>);

impl Radii {
    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    pub(super) fn new(n: usize) -> Self {
        Self((0..n).map(|_| AtomicU64::new(0)).collect())
    }

    pub(super) fn raise(&self, i: u32, key: f64) {
        let need = key.to_bits();
        // Most candidates do not raise the radius; a plain load is far cheaper
        // than fetch_max.
        let r = &self.0[i as usize];
        if r.load(Ordering::Relaxed) < need {
            r.fetch_max(need, Ordering::Relaxed);
        }
    }

    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    pub(super) fn into_radii(self, measure: Measure) -> Vec<f64> {
        self.0
            .into_iter()
            .map(|r| measure.distance_of_key(f64::from_bits(r.into_inner())))
            .collect()
    }
}

/// Per site, the smallest and largest column and row of the cells it may own a
/// pixel of, raised from many threads.
pub(super) struct CellBoxes(Vec<[AtomicU32; 4]>);

impl CellBoxes {
    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    pub(super) fn new(n: usize) -> Self {
        Self(
            (0..n)
                .map(|_| [u32::MAX, u32::MAX, 0, 0].map(AtomicU32::new))
                .collect(),
        )
    }

    pub(super) fn include(&self, i: u32, cx: u32, cy: u32) {
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
    pub(super) fn into_boxes(
        self,
        cell: f64,
        corner: DVec2,
    ) -> impl Iterator<Item = (DVec2, DVec2)> {
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
pub(crate) fn k_cell_and_bin(frame: &Frame, sites: usize, k: usize) -> (f64, f64) {
    let reach = (frame.len() as f64 * k.max(1) as f64 / sites.max(1) as f64).sqrt();
    let least = (frame.len() as f64 / (1u64 << 22) as f64).sqrt();
    ((reach / 6.0).max(2.0).max(least), reach.max(2.0).max(least))
}
