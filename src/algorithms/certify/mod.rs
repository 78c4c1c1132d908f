//! Certified nearest sites: the labels of every exact diagram decided for the
//! doubles the user gave.
//!
//! The device draws float32 sites and keys, and the CPU's pixel algorithm works
//! from f64 pixel coordinates that the frame's mapping rounds: both propose each
//! pixel's nearest sites to within a rounding error. This pass proves or mends
//! the proposal. Around each block of pixels it gathers every site that could be
//! as near as the proposed ones, and gives each a key interval from float
//! arithmetic with a bound on its error: a single point where error-free
//! transformations show the key was computed exactly (integer sites, lattices
//! of powers of two). Where intervals overlap, the keys are compared in rational
//! arithmetic from the user's doubles and the frame's. Equal distances go to the
//! smaller site index, on every route and tiling alike.
//!
//! Proposals are near-exact, so intervals rarely overlap and mending is rare:
//! the pass costs about one distance evaluation per nearby site per pixel.

mod discs;
mod distances;
mod furthest;

use crate::memory::Gather;
use std::cmp::Ordering;

use glam::DVec2;
use rayon::prelude::*;

pub(crate) use discs::Disc;

use crate::{
    cancel::Watch,
    error::{Error, Result},
    geometry::{
        buckets::PointGrid,
        exact::bisector::Bisectors,
        exact::{distance::PixelOffset, exact_float_key, to_pixel_parts, two_difference},
        metric::Metric,
        Frame,
    },
};

/// Pixels a side of the blocks that share one candidate list.
const BLOCK: u32 = 8;

/// The top bit of a proposed label: the pixel needs the exact check.
pub(crate) const MARK: u32 = 1 << 31;

/// The float key the intervals bound: the metric's own, or for integer p the
/// sum of the coordinates' powers, which takes products where the metric's
/// key takes two general powers.
#[derive(Clone, Copy, Debug)]
enum FloatKey {
    Metric(Metric),
    PowerSum(i32),
    /// A polygon's gauge, with its Lipschitz constant.
    Gauge(Metric, f64),
}

impl FloatKey {
    fn of(metric: Metric) -> Self {
        match metric {
            Metric::Lp(p) if p.fract() == 0.0 && (3.0..=16.0).contains(&p) => {
                Self::PowerSum(p as i32)
            }
            Metric::Polygon(g) => Self::Gauge(metric, g.lipschitz()),
            _ => Self::Metric(metric),
        }
    }

    fn key(self, x: f64, y: f64) -> f64 {
        match self {
            Self::Metric(metric) | Self::Gauge(metric, _) => metric.key(DVec2::new(x, y)),
            Self::PowerSum(p) => x.powi(p) + y.powi(p),
        }
    }

    fn distance(self, key: f64) -> f64 {
        match self {
            Self::Metric(metric) | Self::Gauge(metric, _) => metric.distance_of_key(key),
            Self::PowerSum(p) => key.powf(1.0 / p as f64),
        }
    }

    fn of_distance(self, distance: f64) -> f64 {
        match self {
            Self::Metric(metric) | Self::Gauge(metric, _) => metric.key_of_distance(distance),
            Self::PowerSum(p) => distance.powi(p),
        }
    }

    /// The key of the exact offset `(x, y)` as an interval. A polygon's gauge
    /// is found from an angle, linear on its sector with gradients up to its
    /// Lipschitz constant: its error is a few ulps of that times the offset.
    fn bounds(self, x: f64, y: f64) -> (f64, f64) {
        match self {
            Self::Gauge(_, lipschitz) => {
                let k = self.key(x, y);
                let spread =
                    16.0 * f64::EPSILON * lipschitz * (x.abs() + y.abs()) + f64::MIN_POSITIVE;
                ((k - spread).max(0.0), k + spread)
            }
            _ => {
                let (k, r) = (self.key(x.abs(), y.abs()), self.rounding());
                (k * (1.0 - r), k * (1.0 + r))
            }
        }
    }

