//! The medial axis of a raster's free space (its pixels that are not
//! features), from the feature transform: the integer medial axis of
//! Hesselink and Roerdink (2008), under every metric, pruned and then joined
//! so that it keeps the free space's topology.
//!
//! Two free pixels side by side whose nearest features lie far apart straddle
//! the bisector of those features, and the one nearer the bisector is on the
//! axis. A pixel boundary's steps and notches make such pairs too, with
//! features close together or seen under a narrow angle, so two prunings
//! keep the axis to the shape: the features must be more than a length apart
//! and subtend more than an angle at the pair.
//!
//! Pruning alone may cut the axis into pieces, or leave a thin region with
//! none (its features are never far enough apart), or break the loop around a
//! hole. So the pruned pixels anchor a homotopic thinning of the free space
//! ([`thinning`](super::thinning)), nearest the features first: it joins them
//! along the middle and keeps each free region one piece with a loop around
//! each of its holes. A region whose pairs all fall to the length pruning is
//! anchored by its farthest-apart pairs instead, and one with no such pair
//! (a pixel between features) thins to its deepest pixel; lone pruned pixels
//! (a digital curve's lattice points that tie) anchor only a region with no
//! larger piece; a region all of whose pixels are nearest one feature has no
//! axis.

use crate::memory::Gather;
use glam::DVec2;
use rayon::prelude::*;

use super::{
    components::{components, NO_COMPONENT},
    thinning::thin,
    Transform, TransformOptions,
};
use crate::error::{Error, Result};

/// Which pairs of features make an axis between them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pruning {
    /// The features must be more than this far apart (a Euclidean length, in
    /// sampled units). The steps of a digital curve put features a few
    /// pixels apart; a region whose features are all closer is anchored by
    /// its farthest-apart pairs.
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
        return Err(Error::out_of_range(format!(
            "pruning by length {length} and angle {angle}: give a finite length of 0 or more \
             and an angle from 0 to 180 degrees"
        )));
    }
    let angle = angle.to_radians();
    let (w, h) = (t.width as usize, t.height as usize);
    let free: Vec<bool> = (0..w * h).map(|p| is_free(t, p)).gather("free")?;
    let separations = separations(t, options, angle, &free)?;
    let (regions, count) = components(&free, w)?;
    let pruned: Vec<bool> = separations.iter().map(|&s| s > length).gather("pruned")?;
    let (pieces, piece_count) = components(&pruned, w)?;
    let mut piece_size = crate::memory::filled(piece_count as usize, 0u32, "pieces' sizes")?;
    for &piece in pieces.iter().filter(|&&c| c != NO_COMPONENT) {
        piece_size[piece as usize] += 1;
    }
    let in_piece = |p: usize| pruned[p] && piece_size[pieces[p] as usize] > 1;
    // Per region: whether it has a piece of two pixels or more, a pruned
    // pixel, and its largest separation.
    let mut has_piece = crate::memory::filled(count as usize, false, "regions' pieces")?;
    let mut has_pruned = crate::memory::filled(count as usize, false, "regions' pruned pieces")?;
    let mut widest = crate::memory::filled(count as usize, 0.0f64, "regions' widths")?;
    // A region all of whose pixels are nearest one feature has no axis.
    let mut feature = crate::memory::filled(count as usize, None, "regions' features")?;
    let mut has_axis = crate::memory::filled(count as usize, false, "regions' axes")?;
    for p in (0..w * h).filter(|&p| free[p]) {
        let r = regions[p] as usize;
        has_pruned[r] |= pruned[p];
        has_piece[r] |= in_piece(p);
        widest[r] = widest[r].max(separations[p]);
        let f = (t.feature_rows[p], t.feature_columns[p]);
        has_axis[r] |= *feature[r].get_or_insert(f) != f;
    }
    let anchors: Vec<bool> = (0..w * h)
        .map(|p| {
            let r = regions[p] as usize;
            free[p]
                && if has_piece[r] {
                    in_piece(p)
                } else if has_pruned[r] {
                    pruned[p]
                } else {
                    widest[r] > 0.0 && separations[p] == widest[r]
                }
        })
        .gather("medial axis pixels")?;
    let shape: Vec<bool> = (0..w * h)
        .map(|p| free[p] && has_axis[regions[p] as usize])
        .gather("shape")?;
    Ok(thin(&shape, &anchors, &t.distances, w))
}

/// Whether pixel `p` is free: it has a nearest feature, not itself.
fn is_free(t: &Transform, p: usize) -> bool {
    let (row, column) = (t.feature_rows[p], t.feature_columns[p]);
    row != -1 && (row as usize * t.width as usize + column as usize) != p
}

/// Per pixel, how far apart the features are of the widest pair that puts it
/// on the axis, among the pairs with a neighbour whose features subtend more
/// than `angle` (radians) at the two; 0 where none does.
fn separations(
    t: &Transform,
    options: &TransformOptions,
    angle: f64,
    free: &[bool],
) -> Result<Vec<f64>> {
    let (w, h) = (t.width as usize, t.height as usize);
    let [sy, sx] = options.sampling;
    let metric = options.metric;
    let feature = |p: usize| (t.feature_rows[p], t.feature_columns[p]);
    let offset = |p: usize, (row, column): (i32, i32)| {
        let dy = (p / w) as f64 - row as f64;
        let dx = (p % w) as f64 - column as f64;
        DVec2::new(dx * sx, dy * sy)
    };
    // How far apart the features of p and its neighbour q are, where p is the
    // one of the two on the axis.
    let pair = |p: usize, q: usize| {
        let (fp, fq) = (feature(p), feature(q));
        if !free[q] || fp == fq {
            return None;
        }
        // Offsets from the features to the pixels' midpoint.
        let (to_p, to_q) = (offset(p, fp), offset(q, fq));
        let middle = (offset(q, fp) - to_p) * 0.5;
        let (a, b) = (to_p + middle, to_q - middle);
        if a.angle_to(b).abs() <= angle {
            return None;
        }
        // How much farther each pixel is from the other's feature than from
        // its own: the smaller, the nearer the bisector.
        let p_margin = metric.distance(offset(p, fq)) - t.distances[p];
        let q_margin = metric.distance(offset(q, fp)) - t.distances[q];
        (p_margin < q_margin || (p_margin == q_margin && p < q)).then(|| (a - b).length())
    };
    let mut separations = crate::memory::filled(w * h, 0.0, "feature separations")?;
    separations
        .par_chunks_mut(w)
        .enumerate()
        .for_each(|(y, row)| {
            for (x, s) in row.iter_mut().enumerate() {
                let p = y * w + x;
                if !free[p] {
                    continue;
                }
                let neighbours = [
                    (x > 0).then(|| p - 1),
                    (x + 1 < w).then(|| p + 1),
                    (y > 0).then(|| p - w),
                    (y + 1 < h).then(|| p + w),
                ];
                *s = neighbours
                    .into_iter()
                    .flatten()
                    .filter_map(|q| pair(p, q))
                    .fold(0.0, f64::max);
            }
        });
    Ok(separations)
}
