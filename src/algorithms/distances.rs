//! Distances between point sets read off Voronoi pictures (thesis §3.11): the
//! Hausdorff distance from the nearest-site diagram, the diameter and the maximum
//! distance from the furthest-site diagram.
//!
//! A picture names a candidate partner for every query point: the site whose
//! region holds the point's pixel. Its distance, computed from the coordinates, is
//! an upper bound (Hausdorff) or lower bound (furthest) of the point's true value;
//! the picture's distance at the pixel, corrected by how far the point lies from
//! the pixel centre, bounds it from the other side. Only the points whose bounds
//! could still reach the best value are checked exactly, so every answer is exact
//! while the checks stay few.

use crate::memory::Gather;
use std::{borrow::Cow, cmp::Ordering};

use crate::geometry::exact::predicates::convex_hull;
use glam::DVec2;
use rand::SeedableRng;
use rayon::prelude::*;

use crate::{
    error::{Error, Result},
    geometry::{
        buckets::PointGrid,
        exact::{compare_distances, nearest_distance},
        frame::{first_of_each, Checked},
        metric::Metric,
        scale, Frame,
    },
    machine::Machine,
    Backend,
};

use super::{
    higher_order::furthest_checked,
    voronoi::{voronoi_checked, Method as VoronoiMethod, VoronoiOptions},
};

/// Two points, one of each set (indices into the sets as given), and their
/// distance.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Pair {
    pub from: u32,
    pub to: u32,
    pub distance: f64,
}

/// How each query point's partner is proposed before the exact check.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize),
    serde(rename_all = "snake_case")
)]
pub enum Method {
    /// The other set's Voronoi picture names it (thesis §3.11).
    Pixels,
    /// A bucket grid of the other set, searched on the CPU with Taha and
    /// Hanbury's early exit: a query with a partner nearer than the largest
    /// value so far cannot be the answer, and its search stops there.
    Grid,
}

impl Method {
    /// The faster on `backend`, as measured (`docs/benchmarks.md`): a
    /// software rasterizer draws the picture slower than the CPU searches
    /// the grid, and the CPU has only the grid.
    pub fn for_backend(backend: &Backend) -> Self {
        match backend.machine().map(Machine::device_class) {
            Some(crate::machine::DeviceClass::Gpu) => Method::Pixels,
            _ => Method::Grid,
        }
    }
}

/// How to find a Hausdorff distance: the method (`None`: the faster on the
/// backend, [`Method::for_backend`]) and the side of [`Method::Pixels`]'
/// picture (`None`: chosen from the sets).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct HausdorffOptions {
    pub method: Option<Method>,
    pub side: Option<u32>,
}

impl HausdorffOptions {
    pub fn method(self, method: Option<Method>) -> Self {
        Self { method, ..self }
    }

    pub fn side(self, side: Option<u32>) -> Self {
        Self { side, ..self }
    }

    fn method_on(&self, backend: &Backend) -> Method {
        self.method.unwrap_or(Method::for_backend(backend))
    }
}

/// An exact answer and how it was found.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Answer {
    /// The exact answer.
    pub pair: Pair,
    /// How the candidates were proposed.
    pub method: Method,
    /// The pair the picture alone suggests (its distance from the coordinates).
    pub picture_pair: Pair,
    /// Query points checked exactly because the picture could not rule them out.
    pub checked: usize,
    /// Size of the picture used.
    pub width: u32,
    pub height: u32,
    /// The picture used, over the points' world coordinates.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub frame: Frame,
}

/// The Hausdorff distance both ways and the larger of the two.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Hausdorff {
    /// max over a of the distance to the nearest b (`from` in a, `to` in b).
    pub a_to_b: Answer,
    /// max over b of the distance to the nearest a (`from` in b, `to` in a).
    pub b_to_a: Answer,
    /// The larger of the two directed distances.
    pub distance: f64,
}

/// Picture side used when none is given: enough pixels to separate the sites,
/// within the device's largest image.
fn default_side(machine: &Machine, sites: usize) -> u32 {
    let side = (4.0 * (sites as f64).sqrt()).clamp(256.0, 4096.0) as u32;
    side.min(machine.max_picture_side())
}

