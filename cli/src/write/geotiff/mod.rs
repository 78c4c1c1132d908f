//! GeoTIFF rasters and world files: where a raster lies on the earth, written
//! so that GIS tools (GDAL, rasterio, QGIS) place it without help.
//!
//! A GeoTIFF here is a TIFF of one or more bands (interleaved by pixel, as
//! NumPy's `(rows, columns, bands)`) in 256-pixel tiles, each compressed with
//! DEFLATE, as GDAL writes with `TILED=YES COMPRESS=DEFLATE`; GDAL_NODATA
//! names the value of pixels that have none; and the GeoTIFF 1.1 tags place
//! it: ModelPixelScale and ModelTiepoint for a north-up raster
//! (ModelTransformation for one whose rows run north), and a GeoKey directory
//! with the raster type and, when known, the EPSG code, geographic or
//! projected as EPSG's registry says ([`crs`]). Rows stream in; each row of
//! tiles is compressed (in parallel) and written as it fills, the directory
//! after the tiles, and the header is then pointed at it: a file past 4 GiB
//! becomes a BigTIFF.

mod crs;
mod directory;
mod sample;

use std::{
    fs::File,
    io::{BufWriter, Seek, SeekFrom, Write},
    path::Path,
};

use flate2::{write::ZlibEncoder, Compression};
use rayon::prelude::*;

pub use crs::{crs_kind, crs_name, parse_crs, CrsKind};
use directory::Value;
pub use sample::Sample;

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

/// Tiles are this many pixels on a side.
const TILE: u32 = 256;

/// The shape of a raster and the layout of its file.
#[derive(Clone, Copy, Debug)]
struct Layout {
    width: u32,
    height: u32,
    bands: u16,
    /// A BigTIFF (64-bit offsets).
    big: bool,
}

impl Layout {
    fn new(width: u32, height: u32, bands: u16, sample: usize) -> Result<Self> {
        if bands == 0 || width == 0 || height == 0 {
            return Err(Error::InvalidInput(format!(
                "a GeoTIFF of {width} x {height} pixels and {bands} bands holds nothing"
            )));
        }
        let mut layout = Self {
            width,
            height,
            bands,
            big: false,
        };
        // DEFLATE grows data that does not compress by at most 5 bytes in
        // 16 kB, and zlib adds 6 bytes a tile: a classic TIFF holds the file
        // unless that could pass 4 GiB.
        let tiles = layout.across() as u64 * layout.down() as u64;
        let tile_bytes = (TILE as u64).pow(2) * bands as u64 * sample as u64;
        let worst = tiles * (tile_bytes + tile_bytes / 3000 + 64) + (1 << 20);
        layout.big = worst > u32::MAX as u64;
        Ok(layout)
    }

    fn across(&self) -> u32 {
        self.width.div_ceil(TILE)
    }

    fn down(&self) -> u32 {
        self.height.div_ceil(TILE)
    }

    /// Values in one row of pixels.
    fn row_values(&self) -> usize {
        self.width as usize * self.bands as usize
    }

    /// The directory's entries, with the tiles' offsets and sizes and the
    /// georeference.
    fn entries<T: Sample>(
        &self,
        tiles: &[(u64, u64)],
        geo: Option<&GeoReference>,
    ) -> Vec<(u16, Value)> {
        let bands = self.bands as usize;
        let mut entries = vec![
            (256, Value::Longs(vec![self.width])),
            (257, Value::Longs(vec![self.height])),
            (258, Value::Shorts(vec![8 * T::BYTES as u16; bands])),
            (259, Value::Shorts(vec![8])), // DEFLATE (zlib)
            (262, Value::Shorts(vec![1])), // black is zero
            (277, Value::Shorts(vec![self.bands])),
            (284, Value::Shorts(vec![1])), // bands interleaved by pixel
            (322, Value::Longs(vec![TILE])),
            (323, Value::Longs(vec![TILE])),
            (324, Value::Offsets(tiles.iter().map(|t| t.0).collect())),
            (325, Value::Offsets(tiles.iter().map(|t| t.1).collect())),
            (339, Value::Shorts(vec![T::FORMAT; bands])),
        ];
        if T::FORMAT == FLOATING_POINT {
            entries.push((317, Value::Shorts(vec![3]))); // the predictor below
        }
        if bands > 1 {
            // The bands past the first are data, not colour.
            entries.push((338, Value::Shorts(vec![0; bands - 1])));
        }
        if let Some(nodata) = T::NODATA {
            entries.push((42113, Value::Ascii(nodata.to_string())));
        }
        if let Some(g) = geo {
            entries.extend(geo_entries(g));
        }
        entries
    }
}

