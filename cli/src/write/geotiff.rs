//! GeoTIFF rasters and world files: where a raster lies on the earth, written
//! so that GIS tools (GDAL, rasterio, QGIS) place it without help.
//!
//! A GeoTIFF here is a baseline TIFF of one or more bands (interleaved by
//! pixel, as NumPy's `(rows, columns, bands)`), uncompressed, in strips,
//! with the GeoTIFF 1.1 tags: ModelPixelScale and ModelTiepoint for a
//! north-up raster (ModelTransformation for one whose rows run north), and a
//! GeoKey directory with the raster type and, when known, the EPSG code. The
//! directory comes first and the strips after it, so the file streams band by
//! band without seeking, into pipes too.

use std::{
    fs::File,
    io::{BufWriter, Write},
    path::Path,
};

use super::output::OutputFile;
use pixgeo::{Error, Result};

/// Where a raster lies: its upper-left corner (of pixel (0, 0), not its
/// centre) and its pixels' size in world units, and the coordinate system.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeoReference {
    /// World x of the raster's left edge.
    pub left: f64,
    /// World y of row 0's outer edge.
    pub top: f64,
    /// A pixel's width.
    pub pixel_width: f64,
    /// A pixel's height, positive when rows run south (north-up: row 0 is
    /// the largest y), negative when they run north.
    pub pixel_height: f64,
    /// The EPSG code of the coordinate system, if known.
    pub epsg: Option<u16>,
}

/// The names world files take.
pub const WORLD_FILE_EXTENSIONS: [&str; 4] = ["tfw", "pgw", "pngw", "wld"];

impl GeoReference {
    /// Writes an ESRI world file (`.tfw`, `.pgw`, `.wld`): six lines giving
    /// the affine map from a pixel's centre to the world.
    pub fn write_world_file(&self, path: &Path) -> Result<()> {
        let (output, file) = OutputFile::create_any(path, &WORLD_FILE_EXTENSIONS, "world files")?;
        let mut w = BufWriter::new(file);
        let io = |cause| Error::Io {
            path: path.to_path_buf(),
            cause,
        };
        let lines = [
            self.pixel_width,
            0.0,
            0.0,
            -self.pixel_height,
            self.left + self.pixel_width / 2.0,
            self.top - self.pixel_height / 2.0,
        ];
        for v in lines {
            writeln!(w, "{v:?}").map_err(io)?;
        }
        w.flush().map_err(io)?;
        drop(w);
        output.commit()
    }
}

/// Parses `EPSG:N`: the EPSG code of a coordinate system.
pub fn parse_crs(text: &str) -> std::result::Result<u16, String> {
    let code = text
        .strip_prefix("EPSG:")
        .or_else(|| text.strip_prefix("epsg:"))
        .ok_or_else(|| format!("`{text}`: give the coordinate system as EPSG:N"))?;
    match code.parse::<u16>() {
        Ok(n) if (1024..=32766).contains(&n) => Ok(n),
        _ => Err(format!(
            "`{text}`: GeoTIFF keys hold EPSG codes from 1024 to 32766"
        )),
    }
}

/// `EPSG:N`, as [`parse_crs`] reads it.
pub fn crs_name(epsg: Option<u16>) -> Option<String> {
    epsg.map(|code| format!("EPSG:{code}"))
}

/// A sample type a GeoTIFF holds.
pub trait Sample: Copy {
    /// TIFF's SampleFormat: 1 unsigned, 2 signed, 3 floating point.
    const FORMAT: u16;
    /// Bytes per sample.
    const BYTES: usize;
    fn put(self, out: &mut Vec<u8>);
}

impl Sample for u8 {
    const FORMAT: u16 = 1;
    const BYTES: usize = 1;
    fn put(self, out: &mut Vec<u8>) {
        out.push(self);
    }
}

/// A bool raster (a medial axis, a mask) is a byte raster of 0 and 1.
impl Sample for bool {
    const FORMAT: u16 = 1;
    const BYTES: usize = 1;
    fn put(self, out: &mut Vec<u8>) {
        out.push(u8::from(self));
    }
}

