//! Certified labels of diagrams of general sites: weighted points, segments,
//! circles and arcs, decided for the doubles the user gave.
//!
//! The device's float32 fragments (or the CPU's f64 pixel algorithm) propose a
//! label per pixel. Around each block of pixels the sites are ordered by a
//! lower bound of their weighted distance there; each pixel bounds the
//! distances of the sites that may beat its proposal by an f64 evaluation
//! with an error bound, and where the best interval overlaps another the two
//! are ordered exactly (`geometry::exact::site`). Equal distances go to the
//! smaller index. Distances are then recomputed from the labels as the CPU's
//! algorithm computes them, so devices and tilings agree to the bit.

use crate::memory::Gather;
use std::cmp::Ordering;

use glam::DVec2;
use rayon::prelude::*;

use crate::{
    cancel::Watch,
    error::{Error, Result},
    geometry::{
        exact::site::ExactFrame,
        exact::{to_pixel_bounded, two_difference, two_product},
        metric::Metric,
        site::{polygonal_curve_distance, ArcWedge, Shape, Site},
        Frame,
    },
};

/// Pixels a side of the blocks that share one ordering of the sites, and of
/// the sub-blocks proven at once where one site is alone near them.
const BLOCK: usize = 32;
const SUB: usize = 8;

const U: f64 = f64::EPSILON / 2.0;

/// Proves the nearest sites of the pixels of one frame.
pub(crate) struct SiteCertifier<'a> {
    sites: &'a [Site],
    /// The sites in pixel coordinates, as the CPU's algorithm rounds them.
    pixels: Vec<Site>,
    /// The Euclidean distance (pixels) each rounded site may lie from the
    /// exact one.
    errors: Vec<f64>,
    /// The arcs' wedges (pixel coordinates).
    wedges: Vec<Option<ArcWedge>>,
    /// Each site's box (pixel coordinates), the size of its largest corner,
    /// and its pixels per weighted unit of distance.
    boxes: Vec<(DVec2, DVec2)>,
    magnitudes: Vec<f64>,
    per_unit: Vec<f64>,
    /// The metric's least distance of a Euclidean unit.
    lower: f64,
    frame: Frame,
    metric: Metric,
    exact: ExactFrame,
}

/// A site's weighted distance from one pixel lies in `[lo, hi]`; `value` is
/// the f64 evaluation the diagram's distances report.
#[derive(Clone, Copy, Debug)]
struct Bounds {
    lo: f64,
    hi: f64,
    value: f64,
    id: u32,
}

fn down(x: f64) -> f64 {
    x - (4.0 * U * x.abs() + f64::MIN_POSITIVE)
}

fn up(x: f64) -> f64 {
    x + (4.0 * U * x.abs() + f64::MIN_POSITIVE)
}

impl<'a> SiteCertifier<'a> {
    /// For `sites` (world coordinates, checked) on `frame` under `metric`.
    pub fn new(sites: &'a [Site], frame: &Frame, metric: Metric) -> Result<Self> {
        let mut pixels = crate::memory::room(sites.len(), "the sites' pixels")?;
        let mut errors = crate::memory::room(sites.len(), "the sites' errors")?;
        for (i, s) in sites.iter().enumerate() {
            let mut error = 0.0f64;
            let pixel = s.to_pixels(
                |p| {
                    let (x, ex) = to_pixel_bounded(p.x, frame.origin.x, frame.scale);
                    let (y, ey) = to_pixel_bounded(p.y, frame.origin.y, frame.scale);
                    error = error.max(ex.hypot(ey) * (1.0 + 4.0 * U));
                    DVec2::new(x, y)
                },
                frame.scale,
            );
            if let Shape::Circle { radius, .. } | Shape::Arc { radius, .. } = s.shape {
                error += two_product(radius, frame.scale).1.abs();
            }
            let (lo, hi) = pixel.bounds();
            if !(lo.is_finite() && hi.is_finite() && error.is_finite()) {
                return Err(Error::out_of_range(format!(
                    "site {i} lies beyond the range of doubles in this picture's pixels \
                     (scale {} pixels a unit); keep sites within about 1e300 pixels",
                    frame.scale
                )));
            }
            pixels.push(pixel);
            errors.push(error);
        }
        let wedges = pixels.iter().map(Site::wedge).gather("wedges")?;
        let boxes: Vec<(DVec2, DVec2)> = pixels.iter().map(Site::bounds).gather("boxes")?;
        Ok(Self {
            sites,
            magnitudes: boxes
                .iter()
                .map(|(a, b)| a.abs().max(b.abs()).length())
                .gather("magnitudes")?,
            boxes,
            per_unit: pixels
                .iter()
                .map(|s| frame.scale * s.multiplicative)
                .gather("per unit")?,
            lower: metric.euclidean_bounds().0,
            pixels,
            errors,
            wedges,
            frame: *frame,
            metric,
            exact: ExactFrame::new(frame),
        })
    }

