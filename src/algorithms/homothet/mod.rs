//! Smallest enclosing and largest empty homothets (thesis ch. 4 and 5).
//!
//! A homothet of a polygon Q (star-shaped around its kernel point, the origin) is
//! `c + λ Q`. It contains a site s exactly when the gauge of Q at s − c is at most
//! λ, which is the distance of the reflected polygon −Q from s to c: a cone with
//! base −Q stands on every site. The upper envelope of these cones is, at each
//! pixel, the smallest λ of a homothet centred there that holds every site, so its
//! lowest pixel is the smallest enclosing homothet (§4.3); the k-th level gives the
//! smallest one holding k sites (§4.4.1); the lower envelope's highest pixel inside
//! the allowed region is the largest empty one (§5.3), the rest of the picture
//! pushed to depth 0 through a stencil mask of the region (§5.4.1). Only the
//! extreme and the pixels near it leave the device ([`Machine::depth_extremes`]).
//!
//! The pixel answer is a candidate; the pixels near the extreme, in clusters,
//! name the few sites that can decide the exact answer:
//! - the smallest enclosing circle: Welzl's algorithm on them, checked against
//!   every site and repeated with any site left out;
//! - points (and, for circles, segments): every point where three of their
//!   distance pieces (or region edges) meet, evaluated exactly against all sites;
//! - weights and curves: a branch and bound on the exact distances, to a stated
//!   gap.
//!
//! The file is long because the three searches above share their candidate
//! generation and exact evaluation; the refinement lives in `refine.rs`.

use glam::DVec2;
use serde::Serialize;

use crate::{
    error::{Error, Result},
    geometry::seed::Seed,
    geometry::{
        buckets::PointGrid,
        chain::segment_distance,
        frame::check_sites,
        metric::{Gauge, Metric},
        site::{check_general_sites, Shape, Site},
        Frame,
    },
    machine::{
        ChannelMask, Clear, Compare, DepthTest, DrawParams, Format, Machine, NearExtreme,
        PixelRect, RasterState, RectDraw, StencilOp, StencilTest, Target,
    },
};

use crate::algorithms::cones::{draw_cones, ConeDraw, ConePush, SITE_FAN};

mod refine;

use refine::{
    best_of_clusters, best_vertex, branch_and_bound, clearing_vertices, clusters, quadratic_roots,
    smallest_circle, Goal,
};

use super::{
    flooding,
    higher_order::{draw_furthest, k_nearest, KNearestOptions, MAX_LEVELS},
    sites::draw_sites,
    voronoi::{draw_point_tiles, Accuracy, Speedup, VoronoiOptions},
};

/// The shape whose homothets are sought: a circle or a polygon star-shaped
/// around its kernel point (the origin of its [`Gauge`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Unit {
    Circle,
    Polygon(&'static Gauge),
}

impl From<Unit> for Metric {
    fn from(unit: Unit) -> Metric {
        match unit {
            Unit::Circle => Metric::L2,
            Unit::Polygon(g) => Metric::Polygon(g),
        }
    }
}

impl Unit {
    /// The distance from a site to a centre: the gauge of site − centre.
    fn gauge(self, v: DVec2) -> f64 {
        match self {
            Unit::Circle => v.length(),
            Unit::Polygon(g) => g.of(v),
        }
    }

    /// The metric of the cones: the reflected unit −Q.
    fn cone_metric(self) -> Result<Metric> {
        match self {
            Unit::Circle => Ok(Metric::L2),
            Unit::Polygon(g) => {
                let reflected: Vec<DVec2> = g.vertices.iter().map(|v| -*v).collect();
                Metric::polygon(&reflected, DVec2::ZERO).map_err(Error::InvalidInput)
            }
        }
    }

    /// How much the gauge can change per unit of Euclidean motion.
    fn lipschitz(self) -> f64 {
        match self {
            Unit::Circle => 1.0,
            // In the sector of edge (p, q) the gauge is (v × e) / (p × q): its
            // slope is |e| / |p × q|, one over the distance of the edge's line
            // from the kernel (which, for polygons that are not convex, may be
            // closer than the polygon itself).
            Unit::Polygon(g) => {
                let n = g.vertices.len();
                (0..n)
                    .map(|k| {
                        let (p, q) = (g.vertices[k], g.vertices[(k + 1) % n]);
                        (q - p).length() / p.perp_dot(q)
                    })
                    .fold(0.0, f64::max)
            }
        }
    }
}

/// A homothet `centre + scale · Q`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Homothet {
    pub centre: [f64; 2],
    pub scale: f64,
    /// The sites that determine it (on its boundary); with `inside`, ids from
    /// the number of sites on are the region's edges, ring by ring.
    pub sites: Vec<u32>,
}

/// How the picture's values were made.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PixelStage {
    /// The envelope of cones, drawn with a depth test.
    Cones,
    /// The largest empty circle of points on the picture: the exact Euclidean
    /// distance transform of the sites snapped to their pixels (the compute
    /// passes of the digital Voronoi diagram), then the exact clearance at the
    /// pixel centres it lists.
    DistanceTransform,
}

/// The answer: what the picture says, the exact homothet, and how far apart they
/// may be.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HomothetAnswer {
    /// The pixel holding the envelope's extreme, and its depth as a scale.
    pub pixel: Homothet,
    pub pixel_stage: PixelStage,
    pub exact: Homothet,
    /// Bound on |pixel scale − exact scale| from the pixel size: the gauge changes
    /// by at most this much over half a pixel's diagonal.
    pub pixel_bound: f64,
    /// Candidate points (or Welzl rounds, or branch-and-bound cells) evaluated
    /// exactly.
    pub checked: usize,
    /// How far the exact scale may be from the optimum: 0 where candidate
    /// vertices or Welzl's algorithm decide (exact up to rounding), the
    /// branch-and-bound gap for sites other than points.
    pub tolerance: f64,
    pub width: u32,
    pub height: u32,
    /// The picture the envelope was drawn on.
    #[serde(skip)]
    pub frame: Frame,
}

/// Picture side (pixels along the longer axis) used when none is given.
pub const DEFAULT_SIDE: u32 = Frame::DEFAULT_SIDE;

