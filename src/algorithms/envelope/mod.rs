//! The lower envelope of cones that the diagrams share (points, sites with
//! weights and shapes, the k nearest, homothets, alpha hulls).
//!
//! A diagram of points is a pass script over four steps:
//! - [`ConePlan::new`] sizes every cone, chooses its footprint and batches
//!   ([`footprint`]), with the device's costs ([`tuning`]);
//! - [`Tiling`] cuts the picture into the tiles the device holds;
//! - [`ConePlan::render`] draws each tile's envelope, or takes it per screen
//!   tile from lists of sites ([`screen_tiles`]);
//! - each [`DrawnTile`] is read back, its depths mapped to distances by a
//!   [`DepthMap`].
//!
//! The programs that draw the cones are in [`super::cones`].

mod accuracy;
mod footprint;
mod plan;
mod render;
mod screen_tiles;
mod tiling;
mod tuning;

pub(crate) use accuracy::{drawn_accuracy, metric_fan};
pub use accuracy::{Accuracy, Speedup};
pub use plan::{ConeGroup, MAX_EXACT_REACH};
pub(crate) use plan::{ConePlan, ConeSpec};
pub(crate) use render::{Picture, TileView};
pub(crate) use tiling::Tiling;
pub(crate) use tuning::Tuning;

use rayon::prelude::*;

use crate::{
    error::Result,
    geometry::metric::DepthKey,
    machine::{Buffer, Format, Image, Machine, PixelRect},
};

/// One drawn tile of a diagram, still on the device.
pub(crate) struct DrawnTile<'a> {
    pub ids: &'a Image,
    /// Depth, and (when asked for, or with ties) a stencil.
    pub depth: &'a Image,
    pub x0: u32,
    pub y0: u32,
    /// The part of the tile image that is picture.
    pub inner: PixelRect,
    /// Whether the labels' top bit marks the pixels whose runner-up is
    /// within rounding (`ConePlan::marks_near_ties`): only those need the
    /// exact check.
    pub marked: bool,
    pub keys: DepthMap,
}

/// How a diagram's depths map to distances (world units).
#[derive(Clone, Copy, Debug)]
pub(crate) struct DepthMap {
    /// What exact cones wrote; `None` where the depth is the distance itself
    /// (fans, and the surfaces of sites).
    pub key: Option<DepthKey>,
    /// Depth units per key, or per pixel of distance.
    pub scale: f64,
    pub pixels_per_unit: f64,
    /// Added to every distance: the smallest additive weight of sites.
    pub offset: f64,
}

impl DepthMap {
    /// The distance (world units) of a depth.
    pub fn distance(self, z: f32) -> f64 {
        let d = match self.key {
            Some(key) => key.distance(z as f64 / self.scale),
            None => z as f64 / self.scale,
        };
        d / self.pixels_per_unit + self.offset
    }
}

/// Exact cones per batch: the batch programs (`glsl/cone_batch.*`) take eight.
pub(crate) const BATCH: usize = 8;

/// Position of cell `(x, y)` along the Hilbert curve through a 2^16 x 2^16 grid:
/// cells close along the curve are close in the plane.
pub(crate) fn hilbert_index(mut x: u32, mut y: u32) -> u64 {
    const SIDE: u32 = 1 << 16;
    let mut index = 0u64;
    let mut s = SIDE / 2;
    while s > 0 {
        let rx = u32::from(x & s != 0);
        let ry = u32::from(y & s != 0);
        index += u64::from(s) * u64::from(s) * u64::from((3 * rx) ^ ry);
        // Rotate the quadrant so that the sub-curve starts where the last ended.
        if ry == 0 {
            if rx == 1 {
                x = SIDE - 1 - x;
                y = SIDE - 1 - y;
            }
            std::mem::swap(&mut x, &mut y);
        }
        s /= 2;
    }
    index
}

/// The unit square as two triangles: the mesh of a batch's rectangle.
pub(crate) const UNIT_SQUARE: [[f32; 3]; 6] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
];

/// Side of the screen tiles of [`super::cones::NEAREST_TILES`] and
/// [`super::cones::SITE_TILES`] (`glsl/nearest_tiles.frag`, `glsl/site_tiles.frag`:
/// TILE_SIDE).
pub(crate) const SCREEN_TILE_SIDE: u32 = 8;

/// Texels per row of their records images (`glsl/nearest_tiles.frag`,
/// `glsl/site_tiles.frag`: RECORD_ROW); every device has images this wide.
pub(crate) const RECORD_ROW: usize = 4096;

/// A records image from `texels`, filled by the returned upload: rows of
/// [`RECORD_ROW`] texels; `None` where the device cannot hold that many rows.
pub(crate) fn records_image(
    machine: &Machine,
    mut texels: Vec<[u32; 4]>,
) -> Result<Option<(Buffer, Image)>> {
    let rows = texels.len().div_ceil(RECORD_ROW).max(1);
    if rows > machine.max_picture_side() as usize {
        return Ok(None);
    }
    let width = if rows == 1 {
        texels.len().max(1)
    } else {
        RECORD_ROW
    };
    texels.resize(rows * width, [0; 4]);
    let mut upload = machine.readback_buffer(16 * texels.len() as u64)?;
    upload.write(&texels);
    let records = machine.image(Format::Rgba32Uint, width as u32, rows as u32)?;
    Ok(Some((upload, records)))
}

/// Distances of a label map's pixels from their depths (infinity where no site
/// is): the depth-to-distance step every diagram's readback shares.
pub(crate) fn distances_of(
    depths: &[f32],
    labels: &[u32],
    distance: impl Fn(f32) -> f64 + Sync,
) -> Vec<f32> {
    depths
        .par_iter()
        .zip(labels)
        .map(|(z, id)| {
            if *id == u32::MAX {
                f32::INFINITY
            } else {
                distance(*z) as f32
            }
        })
        .collect()
}