/// A frame showing every point with a pixel to spare, `side` pixels along the
/// longer axis.
fn frame_around(points: &[&[DVec2]], side: u32) -> Result<Frame> {
    let all = points.iter().flat_map(|s| s.iter());
    let lo = all.clone().fold(DVec2::INFINITY, |a, p| a.min(*p));
    let hi = all.fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
    // A degenerate box (one point, a line) still needs an area.
    let extent = (hi - lo)
        .max_element()
        .max(1e-9 * (1.0 + lo.abs().max_element()));
    let pad = extent / side as f64 * 2.0;
    let lo = lo - pad;
    let hi = lo + DVec2::splat(extent + 4.0 * pad).max(hi - lo + 2.0 * pad);
    Frame::with_bbox(side, None, [lo.x, lo.y, hi.x, hi.y])
}

/// The pixel of `frame` holding `p` and the distance (world units) from `p` to
/// that pixel's centre.
fn pixel_of(frame: &Frame, p: DVec2) -> (usize, f64) {
    let q = frame.to_pixel(p).round();
    let i = q.x.clamp(0.0, (frame.width - 1) as f64);
    let j = q.y.clamp(0.0, (frame.height - 1) as f64);
    let centre = frame.to_world(DVec2::new(i, j));
    (
        j as usize * frame.width as usize + i as usize,
        centre.distance(p),
    )
}

/// How far a distance read from the picture may be off (world units): the device
/// holds pixel coordinates in float32, a few thousandths of a pixel on the
/// largest pictures, and rounds the squared distance.
fn picture_error(frame: &Frame, d: f64) -> f64 {
    d * 1e-5 + 1e-3 / frame.scale
}

/// Runs `answer` on the two sets' distinct points (repeats change no distance,
/// and a point repeated 10⁵ times would be checked 10⁵ times), scaled by a power
/// of two into the range where squared distances neither overflow nor underflow
/// (coordinates past 1e154 or closer than 1e-154). The pair names each point by
/// its first index in its set, and its distance is scaled back, exact to rounding.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
fn in_range<'p>(
    a: Checked<'p>,
    b: Checked<'p>,
    answer: impl FnOnce(Checked<'_>, Checked<'_>) -> Result<Answer>,
) -> Result<Answer> {
    let (a, b) = (a.sites(), b.sites());
    let (a_kept, b_kept) = (first_of_each(a), first_of_each(b));
    // A set without repeats is taken as it is, not copied.
    let pick = |set: &'p [DVec2], kept: &[u32]| -> Cow<'p, [DVec2]> {
        if kept.len() == set.len() {
            Cow::Borrowed(set)
        } else {
            Cow::Owned(kept.iter().map(|&i| set[i as usize]).collect())
        }
    };
    let (a, b) = (pick(a, &a_kept), pick(b, &b_kept));
    let k = scale::common_predicate_exponent(&[&a, &b])?;
    // The distinct points, scaled: derived from the checked sets.
    let mut found = if k == 0 {
        answer(Checked::derived(&a), Checked::derived(&b))?
    } else {
        let (a, b) = (scale::scaled(&a, k), scale::scaled(&b, k));
        answer(Checked::derived(&a), Checked::derived(&b))?
    };
    found.frame.origin *= 2f64.powi(-k);
    found.frame.scale *= 2f64.powi(k);
    for pair in [&mut found.pair, &mut found.picture_pair] {
        pair.distance = scale::times_power_of_two(pair.distance, -k);
        pair.from = a_kept[pair.from as usize];
        pair.to = b_kept[pair.to as usize];
    }
    Ok(found)
}

/// The two sets, checked, each named in its error.
fn checked_sets<'p>(a: &'p [DVec2], b: &'p [DVec2]) -> Result<(Checked<'p>, Checked<'p>)> {
    let check = |name: &str, set| Checked::new(set).map_err(|e| e.about(name));
    Ok((check("first set", a)?, check("second set", b)?))
}

