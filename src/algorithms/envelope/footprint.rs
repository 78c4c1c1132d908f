//! Cones and their footprints: how far each cone reaches (picture-wide, the
//! quadtree's radius, or a radius per site), the polygon, ball, fan or batch
//! each is drawn with, and the draw order that keeps batches of neighbours.

use crate::memory::Gather;
use std::f64::consts::TAU;

use glam::DVec2;

use crate::{
    algorithms::cones::ConeBatch,
    geometry::{
        chain,
        cone::FanShape,
        frame::farthest2_in_rect,
        metric::{DepthKey, Metric},
        radius, Frame,
    },
};

use super::{
    accuracy::{metric_fan, Accuracy, Speedup},
    hilbert_index,
    plan::ConeSpec,
    tuning::Tuning,
    BATCH,
};

/// One cone to draw, in pixel coordinates.
#[derive(Clone, Copy, Debug)]
pub(super) struct Cone {
    pub site: DVec2,
    pub id: u32,
    /// Every owned pixel centre lies within this (Euclidean) distance; fragments
    /// beyond it are discarded.
    pub radius: f64,
    /// And within this distance in the diagram's metric (the radius for L2): the
    /// metric ball a footprint must cover.
    pub reach: f64,
    /// And inside this box, which batches draw (at most the radius's square).
    pub lo: DVec2,
    pub hi: DVec2,
}

impl Cone {
    /// The box cut to the square of side 2 reach around the site, which holds
    /// the metric's ball of that radius when the metric grows with each
    /// coordinate (all but polygon gauges).
    pub fn clip(&self) -> (DVec2, DVec2) {
        (
            self.lo.max(self.site - self.reach),
            self.hi.min(self.site + self.reach),
        )
    }
}

/// How a cone is drawn; the order is the draw order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Footprint {
    /// One of up to [`BATCH`] nearby exact cones drawn as one rectangle.
    Batch,
    /// A regular polygon with this many corners (exact cones; the square also
    /// around L∞ and L_p balls for p >= 2).
    Polygon(u32),
    /// A polygon around another metric's ball (exact cones): the metric's circle
    /// sampled at [`BALL_CORNERS`] equal angles (`chain::MetricFan::Uniform`).
    Ball,
    /// A triangle fan of this many triangles (for other metrics: over the metric's
    /// circle sampled at equal angles).
    Fan(u32),
    /// A fan over the thesis's polygonal chain of another metric's circle
    /// (§3.6.1–3.6.2), built for the radius of this [`chain::chain_level`].
    Chain(i32),
}

/// A cone with its footprint, ready to draw.
#[derive(Clone, Copy, Debug)]
pub(super) struct Shaped {
    pub cone: Cone,
    pub footprint: Footprint,
    /// Radius of the footprint's corners.
    pub outer_radius: f64,
}

/// Corners of an exact cone's footprint around another metric's ball (L1 and
/// L_p for p < 2): eight hug every L_p ball within 6% of its area for p in
/// [0.5, 3] and within 50% for p = 0.3, where the regular polygon around the
/// Euclidean disc that holds the ball takes up to 5 times the ball's area for
/// p = 0.5 (0.67 r²), 26 times for p = 0.3.
pub(super) const BALL_CORNERS: u32 = 8;

/// Cones of the `reaches` (in the metric) of tile candidates, half a
/// Euclidean pixel wider as other local radii are, each in the square of its
/// reach.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(super) fn reach_cones(
    pixels: &[DVec2],
    frame: &Frame,
    metric: Metric,
    reaches: &[f64],
) -> Vec<Cone> {
    let (a, b) = metric.euclidean_bounds();
    pixels
        .iter()
        .zip(reaches)
        .enumerate()
        .map(|(i, (p, r))| {
            let reach = r + 0.5 * b;
            Cone {
                site: *p,
                id: i as u32,
                radius: (reach / a).min(frame.farthest_pixel(*p) + 0.5),
                reach,
                lo: p - reach,
                hi: p + reach,
            }
        })
        .filter(|c| frame.distance_to_pixels(c.site) <= c.radius)
        .collect()
}