/// The smallest homothet of `unit` holding at least `k` of the point `sites`
/// (every site when `k` is 0 or the number of sites); exact, from Welzl's
/// algorithm (circles, all sites) or the points where three of the candidate
/// sites' distance pieces meet.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::algorithms::homothet::{enclose, Unit, DEFAULT_SIDE};
///
/// let sites = [DVec2::ZERO, DVec2::new(10.0, 0.0), DVec2::new(5.0, 1.0), DVec2::new(50.0, 50.0)];
/// // The smallest circle holding at least 3 of the 4 sites.
/// let c = pixgeo::with_default_machine(|m| enclose(m, &sites, Unit::Circle, 3, DEFAULT_SIDE))?;
/// assert!((c.exact.scale - 5.0).abs() < 1e-9);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn enclose(
    machine: &Machine,
    sites: &[DVec2],
    unit: Unit,
    k: usize,
    side: u32,
) -> Result<HomothetAnswer> {
    check_sites(sites)?;
    let n = sites.len();
    let k = if k == 0 { n } else { k };
    if k > n {
        return Err(Error::InvalidInput(format!(
            "cannot enclose {k} of {n} sites"
        )));
    }
    if k < n && k > MAX_LEVELS as usize {
        return Err(Error::InvalidInput(format!(
            "holding {k} of {n} sites reads the {k}-th nearest site of every pixel, and pixgeo \
             keeps at most {MAX_LEVELS} levels: k takes 1 to {MAX_LEVELS}, or all {n} sites"
        )));
    }
    let frame = enclosing_frame(sites, unit, side, k)?;
    let metric = unit.cone_metric()?;
    let bound = half_diagonal(&frame) * unit.lipschitz();
    // The sites drawn in the upper envelope are the only ones that can be
    // furthest (the hull's, for convex units).
    let (pixel, value, near_pixels, owners) = if k == n {
        let drawn = draw_furthest(machine, sites, &frame, metric, false)?;
        // Every pixel that could be the optimum's: within twice the bound. L2
        // keys are squared distances (pixels); the others are distances.
        let lowest = machine.depth_extremes(
            &drawn.depth,
            Some(near_extreme(
                metric,
                drawn.scale,
                2.0 * bound * frame.scale,
                false,
            )),
        )?;
        let value = super::higher_order::distance_of_depth(metric, drawn.scale, lowest.min, &frame);
        (lowest.at_min, value, lowest.near, drawn.owners)
    } else {
        // The k-th level of the lower envelope, read back: its lowest pixel.
        let levels = kth_levels(machine, sites, frame, metric, k)?;
        let kth = levels.level_distances(k as u32 - 1);
        let (at, d) = kth
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(b.1))
            .expect("a picture has pixels");
        let d = *d as f64;
        let near: Vec<usize> = (0..kth.len())
            .filter(|&p| (kth[p] as f64) <= d + 2.0 * bound)
            .take(NEAR_PIXELS as usize)
            .collect();
        (at, d, near, Vec::new())
    };
    let centre = pixel_centre(&frame, pixel);
    let pixel_bound = bound + rounding(unit, &frame, value);
    let (exact, checked) = if k == n && unit == Unit::Circle {
        let (around, reach) = surroundings(&frame, &near_pixels);
        let slack = 3.0 * pixel_bound + unit.lipschitz() * reach;
        smallest_circle(sites, around, value, slack)
    } else {
        let goal = Goal::Smallest;
        let eps = rounding(unit, &frame, value);
        let window = (value - 2.0 * bound - eps, value + eps);
        let furthest = |c: DVec2| {
            owners
                .iter()
                .map(|&i| unit.gauge(sites[i as usize] - c))
                .fold(0.0, f64::max)
        };
        let (c, v, checked) = best_of_clusters(&frame, &near_pixels, goal, |around, reach| {
            // A site on the best homothet has its gauge from `around` within
            // the window widened by the reach; the k nearest at any centre in
            // reach lie below its top.
            let spread = unit.lipschitz() * reach;
            let (lo, hi) = (window.0 - spread, window.1 + spread);
            let gauge = |i: &u32| unit.gauge(sites[*i as usize] - around);
            let (near, generators): (Vec<u32>, Vec<u32>) = if k == n {
                let far: Vec<u32> = owners.iter().copied().filter(|i| gauge(i) >= lo).collect();
                (far.clone(), far)
            } else {
                let near: Vec<u32> = (0..n as u32).filter(|i| gauge(i) <= hi).collect();
                let ring = near.iter().copied().filter(|i| gauge(i) >= lo).collect();
                (near, ring)
            };
            let always = |_| true;
            best_vertex(
                sites,
                unit,
                around,
                reach,
                (&near, &generators),
                &[],
                goal,
                k,
                window,
                always,
                furthest,
            )
        })
        .ok_or_else(|| Error::InvalidInput("no enclosing homothet found".into()))?;
        (homothet_at(sites, unit, c, v), checked)
    };
    Ok(answer_of(
        &frame,
        centre,
        value,
        pixel_bound,
        (exact, checked),
    ))
}

fn answer_of(
    frame: &Frame,
    centre: DVec2,
    value: f64,
    pixel_bound: f64,
    (exact, checked): (Homothet, usize),
) -> HomothetAnswer {
    HomothetAnswer {
        pixel: Homothet {
            centre: centre.to_array(),
            scale: value,
            sites: Vec::new(),
        },
        exact,
        pixel_stage: PixelStage::Cones,
        pixel_bound,
        checked,
        tolerance: 0.0,
        width: frame.width,
        height: frame.height,
        frame: *frame,
    }
}

/// Points per full turn that stand for a circle in the picture of an enclosing
/// homothet; the chords lose at most r (1 − cos(π / 64)).
const CURVE_SAMPLES: usize = 64;

/// The Euclidean distance from `c` to the farthest point of a site's shape.
fn farthest_euclidean(shape: Shape, c: DVec2) -> f64 {
    let at = |o: DVec2, r: f64, a: f64| o + r * DVec2::new(a.cos(), a.sin());
    match shape {
        Shape::Point(p) => c.distance(p),
        Shape::Segment(a, b) => c.distance(a).max(c.distance(b)),
        Shape::Circle { center, radius } => c.distance(center) + radius,
        Shape::Arc {
            center,
            radius,
            start,
            end,
        } => {
            let d = center - c;
            if d == DVec2::ZERO || crate::geometry::site::on_arc(d.y.atan2(d.x), start, end) {
                d.length() + radius
            } else {
                c.distance(at(center, radius, start))
                    .max(c.distance(at(center, radius, end)))
            }
        }
    }
}

/// The gauge of the farthest point of a site's shape from `c` (how large a
/// homothet centred at `c` must be to hold it). In each sector of a polygon the
/// gauge of p − c is linear in p, so over a shape it peaks at an end, where a
/// vertex ray from `c` crosses the shape, or (on a curve) where the curve's
/// tangent is parallel to an edge: those candidates are evaluated exactly.
fn farthest_gauge(unit: Unit, shape: Shape, c: DVec2) -> f64 {
    let Unit::Polygon(g) = unit else {
        return farthest_euclidean(shape, c);
    };
    let at = |o: DVec2, r: f64, a: f64| o + r * DVec2::from_angle(a);
    let mut candidates: Vec<DVec2> = Vec::new();
    match shape {
        Shape::Point(p) => candidates.push(p),
        Shape::Segment(a, b) => {
            candidates.extend([a, b]);
            if !g.is_convex() {
                let d = b - a;
                for v in &g.vertices {
                    // c + t v = a + s d with t ≥ 0, s in [0, 1].
                    let det = v.perp_dot(d);
                    if det != 0.0 {
                        let w = a - c;
                        let (t, s) = (w.perp_dot(d) / det, w.perp_dot(*v) / det);
                        if t >= 0.0 && (0.0..=1.0).contains(&s) {
                            candidates.push(a + d * s);
                        }
                    }
                }
            }
        }
        Shape::Circle { center, radius } | Shape::Arc { center, radius, .. } => {
            let (start, end) = match shape {
                Shape::Arc { start, end, .. } => (start, end),
                _ => (0.0, std::f64::consts::TAU),
            };
            let on = |p: DVec2| {
                let d = p - center;
                crate::geometry::site::on_arc(d.y.atan2(d.x), start, end)
            };
            if matches!(shape, Shape::Arc { .. }) {
                candidates.extend([at(center, radius, start), at(center, radius, end)]);
            }
            let n = g.vertices.len();
            for k in 0..n {
                // The piece of edge k grows along (e.y, −e.x): its peak on the circle.
                let e = g.vertices[(k + 1) % n] - g.vertices[k];
                let peak = center + radius * DVec2::new(e.y, -e.x).normalize();
                if on(peak) {
                    candidates.push(peak);
                }
                if !g.is_convex() {
                    // Where the ray c + t v (t ≥ 0) meets the circle.
                    let v = g.vertices[k];
                    let w = c - center;
                    let roots = quadratic_roots(
                        v.length_squared(),
                        2.0 * v.dot(w),
                        w.length_squared() - radius * radius,
                    );
                    for t in roots {
                        let p = c + v * t;
                        if t >= 0.0 && on(p) {
                            candidates.push(p);
                        }
                    }
                }
            }
        }
    }
    candidates
        .into_iter()
        .map(|p| g.of(p - c))
        .fold(0.0, f64::max)
}