    /// Site `id`'s shape distance (pixels) from pixel `q`: an arc's through
    /// its wedge, made once.
    fn shape_distance(&self, id: usize, q: DVec2) -> f64 {
        let s = &self.pixels[id];
        match (s.shape, &self.wedges[id]) {
            (Shape::Arc { center, radius, .. }, Some(wedge)) => match self.metric {
                Metric::L2 => wedge.distance(q),
                metric => polygonal_curve_distance(metric, q - center, radius, Some(wedge)),
            },
            _ => s.distance_to_shape(self.metric, q),
        }
    }

    /// A lower bound on site `id`'s weighted distance from every pixel centre
    /// in the box `lo`..`hi` that costs less than a distance: from the
    /// Euclidean gap to the shape's box, or to a circle's ring.
    fn lower_bound(&self, id: usize, lo: DVec2, hi: DVec2) -> f64 {
        let s = &self.pixels[id];
        let (a, b) = self.boxes[id];
        let euclidean = match s.shape {
            Shape::Point(_) | Shape::Segment(..) => (a - hi).max(lo - b).max(DVec2::ZERO).length(),
            Shape::Circle { center, radius } | Shape::Arc { center, radius, .. } => {
                let nearest = (center - center.clamp(lo, hi)).length();
                let farthest = (center - lo).abs().max((center - hi).abs()).length();
                (nearest - radius).max(radius - farthest).max(0.0)
            }
        };
        let sizes = lo.abs().max(hi.abs()).length() + self.magnitudes[id];
        let gap = (euclidean * (1.0 - 8.0 * U) - self.errors[id] - 16.0 * U * sizes).max(0.0);
        down(down(self.lower * gap * (1.0 - 1e-12) / self.per_unit[id]) + s.additive)
    }

    /// Bounds on site `id`'s exact weighted distance from pixel `q`. The f64
    /// evaluation is the exact distance of a site moved by a few ulps of the
    /// sizes involved (an arc's ends and sides by a few ulps of its radius),
    /// and the rounding moved it by `errors`; the metric bounds what such
    /// moves change.
    fn bounds(&self, id: usize, q: DVec2) -> Bounds {
        let s = &self.pixels[id];
        let v = self.shape_distance(id, q);
        let moved = match s.shape {
            Shape::Point(p) => {
                let (_, ex) = two_difference(q.x, p.x);
                let (_, ey) = two_difference(q.y, p.y);
                self.errors[id] + ex.abs() + ey.abs()
            }
            Shape::Segment(..) | Shape::Circle { .. } | Shape::Arc { .. } => {
                let (lo, hi) = s.bounds();
                let sizes = (q - lo).length() + (q - hi).length() + (hi - lo).length();
                self.errors[id] + 64.0 * U * sizes
            }
        };
        let error = self.metric.displacement_error(v, moved) * (1.0 + 1e-9) + 64.0 * U * v;
        let per_unit = self.frame.scale * s.multiplicative;
        let (lo, hi) = ((v - error).max(0.0), v + error);
        Bounds {
            lo: down(down(down(lo) / per_unit) + s.additive),
            hi: up(up(up(hi) / per_unit) + s.additive),
            value: v / per_unit + s.additive,
            id: id as u32,
        }
    }

    /// Proves the proposed `labels` of the whole frame (row-major), mending
    /// those that are not the exact nearest sites, and writes each pixel's
    /// weighted distance (world units) from its site into `distances`, where
    /// given. Returns the number of labels mended.
    pub fn certify(&self, labels: &mut [u32], distances: Option<&mut [f32]>) -> Result<usize> {
        let width = self.frame.width as usize;
        let rows = BLOCK * width;
        let mut scratch = Vec::new();
        let distances = match distances {
            Some(d) => d,
            None => {
                scratch.resize(labels.len(), 0.0);
                &mut scratch
            }
        };
        let watch = Watch::current();
        let mended: Vec<usize> = labels
            .par_chunks_mut(rows)
            .zip(distances.par_chunks_mut(rows))
            .enumerate()
            .map(|(band, (labels, distances))| {
                watch.check()?;
                let mut mended = 0;
                for x0 in (0..width).step_by(BLOCK) {
                    mended += self.block(band * BLOCK, x0, labels, distances)?;
                }
                Ok(mended)
            })
            .collect::<Result<_>>()?;
        Ok(mended.into_iter().sum())
    }