/// The GeoTIFF tags of `g`.
fn geo_entries(g: &GeoReference) -> Vec<(u16, Value)> {
    let mut entries = Vec::new();
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
    // count 1, value): the raster type (1, pixel is area) and the coordinate
    // system, geographic (GeographicTypeGeoKey) or projected
    // (ProjectedCSTypeGeoKey).
    let mut keys = vec![(1025u16, 1u16)];
    if let Some(code) = g.epsg {
        // Codes are checked against the registry as they are read.
        let geographic = crs_kind(code) == Ok(CrsKind::Geographic);
        keys.push((1024, if geographic { 2 } else { 1 }));
        keys.push((if geographic { 2048 } else { 3072 }, code));
    }
    keys.sort();
    let mut directory = vec![1, 1, 0, keys.len() as u16];
    for (key, value) in keys {
        directory.extend([key, 0, 1, value]);
    }
    entries.push((34735, Value::Shorts(directory)));
    entries
}

/// TIFF's SampleFormat for floating point.
const FLOATING_POINT: u16 = 3;

/// TIFF's floating-point predictor (Adobe's Technical Note 3, predictor 3)
/// on one row of a tile, in place: the samples' bytes (little-endian here)
/// regrouped most significant first, each byte plane after the other, then
/// each byte less the one a pixel before, as GDAL's `PREDICTOR=3`: smooth
/// distances compress far better so (`docs/guide.md` has the sizes).
fn floating_point_predictor(row: &mut [u8], bytes: usize, bands: usize) {
    let samples = row.len() / bytes;
    let mut planes = vec![0u8; row.len()];
    for (k, sample) in row.chunks_exact(bytes).enumerate() {
        for (b, plane) in planes.chunks_exact_mut(samples).enumerate() {
            plane[k] = sample[bytes - 1 - b];
        }
    }
    for i in (bands..planes.len()).rev() {
        planes[i] = planes[i].wrapping_sub(planes[i - bands]);
    }
    row.copy_from_slice(&planes);
}