/// What the picture says of one query point: the partner its pixel names, that
/// partner's distance, and bounds on the point's true value.
struct Estimate {
    partner: u32,
    partner_distance: f64,
    lower: f64,
    upper: f64,
}

/// The query point (of `points.0`) with the largest true value, found
/// exactly: every query whose upper bound reaches the largest lower bound is
/// checked with `exact` (its partner in `points.1`); the others cannot be the
/// answer.
fn refine(
    frame: &Frame,
    points: (&[DVec2], &[DVec2]),
    queries: &[u32],
    estimates: &[Estimate],
    exact: impl Fn(u32) -> Option<u32> + Sync,
) -> Result<Answer> {
    let empty = || Error::too_few(1, 0, "empty set".into());
    // Bounds are floats: a few ulps lower keeps every query that may tie.
    let floor = estimates.iter().map(|e| e.lower).fold(0.0, f64::max) * (1.0 - 8.0 * f64::EPSILON);
    let (q, e) = queries
        .iter()
        .zip(estimates)
        .max_by(|x, y| x.1.partner_distance.total_cmp(&y.1.partner_distance))
        .ok_or_else(empty)?;
    let picture_pair = Pair {
        from: *q,
        to: e.partner,
        distance: e.partner_distance,
    };
    let candidates: Vec<u32> = queries
        .iter()
        .zip(estimates)
        .filter(|(_, e)| e.upper >= floor)
        .map(|(q, _)| *q)
        .gather("candidates")?;
    // The largest exactly; of equal ones the first query.
    let pairs: Vec<(u32, u32)> = candidates
        .par_iter()
        .filter_map(|&from| exact(from).map(|to| (from, to)))
        .collect();
    let (from, to) = pairs
        .into_iter()
        .reduce(|best, x| {
            let (p, q) = (points.0[x.0 as usize], points.1[x.1 as usize]);
            let (bp, bq) = (points.0[best.0 as usize], points.1[best.1 as usize]);
            match compare_distances(p, q, bp, bq) {
                Ordering::Greater => x,
                Ordering::Equal if x.0 < best.0 => x,
                _ => best,
            }
        })
        .ok_or_else(empty)?;
    let pair = Pair {
        from,
        to,
        distance: nearest_distance(points.0[from as usize], points.1[to as usize]),
    };
    Ok(Answer {
        pair,
        method: Method::Pixels,
        picture_pair,
        checked: candidates.len(),
        width: frame.width,
        height: frame.height,
        frame: *frame,
    })
}

/// The directed Hausdorff distance from `a` to `b`: the point of `a` farthest from
/// its nearest point of `b`, read off the Voronoi diagram of `b` (thesis §3.11.1)
/// or found with a grid, as `options` say.
pub fn directed_hausdorff(
    backend: &Backend,
    a: &[DVec2],
    b: &[DVec2],
    options: &HausdorffOptions,
) -> Result<Answer> {
    let (a, b) = checked_sets(a, b)?;
    directed_checked(backend, a, b, options.side, options.method_on(backend))
}

/// [`directed_hausdorff`] of sets checked where they entered.
fn directed_checked(
    backend: &Backend,
    a: Checked<'_>,
    b: Checked<'_>,
    side: Option<u32>,
    method: Method,
) -> Result<Answer> {
    in_range(a, b, |a, b| match method {
        Method::Pixels => directed_in_range(
            backend.device_for("the pixels method of Hausdorff")?,
            a,
            b,
            side,
        ),
        Method::Grid => directed_by_grid(a.sites(), b.sites()),
    })
}

/// The nearest point of `b` to `p` exactly, of equal ones the first: among
/// the points within rounding of the float search's nearest.
fn exact_nearest(grid: &PointGrid, b: &[DVec2], p: DVec2) -> Option<u32> {
    let (_, d) = grid.nearest(p)?;
    grid.around(p, d * (1.0 + 1e-9) + f64::MIN_POSITIVE)
        .reduce(
            |best, j| match compare_distances(p, b[j as usize], p, b[best as usize]) {
                Ordering::Less => j,
                Ordering::Equal if j < best => j,
                _ => best,
            },
        )
}

