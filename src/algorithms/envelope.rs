//! The machinery that the lower-envelope diagrams share (points, sites with
//! weights and shapes, the k nearest, homothets, alpha hulls): tiles as drawn
//! and how their depths map to distances, the Hilbert order that keeps batched
//! cones together, the unit square of batch rectangles, and the screen tiles
//! whose records fragment shaders read. The programs that draw them are in
//! [`super::cones`].

use rayon::prelude::*;

use crate::{
    error::{Error, Result},
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

/// Side of the screen tiles of [`NEAREST_TILES`] and
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

/// How a window of the picture is cut into tiles that the device (or the
/// caller's `max_tile`) can hold, drawn row by row, left to right.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Tiling {
    pub window: PixelRect,
    /// The tile images' size.
    pub tile_w: u32,
    pub tile_h: u32,
}

impl Tiling {
    /// Tiles of at most `max_tile` pixels a side (the device's largest picture
    /// when `None`) and at most `max_rows` rows.
    pub fn new(
        machine: &Machine,
        max_tile: Option<u32>,
        window: PixelRect,
        max_rows: u32,
    ) -> Result<Self> {
        let side = machine.max_picture_side();
        let max_tile = max_tile.unwrap_or(side).min(side);
        if max_tile == 0 {
            return Err(Error::InvalidInput("tile size must be at least 1".into()));
        }
        Ok(Self {
            window,
            tile_w: max_tile.min(window.width),
            tile_h: max_tile.min(window.height).min(max_rows.max(1)),
        })
    }

    /// Whether the window fits one tile image.
    pub fn is_single(&self) -> bool {
        self.tile_w == self.window.width && self.tile_h == self.window.height
    }

    /// Each tile's picture pixel at the tile image's (0, 0), and the part of
    /// the tile image that is window.
    pub fn tiles(&self) -> impl Iterator<Item = (u32, u32, PixelRect)> + '_ {
        let (x_end, y_end) = (
            self.window.x + self.window.width,
            self.window.y + self.window.height,
        );
        (self.window.y..y_end)
            .step_by(self.tile_h as usize)
            .flat_map(move |y0| {
                (self.window.x..x_end)
                    .step_by(self.tile_w as usize)
                    .map(move |x0| {
                        let inner = PixelRect {
                            x: 0,
                            y: 0,
                            width: self.tile_w.min(x_end - x0),
                            height: self.tile_h.min(y_end - y0),
                        };
                        (x0, y0, inner)
                    })
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cover_the_window_once_row_by_row() {
        for (window, tile_w, tile_h) in [
            (
                PixelRect {
                    x: 0,
                    y: 0,
                    width: 10,
                    height: 7,
                },
                3,
                2,
            ),
            (
                PixelRect {
                    x: 8,
                    y: 16,
                    width: 33,
                    height: 20,
                },
                33,
                20,
            ),
            (
                PixelRect {
                    x: 5,
                    y: 2,
                    width: 1,
                    height: 9,
                },
                1,
                4,
            ),
            (
                PixelRect {
                    x: 0,
                    y: 0,
                    width: 64,
                    height: 64,
                },
                16,
                64,
            ),
        ] {
            let tiling = Tiling {
                window,
                tile_w,
                tile_h,
            };
            let mut covered = vec![0u32; (window.width * window.height) as usize];
            let mut last = (0, 0);
            for (x0, y0, inner) in tiling.tiles() {
                assert!((y0, x0) >= last, "row by row, left to right");
                last = (y0, x0);
                assert!(inner.width <= tile_w && inner.height <= tile_h);
                for y in y0..y0 + inner.height {
                    for x in x0..x0 + inner.width {
                        let (i, j) = (x - window.x, y - window.y);
                        covered[(j * window.width + i) as usize] += 1;
                    }
                }
            }
            assert!(
                covered.iter().all(|&c| c == 1),
                "{window:?} in {tile_w}x{tile_h}"
            );
            let single = tile_w == window.width && tile_h == window.height;
            assert_eq!(tiling.is_single(), single);
        }
    }
}