    /// Relative rounding error of a key of offsets that are doubles, with
    /// room: general powers are not correctly rounded.
    fn rounding(self) -> f64 {
        let u = f64::EPSILON / 2.0;
        match self {
            Self::Metric(Metric::Lp(p)) => 64.0 * u * p.recip().max(1.0),
            Self::Metric(_) | Self::Gauge(..) => 8.0 * u,
            Self::PowerSum(p) => 4.0 * p as f64 * u,
        }
    }
}

/// Proves the nearest sites of pixels of one frame and metric.
pub(crate) struct Certifier<'a> {
    sites: &'a [DVec2],
    frame: Frame,
    metric: Metric,
    /// The sites in pixel coordinates, rounded, with their error bounds (zero
    /// where exact).
    grid: PointGrid<'static>,
    places: Vec<DVec2>,
    /// What the places leave out of the exact positions, signed.
    rests: Vec<DVec2>,
    errors: Vec<f64>,
    largest_error: f64,
    keys: FloatKey,
    /// L2's near ties, decided by each pair's exact bisector.
    bisectors: Bisectors,
}

/// A part of a diagram's arrays: `width` x `height` pixels whose first is the
/// frame's pixel `(x0, y0)`, row r starting `r * stride` pixels into the
/// arrays, `k` labels (nearest first) to a pixel.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Region {
    pub x0: u32,
    pub y0: u32,
    pub width: u32,
    pub height: u32,
    pub stride: usize,
    pub k: usize,
}

/// A candidate of one pixel: its key lies in `[lo, hi]`.
#[derive(Clone, Copy, Debug)]
struct Candidate {
    lo: f64,
    hi: f64,
    id: u32,
    /// The offset from the site to the pixel when f64 holds it exactly.
    offset: Option<[f64; 2]>,
}

/// A pixel's proposed labels (and tie count, where counted).
struct Proposal<'p> {
    pixel: [i64; 2],
    labels: &'p [u32],
    ties: Option<u32>,
}

/// Buffers reused from pixel to pixel.
#[derive(Default)]
struct Work {
    scratch: Vec<Candidate>,
    tied: Vec<bool>,
}

/// Writes `mends` into a region's arrays; returns how many there were.
fn apply(
    region: Region,
    mends: impl IntoIterator<Item = Mend>,
    labels: &mut [u32],
    mut distances: Option<&mut [f32]>,
    mut ties: Option<&mut [u32]>,
) -> usize {
    let mut mended = 0;
    for mend in mends {
        mended += 1;
        let at = mend.at * region.k;
        labels[at..at + region.k].copy_from_slice(&mend.labels);
        if let Some(d) = distances.as_deref_mut() {
            d[at..at + region.k].copy_from_slice(&mend.distances);
        }
        if let Some(t) = ties.as_deref_mut() {
            t[mend.at] = mend.ties;
        }
    }
    mended
}

/// A pixel whose proposal was mended.
struct Mend {
    at: usize,
    labels: Vec<u32>,
    distances: Vec<f32>,
    ties: u32,
}

impl<'a> Certifier<'a> {
    /// For `sites` (world coordinates, finite) on `frame` under `metric`.
    pub fn new(sites: &'a [DVec2], frame: &Frame, metric: Metric) -> Result<Self> {
        let mut places = crate::memory::room(sites.len(), "the sites' places")?;
        let mut rests = crate::memory::room(sites.len(), "the sites' rests")?;
        let mut errors = crate::memory::room(sites.len(), "the sites' errors")?;
        for (i, s) in sites.iter().enumerate() {
            let (x, rx, ex) = to_pixel_parts(s.x, frame.origin.x, frame.scale);
            let (y, ry, ey) = to_pixel_parts(s.y, frame.origin.y, frame.scale);
            if !(x.is_finite() && y.is_finite() && ex.is_finite() && ey.is_finite()) {
                return Err(Error::out_of_range(format!(
                    "site {i} ({}, {}) lies beyond the range of doubles in this picture's \
                     pixels (scale {} pixels a unit); keep sites within about 1e300 pixels",
                    s.x, s.y, frame.scale
                )));
            }
            places.push(DVec2::new(x, y));
            rests.push(DVec2::new(rx, ry));
            errors.push(ex.max(ey));
        }
        let largest_error = errors.iter().copied().fold(0.0, f64::max);
        Ok(Self {
            sites,
            frame: *frame,
            metric,
            grid: PointGrid::owning(places.clone()),
            places,
            rests,
            errors,
            largest_error,
            keys: FloatKey::of(metric),
            bisectors: Bisectors::default(),
        })
    }