/// A GeoTIFF being written row-major, band by band.
pub struct TiffStream<T: Sample> {
    output: OutputFile,
    writer: BufWriter<File>,
    layout: Layout,
    geo: Option<GeoReference>,
    /// Values of the row of tiles being filled.
    pending: Vec<T>,
    /// Rows written into tiles.
    rows_done: u32,
    /// Each tile's offset and size, row by row.
    tiles: Vec<(u64, u64)>,
    /// Bytes written.
    at: u64,
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
        let layout = Layout::new(width, height, bands, T::BYTES)?;
        Self::create_as(path, layout, geo)
    }

    fn create_as(path: &Path, layout: Layout, geo: Option<&GeoReference>) -> Result<Self> {
        let (output, file) = OutputFile::create_any(path, &["tif", "tiff"], "GeoTIFFs")?;
        let mut stream = Self {
            output,
            writer: BufWriter::new(file),
            layout,
            geo: geo.copied(),
            pending: Vec::new(),
            rows_done: 0,
            tiles: Vec::new(),
            at: 0,
        };
        stream.put(&directory::header(layout.big))?;
        Ok(stream)
    }

    fn io(&self, cause: std::io::Error) -> Error {
        Error::Io {
            path: self.output.path().to_path_buf(),
            cause,
        }
    }

    fn put(&mut self, bytes: &[u8]) -> Result<()> {
        self.writer.write_all(bytes).map_err(|e| self.io(e))?;
        self.at += bytes.len() as u64;
        Ok(())
    }

    /// Appends values.
    pub fn write(&mut self, data: &[T]) -> Result<()> {
        let layout = self.layout;
        if data.len() as u64 > self.remaining() {
            return Err(Error::InvalidInput(format!(
                "{}: more values than the raster holds",
                self.output.path().display()
            )));
        }
        let tile_row = TILE as usize * layout.row_values();
        let mut data = data;
        while !data.is_empty() {
            let take = (tile_row - self.pending.len()).min(data.len());
            self.pending.extend_from_slice(&data[..take]);
            data = &data[take..];
            if self.pending.len() == tile_row {
                self.flush_tiles()?;
            }
        }
        Ok(())
    }

    /// Compresses the pending rows into a row of tiles and writes them.
    fn flush_tiles(&mut self) -> Result<()> {
        let layout = self.layout;
        let rows = self.pending.len() / layout.row_values();
        let pending = std::mem::take(&mut self.pending);
        let compressed: Vec<Vec<u8>> = (0..layout.across())
            .into_par_iter()
            .map(|column| tile(&layout, &pending, rows, column))
            .collect::<std::io::Result<_>>()
            .map_err(|e| self.io(e))?;
        for bytes in compressed {
            self.tiles.push((self.at, bytes.len() as u64));
            self.put(&bytes)?;
        }
        self.rows_done += rows as u32;
        self.pending = pending;
        self.pending.clear();
        Ok(())
    }

    /// Finishes the file; every value must have been written.
    pub fn finish(mut self) -> Result<()> {
        if !self.pending.is_empty() {
            if self.pending.len() % self.layout.row_values() != 0 {
                return self.missing();
            }
            self.flush_tiles()?;
        }
        if self.rows_done != self.layout.height {
            return self.missing();
        }
        if self.at % 2 == 1 {
            self.put(&[0])?;
        }
        let big = self.layout.big;
        let directory_at = self.at;
        let entries = self.layout.entries::<T>(&self.tiles, self.geo.as_ref());
        let bytes = directory::encode(entries, directory_at, big);
        self.put(&bytes)?;
        if !big && self.at > u32::MAX as u64 {
            return Err(Error::Internal(format!(
                "{}: a classic TIFF of {} bytes",
                self.output.path().display(),
                self.at
            )));
        }
        let (pointer, width) = directory::first_directory_at(big);
        let pointed = directory_at.to_le_bytes();
        let writer = &mut self.writer;
        let patched = writer
            .seek(SeekFrom::Start(pointer))
            .and_then(|_| writer.write_all(&pointed[..width]))
            .and_then(|_| writer.flush());
        if let Err(e) = patched {
            let what = match e.kind() {
                std::io::ErrorKind::NotSeekable => std::io::Error::other(
                    "a GeoTIFF's directory follows its tiles, so it is written to a file, \
                     not a pipe or device",
                ),
                _ => e,
            };
            return Err(self.io(what));
        }
        drop(self.writer);
        self.output.commit()
    }

    /// Values the raster still lacks.
    fn remaining(&self) -> u64 {
        let row = self.layout.row_values() as u64;
        row * self.layout.height as u64 - (self.rows_done as u64 * row + self.pending.len() as u64)
    }

    fn missing(&self) -> Result<()> {
        Err(Error::InvalidInput(format!(
            "{}: {} values missing",
            self.output.path().display(),
            self.remaining()
        )))
    }
}