impl Sample for i32 {
    const FORMAT: u16 = 2;
    const BYTES: usize = 4;
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

impl Sample for u32 {
    const FORMAT: u16 = 1;
    const BYTES: usize = 4;
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

impl Sample for f32 {
    const FORMAT: u16 = 3;
    const BYTES: usize = 4;
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

impl Sample for f64 {
    const FORMAT: u16 = 3;
    const BYTES: usize = 8;
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

/// Bytes in one strip, about: GDAL reads strips of this size well.
const STRIP_BYTES: usize = 64 * 1024;

/// TIFF field types.
const SHORT: u16 = 3;
const LONG: u16 = 4;
const DOUBLE: u16 = 12;

/// One directory entry's value.
enum Value {
    Shorts(Vec<u16>),
    Longs(Vec<u32>),
    Doubles(Vec<f64>),
}

impl Value {
    fn kind_and_count(&self) -> (u16, usize, usize) {
        match self {
            Value::Shorts(v) => (SHORT, v.len(), 2),
            Value::Longs(v) => (LONG, v.len(), 4),
            Value::Doubles(v) => (DOUBLE, v.len(), 8),
        }
    }

    fn bytes(&self) -> Vec<u8> {
        match self {
            Value::Shorts(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Value::Longs(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Value::Doubles(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
        }
    }
}

/// The header and directory of a `width` x `height` raster of `bands` values
/// of `T` per pixel, ready for its strips, which follow it; and the rows per
/// strip.
fn header<T: Sample>(
    width: u32,
    height: u32,
    bands: u16,
    geo: Option<&GeoReference>,
) -> Result<(Vec<u8>, u32)> {
    if bands == 0 || width == 0 || height == 0 {
        return Err(Error::InvalidInput(format!(
            "a GeoTIFF of {width} x {height} pixels and {bands} bands holds nothing"
        )));
    }
    let row_bytes = width as usize * bands as usize * T::BYTES;
    let rows_per_strip = (STRIP_BYTES / row_bytes).clamp(1, height as usize) as u32;
    let strips = height.div_ceil(rows_per_strip);
    let strip_bytes = |s: u32| {
        let rows = rows_per_strip.min(height - s * rows_per_strip);
        rows as u64 * row_bytes as u64
    };
    let mut entries: Vec<(u16, Value)> = vec![
        (256, Value::Longs(vec![width])),
        (257, Value::Longs(vec![height])),
        (
            258,
            Value::Shorts(vec![8 * T::BYTES as u16; bands as usize]),
        ),
        (259, Value::Shorts(vec![1])),                 // no compression
        (262, Value::Shorts(vec![1])),                 // black is zero
        (273, Value::Longs(vec![0; strips as usize])), // strip offsets, below
        (277, Value::Shorts(vec![bands])),
        (278, Value::Longs(vec![rows_per_strip])),
        (
            279,
            Value::Longs((0..strips).map(|s| strip_bytes(s) as u32).collect()),
        ),
        (284, Value::Shorts(vec![1])), // bands interleaved by pixel
    ];
    if bands > 1 {
        // The bands past the first are data, not colour.
        entries.push((338, Value::Shorts(vec![0; bands as usize - 1])));
    }
    entries.push((339, Value::Shorts(vec![T::FORMAT; bands as usize])));
    if let Some(g) = geo {
        if g.pixel_height > 0.0 {
            entries.push((
                33550,
                Value::Doubles(vec![g.pixel_width, g.pixel_height, 0.0]),
            ));
            entries.push((
                33922,
                Value::Doubles(vec![0.0, 0.0, 0.0, g.left, g.top, 0.0]),
            ));
        } else {
            #[rustfmt::skip]
            let matrix = vec![
                g.pixel_width, 0.0, 0.0, g.left,
                0.0, -g.pixel_height, 0.0, g.top,
                0.0, 0.0, 0.0, 0.0,
                0.0, 0.0, 0.0, 1.0,
            ];
            entries.push((34264, Value::Doubles(matrix)));
        }
        // GeoKeys: version 1.1.0, then (key, location 0 = the value itself,
        // count 1, value): the raster type (1, pixel is area) and the
        // coordinate system, geographic for EPSG's 4000 to 4999 (the 2-D
        // geographic systems, as 4326) and projected otherwise.
        let mut keys = vec![(1025u16, 1u16)];
        if let Some(code) = g.epsg {
            let geographic = (4000..5000).contains(&code);
            keys.push((1024, if geographic { 2 } else { 1 }));
            keys.push((if geographic { 2048 } else { 3072 }, code));
        }
        keys.sort();
        let mut directory = vec![1, 1, 0, keys.len() as u16];
        for (key, value) in keys {
            directory.extend([key, 0, 1, value]);
        }
        entries.push((34735, Value::Shorts(directory)));
    }
    // Out-of-line values follow the directory; then the strips.
    let directory_bytes = 2 + 12 * entries.len() + 4;
    let mut extra_at = 8 + directory_bytes;
    let mut placed = Vec::new();
    for (_, value) in &entries {
        let (_, count, size) = value.kind_and_count();
        let bytes = count * size;
        if bytes > 4 {
            placed.push(Some(extra_at));
            extra_at += bytes + bytes % 2;
        } else {
            placed.push(None);
        }
    }
    let data_at = extra_at as u64;
    let total = data_at + height as u64 * row_bytes as u64;
    if total > u32::MAX as u64 {
        return Err(Error::InvalidInput(format!(
            "a {width} x {height} GeoTIFF of {}-byte samples passes TIFF's 4 GiB: write .npy",
            T::BYTES
        )));
    }
    let offsets: Vec<u32> = (0..strips)
        .map(|s| (data_at + s as u64 * rows_per_strip as u64 * row_bytes as u64) as u32)
        .collect();
    entries[5].1 = Value::Longs(offsets);

    let mut out = Vec::with_capacity(extra_at);
    out.extend_from_slice(b"II");
    out.extend_from_slice(&42u16.to_le_bytes());
    out.extend_from_slice(&8u32.to_le_bytes());
    out.extend_from_slice(&(entries.len() as u16).to_le_bytes());
    for ((tag, value), at) in entries.iter().zip(&placed) {
        let (kind, count, _) = value.kind_and_count();
        out.extend_from_slice(&tag.to_le_bytes());
        out.extend_from_slice(&kind.to_le_bytes());
        out.extend_from_slice(&(count as u32).to_le_bytes());
        let mut field = match at {
            Some(at) => (*at as u32).to_le_bytes().to_vec(),
            None => value.bytes(),
        };
        field.resize(4, 0);
        out.extend_from_slice(&field);
    }
    out.extend_from_slice(&0u32.to_le_bytes()); // no next directory
    for ((_, value), at) in entries.iter().zip(&placed) {
        if at.is_some() {
            out.extend_from_slice(&value.bytes());
            if out.len() % 2 == 1 {
                out.push(0);
            }
        }
    }
    debug_assert_eq!(out.len() as u64, data_at);
    Ok((out, rows_per_strip))
}

/// A GeoTIFF being written row-major, band by band.
pub struct TiffStream<T: Sample> {
    output: OutputFile,
    writer: BufWriter<File>,
    remaining: u64,
    buffer: Vec<u8>,
    _sample: std::marker::PhantomData<T>,
}

impl<T: Sample> TiffStream<T> {
    /// Creates `path` (named `*.tif` or `*.tiff`) for a `width` x `height`
    /// raster of `bands` values per pixel; the file appears only when
    /// [`TiffStream::finish`] succeeds.
    pub fn create(
        path: &Path,
        width: u32,
        height: u32,
        bands: u16,
        geo: Option<&GeoReference>,
    ) -> Result<Self> {
        let (head, _) = header::<T>(width, height, bands, geo)?;
        let (output, file) = OutputFile::create_any(path, &["tif", "tiff"], "GeoTIFFs")?;
        let mut writer = BufWriter::new(file);
        writer.write_all(&head).map_err(|cause| Error::Io {
            path: path.to_path_buf(),
            cause,
        })?;
        Ok(Self {
            output,
            writer,
            remaining: width as u64 * height as u64 * bands as u64,
            buffer: Vec::new(),
            _sample: std::marker::PhantomData,
        })
    }

    /// Appends values.
    pub fn write(&mut self, data: &[T]) -> Result<()> {
        if data.len() as u64 > self.remaining {
            return Err(Error::InvalidInput(format!(
                "{}: more values than the raster holds",
                self.output.path().display()
            )));
        }
        self.remaining -= data.len() as u64;
        self.buffer.clear();
        for &v in data {
            v.put(&mut self.buffer);
        }
        self.writer
            .write_all(&self.buffer)
            .map_err(|cause| Error::Io {
                path: self.output.path().to_path_buf(),
                cause,
            })
    }

    /// Finishes the file; every value must have been written.
    pub fn finish(mut self) -> Result<()> {
        if self.remaining != 0 {
            return Err(Error::InvalidInput(format!(
                "{}: {} values missing",
                self.output.path().display(),
                self.remaining
            )));
        }
        self.writer.flush().map_err(|cause| Error::Io {
            path: self.output.path().to_path_buf(),
            cause,
        })?;
        drop(self.writer);
        self.output.commit()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The directory's entries: tag, type, count and the value or offset.
    fn entries(file: &[u8]) -> Vec<(u16, u16, u32, u32)> {
        let u16_at = |i: usize| u16::from_le_bytes([file[i], file[i + 1]]);
        let u32_at = |i: usize| u32::from_le_bytes(file[i..i + 4].try_into().unwrap());
        assert_eq!(&file[..4], b"II*\0");
        let at = u32_at(4) as usize;
        (0..u16_at(at) as usize)
            .map(|k| {
                let e = at + 2 + 12 * k;
                (u16_at(e), u16_at(e + 2), u32_at(e + 4), u32_at(e + 8))
            })
            .collect()
    }

    #[test]
    fn strips_follow_a_sorted_directory_and_hold_every_row() {
        let geo = GeoReference {
            left: 10.0,
            top: 20.0,
            pixel_width: 0.5,
            pixel_height: 0.25,
            epsg: Some(32633),
        };
        let (width, height) = (7000u32, 5u32); // 28000-byte rows: 2 per strip
        let (head, rows_per_strip) = header::<u32>(width, height, 1, Some(&geo)).unwrap();
        assert_eq!(rows_per_strip, 2);
        let e = entries(&head);
        let tags: Vec<u16> = e.iter().map(|e| e.0).collect();
        let mut sorted = tags.clone();
        sorted.sort();
        assert_eq!(tags, sorted);
        assert!(tags.contains(&33550) && tags.contains(&33922) && !tags.contains(&34264));
        let count = |tag| e.iter().find(|e| e.0 == tag).unwrap().2;
        assert_eq!((count(273), count(279)), (3, 3));
        // The first strip starts where the header ends.
        let offsets = e.iter().find(|e| e.0 == 273).unwrap().3 as usize;
        let first = u32::from_le_bytes(head[offsets..offsets + 4].try_into().unwrap());
        assert_eq!(first as usize, head.len());
    }

    #[test]
    fn rasters_whose_rows_run_north_take_a_transformation() {
        let geo = GeoReference {
            left: 0.0,
            top: 0.0,
            pixel_width: 1.0,
            pixel_height: -1.0,
            epsg: None,
        };
        let (head, _) = header::<f32>(3, 3, 2, Some(&geo)).unwrap();
        let tags: Vec<u16> = entries(&head).iter().map(|e| e.0).collect();
        assert!(tags.contains(&34264) && !tags.contains(&33550));
        assert!(tags.contains(&338), "two bands: one extra sample");
    }

    #[test]
    fn too_large_and_bad_codes_are_refused() {
        let err = header::<f64>(1 << 16, 1 << 14, 1, None).unwrap_err();
        assert!(err.to_string().contains("4 GiB"), "{err}");
        assert_eq!(parse_crs("EPSG:4326"), Ok(4326));
        assert!(parse_crs("4326").is_err());
        assert!(parse_crs("EPSG:900913").is_err());
    }
}
