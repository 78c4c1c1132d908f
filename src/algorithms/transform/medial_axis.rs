//! The medial axis of a raster's free space (its pixels that are not
//! features), from the feature transform: the integer medial axis of
//! Hesselink and Roerdink (2008), under every metric.
//!
//! Two free pixels side by side whose nearest features lie far apart straddle
//! the bisector of those features, and the one nearer the bisector is on the
//! axis. A pixel boundary's steps and notches make such pairs too, with
//! features close together or seen under a narrow angle, so two prunings
//! keep the axis to the shape: the features must be more than a length apart
//! and subtend more than an angle at the pair. Unlike a thinning, the axis
//! need not be connected, but each pixel of it comes from the exact transform,
//! with no pass order to depend on.

use glam::DVec2;
use rayon::prelude::*;

use super::{Transform, TransformOptions};
use crate::error::{Error, Result};

/// Which pairs of features make an axis between them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pruning {
    /// The features must be more than this far apart (a Euclidean length, in
    /// sampled units). The steps of a digital curve put features a few
    /// pixels apart; corridors narrower than this have no axis.
    pub length: f64,
    /// And subtend more than this angle, in degrees, at the midpoint of the
    /// two pixels. A square corner's bisector is seen under 90°; a digital
    /// circle's notches under a few degrees.
    pub angle: f64,
}

impl Default for Pruning {
    fn default() -> Self {
        Self {
            length: 4.0,
            angle: 45.0,
        }
    }
}

/// The medial axis of the free space of the raster that `t` transforms, with
/// `options` (its metric and sampling): `true` at the axis's pixels,
/// row-major.
pub fn medial_axis(
    t: &Transform,
    options: &TransformOptions,
    pruning: Pruning,
) -> Result<Vec<bool>> {
    let Pruning { length, angle } = pruning;
    if !(length.is_finite() && length >= 0.0 && (0.0..=180.0).contains(&angle)) {
        return Err(Error::InvalidInput(format!(
            "pruning by length {length} and angle {angle}: give a finite length of 0 or more \
             and an angle from 0 to 180 degrees"
        )));
    }
    let angle = angle.to_radians();
    let (w, h) = (t.width as usize, t.height as usize);
    let [sy, sx] = options.sampling;
    let metric = options.metric;
    let feature = |p: usize| (t.feature_rows[p], t.feature_columns[p]);
    let offset = |p: usize, (row, column): (i32, i32)| {
        let dy = (p / w) as f64 - row as f64;
        let dx = (p % w) as f64 - column as f64;
        DVec2::new(dx * sx, dy * sy)
    };
    let free = |p: usize| {
        let (row, column) = feature(p);
        row != -1 && (row as usize * w + column as usize) != p
    };
    // Whether p, beside q, is the one of the two on the axis.
    let on_axis = |p: usize, q: usize| {
        let (fp, fq) = (feature(p), feature(q));
        if !free(q) || fp == fq {
            return false;
        }
        // Offsets from the features to the pixels' midpoint.
        let (to_p, to_q) = (offset(p, fp), offset(q, fq));
        let middle = (offset(q, fp) - to_p) * 0.5;
        let (a, b) = (to_p + middle, to_q - middle);
        if (a - b).length() <= length || a.angle_to(b).abs() <= angle {
            return false;
        }
        // How much farther each pixel is from the other's feature than from
        // its own: the smaller, the nearer the bisector.
        let p_margin = metric.distance(offset(p, fq)) - t.distances[p];
        let q_margin = metric.distance(offset(q, fp)) - t.distances[q];
        p_margin < q_margin || (p_margin == q_margin && p < q)
    };
    let mut axis = vec![false; w * h];
    axis.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        for (x, a) in row.iter_mut().enumerate() {
            let p = y * w + x;
            if !free(p) {
                continue;
            }
            let neighbours = [
                (x > 0).then(|| p - 1),
                (x + 1 < w).then(|| p + 1),
                (y > 0).then(|| p - w),
                (y + 1 < h).then(|| p + w),
            ];
            *a = neighbours.into_iter().flatten().any(|q| on_axis(p, q));
        }
    });
    Ok(axis)
}