/// The smallest homothet of `unit` holding every site: points, segments,
/// circles and arcs (thesis §4.4: the minimum enclosing circle of circles). Points and
/// segments under convex units are exact through [`enclose`] (a segment's ends
/// decide); the rest are drawn as points on them and refined by a branch and
/// bound on their farthest gauges, to a relative gap of 1e-9.
pub fn enclose_sites(
    machine: &Machine,
    sites: &[Site],
    unit: Unit,
    k: usize,
    side: u32,
) -> Result<HomothetAnswer> {
    check_general_sites(sites)?;
    if sites
        .iter()
        .any(|s| s.multiplicative != 1.0 || s.additive != 0.0)
    {
        return Err(Error::InvalidInput(
            "enclosing homothets take unweighted sites".into(),
        ));
    }
    let curved = sites
        .iter()
        .any(|s| matches!(s.shape, Shape::Circle { .. } | Shape::Arc { .. }));
    let points_only = sites.iter().all(|s| matches!(s.shape, Shape::Point(_)));
    if !points_only && k != 0 && k != sites.len() {
        return Err(Error::InvalidInput(
            "the smallest k-enclosing homothet takes point sites".into(),
        ));
    }
    let convex = match unit {
        Unit::Polygon(g) => g.is_convex(),
        Unit::Circle => true,
    };
    // Points standing for each site, and whose site they are.
    let mut samples = Vec::new();
    let mut owner = Vec::new();
    for (i, s) in sites.iter().enumerate() {
        let mut add = |p: DVec2| {
            samples.push(p);
            owner.push(i as u32);
        };
        match s.shape {
            Shape::Point(p) => add(p),
            // A convex homothet holds a segment when it holds its ends; others
            // see its inside too.
            Shape::Segment(a, b) => {
                let steps = if convex { 1 } else { CURVE_SAMPLES };
                for j in 0..=steps {
                    add(a + (b - a) * (j as f64 / steps as f64));
                }
            }
            Shape::Circle { center, radius } => {
                for j in 0..CURVE_SAMPLES {
                    let a = std::f64::consts::TAU * j as f64 / CURVE_SAMPLES as f64;
                    add(center + radius * DVec2::new(a.cos(), a.sin()));
                }
            }
            Shape::Arc {
                center,
                radius,
                start,
                end,
            } => {
                let span = (end - start).min(std::f64::consts::TAU);
                let steps =
                    ((span / std::f64::consts::TAU * CURVE_SAMPLES as f64).ceil() as usize).max(1);
                for j in 0..=steps {
                    let a = start + span * j as f64 / steps as f64;
                    add(center + radius * DVec2::new(a.cos(), a.sin()));
                }
            }
        }
    }
    let mut answer = enclose(machine, &samples, unit, k, side)?;
    // The picture saw chords of the curves.
    let chord_loss = sites
        .iter()
        .map(|s| match s.shape {
            Shape::Circle { radius, .. } | Shape::Arc { radius, .. } => {
                radius * (1.0 - (std::f64::consts::PI / CURVE_SAMPLES as f64).cos())
            }
            _ => 0.0,
        })
        .fold(0.0, f64::max);
    answer.pixel_bound += chord_loss * unit.lipschitz();
    let mut named: Vec<u32> = answer
        .exact
        .sites
        .iter()
        .map(|&s| owner[s as usize])
        .collect();
    named.dedup();
    answer.exact.sites = named;
    if !curved && (convex || points_only) {
        return Ok(answer);
    }
    // The samples' circle is a start; the sites' farthest distances decide.
    let start = DVec2::from(answer.exact.centre);
    let farthest = |c: DVec2| {
        sites
            .iter()
            .map(|s| farthest_gauge(unit, s.shape, c))
            .fold(0.0, f64::max)
    };
    // Convex units have one basin: search around the samples' answer. Others
    // search every centre whose homothet of the scale at the sites' middle holds
    // all the samples.
    let (start, mut reach) = if convex {
        (
            start,
            0.1 * answer.exact.scale + 8.0 * half_diagonal(&answer.frame),
        )
    } else {
        let lo = samples.iter().fold(DVec2::INFINITY, |a, p| a.min(*p));
        let hi = samples.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
        let (qlo, qhi) = unit_box(unit);
        let scale0 = farthest((lo + hi) / 2.0);
        let (blo, bhi) = (hi - qhi * scale0, lo - qlo * scale0);
        (
            (blo + bhi) / 2.0,
            (bhi - blo).max_element() / 2.0 * 1.01 + 1e-9,
        )
    };
    loop {
        let (c, v, gap, cells) = branch_and_bound(
            start,
            reach,
            unit.lipschitz(),
            |c| -farthest(c),
            |c| -farthest(c),
            |_| true,
            |_, _| true,
        )
        .ok_or_else(|| Error::InvalidInput("no enclosing circle found".into()))?;
        // The optimum is inside the square searched, or (convex units) the
        // square was too small.
        if !convex || (c - start).abs().max_element() < reach * 0.99 {
            let tol = 1e-9 * (1.0 + v.abs());
            answer.exact = Homothet {
                centre: c.to_array(),
                scale: -v,
                sites: (0..sites.len() as u32)
                    .filter(|&i| {
                        (farthest_gauge(unit, sites[i as usize].shape, c) + v).abs() <= tol.max(gap)
                    })
                    .collect(),
            };
            answer.tolerance = gap;
            answer.checked += cells;
            return Ok(answer);
        }
        reach *= 4.0;
    }
}

/// The k nearest sites of every pixel, exact.
fn kth_levels(
    machine: &Machine,
    sites: &[DVec2],
    frame: Frame,
    metric: Metric,
    k: usize,
) -> Result<super::higher_order::KNearest> {
    let options = KNearestOptions {
        frame,
        k: k as u32,
        metric,
        accuracy: Accuracy::Exact,
        speedup: Speedup::Quadtree,
    };
    k_nearest(machine, sites, &options)
}

/// Where the centre of the largest empty homothet may lie.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Region {
    /// Closed rings (polygons and their holes, any orientation); a point is inside
    /// when it is inside an odd number of rings. Empty: the sites' bounding box.
    pub rings: Vec<Vec<DVec2>>,
}