/// [`Method::Grid`]: every query's bounds from a grid of `b`. The queries
/// go in runs along a Hilbert curve, the runs in a shuffled order: the
/// largest value so far grows fast, and a query's search mostly stops at
/// the partner of the query before it, which lies near.
fn directed_by_grid(a: &[DVec2], b: &[DVec2]) -> Result<Answer> {
    use rand::seq::SliceRandom;
    use std::sync::atomic::{AtomicU64, Ordering as Atomic};
    let grid = PointGrid::new(b);
    let lo = a.iter().fold(DVec2::INFINITY, |m, p| m.min(*p));
    let hi = a.iter().fold(DVec2::NEG_INFINITY, |m, p| m.max(*p));
    let to_cell = 65535.0 / (hi - lo).max_element().max(f64::MIN_POSITIVE);
    // Cells of at most 2^16 a side: the curve's index fits in 32 bits.
    let mut order: Vec<(u32, u32)> = a
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let c = (*p - lo) * to_cell;
            let index = super::envelope::hilbert_index(c.x as u32, c.y as u32);
            (index as u32, i as u32)
        })
        .gather("Hilbert keys")?;
    order.sort_unstable();
    let mut runs: Vec<&[(u32, u32)]> = order.chunks(256).gather("runs")?;
    runs.shuffle(&mut rand_chacha::ChaCha8Rng::seed_from_u64(0x4a75));
    // The largest nearest distance so far (its bits: positive doubles order
    // as their bits do); the float nearest is within rounding of the exact.
    let largest = AtomicU64::new(0);
    let slack = 1.0 - 8.0 * f64::EPSILON;
    let (grid_ref, largest_ref) = (&grid, &largest);
    let mut estimates: Vec<(u32, Estimate)> = runs
        .par_iter()
        .flat_map_iter(|run| {
            let (grid, largest) = (grid_ref, largest_ref);
            let mut hint: Option<u32> = None;
            // A query with a partner nearer than the floor is below the
            // answer (its bound, rounded, stays under the floor less 8
            // ulps, refine's margin): only the others are kept.
            run.iter().filter_map(move |&(_, q)| {
                let p = a[q as usize];
                let floor = f64::from_bits(largest.load(Atomic::Relaxed)) * slack;
                let nearer = |j: &u32| b[*j as usize].distance(p) < floor;
                if let Some(j) = hint
                    .filter(nearer)
                    .or_else(|| grid.around(p, floor).find(nearer))
                {
                    hint = Some(j);
                    return None;
                }
                let (j, d) = grid.nearest(p).expect("a set has points");
                largest.fetch_max(d.to_bits(), Atomic::Relaxed);
                hint = Some(j);
                Some((
                    q,
                    Estimate {
                        partner: j,
                        partner_distance: d,
                        lower: d * slack,
                        upper: d,
                    },
                ))
            })
        })
        .collect();
    estimates.sort_unstable_by_key(|e| e.0);
    let (queries, estimates): (Vec<u32>, Vec<Estimate>) = estimates.into_iter().unzip();
    let frame = frame_around(&[a, b], 1)?;
    let mut answer = refine(&frame, (a, b), &queries, &estimates, |i| {
        exact_nearest(&grid, b, a[i as usize])
    })?;
    answer.method = Method::Grid;
    (answer.width, answer.height) = (0, 0);
    Ok(answer)
}

fn directed_in_range(
    machine: &Machine,
    a: Checked<'_>,
    b_checked: Checked<'_>,
    side: Option<u32>,
) -> Result<Answer> {
    let (a, b) = (a.sites(), b_checked.sites());
    let side = side.unwrap_or_else(|| default_side(machine, b.len()));
    let frame = frame_around(&[a, b], side)?;
    // The picture the method is named for, drawn whichever the device.
    let options = VoronoiOptions::exact(frame).method(VoronoiMethod::Cones);
    let diagram = voronoi_checked(&Backend::Device(machine), b_checked, &options)?;
    // Per point of a: the picture's partner, whose distance is an upper bound, and
    // a lower bound (the pixel's distance less the offset from the pixel centre).
    let queries: Vec<u32> = (0..a.len() as u32).gather("queries")?;
    let estimates: Vec<Estimate> = a
        .par_iter()
        .map(|p| {
            let (k, offset) = pixel_of(&frame, *p);
            let partner = diagram.labels[k];
            let partner_distance = b[partner as usize].distance(*p);
            let d = diagram.distances[k] as f64;
            Estimate {
                partner,
                partner_distance,
                lower: (d - picture_error(&frame, d) - offset).max(0.0),
                upper: partner_distance,
            }
        })
        .collect();
    let grid = PointGrid::new(b);
    refine(&frame, (a, b), &queries, &estimates, |i| {
        exact_nearest(&grid, b, a[i as usize])
    })
}