/// Tile `column` of a row of tiles whose `rows` rows are `values`, padded
/// with zeros to a whole tile and compressed.
fn tile<T: Sample>(
    layout: &Layout,
    values: &[T],
    rows: usize,
    column: u32,
) -> std::io::Result<Vec<u8>> {
    let bands = layout.bands as usize;
    let side = TILE as usize;
    let x0 = column as usize * side;
    let x1 = (x0 + side).min(layout.width as usize);
    let mut raw = Vec::with_capacity(side * side * bands * T::BYTES);
    for row in 0..side {
        if row < rows {
            let start = row * layout.row_values();
            for &v in &values[start + x0 * bands..start + x1 * bands] {
                v.put(&mut raw);
            }
        }
        raw.resize((row + 1) * side * bands * T::BYTES, 0);
    }
    if T::FORMAT == FLOATING_POINT {
        for row in raw.chunks_exact_mut(side * bands * T::BYTES) {
            floating_point_predictor(row, T::BYTES, bands);
        }
    }
    let mut encoder = ZlibEncoder::new(Vec::new(), Compression::default());
    encoder.write_all(&raw)?;
    encoder.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use tiff::{decoder::Decoder, tags::Tag};

    /// Writes `values` (`width` x `height` x `bands`) in pieces of `piece`,
    /// as BigTIFF when `big`, and reads the file back with the `tiff` crate.
    fn round_trip<T: Sample>(
        name: &str,
        [width, height, bands]: [u32; 3],
        values: &[T],
        big: bool,
        piece: usize,
    ) -> Decoder<File> {
        let path = std::env::temp_dir().join(format!("pixgeo-{}-{name}.tif", std::process::id()));
        let mut layout = Layout::new(width, height, bands as u16, T::BYTES).unwrap();
        layout.big = big;
        let geo = GeoReference {
            left: 10.0,
            top: 20.0,
            pixel_width: 0.5,
            pixel_height: 0.25,
            epsg: Some(6318),
        };
        let transaction = crate::write::output::TRANSACTION_TESTS.lock();
        let _one = transaction.unwrap_or_else(|e| e.into_inner());
        let mut stream = TiffStream::<T>::create_as(&path, layout, Some(&geo)).unwrap();
        for chunk in values.chunks(piece) {
            stream.write(chunk).unwrap();
        }
        stream.finish().unwrap();
        crate::write::output::finish(true).unwrap();
        let mut decoder = Decoder::new(File::open(&path).unwrap()).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert_eq!(decoder.dimensions().unwrap(), (width, height));
        decoder
    }

    #[test]
    fn tiles_hold_every_value_in_classic_and_big_tiffs() {
        use tiff::decoder::DecodingResult;
        // Partial tiles at the right and the bottom; rows arriving in pieces
        // that straddle rows of tiles.
        for big in [false, true] {
            let size = [300, 520, 1];
            let labels: Vec<u32> = (0..300 * 520).collect();
            let mut d = round_trip(&format!("one-{big}"), size, &labels, big, 777);
            assert_eq!(d.tile_count().unwrap(), 2 * 3);
            assert_eq!(
                d.find_tag(Tag::Compression)
                    .unwrap()
                    .unwrap()
                    .into_u16()
                    .unwrap(),
                8
            );
            let nodata = d.find_tag(Tag::Unknown(42113)).unwrap().unwrap();
            assert_eq!(nodata.into_string().unwrap(), "4294967295");
            // EPSG:6318 is geographic: GTModelTypeGeoKey 2, GeographicTypeGeoKey.
            let keys = d
                .find_tag(Tag::GeoKeyDirectoryTag)
                .unwrap()
                .unwrap()
                .into_u16_vec()
                .unwrap();
            assert_eq!(
                &keys[4..],
                &[1024, 0, 1, 2, 1025, 0, 1, 1, 2048, 0, 1, 6318]
            );
            assert!(matches!(d.read_image().unwrap(), DecodingResult::U32(v) if v == labels));
            // Floats through the floating-point predictor, three bands.
            let distances: Vec<f32> = (0..17 * 9 * 3)
                .map(|k| (k as f32 * 0.37).sin() * 1e3)
                .collect();
            let mut d = round_trip(&format!("bands-{big}"), [17, 9, 3], &distances, big, 5);
            assert_eq!(
                d.find_tag(Tag::Predictor)
                    .unwrap()
                    .unwrap()
                    .into_u16()
                    .unwrap(),
                3
            );
            assert!(matches!(d.read_image().unwrap(), DecodingResult::F32(v) if v == distances));
        }
    }

    #[test]
    fn the_layout_turns_big_only_past_four_gibibytes() {
        assert!(!Layout::new(16384, 16384, 1, 8).unwrap().big); // 2 GiB
        assert!(Layout::new(16384, 16384, 2, 8).unwrap().big); // 4 GiB
        assert!(!Layout::new(32000, 32000, 1, 4).unwrap().big); // 3.8 GiB
        assert!(Layout::new(0, 5, 1, 4).is_err());
    }

    #[test]
    fn rasters_whose_rows_run_north_take_a_transformation() {
        let geo = GeoReference {
            left: 0.0,
            top: 0.0,
            pixel_width: 1.0,
            pixel_height: -1.0,
            epsg: Some(4087),
        };
        let tags: Vec<u16> = geo_entries(&geo).iter().map(|e| e.0).collect();
        assert!(tags.contains(&34264) && !tags.contains(&33550));
        let Value::Shorts(keys) = &geo_entries(&geo)[1].1 else {
            panic!("GeoKeys are shorts")
        };
        // EPSG:4087 is projected: GTModelTypeGeoKey 1, ProjectedCSTypeGeoKey.
        assert_eq!(
            &keys[4..],
            &[1024, 0, 1, 1, 1025, 0, 1, 1, 3072, 0, 1, 4087]
        );
    }
}