    /// Certifies the block of pixels whose first is column `x0` of the first
    /// of the rows of `labels` and `distances` (frame row `y0`).
    fn block(
        &self,
        y0: usize,
        x0: usize,
        labels: &mut [u32],
        distances: &mut [f32],
    ) -> Result<usize> {
        let width = self.frame.width as usize;
        let (columns, height) = (BLOCK.min(width - x0), labels.len() / width);
        let lo = DVec2::new(x0 as f64, y0 as f64);
        let hi = lo + DVec2::new(columns as f64 - 1.0, height as f64 - 1.0);
        let pixel = |x: usize, y: usize| DVec2::new(x as f64, (y0 + y) as f64);
        // The proposals' bounds first: the farthest of them bounds the sites
        // worth ordering for the block.
        let proposals: Vec<Option<Bounds>> = (0..height)
            .flat_map(|y| (x0..x0 + columns).map(move |x| (x, y)))
            .map(|(x, y)| {
                let proposed = labels[y * width + x] as usize;
                (proposed < self.sites.len()).then(|| self.bounds(proposed, pixel(x, y)))
            })
            .gather("proposed")?;
        let reach = proposals
            .iter()
            .map(|b| b.map_or(f64::INFINITY, |b| b.hi))
            .fold(f64::NEG_INFINITY, f64::max);
        // The sites' lower bounds over the block within that, smallest first.
        let mut order: Vec<(f64, usize)> = (0..self.pixels.len())
            .map(|i| (self.lower_bound(i, lo, hi), i))
            .filter(|&(bound, _)| bound <= reach)
            .gather("order")?;
        order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut mended = 0;
        let mut near = Vec::new();
        for sy in (0..height).step_by(SUB) {
            for sx in (x0..x0 + columns).step_by(SUB) {
                let ys = sy..(sy + SUB).min(height);
                let xs = sx..(sx + SUB).min(x0 + columns);
                let proposal = |x: usize, y: usize| proposals[y * columns + x - x0];
                let cells = || ys.clone().flat_map(|y| xs.clone().map(move |x| (x, y)));
                // Where every pixel proposes one site and no other can come
                // as near anywhere in the sub-block, all are proven at once.
                let first = proposal(sx, sy);
                let same = cells().all(
                    |(x, y)| matches!((proposal(x, y), first), (Some(b), Some(f)) if b.id == f.id),
                );
                if let (true, Some(first)) = (same, first) {
                    let top = cells()
                        .map(|(x, y)| proposal(x, y).unwrap().hi)
                        .fold(0.0, f64::max);
                    let (slo, shi) = (pixel(sx, sy), pixel(xs.end - 1, ys.end - 1));
                    let alone =
                        order
                            .iter()
                            .take_while(|(bound, _)| *bound <= top)
                            .all(|&(_, i)| {
                                i == first.id as usize || self.lower_bound(i, slo, shi) > top
                            });
                    if alone {
                        for (x, y) in cells() {
                            distances[y * width + x] = proposal(x, y).unwrap().value as f32;
                        }
                        continue;
                    }
                }
                for (x, y) in cells() {
                    let at = y * width + x;
                    let q = pixel(x, y);
                    let proposal = proposal(x, y);
                    near.clear();
                    near.extend(proposal);
                    let mut best = proposal.map_or(f64::INFINITY, |b| b.hi);
                    let proposed = proposal.map_or(usize::MAX, |b| b.id as usize);
                    for &(bound, i) in &order {
                        if bound > best {
                            break;
                        }
                        if i == proposed || self.lower_bound(i, q, q) > best {
                            continue;
                        }
                        let b = self.bounds(i, q);
                        best = best.min(b.hi);
                        near.push(b);
                    }
                    near.retain(|b| b.lo <= best);
                    let nearest = self.nearest(&mut near, [x as i64, (y0 + y) as i64])?;
                    distances[at] = nearest.map_or(f32::INFINITY, |b| b.value as f32);
                    let label = nearest.map_or(u32::MAX, |b| b.id);
                    if label != labels[at] {
                        labels[at] = label;
                        mended += 1;
                    }
                }
            }
        }
        Ok(mended)
    }

    /// The exact nearest of the candidates `near` of pixel `pixel`, the
    /// smallest index of equally near ones.
    fn nearest(&self, near: &mut [Bounds], pixel: [i64; 2]) -> Result<Option<Bounds>> {
        near.sort_unstable_by(|a, b| a.lo.total_cmp(&b.lo).then(a.id.cmp(&b.id)));
        let Some((first, rest)) = near.split_first() else {
            return Ok(None);
        };
        let mut best = *first;
        for c in rest {
            let order = if best.hi < c.lo {
                Ordering::Less
            } else if c.hi < best.lo {
                Ordering::Greater
            } else {
                self.compare(best.id, c.id, pixel)?
            };
            if order.then(best.id.cmp(&c.id)) == Ordering::Greater {
                best = *c;
            }
        }
        Ok(Some(best))
    }

    fn compare(&self, a: u32, b: u32, pixel: [i64; 2]) -> Result<Ordering> {
        let (sa, sb) = (&self.sites[a as usize], &self.sites[b as usize]);
        self.exact.order(sa, sb, self.metric, pixel).ok_or_else(|| {
            Error::out_of_range(format!(
                "pixel ({}, {}) is as near site {a} as site {b} under {} to 1024 bits, and \
                 pixgeo cannot decide such a tie: an arc's end at an angle other than 0 is a \
                 transcendental point (arcs mirrored about the pixel tie there), and under L_p \
                 points of different weights compare exactly only where their distances \
                 separate in floats",
                pixel[0], pixel[1], self.metric
            ))
        })
    }
}