/// The cones of each pass to try, with the quadtree radius a pass uses (if any).
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(super) fn cone_attempts(
    pixels: &[DVec2],
    frame: &Frame,
    speedup: Speedup,
    metric: Metric,
) -> crate::Result<Vec<(Option<f64>, Vec<Cone>)>> {
    // The radius that reaches every pixel from a site, plus half a pixel so that
    // rasterization rules at a footprint's rim never drop a pixel centre.
    let picture_wide: Vec<f64> = pixels
        .iter()
        .map(|p| frame.farthest_pixel(*p) + 0.5)
        .gather("picture wide")?;
    let b = metric.euclidean_bounds().1;
    let cones_with = |radius: &dyn Fn(usize) -> f64| -> Vec<Cone> {
        pixels
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let r = radius(i);
                Cone {
                    site: *p,
                    id: i as u32,
                    radius: r,
                    reach: b * r,
                    lo: p - r,
                    hi: p + r,
                }
            })
            .filter(|c| c.radius > 0.0 && frame.distance_to_pixels(c.site) <= c.radius)
            .collect()
    };
    Ok(match speedup {
        Speedup::None => Vec::from([(None, cones_with(&|i| picture_wide[i]))]),
        Speedup::Local if metric != Metric::L2 => {
            // L1 and L∞ regions lie in boxes from their neighbours, clipped to the
            // picture's pixel centres.
            let boxes = radius::region_boxes(pixels, frame, metric).map_or_else(
                || crate::memory::filled(pixels.len(), None, "regions' boxes"),
                Ok,
            )?;
            let (first, last) = frame.pixel_centres();
            let clipped: Vec<Option<(DVec2, DVec2)>> = boxes
                .iter()
                .map(|b| b.map(|(lo, hi)| (lo.clamp(first, last), hi.clamp(first, last))))
                .gather("clipped")?;
            // The other metrics, the sites left without a box, and L∞'s boxes
            // (which hold diamonds) are bounded by the cover measured in the
            // metric (radius::local_metric_radii), half a Euclidean pixel wider
            // as for L2 (b / 2 in the metric); polygon gauges by the Euclidean
            // cover, stretched. Each is (Euclidean radius, reach in the metric).
            let covered = metric != Metric::L1 || boxes.iter().any(Option::is_none);
            let a = metric.euclidean_bounds().0;
            // Each with the box of the cover's cells the site may own a pixel of.
            let everywhere = (DVec2::NEG_INFINITY, DVec2::INFINITY);
            let cover: Vec<(f64, f64, (DVec2, DVec2))> = if !covered {
                crate::memory::filled(
                    pixels.len(),
                    (f64::INFINITY, f64::INFINITY, everywhere),
                    "covers",
                )?
            } else if let Some(regions) = radius::local_metric_regions(pixels, frame, metric) {
                regions
                    .into_iter()
                    .map(|r| ((r.reach + 0.5 * b) / a, r.reach + 0.5 * b, (r.lo, r.hi)))
                    .gather("cover")?
            } else {
                let (cell, bin) = radius::k_cell_and_bin(frame, pixels.len(), 1);
                radius::k_local_radii(pixels, frame, 1, cell, bin, metric.stretch())
                    .into_iter()
                    .map(|r| (r + 0.5, b * (r + 0.5), everywhere))
                    .gather("values")?
            };
            let mut cones = cones_with(&|i| {
                let corner = clipped[i].map_or(f64::INFINITY, |(lo, hi)| {
                    farthest2_in_rect(pixels[i], lo, hi).sqrt() + 0.5
                });
                cover[i].0.min(corner).min(picture_wide[i])
            });
            // A metric that grows with each coordinate and is 1 on the axes keeps
            // each coordinate's offset within the reach.
            let axes_bounded = !matches!(metric, Metric::Polygon(_));
            for cone in &mut cones {
                let i = cone.id as usize;
                let (_, reach, (lo, hi)) = cover[i];
                cone.reach = cone.reach.min(reach);
                if axes_bounded {
                    cone.lo = cone.lo.max(cone.site - reach);
                    cone.hi = cone.hi.min(cone.site + reach);
                }
                for (lo, hi) in clipped[i].into_iter().chain([(lo, hi)]) {
                    cone.lo = cone.lo.max(lo - 0.5);
                    cone.hi = cone.hi.min(hi + 0.5);
                }
            }
            Vec::from([(None, cones)])
        }
        Speedup::Local => {
            let bounds =
                radius::cell_bounds(pixels, frame, radius::default_bin(frame, pixels.len()));
            let mut cones = cones_with(&|i| (bounds[i].radius + 0.5).min(picture_wide[i]));
            // The region's box, half a pixel wider like the radius.
            for cone in &mut cones {
                let b = &bounds[cone.id as usize];
                cone.lo = cone.lo.max(b.lo - 0.5);
                cone.hi = cone.hi.min(b.hi + 0.5);
            }
            Vec::from([(None, cones)])
        }
        Speedup::Quadtree => {
            let bounds = radius::quadtree_width_bounds(pixels, frame);
            let widest = picture_wide.iter().copied().fold(0.0, f64::max);
            // The quadtree's widths are Euclidean; other metrics stretch them.
            let stretch = metric.stretch();
            let bounds = radius::WidthBounds {
                lower: bounds.lower * stretch,
                upper: bounds.upper.map(|u| u * stretch),
                ..bounds
            };
            // Coverage certifies a radius for Euclidean cones alone: under another
            // metric a pixel's nearest site may lie `stretch` times farther
            // (Euclidean) than the site whose cone covered it. Only the upper
            // bound, stretched, holds every region.
            let mut radii = radius::retry_radii(&bounds, widest);
            if metric != Metric::L2 {
                radii.drain(..radii.len() - 1);
            }
            radii
                .into_iter()
                .map(|r| (Some(r), cones_with(&|i| (r + 0.5).min(picture_wide[i]))))
                .gather("radii")?
        }
    })
}