impl Region {
    /// Even-odd inside test.
    pub fn contains(&self, p: DVec2) -> bool {
        let mut inside = false;
        for ring in &self.rings {
            for k in 0..ring.len() {
                let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
                if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x)
                {
                    inside = !inside;
                }
            }
        }
        inside
    }

    fn edges(&self) -> impl Iterator<Item = (DVec2, DVec2)> + '_ {
        self.rings
            .iter()
            .flat_map(|r| (0..r.len()).map(move |k| (r[k], r[(k + 1) % r.len()])))
    }
}

/// The largest homothet of `unit` containing none of the point `sites`, its
/// centre in `region` (empty: the sites' bounding box); exact, from the points
/// where three of the candidate sites' distance pieces or region edges meet.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::algorithms::homothet::{largest_empty, Region, Unit, DEFAULT_SIDE};
///
/// let sites = [DVec2::ZERO, DVec2::new(4.0, 0.0), DVec2::new(0.0, 3.0)];
/// let square = Region { rings: vec![vec![DVec2::ZERO, DVec2::new(4.0, 0.0), DVec2::new(4.0, 4.0), DVec2::new(0.0, 4.0)]] };
/// let c = pixgeo::with_default_machine(|m| largest_empty(m, &sites, Unit::Circle, &square, DEFAULT_SIDE))?;
/// // On the top side, as far from (0, 3) as from (4, 0): farther than the corner (4, 4).
/// assert_eq!(c.exact.centre, [3.875, 4.0]);
/// assert!(c.exact.scale > 4.0);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn largest_empty(
    machine: &Machine,
    sites: &[DVec2],
    unit: Unit,
    region: &Region,
    side: u32,
) -> Result<HomothetAnswer> {
    largest_empty_by(machine, sites, unit, region, side, None)
}

/// More pixels near the largest value than this, and the picture is too coarse
/// for the sites: the exact search would cost more than a finer picture.
const MAX_NEAR_PIXELS: usize = 1024;

/// The side up to which a coarse picture is refined.
const MAX_REFINED_SIDE: u32 = 4096;

/// [`largest_empty`] with its pixel stage chosen: `None` takes the distance
/// transform where it applies (circles, every site on the picture or within a
/// pixel of it, a picture the device holds whole) and cones elsewhere; asking
/// for the transform where it does not apply is an error.
pub fn largest_empty_by(
    machine: &Machine,
    sites: &[DVec2],
    unit: Unit,
    region: &Region,
    side: u32,
    stage: Option<PixelStage>,
) -> Result<HomothetAnswer> {
    check_sites(sites)?;
    let finer = |side| largest_empty_by(machine, sites, unit, region, side, stage);
    let lo = sites.iter().fold(DVec2::INFINITY, |a, p| a.min(*p));
    let hi = sites.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
    let (region, frame) = region_and_frame(region, (lo, hi), side)?;
    let metric = unit.cone_metric()?;
    let region_mesh = RegionMesh::new(&region, &frame);
    let bound = half_diagonal(&frame) * unit.lipschitz();
    // A gauge of at most g is within Euclidean distance g · rmax.
    let rmax = 1.0 / Metric::from(unit).euclidean_bounds().0;
    let grid = PointGrid::new(sites);
    let nearest = |c: DVec2| {
        let (i, _) = grid.nearest(c).expect("sites exist");
        let upper = unit.gauge(sites[i as usize] - c);
        grid.around(c, upper * rmax)
            .map(|j| unit.gauge(sites[j as usize] - c))
            .fold(upper, f64::min)
    };
    // Per tile: its highest value and the pixels near it, exact at pixel centres.
    let seeds = match stage {
        Some(PixelStage::Cones) => None,
        _ => snapped_seeds(machine, sites, unit, &frame),
    };
    if stage == Some(PixelStage::DistanceTransform) && seeds.is_none() {
        return Err(Error::InvalidInput(format!(
            "the distance transform takes circles, sites on the picture (within a pixel) and sides up to {}: use cones",
            flooding::MAX_SIDE.min(machine.max_picture_side())
        )));
    }
    let stage = if seeds.is_some() {
        PixelStage::DistanceTransform
    } else {
        PixelStage::Cones
    };
    let tiles = match seeds {
        Some((seeds, moved)) => {
            // A pixel's value is within `snap` of its clearance (rounding aside),
            // so the best centre's pixel is listed; the exact clearances of the
            // listed centres then keep those within twice the bound.
            let snap = moved * (1.0 + 1e-9) / frame.scale;
            let within = 2.0 * (bound + snap) * frame.scale;
            let listed = listed_of_transform(machine, &seeds, &frame, &region_mesh, within)?;
            let mut exact: Vec<(f64, usize)> = listed
                .into_iter()
                .map(|p| (nearest(pixel_centre(&frame, p)), p))
                .collect();
            exact.sort_by(|a, b| b.0.total_cmp(&a.0));
            let top = exact.first().map_or(0.0, |e| e.0);
            exact.retain(|e| e.0 >= top - 2.0 * bound);
            let pixels: Vec<usize> = exact.into_iter().map(|e| e.1).collect();
            if pixels.is_empty() {
                Vec::new()
            } else {
                vec![(top, pixels)]
            }
        }
        None => {
            let options = VoronoiOptions {
                metric,
                speedup: Speedup::Local,
                ..VoronoiOptions::exact(frame)
            };
            let mut tiles: Vec<(f32, Vec<usize>)> = Vec::new();
            let mut keys = None;
            draw_point_tiles(machine, sites, &options, true, false, |tile| {
                keys = Some(tile.keys);
                let within = 2.0 * bound * frame.scale;
                let near = near_extreme(metric, tile.keys.scale, within, true);
                let picture = (Some(tile.ids), tile.depth, tile.x0, tile.y0, tile.inner);
                tiles.extend(highest_in_region(
                    machine,
                    &frame,
                    &region_mesh,
                    picture,
                    near,
                )?);
                Ok(())
            })?;
            let depth = keys.expect("a picture has a tile");
            tiles
                .into_iter()
                .map(|(z, p)| (depth.distance(z), p))
                .collect()
        }
    };
    let value = tiles.iter().map(|t| t.0).fold(f64::NEG_INFINITY, f64::max);
    if tiles.is_empty() {
        return Err(Error::InvalidInput(
            "no pixel centre lies in the region".into(),
        ));
    }
    let near_pixels = near_top(&tiles, value, bound);
    // Sites denser than the picture resolves leave most pixels near the top,
    // and the exact search around each would cost cubic time in the sites
    // there: the picture is made finer instead (the answer does not depend on
    // it), up to a side the device holds.
    if near_pixels.len() > MAX_NEAR_PIXELS && side < MAX_REFINED_SIDE {
        return finer(side * 2);
    }
    let centre = pixel_centre(&frame, near_pixels[0]);
    let eps = rounding(unit, &frame, value);
    let pixel_bound = bound + eps;
    let goal = Goal::Largest;
    // The best centre's pixel is among the near ones; a pixel left standing
    // outside the region is within the bound of a centre inside it.
    let window = (value - bound - eps, value + 2.0 * bound + eps);
    let (c, v, checked) = best_of_clusters(&frame, &near_pixels, goal, |around, reach| {
        // Every site that can be nearest at a centre in reach, and of them those
        // that can lie on the best homothet.
        let spread = unit.lipschitz() * reach;
        let (lo, hi) = (window.0 - spread, window.1 + spread);
        let gauge = |i: u32| unit.gauge(sites[i as usize] - around);
        let near: Vec<u32> = grid
            .around(around, hi * rmax)
            .filter(|&i| gauge(i) <= hi)
            .collect();
        let generators: Vec<u32> = near.iter().copied().filter(|&i| gauge(i) >= lo).collect();
        let edges: Vec<(DVec2, DVec2)> = region
            .edges()
            .filter(|(a, b)| segment_distance(around, *a, *b) <= reach)
            .collect();
        let allowed = |c: DVec2| {
            let tol = 1e-9 * (1.0 + c.abs().max_element());
            region.contains(c) || edges.iter().any(|(a, b)| segment_distance(c, *a, *b) < tol)
        };
        let sets = (&near[..], &generators[..]);
        best_vertex(
            sites, unit, around, reach, sets, &edges, goal, 1, window, allowed, nearest,
        )
    })
    .ok_or_else(|| Error::InvalidInput("no empty homothet found".into()))?;
    let exact = homothet_at(sites, unit, c, v);
    Ok(HomothetAnswer {
        pixel_stage: stage,
        ..answer_of(&frame, centre, value, pixel_bound, (exact, checked))
    })
}

