//! Pictures for people: a label map with one colour per region and the sites drawn
//! on top.

use std::path::Path;

use glam::DVec2;
use image::{Rgb, RgbImage};

use crate::error::{Error, Result};

/// A bright, distinct colour for site `id` (golden-ratio hues); black for "no site".
pub fn site_color(id: u32) -> [u8; 3] {
    if id == u32::MAX {
        return [0, 0, 0];
    }
    let hue = (id as f64 * 0.618_033_988_749_895).fract() * 6.0;
    // Vary saturation and value a little so neighbouring hues still differ.
    let s = 0.45 + 0.3 * ((id as f64 * 0.414_213_562).fract());
    let v = 0.8 + 0.2 * ((id as f64 * 0.732_050_807).fract());
    let c = v * s;
    let x = c * (1.0 - ((hue % 2.0) - 1.0).abs());
    let (r, g, b) = match hue as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = v - c;
    [r, g, b].map(|t| ((t + m) * 255.0).round() as u8)
}

/// Renders a label map (row-major, `width` x `height`) with the sites (pixel
/// coordinates) as small dark dots.
pub fn label_picture(labels: &[u32], width: u32, height: u32, sites: &[DVec2]) -> RgbImage {
    let mut img = RgbImage::from_fn(width, height, |i, j| {
        Rgb(site_color(labels[(j * width + i) as usize]))
    });
    let dot = if sites.len() > 4000 { 0 } else { 1 };
    for s in sites {
        let (ci, cj) = (s.x.round() as i64, s.y.round() as i64);
        for dj in -dot..=dot {
            for di in -dot..=dot {
                let (i, j) = (ci + di, cj + dj);
                if i >= 0 && j >= 0 && i < width as i64 && j < height as i64 {
                    img.put_pixel(i as u32, j as u32, Rgb([20, 20, 20]));
                }
            }
        }
    }
    img
}

/// Writes a picture as PNG.
pub fn save_png(img: &RgbImage, path: &Path) -> Result<()> {
    img.save_with_format(path, image::ImageFormat::Png)
        .map_err(|e| Error::Io {
            path: path.to_path_buf(),
            source: std::io::Error::other(e),
        })
}
