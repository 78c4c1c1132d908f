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
//! `enclose.rs` and `empty.rs` hold the two searches, `refine.rs` their exact
//! refinement; the candidates and exact evaluation they share are here.

use crate::memory::Gather;
use glam::DVec2;

use crate::{
    error::{Error, Result},
    geometry::seed::Seed,
    geometry::{
        buckets::PointGrid,
        frame::{check_sites, first_of_each, Checked},
        metric::{segment_distance, Gauge, Metric},
        scale,
        site::{check_general_sites, Shape, Site, Sites},
        Frame,
    },
    machine::{
        ChannelMask, Clear, Compare, DepthTest, DrawParams, Format, Machine, NearExtreme,
        PixelRect, RasterState, RectDraw, StencilOp, StencilTest, Target,
    },
};

use crate::algorithms::cones::{draw_cones, ConeDraw, ConePush, SITE_FAN};

mod clearing;
mod refine;

use crate::geometry::exact::clearing::{certify, Certified, Obstacle, Piece, Placement, Vertex};
use clearing::clearing_vertices;
use refine::{
    best_of_clusters, best_vertex, branch_and_bound, clusters, quadratic_roots, smallest_circle,
    Goal,
};

use super::{
    flooding,
    higher_order::{draw_furthest, k_nearest_checked, KNearestOptions, MAX_LEVELS},
    voronoi::{draw_point_tiles, sites::draw_sites, Speedup, TileExtras, VoronoiOptions},
};

mod cell_bound;
mod empty;
mod enclose;
mod labels;
mod mask;

use cell_bound::clearance_over_square;
pub use empty::*;
pub use enclose::*;
pub use labels::*;
use mask::*;

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
    pub fn gauge(self, v: DVec2) -> f64 {
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
                let reflected: Vec<DVec2> = g.vertices.iter().map(|v| -*v).gather("reflected")?;
                Metric::polygon(&reflected, DVec2::ZERO).map_err(Error::malformed)
            }
        }
    }

    /// How much the gauge can change per unit of Euclidean motion.
    pub fn lipschitz(self) -> f64 {
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
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Homothet {
    pub centre: [f64; 2],
    pub scale: f64,
    /// The sites that determine it (on its boundary); with `inside`, ids from
    /// the number of sites on are the region's edges, ring by ring.
    pub sites: Vec<u32>,
}

/// How the picture's values were made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
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
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
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
    /// vertices or Welzl's algorithm decide, the branch-and-bound gap for
    /// sites other than points (for circles clearing points and segments,
    /// the proof of their best vertex, rounding counted).
    pub tolerance: f64,
    pub width: u32,
    pub height: u32,
    /// The picture the envelope was drawn on.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub frame: Frame,
}

impl Homothet {
    fn scaled(self, k: i32) -> Self {
        Self {
            centre: self.centre.map(|v| scale::times_power_of_two(v, k)),
            scale: scale::times_power_of_two(self.scale, k),
            ..self
        }
    }
}

impl HomothetAnswer {
    /// The answer for the sites moved by `by` (the centres rounded to the
    /// nearest double).
    fn moved(self, by: DVec2) -> Self {
        let shift = |h: Homothet| Homothet {
            centre: [h.centre[0] + by.x, h.centre[1] + by.y],
            ..h
        };
        Self {
            pixel: shift(self.pixel),
            exact: shift(self.exact),
            frame: Frame {
                origin: self.frame.origin + by,
                ..self.frame
            },
            ..self
        }
    }

    /// The answer for the sites scaled by 2^k.
    fn scaled(self, k: i32) -> Self {
        let frame = Frame {
            origin: DVec2::new(
                scale::times_power_of_two(self.frame.origin.x, k),
                scale::times_power_of_two(self.frame.origin.y, k),
            ),
            scale: scale::times_power_of_two(self.frame.scale, -k),
            ..self.frame
        };
        Self {
            pixel: self.pixel.scaled(k),
            exact: self.exact.scaled(k),
            pixel_bound: scale::times_power_of_two(self.pixel_bound, k),
            tolerance: scale::times_power_of_two(self.tolerance, k),
            frame,
            ..self
        }
    }
}

/// Picture side (pixels along the longer axis) used when none is given.
pub const DEFAULT_SIDE: u32 = Frame::DEFAULT_SIDE;

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
#[expect(
    clippy::disallowed_methods,
    reason = "per-pixel values of a picture whose room was reserved where it was placed"
)]
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
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
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

#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
fn candidates(sites: &[DVec2], keep: impl Fn(DVec2) -> bool) -> Vec<u32> {
    (0..sites.len() as u32)
        .filter(|&i| keep(sites[i as usize]))
        .collect()
}

/// The k-th smallest gauge from `c` to the sites (1 = nearest; n = furthest).
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
fn kth_gauge(sites: &[DVec2], unit: Unit, c: DVec2, k: usize) -> Option<f64> {
    let mut g: Vec<f64> = sites.iter().map(|s| unit.gauge(*s - c)).collect();
    let (_, kth, _) = g.select_nth_unstable_by(k - 1, f64::total_cmp);
    Some(*kth)
}