/// The largest homothet of `unit` meeting none of `sites` (points, segments,
/// circles and arcs, with multiplicative weights scaling the clearance each
/// demands, thesis §5.4.2–5.4.3), its centre in `region`; with `inside`, the
/// whole homothet inside the region, its boundary added as segment sites
/// (§5.4.1). Plain points without `inside` take [`largest_empty`]'s exact
/// vertices; circles clearing unweighted points and segments the vertices of
/// their Voronoi diagram; the others a branch and bound on the exact distances
/// around the candidate pixels, to a relative gap of 1e-9 (reported as
/// [`HomothetAnswer::tolerance`]).
pub fn largest_empty_sites(
    machine: &Machine,
    sites: &[Site],
    unit: Unit,
    region: &Region,
    inside: bool,
    side: u32,
) -> Result<HomothetAnswer> {
    largest_empty_sites_by(machine, sites, unit, region, inside, side, None)
}

/// [`largest_empty_sites`] with its pixel stage chosen, as for
/// [`largest_empty_by`]: the distance transform takes plain points only.
pub fn largest_empty_sites_by(
    machine: &Machine,
    sites: &[Site],
    unit: Unit,
    region: &Region,
    inside: bool,
    side: u32,
    stage: Option<PixelStage>,
) -> Result<HomothetAnswer> {
    check_general_sites(sites)?;
    if !inside && sites.iter().all(Site::is_plain_point) {
        let points: Vec<DVec2> = sites
            .iter()
            .map(|s| match s.shape {
                Shape::Point(p) => p,
                _ => unreachable!("plain points"),
            })
            .collect();
        return largest_empty_by(machine, &points, unit, region, side, stage);
    }
    if stage == Some(PixelStage::DistanceTransform) {
        return Err(Error::InvalidInput(
            "the distance transform takes unweighted points without `inside`: use cones".into(),
        ));
    }
    let bounds = sites
        .iter()
        .map(Site::bounds)
        .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(a, b), (l, h)| {
            (a.min(l), b.max(h))
        });
    let (region, frame) = region_and_frame(region, bounds, side)?;
    let metric = unit.cone_metric()?;
    let mut all = sites.to_vec();
    if inside {
        all.extend(region.edges().map(|(a, b)| Site::new(Shape::Segment(a, b))));
    }
    let options = VoronoiOptions {
        metric,
        speedup: Speedup::Quadtree,
        distances: false,
        ..VoronoiOptions::exact(frame)
    };
    let region_mesh = RegionMesh::new(&region, &frame);
    let least_m = all
        .iter()
        .map(|s| s.multiplicative)
        .fold(f64::INFINITY, f64::min);
    let lipschitz = unit.lipschitz() / least_m;
    let bound = half_diagonal(&frame) * lipschitz;
    let mut tiles: Vec<(f64, Vec<usize>)> = Vec::new();
    let (stats, _) = draw_sites(machine, &all, &options, |tile| {
        let near = NearExtreme {
            maximum: true,
            within: (2.0 * bound * tile.keys.scale) as f32,
            squared_scale: 0.0,
            capacity: NEAR_PIXELS,
        };
        let picture = (Some(tile.ids), tile.depth, tile.x0, tile.y0, tile.inner);
        if let Some((z, pixels)) = highest_in_region(machine, &frame, &region_mesh, picture, near)?
        {
            tiles.push((tile.keys.distance(z), pixels));
        }
        Ok(())
    })?;
    let value = tiles.iter().map(|t| t.0).fold(f64::NEG_INFINITY, f64::max);
    if tiles.is_empty() {
        return Err(Error::InvalidInput(
            "no pixel centre lies in the region".into(),
        ));
    }
    // Fans (polygons, curves under other metrics) add their own error.
    let bound = bound + stats.distance_error_bound;
    let near_pixels = near_top(&tiles, value, bound);
    let centre = pixel_centre(&frame, near_pixels[0]);
    let pixel_bound = bound + 1e-5 * value.abs();
    let clearance = |c: DVec2, set: &[Site]| {
        set.iter()
            .map(|s| s.distance(metric, c))
            .fold(f64::INFINITY, f64::min)
    };
    let edges: Vec<(DVec2, DVec2)> = region.edges().collect();
    let mut best: Option<(DVec2, f64, f64, usize)> = None;
    for cluster in clusters(&frame, &near_pixels) {
        let (around, reach) = surroundings(&frame, &cluster);
        let slack = 3.0 * pixel_bound + lipschitz * reach;
        let near: Vec<Site> = all
            .iter()
            .filter(|s| s.distance(metric, around) <= value + slack)
            .copied()
            .collect();
        let allowed = |c: DVec2| {
            let tol = 1e-9 * (1.0 + c.abs().max_element());
            region.contains(c) || edges.iter().any(|(a, b)| segment_distance(c, *a, *b) < tol)
        };
        let found = if unit == Unit::Circle && near.iter().all(is_plain_point_or_segment) {
            // Exact: the best centre is a vertex of the diagram of points and
            // segments, or where its edges meet the region's boundary.
            let mut points = Vec::new();
            let mut lines = Vec::new();
            for site in &near {
                match site.shape {
                    Shape::Point(p) => points.push(p),
                    Shape::Segment(a, b) => {
                        points.extend([a, b]);
                        if a != b {
                            lines.push((a, b));
                        }
                    }
                    _ => unreachable!("points and segments"),
                }
            }
            let walls: Vec<(DVec2, DVec2)> = edges
                .iter()
                .filter(|(a, b)| segment_distance(around, *a, *b) <= reach)
                .copied()
                .collect();
            let mut candidates = clearing_vertices(&points, &lines, &walls, |_| true);
            candidates.extend(walls.iter().flat_map(|(a, b)| [*a, *b]));
            candidates.extend(points.iter().copied());
            candidates.retain(|c| c.is_finite() && c.distance(around) <= reach && allowed(*c));
            let cells = candidates.len();
            let mut bounded: Vec<(DVec2, f64)> = candidates
                .into_iter()
                .map(|c| (c, clearance(c, &near)))
                .collect();
            bounded.sort_by(|a, b| b.1.total_cmp(&a.1));
            let mut best: Option<(DVec2, f64)> = None;
            for (c, upper) in bounded {
                if best.is_some_and(|b| upper <= b.1) {
                    break;
                }
                let v = clearance(c, &all);
                if best.is_none_or(|b| v > b.1) {
                    best = Some((c, v));
                }
            }
            best.map(|(c, v)| (c, v, 0.0, cells))
        } else {
            branch_and_bound(
                around,
                reach,
                lipschitz,
                |c| clearance(c, &near),
                |c| clearance(c, &all),
                allowed,
                |c, r| {
                    region.contains(c)
                        || edges.iter().any(|(a, b)| segment_distance(c, *a, *b) <= r)
                },
            )
        };
        if let Some((c, v, gap, cells)) = found {
            if best.is_none_or(|b| v > b.1) {
                best = Some((c, v, gap, cells));
            }
        }
    }
    let (c, v, gap, cells) =
        best.ok_or_else(|| Error::InvalidInput("no empty homothet found".into()))?;
    let tol = 1e-9 * (1.0 + v.abs());
    let on: Vec<u32> = (0..all.len() as u32)
        .filter(|&i| (all[i as usize].distance(metric, c) - v).abs() <= tol.max(gap))
        .collect();
    let mut answer = answer_of(
        &frame,
        centre,
        value,
        pixel_bound,
        (
            Homothet {
                centre: c.to_array(),
                scale: v,
                sites: on,
            },
            cells,
        ),
    );
    answer.tolerance = gap;
    Ok(answer)
}

