//! How a window of the picture is cut into the tiles a device can hold.

use crate::{
    error::{Error, Result},
    machine::{Machine, PixelRect},
};

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
            return Err(Error::out_of_range("tile size must be at least 1".into()));
        }
        Ok(Self {
            window,
            tile_w: max_tile.min(window.width),
            tile_h: max_tile.min(window.height).min(max_rows.max(1)),
        })
    }

    /// Whether the window fits one tile image.
    pub(crate) fn is_single(&self) -> bool {
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