    /// The sites in pixel coordinates, rounded.
    pub fn places(&self) -> &[DVec2] {
        &self.places
    }

    /// The places' grid.
    pub fn grid(&self) -> &PointGrid<'static> {
        &self.grid
    }

    /// The largest error of a place's coordinate.
    pub fn largest_error(&self) -> f64 {
        self.largest_error
    }

    /// Proves the proposed labels of `region` in `labels` (and with them
    /// `distances` and tie counts, where given), mending those that are not the
    /// exact nearest sites. Returns the number of pixels mended.
    pub fn certify(
        &self,
        region: Region,
        labels: &mut [u32],
        distances: Option<&mut [f32]>,
        ties: Option<&mut [u32]>,
    ) -> Result<usize> {
        let blocks_across = region.width.div_ceil(BLOCK);
        let blocks = blocks_across * region.height.div_ceil(BLOCK);
        let count_ties = ties.is_some();
        let current_ties = ties.as_deref();
        let proposed: &[u32] = labels;
        let watch = Watch::current();
        let mends: Vec<Vec<Mend>> = (0..blocks)
            .into_par_iter()
            .map(|b| {
                watch.check()?;
                let corner = [(b % blocks_across) * BLOCK, (b / blocks_across) * BLOCK];
                self.block(region, corner, proposed, current_ties, count_ties)
            })
            .collect::<Result<_>>()?;
        Ok(apply(
            region,
            mends.into_iter().flatten(),
            labels,
            distances,
            ties,
        ))
    }

    /// The mends of the block whose first pixel is `corner` in `region`.
    fn block(
        &self,
        region: Region,
        corner: [u32; 2],
        labels: &[u32],
        ties: Option<&[u32]>,
        count_ties: bool,
    ) -> Result<Vec<Mend>> {
        let columns = corner[0]..(corner[0] + BLOCK).min(region.width);
        let rows = corner[1]..(corner[1] + BLOCK).min(region.height);
        let at = |i: u32, j: u32| j as usize * region.stride + i as usize;
        let pixel = |i: u32, j: u32| DVec2::new((region.x0 + i) as f64, (region.y0 + j) as f64);
        let levels = region.k.min(self.sites.len());
        let proposed = |i: u32, j: u32| &labels[at(i, j) * region.k..][..levels];
        let reaches: Vec<f64> = rows
            .clone()
            .flat_map(|j| columns.clone().map(move |i| (i, j)))
            .map(|(i, j)| self.reach(pixel(i, j), proposed(i, j)))
            .gather("reaches")?;
        let first = pixel(columns.start, rows.start);
        let last = pixel(columns.end - 1, rows.end - 1);
        let centre = (first + last) / 2.0;
        let half_diagonal = first.distance(last) / 2.0 * (1.0 + 1e-12) + 1e-9;
        let radius = reaches.iter().copied().fold(0.0, f64::max) + half_diagonal;
        // By distance from the centre: a pixel stops at the first site beyond
        // its reach plus the half diagonal.
        let mut candidates: Vec<(f64, u32)> = self
            .grid
            .around(centre, radius)
            .map(|id| (self.places[id as usize].distance(centre), id))
            .gather("candidates")?;
        candidates.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));

        let mut mends = Vec::new();
        let mut work = Work::default();
        let mut reaches = reaches.into_iter();
        for j in rows {
            for i in columns.clone() {
                let index = at(i, j);
                let at_pixel = pixel(i, j);
                let reach = reaches.next().expect("a reach per pixel");
                let within = reach * reach * (1.0 + 1e-12);
                let near = candidates
                    .iter()
                    .take_while(|c| c.0 <= reach + half_diagonal)
                    .filter(|c| self.places[c.1 as usize].distance_squared(at_pixel) <= within)
                    .map(|c| c.1);
                let proposal = Proposal {
                    pixel: [(region.x0 + i) as i64, (region.y0 + j) as i64],
                    labels: &labels[index * region.k..][..region.k],
                    ties: ties.map(|t| t[index]),
                };
                if let Some(mend) = self.decide(&proposal, near, count_ties, &mut work)? {
                    mends.push(Mend { at: index, ..mend });
                }
            }
        }
        Ok(mends)
    }

    /// The mend of one pixel's proposal, from `near`: every site within the
    /// pixel's reach (and maybe more); `None` where the proposal is exact.
    #[expect(clippy::disallowed_methods, reason = "one pixel's k levels")]
    fn decide(
        &self,
        proposal: &Proposal<'_>,
        near: impl Iterator<Item = u32>,
        count_ties: bool,
        work: &mut Work,
    ) -> Result<Option<Mend>> {
        let at = DVec2::new(proposal.pixel[0] as f64, proposal.pixel[1] as f64);
        let k = proposal.labels.len();
        let Work { scratch, tied } = work;
        scratch.clear();
        scratch.extend(near.map(|id| self.candidate(at, id)));
        self.order(
            proposal.pixel,
            k.min(self.sites.len()),
            count_ties,
            scratch,
            tied,
        )?;
        let label = |l: usize| scratch.get(l).map_or(u32::MAX, |c| c.id);
        let tie_count = if count_ties {
            1 + tied.iter().skip(1).take_while(|t| **t).count().min(254) as u32
        } else {
            0
        };
        let same = (0..k).all(|l| proposal.labels[l] == label(l))
            && proposal.ties.is_none_or(|t| t == tie_count);
        Ok((!same).then(|| Mend {
            at: 0,
            labels: (0..k).map(label).collect(),
            distances: (0..k)
                .map(|l| scratch.get(l).map_or(f32::INFINITY, |c| self.distance(c)))
                .collect(),
            ties: tie_count,
        }))
    }

    /// [`Certifier::certify`] for labels whose top bit marks the pixels that
    /// need the check (`DrawnTile::marked`), the others being exact already:
    /// clears the marks and checks the marked pixels.
    pub fn certify_marked(
        &self,
        region: Region,
        labels: &mut [u32],
        distances: Option<&mut [f32]>,
        ties: Option<&mut [u32]>,
    ) -> Result<usize> {
        let mut marked = Vec::new();
        for j in 0..region.height as usize {
            let row =
                &mut labels[j * region.stride * region.k..][..region.width as usize * region.k];
            for (i, label) in row.iter_mut().enumerate() {
                if *label != u32::MAX && *label & MARK != 0 {
                    *label &= !MARK;
                    marked.push((i as u32, j as u32));
                }
            }
        }
        let count_ties = ties.is_some();
        let current_ties = ties.as_deref();
        let proposed: &[u32] = labels;
        let mends: Vec<Mend> = marked
            .into_par_iter()
            .map_init(Work::default, |work, (i, j)| {
                let index = j as usize * region.stride + i as usize;
                let p = DVec2::new((region.x0 + i) as f64, (region.y0 + j) as f64);
                let proposal = Proposal {
                    pixel: [p.x as i64, p.y as i64],
                    labels: &proposed[index * region.k..][..region.k],
                    ties: current_ties.map(|t| t[index]),
                };
                let reach = self.reach(p, proposal.labels);
                let within = reach * reach * (1.0 + 1e-12);
                let near = self
                    .grid
                    .around(p, reach)
                    .filter(|&id| self.places[id as usize].distance_squared(p) <= within);
                let mend = self.decide(&proposal, near, count_ties, work)?;
                Ok(mend.map(|m| Mend { at: index, ..m }))
            })
            .filter_map(Result::transpose)
            .collect::<Result<_>>()?;
        Ok(apply(region, mends, labels, distances, ties))
    }

    /// The Euclidean distance from pixel `p` within which every site lies that
    /// is as near as the farthest of the distinct sites `proposed` (pixel
    /// units, rounded sites); infinite if they are not distinct sites.
    fn reach(&self, p: DVec2, proposed: &[u32]) -> f64 {
        let mut farthest = 0.0f64;
        for (l, &label) in proposed.iter().enumerate() {
            if label as usize >= self.sites.len() || proposed[..l].contains(&label) {
                return f64::INFINITY;
            }
            farthest = farthest.max(self.candidate(p, label).hi);
        }
        let (lower, _) = self.metric.euclidean_bounds();
        self.keys.distance(farthest) / lower * (1.0 + 1e-9) + self.largest_error * 2.0 + 1e-9
    }

    /// The distance (world units) of a candidate, rounded to float32.
    fn distance(&self, c: &Candidate) -> f32 {
        let key = c.lo + (c.hi - c.lo) / 2.0;
        (self.keys.distance(key) / self.frame.scale) as f32
    }

    /// The key interval of site `id` at pixel `p` (pixel coordinates).
    fn candidate(&self, p: DVec2, id: u32) -> Candidate {
        let q = self.places[id as usize];
        let error = self.errors[id as usize];
        let (dx, ex) = two_difference(p.x, q.x);
        let (dy, ey) = two_difference(p.y, q.y);
        if error == 0.0 && ex == 0.0 && ey == 0.0 {
            let offset = Some([dx, dy]);
            if let Some(key) = exact_float_key(self.metric, dx, dy) {
                return Candidate {
                    lo: key,
                    hi: key,
                    id,
                    offset,
                };
            }
        }
        let u = f64::EPSILON;
        let (ex, ey) = (ex.abs() + error, ey.abs() + error);
        let low = |v: f64, e: f64| ((v.abs() - e) * (1.0 - u)).max(0.0);
        let high = |v: f64, e: f64| (v.abs() + e) * (1.0 + u);
        let key = |x: f64, y: f64| self.keys.key(x, y);
        let rounding = self.keys.rounding();
        let tiny = f64::MIN_POSITIVE;
        let offset = (error == 0.0 && ex == 0.0 && ey == 0.0).then_some([dx, dy]);
        if let FloatKey::Gauge(_, lipschitz) = self.keys {
            // The gauge moves by at most its Lipschitz constant times the move.
            let (lo, hi) = self.keys.bounds(dx, dy);
            let moved = lipschitz * (ex + ey) * (1.0 + u);
            return Candidate {
                lo: ((lo - moved) * (1.0 - u) - tiny).max(0.0),
                hi: (hi + moved) * (1.0 + u) + tiny,
                id,
                offset,
            };
        }
        if let FloatKey::Metric(Metric::Lp(p)) = self.keys {
            if p >= 1.0 {
                // A norm moves by at most its value of the move, here at most
                // twice the larger coordinate's: one evaluation of the powers.
                let k = key(dx.abs(), dy.abs());
                let moved = 2.0 * ex.max(ey) * (1.0 + u);
                return Candidate {
                    lo: ((k * (1.0 - rounding) - moved) * (1.0 - u) - tiny).max(0.0),
                    hi: (k * (1.0 + rounding) + moved) * (1.0 + u) + tiny,
                    id,
                    offset,
                };
            }
        }
        Candidate {
            lo: (key(low(dx, ex), low(dy, ey)) * (1.0 - rounding) - tiny).max(0.0),
            hi: key(high(dx, ex), high(dy, ey)) * (1.0 + rounding) + tiny,
            id,
            offset,
        }
    }

    /// Leaves in `scratch` the `levels` nearest of its candidates to pixel `p`,
    /// nearest first, equal distances by index, and in `tied` whether each is
    /// as near as the one before it. With `all_ties`, every site tied with the
    /// last of them follows it.
    fn order(
        &self,
        p: [i64; 2],
        levels: usize,
        all_ties: bool,
        scratch: &mut Vec<Candidate>,
        tied: &mut Vec<bool>,
    ) -> Result<()> {
        let levels = levels.min(scratch.len());
        if levels == 0 {
            tied.clear();
            return Ok(());
        }
        // Only candidates that may be among the `levels` nearest matter.
        scratch.select_nth_unstable_by(levels - 1, |a, b| a.hi.total_cmp(&b.hi));
        let bound = scratch[levels - 1].hi;
        scratch.retain(|c| c.lo <= bound);
        scratch.sort_unstable_by(|a, b| a.lo.total_cmp(&b.lo).then(a.id.cmp(&b.id)));
        let keep = if all_ties { scratch.len() } else { levels };
        // Mostly the intervals order the candidates already: each apart from
        // the next, or both exact and equal (an exact tie, in index order).
        let point = |c: &Candidate| c.lo == c.hi;
        let decided = scratch
            .windows(2)
            .take(keep)
            .all(|w| w[0].hi < w[1].lo || (point(&w[0]) && point(&w[1]) && w[0].lo == w[1].lo));
        tied.clear();
        if decided {
            tied.push(false);
            tied.extend(
                scratch
                    .windows(2)
                    .take(keep - 1)
                    .map(|w| point(&w[0]) && w[0].lo == w[1].lo),
            );
        } else {
            self.sort_exactly(p, scratch, tied)?;
        }
        let keep = if all_ties {
            levels + tied[levels..].iter().take_while(|t| **t).count()
        } else {
            levels
        };
        scratch.truncate(keep);
        tied.truncate(keep);
        Ok(())
    }

    /// Sorts `candidates` of pixel `p` by exact distance, equal ones by index,
    /// and marks in `tied` each that is as near as the one before it.
    fn sort_exactly(
        &self,
        p: [i64; 2],
        candidates: &mut Vec<Candidate>,
        tied: &mut Vec<bool>,
    ) -> Result<()> {
        // An insertion sort: nearly sorted already, and most comparisons are
        // decided by the intervals.
        let mut exact: Vec<Option<PixelOffset>> =
            crate::memory::filled(candidates.len(), None, "exact candidates")?;
        let mut ranked: Vec<usize> = crate::memory::room(candidates.len(), "ranked candidates")?;
        for n in 0..candidates.len() {
            let mut slot = ranked.len();
            while slot > 0 {
                let before = ranked[slot - 1];
                let order = self.compare(p, candidates, &mut exact, before, n)?;
                if order.then(candidates[before].id.cmp(&candidates[n].id)) == Ordering::Greater {
                    slot -= 1;
                } else {
                    break;
                }
            }
            ranked.insert(slot, n);
        }
        tied.push(false);
        for w in ranked.windows(2) {
            tied.push(self.compare(p, candidates, &mut exact, w[0], w[1])? == Ordering::Equal);
        }
        *candidates = ranked.iter().map(|&n| candidates[n]).gather("values")?;
        Ok(())
    }

    /// The order of candidates `a` and `b` of pixel `p` by exact distance.
    fn compare(
        &self,
        p: [i64; 2],
        candidates: &[Candidate],
        exact: &mut [Option<PixelOffset>],
        a: usize,
        b: usize,
    ) -> Result<Ordering> {
        let (ca, cb) = (&candidates[a], &candidates[b]);
        if ca.hi < cb.lo {
            return Ok(Ordering::Less);
        }
        if cb.hi < ca.lo {
            return Ok(Ordering::Greater);
        }
        if ca.lo == ca.hi && cb.lo == cb.hi {
            return Ok(ca.lo.total_cmp(&cb.lo));
        }
        let symmetric = !matches!(self.metric, Metric::Polygon(_));
        if let (Some(oa), Some(ob), true) = (ca.offset, cb.offset, symmetric) {
            let sorted = |o: [f64; 2]| {
                let (x, y) = (o[0].abs(), o[1].abs());
                (x.min(y), x.max(y))
            };
            if sorted(oa) == sorted(ob) {
                return Ok(Ordering::Equal);
            }
        }
        if self.metric == Metric::L2 {
            let (frame, sites) = (&self.frame, self.sites);
            return Ok(self.bisectors.order(frame, sites, ca.id, cb.id, p));
        }
        for n in [a, b] {
            if exact[n].is_none() {
                let site = self.sites[candidates[n].id as usize];
                exact[n] = Some(PixelOffset::of(&self.frame, site, p));
            }
        }
        let (ea, eb) = (exact[a].as_ref().unwrap(), exact[b].as_ref().unwrap());
        match ea.order(self.metric, eb) {
            Some(order) => Ok(order),
            None => Err(Error::out_of_range(format!(
                "pixel ({}, {}) is as far from site {} as from site {} under {} to 4096 bits, \
                 and pixgeo decides such near ties exactly for L1, L2, L∞ and L_p with p a \
                 fraction m/n of n up to 64; use one of those",
                p[0], p[1], ca.id, cb.id, self.metric
            ))),
        }
    }
}