fn is_plain_point_or_segment(s: &Site) -> bool {
    matches!(s.shape, Shape::Point(_) | Shape::Segment(..))
        && s.multiplicative == 1.0
        && s.additive == 0.0
}

/// The region to search (the box `bounds` when none is given, checked
/// otherwise) and the frame that shows it.
fn region_and_frame(
    region: &Region,
    (lo, hi): (DVec2, DVec2),
    side: u32,
) -> Result<(Region, Frame)> {
    let defaulted = region.rings.is_empty();
    let region = if defaulted {
        Region {
            rings: vec![vec![lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)]],
        }
    } else {
        check_region(region)?;
        region.clone()
    };
    let (lo, hi) = region
        .rings
        .iter()
        .flatten()
        .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(a, b), p| {
            (a.min(*p), b.max(*p))
        });
    if !(hi - lo).cmpgt(DVec2::ZERO).all() {
        return Err(Error::InvalidInput(if defaulted {
            "the sites' bounding box has no area (one site, or all on a line along an axis): give a region".into()
        } else {
            "the region has no area".into()
        }));
    }
    let frame = Frame::fitting(side, lo, hi)?;
    Ok((region, frame))
}

/// A drawn tile: ids, depth, its corner in the picture, the part that is
/// picture.
type Tile<'a> = (
    Option<&'a crate::machine::Image>,
    &'a crate::machine::Image,
    u32,
    u32,
    crate::machine::PixelRect,
);

/// A tile's highest depth inside the region (its `triangles`, the rest masked)
/// and the picture pixels near it (the highest first), unless the whole tile
/// is masked.
fn highest_in_region(
    machine: &Machine,
    frame: &Frame,
    region_mesh: &RegionMesh,
    (ids, depth, x0, y0, inner): Tile<'_>,
    near: NearExtreme,
) -> Result<Option<(f32, Vec<usize>)>> {
    mask_outside(machine, ids, depth, region_mesh, x0, y0)?;
    let mut highest = machine.depth_extremes(depth, Some(near))?;
    if highest.near_count > highest.near.len() {
        // The list overflowed: ask again with room for every near pixel.
        let capacity = highest.near_count as u32;
        highest = machine.depth_extremes(depth, Some(NearExtreme { capacity, ..near }))?;
    }
    let w = depth.width() as usize;
    let to_picture = |at: usize| {
        let (i, j) = ((at % w) as u32, (at / w) as u32);
        (i < inner.width && j < inner.height)
            .then(|| (y0 + j) as usize * frame.width as usize + (x0 + i) as usize)
    };
    if highest.max <= 0.0 {
        return Ok(None);
    }
    Ok(to_picture(highest.at_max).map(|at| {
        let near = highest.near.iter().filter_map(|&a| to_picture(a));
        (highest.max, std::iter::once(at).chain(near).collect())
    }))
}

/// The sites' pixels (each once) and the farthest any site moved to its pixel
/// (in pixels), when the largest empty circle may take its pixel stage from
/// the distance transform: the device holds the picture whole and every site
/// lies on it or within a pixel of it (the frame fits the box's shorter side
/// to whole pixels). A pixel's distance to the snapped sites is within that
/// move of its true clearance.
fn snapped_seeds(
    machine: &Machine,
    sites: &[DVec2],
    unit: Unit,
    frame: &Frame,
) -> Option<(Vec<Seed>, f64)> {
    let (w, h) = (frame.width, frame.height);
    let side = flooding::MAX_SIDE.min(machine.max_picture_side());
    if unit != Unit::Circle || w > side || h > side {
        return None;
    }
    let far = DVec2::new((w - 1) as f64, (h - 1) as f64);
    let mut taken = vec![false; w as usize * h as usize];
    let mut seeds = Vec::new();
    let mut moved2: f64 = 0.0;
    for p in sites {
        let q = frame.to_pixel(*p);
        let pixel = q.round().clamp(DVec2::ZERO, far);
        moved2 = moved2.max(q.distance_squared(pixel));
        if moved2 > 1.0 {
            return None;
        }
        let (i, j) = (pixel.x as u32, pixel.y as u32);
        if !std::mem::replace(&mut taken[(j * w + i) as usize], true) {
            seeds.push([i as i32, j as i32]);
        }
    }
    Some((seeds, moved2.sqrt()))
}

/// The pixel stage of the largest empty circle by the exact Euclidean distance
/// transform of the snapped sites (compute passes instead of cones): the
/// region's pixels within `within` pixels of its highest value, the highest
/// first.
fn listed_of_transform(
    machine: &Machine,
    seeds: &[Seed],
    frame: &Frame,
    region_mesh: &RegionMesh,
    within: f64,
) -> Result<Vec<usize>> {
    let (w, h) = (frame.width, frame.height);
    let depth = machine.image(Format::DepthStencil, w, h)?;
    // Squared distances in pixels plus one, scaled into [0, 1]; the listing
    // window on their roots is then a little wider than asked.
    let scale = (1.0 / (w as f64 * w as f64 + h as f64 * h as f64)) as f32;
    flooding::euclidean_depth(machine, seeds, &depth, scale)?;
    let near = near_extreme(Metric::L2, scale as f64, within, true);
    let picture = (None, &depth, 0, 0, PixelRect::of(&depth));
    let highest = highest_in_region(machine, frame, region_mesh, picture, near)?;
    Ok(highest.map(|(_, p)| p).unwrap_or_default())
}

/// The pixels of the tiles whose highest value is within `2 bound` of the
/// highest of all, `value`.
fn near_top(tiles: &[(f64, Vec<usize>)], value: f64, bound: f64) -> Vec<usize> {
    tiles
        .iter()
        .filter(|t| t.0 >= value - 2.0 * bound)
        .flat_map(|t| t.1.iter().copied())
        .collect()
}