/// The Hausdorff distance between `a` and `b`, both directions, as `options`
/// say.
pub fn hausdorff(
    backend: &Backend,
    a: &[DVec2],
    b: &[DVec2],
    options: &HausdorffOptions,
) -> Result<Hausdorff> {
    let (side, method) = (options.side, options.method_on(backend));
    let (a, b) = checked_sets(a, b)?;
    let a_to_b = directed_checked(backend, a, b, side, method)?;
    let b_to_a = directed_checked(backend, b, a, side, method)?;
    Ok(Hausdorff {
        a_to_b,
        b_to_a,
        distance: a_to_b.pair.distance.max(b_to_a.pair.distance),
    })
}

/// The largest distance from a point of `a` to a point of `b`, read off the
/// furthest-site diagram of `b` (thesis §3.11.3). Only hull vertices of either set
/// can be the answer's ends.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::algorithms::distances::max_distance;
///
/// let red = [DVec2::ZERO, DVec2::X];
/// let blue = [DVec2::new(4.0, 3.0), DVec2::Y];
/// let far = pixgeo::with_default_machine(|m| max_distance(m, &red, &blue, None))?;
/// assert_eq!((far.pair.from, far.pair.to, far.pair.distance), (0, 0, 5.0));
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn max_distance(
    machine: &Machine,
    a: &[DVec2],
    b: &[DVec2],
    side: Option<u32>,
) -> Result<Answer> {
    let (a, b) = checked_sets(a, b)?;
    in_range(a, b, |a, b| max_distance_in_range(machine, a, b, side))
}

fn max_distance_in_range(
    machine: &Machine,
    a: Checked<'_>,
    b_checked: Checked<'_>,
    side: Option<u32>,
) -> Result<Answer> {
    let (a, b) = (a.sites(), b_checked.sites());
    let side = side.unwrap_or_else(|| default_side(machine, convex_hull(b).len()));
    let frame = frame_around(&[a, b], side)?;
    let diagram = furthest_checked(&Backend::Device(machine), b_checked, &frame, Metric::L2)?;
    // The farthest point from a fixed point over a set is a hull vertex, and the
    // distance to the farthest point of b is convex, so its maximum over a is at a
    // hull vertex of a. The picture's partner's distance is a lower bound, the
    // pixel's distance plus the offset from the pixel centre an upper one.
    let queries = convex_hull(a);
    let estimates: Vec<Estimate> = queries
        .par_iter()
        .map(|&i| {
            let p = a[i as usize];
            let (k, offset) = pixel_of(&frame, p);
            let partner = diagram.labels[k];
            let partner_distance = b[partner as usize].distance(p);
            let d = diagram.distances[k] as f64;
            Estimate {
                partner,
                partner_distance,
                lower: partner_distance,
                upper: d + picture_error(&frame, d) + offset,
            }
        })
        .collect();
    refine(&frame, (a, b), &queries, &estimates, |i| {
        let p = a[i as usize];
        diagram.hull.iter().copied().reduce(|best, j| {
            match compare_distances(p, b[j as usize], p, b[best as usize]) {
                Ordering::Greater => j,
                Ordering::Equal if j < best => j,
                _ => best,
            }
        })
    })
}

/// The diameter of `sites`: the largest distance between two of them, read off
/// their furthest-site diagram (thesis §3.11.2).
pub fn diameter(machine: &Machine, sites: &[DVec2], side: Option<u32>) -> Result<Answer> {
    max_distance(machine, sites, sites, side)
}
