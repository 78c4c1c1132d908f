//! Rasters of features: a pixel is a feature where its value is not zero.
//! Read from a 2-D `.npy` array of any numeric or bool dtype, or from a PNG
//! (grey or colour, any depth; a pixel is a feature where any colour channel
//! is not zero, whatever its alpha). Row 0 is the array's first row, the
//! picture's top row.

use pixgeo::memory::Gather;
use std::{io::BufReader, path::Path};

use pixgeo::error::{Error, Result};

/// A raster of features, row-major.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mask {
    pub width: u32,
    pub height: u32,
    pub features: Vec<bool>,
}

/// Reads a mask from `path`, by its extension: `.npy` or `.png`.
pub fn read_mask(path: &Path) -> Result<Mask> {
    let parse = |message: String| parse_error(path, message);
    match extension(path).as_deref() {
        Some("npy") => read_npy_values(path)?.mask(None).map_err(parse),
        Some("png") => {
            let picture = read_png(path)?;
            // Grey and grey-alpha have one colour channel, RGB and RGBA three.
            let colours = if picture.channels >= 3 { 3 } else { 1 };
            let features = picture
                .samples
                .chunks_exact(picture.channels)
                .map(|p| p[..colours].iter().any(|&c| c != 0))
                .gather("features")?;
            mask(picture.width as u64, picture.height as u64, features).map_err(parse)
        }
        _ => Err(parse(
            "a mask is read from .npy or .png (by the file's extension)".into(),
        )),
    }
}

/// A file's extension in lower case.
fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}

fn parse_error(path: &Path, message: String) -> Error {
    Error::Parse {
        path: path.to_path_buf(),
        message,
    }
}

/// A PNG picture's pixels at 8 bits a sample, row-major, packed.
pub(crate) struct Png {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel: 1 grey, 2 grey and alpha, 3 RGB, 4 RGBA.
    pub channels: usize,
    pub samples: Vec<u8>,
}

/// Reads the PNG picture at `path`, any colour type and depth.
pub(crate) fn read_png(path: &Path) -> Result<Png> {
    super::decoding::decoding(path, "PNG", || decode_png(path))?
}

fn decode_png(path: &Path) -> Result<Png> {
    let parse = |message: String| parse_error(path, message);
    let file = std::fs::File::open(path).map_err(|e| Error::Io {
        path: path.to_path_buf(),
        cause: e,
    })?;
    let mut decoder = png::Decoder::new(BufReader::new(file));
    decoder.set_transformations(png::Transformations::normalize_to_color8());
    let mut reader = decoder
        .read_info()
        .map_err(|e| parse(format!("not a PNG picture: {e}")))?;
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| parse("the picture is too large to read".into()))?;
    let mut pixels = pixgeo::memory::filled(size, 0u8, "a mask's pixels")?;
    let info = reader
        .next_frame(&mut pixels)
        .map_err(|e| parse(format!("not a PNG picture: {e}")))?;
    let channels = info.color_type.samples();
    let samples = pixels[..info.buffer_size()]
        .chunks_exact(info.line_size)
        .flat_map(|row| &row[..info.width as usize * channels])
        .copied()
        .gather("samples")?;
    Ok(Png {
        width: info.width,
        height: info.height,
        channels,
        samples,
    })
}

/// A density raster for weighted Lloyd iterations (stippling), read by its
/// extension: a 2-D `.npy` array (its values), or a PNG picture, where dark
/// is dense: 255 minus the grey level (the luminance `(299 r + 587 g + 114
/// b) / 1000`, rounded, for colour), 8 bits a sample.
pub fn read_density(path: &Path) -> Result<Values> {
    match extension(path).as_deref() {
        Some("npy") => read_npy_values(path),
        Some("png") => {
            let picture = read_png(path)?;
            let values = picture
                .samples
                .chunks_exact(picture.channels)
                .map(|p| {
                    let grey = if picture.channels >= 3 {
                        (299 * p[0] as u32 + 587 * p[1] as u32 + 114 * p[2] as u32 + 500) / 1000
                    } else {
                        p[0] as u32
                    };
                    (255 - grey) as f64
                })
                .gather("grey")?;
            Ok(Values {
                width: picture.width as u64,
                height: picture.height as u64,
                values,
            })
        }
        _ => Err(parse_error(
            path,
            "a density is read from .npy or .png (by the file's extension)".into(),
        )),
    }
}

/// A raster's values, row-major, as doubles.
#[derive(Clone, Debug, PartialEq)]
pub struct Values {
    pub width: u64,
    pub height: u64,
    pub values: Vec<f64>,
}

impl Values {
    /// The mask of the pixels whose value is among `picked`, or (without)
    /// of those not zero, where NaN is neither and refused.
    #[expect(
        clippy::disallowed_methods,
        reason = "per-pixel values of a raster already read"
    )]
    pub fn mask(self, picked: Option<&[f64]>) -> std::result::Result<Mask, String> {
        let features = match picked {
            Some(picked) => self.values.iter().map(|v| picked.contains(v)).collect(),
            None if self.values.iter().any(|v| v.is_nan()) => {
                return Err(
                    "NaN is neither a feature nor background: give 0 or non-zero values".into(),
                )
            }
            None => self.values.iter().map(|&v| v != 0.0).collect(),
        };
        mask(self.width, self.height, features)
    }
}

/// The values of a 2-D `.npy` array of any numeric or bool dtype.
pub fn read_npy_values(path: &Path) -> Result<Values> {
    let (shape, values) = super::npy::read_f64(path)?;
    let [height, width] = shape[..] else {
        return Err(Error::Parse {
            path: path.to_path_buf(),
            message: format!("a raster is a 2-D array (rows, columns), not of shape {shape:?}"),
        });
    };
    Ok(Values {
        width,
        height,
        values,
    })
}

fn mask(width: u64, height: u64, features: Vec<bool>) -> std::result::Result<Mask, String> {
    if width == 0 || height == 0 {
        return Err(format!("the mask is empty ({height} x {width})"));
    }
    let side = |n: u64| u32::try_from(n).map_err(|_| format!("a side of {n} pixels is too long"));
    Ok(Mask {
        width: side(width)?,
        height: side(height)?,
        features,
    })
}