fn check_region(region: &Region) -> Result<()> {
    for (r, ring) in region.rings.iter().enumerate() {
        if ring.len() < 3 {
            return Err(Error::InvalidInput(format!(
                "region ring {r} has {} vertices; it needs 3",
                ring.len()
            )));
        }
        if ring.iter().any(|p| !p.is_finite()) {
            return Err(Error::InvalidInput(format!(
                "region ring {r} has a coordinate that is not finite"
            )));
        }
    }
    Ok(())
}

/// A frame sure to hold the best centre. The homothet centred on the sites'
/// bounding box's middle that holds k of them has a scale λ₀ no smaller than the
/// optimum's, so the best centre lies in the intersection (all sites) or the
/// union (k of them) of the boxes of `s − λ₀ Q`.
fn enclosing_frame(sites: &[DVec2], unit: Unit, side: u32, k: usize) -> Result<Frame> {
    let lo = sites.iter().fold(DVec2::INFINITY, |a, p| a.min(*p));
    let hi = sites.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
    let mid = (lo + hi) / 2.0;
    let scale0 = kth_gauge(sites, unit, mid, k).unwrap_or(0.0);
    // Fewer than all: the centre is within λ₀ (−Q) of one of the k it holds.
    let (lo, hi) = if k < sites.len() { (hi, lo) } else { (lo, hi) };
    let (qlo, qhi) = match unit {
        Unit::Circle => (DVec2::splat(-1.0), DVec2::splat(1.0)),
        Unit::Polygon(g) => (
            g.vertices.iter().fold(DVec2::INFINITY, |a, p| a.min(*p)),
            g.vertices
                .iter()
                .fold(DVec2::NEG_INFINITY, |a, p| a.max(*p)),
        ),
    };
    // c ∈ s − λ₀Q for every s: c ≥ s − λ₀ qhi and c ≤ s − λ₀ qlo.
    let mut blo = hi - qhi * scale0;
    let mut bhi = lo - qlo * scale0;
    // The box can shrink to the answer itself (co-circular sites): keep a few
    // percent of the sites' extent around it.
    let floor = 0.05 * (hi - lo).abs().max_element() + 1e-9 * (1.0 + mid.abs().max_element());
    let middle = (blo + bhi) / 2.0;
    blo = blo.min(middle - DVec2::splat(floor / 2.0));
    bhi = bhi.max(middle + DVec2::splat(floor / 2.0));
    let extent = (bhi - blo).max_element();
    let pad = DVec2::splat(extent * 4.0 / side as f64);
    blo -= pad;
    bhi = bhi.max(blo + DVec2::splat(extent * 1e-3)) + pad;
    Frame::fitting(side, blo, bhi)
}

/// The bounding box of the unit shape around its kernel point.
fn unit_box(unit: Unit) -> (DVec2, DVec2) {
    match unit {
        Unit::Circle => (DVec2::splat(-1.0), DVec2::splat(1.0)),
        Unit::Polygon(g) => (
            g.vertices.iter().fold(DVec2::INFINITY, |a, p| a.min(*p)),
            g.vertices
                .iter()
                .fold(DVec2::NEG_INFINITY, |a, p| a.max(*p)),
        ),
    }
}

/// The frame showing the box `lo..hi` with `side` pixels along its longer axis.
/// The pixels within `within` (pixels of distance) of an extreme of depths
/// that are keys times `scale`: L2 keys are squared distances, the other
/// metrics' are distances.
fn near_extreme(metric: Metric, scale: f64, within: f64, maximum: bool) -> NearExtreme {
    let (within, squared_scale) = match metric {
        Metric::L2 => (within, scale),
        _ => (within * scale, 0.0),
    };
    NearExtreme {
        maximum,
        within: within as f32,
        squared_scale: squared_scale as f32,
        capacity: NEAR_PIXELS,
    }
}

/// Pixels near the extreme that are refined around, at most.
const NEAR_PIXELS: u32 = 4096;

/// A disc holding every centre the near-extreme pixels stand for: around their
/// bounding box's middle, reaching its corners and a pixel beyond.
fn surroundings(frame: &Frame, pixels: &[usize]) -> (DVec2, f64) {
    let centres: Vec<DVec2> = pixels.iter().map(|&p| pixel_centre(frame, p)).collect();
    let lo = centres.iter().fold(DVec2::INFINITY, |a, p| a.min(*p));
    let hi = centres.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
    (
        (lo + hi) / 2.0,
        // The best centre is within a pixel's diagonal of a near pixel's centre.
        (hi - lo).length() / 2.0 + 2.5 * half_diagonal(frame),
    )
}

fn pixel_centre(frame: &Frame, at: usize) -> DVec2 {
    let w = frame.width as usize;
    frame.to_world(DVec2::new((at % w) as f64, (at / w) as f64))
}

/// How far a depth may be from the scale it stands for (world units): float32
/// rounding, and for polygon fans the rasterizer's 1/256-pixel vertex snapping.
fn rounding(unit: Unit, frame: &Frame, value: f64) -> f64 {
    let snap = match unit {
        Unit::Circle => 0.0,
        Unit::Polygon(_) => unit.lipschitz() / (128.0 * frame.scale),
    };
    1e-5 * value.abs() + snap
}

fn half_diagonal(frame: &Frame) -> f64 {
    std::f64::consts::FRAC_1_SQRT_2 / frame.scale
}

/// The homothet at `centre` of scale `v` with the sites on its boundary.
fn homothet_at(sites: &[DVec2], unit: Unit, centre: DVec2, v: f64) -> Homothet {
    let tol = 1e-9 * (1.0 + v + centre.abs().max_element());
    Homothet {
        centre: centre.to_array(),
        scale: v,
        sites: (0..sites.len() as u32)
            .filter(|&i| (unit.gauge(sites[i as usize] - centre) - v).abs() <= tol)
            .collect(),
    }
}

fn candidates(sites: &[DVec2], keep: impl Fn(DVec2) -> bool) -> Vec<u32> {
    (0..sites.len() as u32)
        .filter(|&i| keep(sites[i as usize]))
        .collect()
}

/// The k-th smallest gauge from `c` to the sites (1 = nearest; n = furthest).
fn kth_gauge(sites: &[DVec2], unit: Unit, c: DVec2, k: usize) -> Option<f64> {
    let mut g: Vec<f64> = sites.iter().map(|s| unit.gauge(*s - c)).collect();
    let (_, kth, _) = g.select_nth_unstable_by(k - 1, f64::total_cmp);
    Some(*kth)
}

/// The region in picture pixels for its stencil mask, as triangles in the
/// `[x, y, depth]` layout of [`SITE_FAN`]: fans from each ring's first
/// vertex (filled by even-odd parity), and the band of pixels whose squares
/// meet its boundary (each edge swept by a pixel's square, a hexagon).
struct RegionMesh {
    fans: Vec<[f32; 3]>,
    band: Vec<[f32; 3]>,
}