/// Chooses each cone's footprint and sorts the cones into draw order: batched
/// cones first, along a Hilbert curve so that a batch's cones are neighbours, then
/// the others by footprint and site id.
///
/// With ties every exact cone gets a footprint of its own: counting ties
/// needs each cone's own fragments. `key` is what exact cones write: keys that
/// need powers batch only short cones.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(super) fn shape_cones(
    cones: &[Cone],
    frame: &Frame,
    spec: &ConeSpec,
    key: DepthKey,
    tuning: &Tuning,
) -> Vec<Shaped> {
    let (accuracy, metric, batch) = (spec.accuracy, spec.metric, !spec.ties);
    let batch_radius_limit = match key {
        DepthKey::Metric(Metric::Lp(_)) => tuning.batch_radius_lp,
        _ => tuning.batch_radius,
    };
    // L∞ balls and L_p balls for p >= 2 fill 88% or more of their bounding
    // square, which takes two triangles where the octagon takes eight (lavapipe
    // sets up and bins each).
    let square_ball = match metric {
        Metric::LInf => true,
        Metric::Lp(p) => p >= 2.0,
        _ => false,
    };
    // Measuring the sampled circle costs far more than scaling it: the ball
    // footprint's outer radius and area at reach 1.
    let (unit_ball_outer, unit_ball_area) = match (accuracy, metric) {
        (Accuracy::Exact, Metric::L1 | Metric::Lp(_)) if !square_ball => {
            let fan = chain::MetricFan::Uniform {
                corners: BALL_CORNERS,
            };
            let outer = fan.outer_radius_of_reach(metric, 1.0);
            let rim = fan.unit_mesh(metric, 1.0);
            let area = (1..rim.len() - 1)
                .map(|k| f64::from(rim[k][0] * rim[k + 1][1] - rim[k + 1][0] * rim[k][1]) / 2.0)
                .sum::<f64>();
            (outer, area * outer * outer)
        }
        _ => (1.0, 0.0),
    };
    // An exact cone drawn on its own: its footprint, outer radius and cost in
    // fragments, a triangle counting as the device's `triangle_fragments`. The square of side
    // 2 reach around the site (its corners reach √2 away), cut to the region's
    // box, holds the ball of every metric that grows with each coordinate.
    let alone = |cone: &Cone| -> (Footprint, f64, f64) {
        let (lo, hi) = cone.clip();
        let square_area = (hi - lo).max(DVec2::ZERO).element_product();
        let square = (
            Footprint::Polygon(4),
            cone.reach * std::f64::consts::SQRT_2,
            square_area + 2.0 * tuning.triangle_fragments,
        );
        if square_ball {
            return square;
        }
        let r = cone.reach;
        let (footprint, outer, area) = if metric != Metric::L2 {
            (Footprint::Ball, r * unit_ball_outer, unit_ball_area * r * r)
        } else {
            let k = tuning.polygon_corners(cone.radius);
            let outer = FanShape::with_triangles(cone.radius, k).outer_radius;
            let area = 0.5 * k as f64 * (TAU / k as f64).sin() * outer * outer;
            (Footprint::Polygon(k), outer, area)
        };
        let corners = match footprint {
            Footprint::Polygon(k) => k,
            _ => BALL_CORNERS,
        };
        let cost = area + (corners - 2) as f64 * tuning.triangle_fragments;
        if square.2 < cost {
            square
        } else {
            (footprint, outer, cost)
        }
    };
    let mut shaped: Vec<Shaped> = cones
        .iter()
        .map(|cone| {
            let fan = |s: FanShape| (Footprint::Fan(s.triangles), s.outer_radius);
            let (footprint, outer_radius) = match accuracy {
                Accuracy::Exact if batch && cone.radius < batch_radius_limit => {
                    (Footprint::Batch, cone.radius)
                }
                Accuracy::Exact => {
                    let (footprint, outer, _) = alone(cone);
                    (footprint, outer)
                }
                Accuracy::Fan {
                    triangles: Some(t), ..
                } if metric == Metric::L2 => fan(FanShape::with_triangles(cone.radius, t)),
                Accuracy::Fan {
                    epsilon,
                    triangles: None,
                } if metric == Metric::L2 => {
                    fan(FanShape::for_distance_error(cone.radius, epsilon))
                }
                Accuracy::Fan {
                    triangles: Some(t), ..
                } => (
                    Footprint::Fan(t),
                    metric_fan(accuracy).outer_radius_of_reach(metric, cone.reach),
                ),
                Accuracy::Fan { .. } => {
                    let outer = metric_fan(accuracy).outer_radius_of_reach(metric, cone.reach);
                    // L1 and L∞ chains are their exact circles at every radius.
                    let level = match metric {
                        Metric::L1 | Metric::LInf | Metric::Polygon(_) => 0,
                        _ => chain::chain_level(outer),
                    };
                    (Footprint::Chain(level), outer)
                }
            };
            Shaped {
                cone: *cone,
                footprint,
                outer_radius,
            }
        })
        .collect();
    let side = frame.width.max(frame.height) as f64;
    let curve = |p: DVec2| {
        let q = |v: f64| ((v + 0.5) / side * 65536.0).clamp(0.0, 65535.0) as u32;
        hilbert_index(q(p.x), q(p.y))
    };
    let order = |s: &Shaped| match s.footprint {
        Footprint::Batch => (s.footprint, curve(s.cone.site), s.cone.id),
        _ => (s.footprint, 0, s.cone.id),
    };
    shaped.sort_by_cached_key(order);
    // Cheap keys batch wide cones where the batch's rectangle, evaluating
    // every cone per fragment, costs less than the cones drawn alone. Whole
    // batches leave, so the others keep their grouping.
    if matches!(key, DepthKey::PowerSum(_)) {
        let batched = shaped
            .iter()
            .take_while(|s| s.footprint == Footprint::Batch)
            .count();
        for chunk in shaped[..batched].chunks_mut(BATCH) {
            let (lo, hi) = chunk
                .iter()
                .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), s| {
                    (lo.min(s.cone.lo - 0.5), hi.max(s.cone.hi + 0.5))
                });
            let singles: Vec<(Footprint, f64, f64)> =
                chunk.iter().map(|s| alone(&s.cone)).collect();
            let batch_cost = (hi - lo).element_product() * BATCH as f64;
            if batch_cost > singles.iter().map(|a| a.2).sum::<f64>() {
                for (s, a) in chunk.iter_mut().zip(singles) {
                    (s.footprint, s.outer_radius, _) = a;
                }
            }
        }
        shaped.sort_by_cached_key(order);
    }
    shaped
}

