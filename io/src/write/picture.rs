//! Pictures for people: a label map with one colour per region and the sites drawn
//! on top, written as PNG row band by row band.

use std::{fs::File, path::Path};

use glam::DVec2;

use super::output::OutputFile;
use pixgeo::{Error, Result};

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

/// A colour for `t` in [0, 1], dark blue through teal and green to yellow
/// (close to viridis), so that lighter is higher in grey too.
pub fn ramp(t: f64) -> [u8; 3] {
    const STOPS: [[f64; 3]; 5] = [
        [68.0, 1.0, 84.0],
        [59.0, 82.0, 139.0],
        [33.0, 145.0, 140.0],
        [94.0, 201.0, 98.0],
        [253.0, 231.0, 37.0],
    ];
    let x = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let k = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - k as f64;
    std::array::from_fn(|c| (STOPS[k][c] + (STOPS[k + 1][c] - STOPS[k][c]) * f).round() as u8)
}

/// Contour lines of the distance map drawn over a picture: one every `step` of
/// distance, so the cones' lower envelope shows as rings.
#[derive(Clone, Copy, Debug)]
pub struct Contours<'a> {
    /// Distances, the same rows as the labels.
    pub distances: &'a [f32],
    pub step: f32,
    /// Width of a line in the same units (one pixel).
    pub line: f32,
}

/// RGB bytes of rows `y0 ..` of a label map (`labels` holds whole rows of
/// `width`), with the sites (pixel coordinates) as small dark dots and, if given,
/// distance contours.
pub fn label_rows(
    labels: &[u32],
    width: u32,
    y0: u32,
    sites: &[DVec2],
    contours: Option<Contours<'_>>,
) -> Vec<u8> {
    let mut rgb: Vec<u8> = labels.iter().flat_map(|&id| site_color(id)).collect();
    if let Some(c) = contours {
        for (px, d) in rgb.chunks_exact_mut(3).zip(c.distances) {
            // A line about one pixel wide where the distance crosses a multiple of
            // the step.
            if (d / c.step).fract() * c.step < c.line {
                px.iter_mut().for_each(|v| *v = (*v as f32 * 0.55) as u8);
            }
        }
    }
    let rows = (labels.len() / width.max(1) as usize) as i64;
    let dot = if sites.len() > 4000 { 0 } else { 1 };
    for s in sites {
        let (ci, cj) = (s.x.round() as i64, s.y.round() as i64 - y0 as i64);
        for dj in -dot..=dot {
            for di in -dot..=dot {
                let (i, j) = (ci + di, cj + dj);
                if i >= 0 && j >= 0 && i < width as i64 && j < rows {
                    let k = 3 * (j as usize * width as usize + i as usize);
                    rgb[k..k + 3].copy_from_slice(&[20, 20, 20]);
                }
            }
        }
    }
    rgb
}

/// A PNG picture written row band by row band.
pub struct PngStream {
    output: OutputFile,
    writer: png::StreamWriter<'static, File>,
}

impl PngStream {
    /// Creates an RGB picture of `width` x `height` at `path` (named `*.png`);
    /// the file appears only when [`PngStream::finish`] succeeds.
    pub fn create(path: &Path, width: u32, height: u32) -> Result<Self> {
        let err = |e: png::EncodingError| Error::Io {
            path: path.to_path_buf(),
            cause: std::io::Error::other(e),
        };
        // The encoder writes whole chunks, so the file is left unbuffered: every
        // write error reaches `write` or `finish` instead of a buffer's `Drop`.
        let (output, file) = OutputFile::create(path, "png", "pictures")?;
        let mut encoder = png::Encoder::new(file, width, height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let writer = encoder
            .write_header()
            .map_err(err)?
            .into_stream_writer()
            .map_err(err)?;
        Ok(Self { output, writer })
    }

    /// Appends RGB rows.
    pub fn write(&mut self, rgb: &[u8]) -> Result<()> {
        use std::io::Write;
        self.writer.write_all(rgb).map_err(|source| Error::Io {
            path: self.output.path().to_path_buf(),
            cause: source,
        })
    }

    /// Finishes the file; every row must have been written.
    pub fn finish(self) -> Result<()> {
        self.writer.finish().map_err(|e| Error::Io {
            path: self.output.path().to_path_buf(),
            cause: std::io::Error::other(e),
        })?;
        self.output.commit()
    }
}