impl RegionMesh {
    fn new(region: &Region, frame: &Frame) -> Self {
        let vertex = |v: DVec2| [v.x as f32, v.y as f32, 0.0];
        let mut fans = Vec::new();
        for ring in &region.rings {
            let p: Vec<DVec2> = ring.iter().map(|v| frame.to_pixel(*v)).collect();
            for k in 1..p.len() - 1 {
                fans.extend([p[0], p[k], p[k + 1]].map(vertex));
            }
        }
        let mut band = Vec::new();
        for (a, b) in region.edges() {
            let (a, b) = (frame.to_pixel(a), frame.to_pixel(b));
            // A hair more than half a pixel, so that a square that only
            // touches the boundary still counts whatever the rasterizer's
            // rule for centres on an edge.
            let h = 0.5 + 1e-3;
            let corners: Vec<DVec2> = [a, b]
                .iter()
                .flat_map(|&e| {
                    [(-h, -h), (h, -h), (h, h), (-h, h)].map(|(x, y)| e + DVec2::new(x, y))
                })
                .collect();
            let hull: Vec<DVec2> = super::higher_order::convex_hull(&corners)
                .into_iter()
                .map(|i| corners[i as usize])
                .collect();
            for k in 1..hull.len() - 1 {
                band.extend([hull[0], hull[k], hull[k + 1]].map(vertex));
            }
        }
        Self { fans, band }
    }
}

/// Pushes every pixel whose square misses the region to depth 0 (thesis
/// §5.4.1, widened by the boundary's band so that every point of the region is
/// within half a pixel's diagonal of a pixel left standing): the region's fans
/// invert the stencil's low bit, the band sets the next, then a picture-wide
/// rectangle at depth 0 is drawn where both are clear.
fn mask_outside(
    machine: &Machine,
    ids: Option<&crate::machine::Image>,
    depth: &crate::machine::Image,
    region: &RegionMesh,
    x0: u32,
    y0: u32,
) -> Result<()> {
    let (w, h) = (depth.width(), depth.height());
    let mut vertices = region.fans.clone();
    vertices.extend(&region.band);
    vertices.push([0.0; 3]);
    let mesh = machine.vertex_buffer(&vertices)?;
    // Site ids, one per vertex.
    let zeros = machine.vertex_buffer(&vec![0u32; vertices.len()])?;
    let parity = RasterState {
        stencil: StencilTest::on_pass(Compare::Always, 1, 1, StencilOp::Invert),
        color_mask: ChannelMask::NONE,
        ..RasterState::OVERWRITE
    };
    let banded = RasterState {
        stencil: StencilTest::on_pass(Compare::Always, 2, 2, StencilOp::Replace),
        ..parity
    };
    let forbid = RasterState {
        depth: DepthTest {
            compare: Compare::Always,
            write: true,
        },
        stencil: StencilTest::on_pass(Compare::Equal, 3, 0, StencilOp::Keep),
        color_mask: ChannelMask::NONE,
        ..RasterState::OVERWRITE
    };
    let push = ConePush {
        picture_size: [w as f32, h as f32],
        offset: [x0 as f32, y0 as f32],
        vertex_depth_scale: 0.0,
        fragment_depth_scale: 0.0,
        levels: 1,
        metric: (0, 2.0).into(),
    };
    let draw = |first_vertex: usize, count: usize| ConeDraw {
        mesh: &mesh,
        first_vertex: first_vertex as u32,
        vertex_count: count as u32,
        instances: &zeros,
        first_instance: 0,
        instance_count: u32::from(count > 0),
    };
    let (fans, band) = (region.fans.len(), region.band.len());
    machine.run(|pass| {
        pass.begin(
            Target {
                color: ids,
                depth_stencil: Some(depth),
            },
            Clear {
                stencil: Some(0),
                ..Clear::default()
            },
        )?;
        draw_cones(
            pass,
            &SITE_FAN,
            &parity,
            &DrawParams::default(),
            &push,
            &draw(0, fans),
        )?;
        let reference = DrawParams {
            stencil_reference: 2,
            ..DrawParams::default()
        };
        draw_cones(
            pass,
            &SITE_FAN,
            &banded,
            &reference,
            &push,
            &draw(fans, band),
        )?;
        pass.draw_rect(
            &forbid,
            &DrawParams::default(),
            &RectDraw::full_picture(w, h),
        )?;
        pass.end()
    })
}

/// Which envelope a picture shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Envelope {
    /// The regions of the furthest sites (or of the k-th nearest), as `enclose`
    /// draws them.
    Enclosing { k: usize },
    /// The nearest-site regions, outside the region darkened, as `empty` draws them.
    Empty,
}

/// A picture (RGB rows) of the envelope behind `answer`, like the thesis's
/// Figs. 4.1 and 5.1: the regions coloured by their site, the point sites as
/// dots, the exact homothet's outline in red and its centre in yellow; with its
/// width and height. Enclosing pictures show the sites and the whole homothet.
pub fn picture(
    machine: &Machine,
    shapes: &[Site],
    unit: Unit,
    answer: &HomothetAnswer,
    envelope: Envelope,
    region: &Region,
) -> Result<(Vec<u8>, u32, u32)> {
    let metric = unit.cone_metric()?;
    let centre = DVec2::from(answer.exact.centre);
    let scale = answer.exact.scale;
    let frame = match envelope {
        Envelope::Empty => answer.frame,
        // The sites and the whole homothet, a little margin around them.
        Envelope::Enclosing { .. } => {
            let (qlo, qhi) = unit_box(unit);
            let (lo, hi) = shapes.iter().map(Site::bounds).fold(
                (centre + qlo * scale, centre + qhi * scale),
                |(a, b), (l, h)| (a.min(l), b.max(h)),
            );
            let pad = 0.03 * (hi - lo).max_element() + 1e-9;
            let side = answer.frame.width.max(answer.frame.height);
            Frame::fitting(side, lo - pad, hi + pad)?
        }
    };
    let sites: Vec<DVec2> = shapes
        .iter()
        .filter_map(|s| match s.shape {
            Shape::Point(p) => Some(p),
            _ => None,
        })
        .collect();
    let sites = &sites[..];
    let labels = match envelope {
        Envelope::Enclosing { k } if k == 0 || k >= sites.len() => {
            super::higher_order::furthest(machine, sites, &frame, metric)?.labels
        }
        Envelope::Enclosing { k } => {
            kth_levels(machine, sites, frame, metric, k)?.level_labels(k as u32 - 1)
        }
        Envelope::Empty => {
            let options = VoronoiOptions {
                metric,
                distances: false,
                ..VoronoiOptions::exact(frame)
            };
            super::sites::voronoi_sites(machine, shapes, &options)?.labels
        }
    };
    let marks: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p)).collect();
    let mut rgb = crate::io::picture::label_rows(&labels, frame.width, 0, &marks, None);
    // A band about a pixel wide around the outline, in gauge units.
    let band = 0.8 / frame.scale * unit.lipschitz();
    let w = frame.width as usize;
    for (at, px) in rgb.chunks_exact_mut(3).enumerate() {
        let q = frame.to_world(DVec2::new((at % w) as f64, (at / w) as f64));
        if envelope == Envelope::Empty && !region.rings.is_empty() && !region.contains(q) {
            px.iter_mut().for_each(|v| *v = (*v as f32 * 0.35) as u8);
        }
        let g = unit.gauge(q - centre);
        if (g - scale).abs() <= band {
            px.copy_from_slice(&[220, 20, 30]);
        } else if q.distance(centre) * frame.scale <= 2.5 {
            px.copy_from_slice(&[255, 220, 0]);
        }
    }
    Ok((rgb, frame.width, frame.height))
}