/// Instances of the batch program: the batched cones (a prefix of `shaped`) in
/// runs of [`BATCH`], each with the bounding box of its cones' footprints. The
/// last batch repeats its last cone to fill its slots.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(super) fn batches_of(shaped: &[Shaped]) -> Vec<ConeBatch> {
    let batched = shaped
        .iter()
        .take_while(|s| s.footprint == Footprint::Batch)
        .count();
    shaped[..batched]
        .chunks(BATCH)
        .map(|chunk| {
            let mut batch = ConeBatch {
                rect: [f32::MAX, f32::MAX, f32::MIN, f32::MIN],
                sites: [0.0; 2 * BATCH],
                radii2: [0.0; BATCH],
                ids: [0; BATCH],
            };
            for k in 0..BATCH {
                let cone = chunk[k.min(chunk.len() - 1)].cone;
                let (p, r) = (cone.site, cone.radius);
                batch.sites[2 * k] = p.x as f32;
                batch.sites[2 * k + 1] = p.y as f32;
                batch.radii2[k] = (r * r) as f32;
                batch.ids[k] = cone.id;
                // Half a pixel more, so that the rectangle's rasterization rules
                // never drop a pixel centre on the rim.
                let (lo, hi) = (cone.lo - 0.5, cone.hi + 0.5);
                batch.rect = [
                    batch.rect[0].min(lo.x as f32),
                    batch.rect[1].min(lo.y as f32),
                    batch.rect[2].max(hi.x as f32),
                    batch.rect[3].max(hi.y as f32),
                ];
            }
            batch
        })
        .collect()
}

/// A run of cones with one footprint: one instanced draw.
#[derive(Clone, Copy, Debug)]
pub(super) struct Group {
    pub footprint: Footprint,
    pub first: u32,
    pub count: u32,
}

pub(super) fn groups_of(shaped: &[Shaped]) -> Vec<Group> {
    let mut groups: Vec<Group> = Vec::new();
    for (i, s) in shaped.iter().enumerate() {
        match groups.last_mut() {
            Some(g) if g.footprint == s.footprint => g.count += 1,
            _ => groups.push(Group {
                footprint: s.footprint,
                first: i as u32,
                count: 1,
            }),
        }
    }
    groups
}
