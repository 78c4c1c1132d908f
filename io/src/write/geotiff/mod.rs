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
//! projected as EPSG's registry says ([`crate::crs`]). Rows stream in; each row of
//! tiles is compressed (in parallel) and written as it fills, the directory
//! after the tiles, and the header is then pointed at it: a file past 4 GiB
//! becomes a BigTIFF.

mod directory;
mod read;
mod sample;

use std::{
    fs::File,
    io::{BufWriter, Seek, SeekFrom, Write},
    path::Path,
};

use flate2::{write::ZlibEncoder, Compression};
use rayon::prelude::*;

pub use crate::crs::{crs_kind, crs_name, parse_crs, CrsKind};
use directory::Value;
pub use read::read_geotiff;
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
    /// Whether GeoTIFFs placed so are cloud-optimised (`--cog`): overviews,
    /// and the directories before the tiles.
    pub cloud_optimized: bool,
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
    fn new(width: u32, height: u32, bands: u16, sample: usize, cog: bool) -> Result<Self> {
        if bands == 0 || width == 0 || height == 0 {
            return Err(Error::malformed(format!(
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
        // Overviews add at most a third.
        let worst = if cog { worst / 3 * 4 } else { worst };
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
        nodata: Option<&str>,
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
        if let Some(nodata) = nodata {
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
    geo: Option<GeoReference>,
    /// The full-resolution tiles: written into the file (after the header),
    /// or for a cloud-optimised GeoTIFF spooled with the overviews'.
    full: Tiles<T>,
    /// Cloud-optimised: each overview's tiles, halving down to one tile.
    overviews: Vec<Tiles<T>>,
    /// Cloud-optimised: the row being gathered, the rows seen, and the file,
    /// written whole at the end.
    row: Vec<T>,
    rows_seen: u32,
    whole: Option<File>,
    /// GDAL_NODATA: `T::NODATA` unless the raster's own is given.
    nodata: Option<&'static str>,
}

/// One resolution's tiles as its rows arrive, compressed a row of tiles at a
/// time into `sink`.
struct Tiles<T: Sample> {
    layout: Layout,
    /// Values of the row of tiles being filled.
    pending: Vec<T>,
    /// Rows written into tiles.
    rows_done: u32,
    /// Each tile's offset in the sink and size, row by row.
    tiles: Vec<(u64, u64)>,
    /// Bytes written into the sink.
    at: u64,
    sink: BufWriter<File>,
    /// Each tile framed by its size before and its last 4 bytes after, as
    /// GDAL's cloud-optimised layout does, so that a reader fetching a tile
    /// can check it and read its neighbour's size in the same request.
    framed: bool,
}

impl<T: Sample> Tiles<T> {
    fn new(layout: Layout, sink: File, at: u64) -> Self {
        Self {
            layout,
            pending: Vec::new(),
            rows_done: 0,
            tiles: Vec::new(),
            at,
            sink: BufWriter::new(sink),
            framed: false,
        }
    }

    /// A spool for tiles that are copied into the file at its end: a file in
    /// `folder`, removed from it at once (it lives while open).
    fn spooled(layout: Layout, folder: &Path, level: usize) -> std::io::Result<Self> {
        let path = folder.join(format!(".pixgeo-{}-{level}.tiles", std::process::id()));
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create_new(true)
            .open(&path)?;
        std::fs::remove_file(&path)?;
        Ok(Self {
            framed: true,
            ..Self::new(layout, file, 0)
        })
    }

    fn put(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.sink.write_all(bytes)?;
        self.at += bytes.len() as u64;
        Ok(())
    }

    /// Values the raster still lacks.
    fn remaining(&self) -> u64 {
        let row = self.layout.row_values() as u64;
        row * self.layout.height as u64 - (self.rows_done as u64 * row + self.pending.len() as u64)
    }

    /// Appends values (no more than remain).
    fn write(&mut self, data: &[T]) -> std::io::Result<()> {
        let tile_row = TILE as usize * self.layout.row_values();
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
    fn flush_tiles(&mut self) -> std::io::Result<()> {
        let layout = self.layout;
        let rows = self.pending.len() / layout.row_values();
        let pending = std::mem::take(&mut self.pending);
        let compressed: Vec<Vec<u8>> = (0..layout.across())
            .into_par_iter()
            .map(|column| tile(&layout, &pending, rows, column))
            .collect::<std::io::Result<_>>()?;
        for bytes in compressed {
            if self.framed {
                self.put(&(bytes.len() as u32).to_le_bytes())?;
            }
            self.tiles.push((self.at, bytes.len() as u64));
            self.put(&bytes)?;
            if self.framed {
                self.put(&bytes[bytes.len() - 4..])?;
            }
        }
        self.rows_done += rows as u32;
        self.pending = pending;
        self.pending.clear();
        Ok(())
    }

    /// Writes the last, partial row of tiles; whether every row came.
    fn complete(&mut self) -> std::io::Result<bool> {
        if !self.pending.is_empty() {
            if self.pending.len() % self.layout.row_values() != 0 {
                return Ok(false);
            }
            self.flush_tiles()?;
        }
        Ok(self.rows_done == self.layout.height)
    }
}

/// The overviews of a cloud-optimised GeoTIFF of `full`'s size: each half
/// the last (rounded up), until one fits in a tile.
fn overview_layouts(full: Layout) -> Vec<Layout> {
    let mut levels: Vec<Layout> = Vec::new();
    let mut last = full;
    while last.width > TILE || last.height > TILE {
        last = Layout {
            width: last.width.div_ceil(2),
            height: last.height.div_ceil(2),
            ..full
        };
        levels.push(last);
    }
    levels
}

/// The full-resolution row or column that sample `j` of overview level
/// `level` (1 = half size) takes: the nearest, as GDAL's NEAREST resampling
/// picks it, within `n`.
fn sampled(j: u32, level: usize, n: u32) -> u32 {
    let f = 1u64 << level;
    ((j as u64 * f + f / 2) as u32).min(n - 1)
}

impl<T: Sample> TiffStream<T> {
    /// Creates `path` (named `*.tif` or `*.tiff`) for a `width` x `height`
    /// raster of `bands` values per pixel, cloud-optimised (overviews, the
    /// directories first) where `geo` asks; the file appears only when
    /// [`TiffStream::finish`] succeeds.
    pub fn create(
        path: &Path,
        width: u32,
        height: u32,
        bands: u16,
        geo: Option<&GeoReference>,
    ) -> Result<Self> {
        let cog = geo.is_some_and(|g| g.cloud_optimized);
        let layout = Layout::new(width, height, bands, T::BYTES, cog)?;
        Self::create_as(path, layout, geo)
    }

    /// Marks the pixels holding `nodata` (as GDAL spells it) as empty.
    pub fn with_nodata(self, nodata: &'static str) -> Self {
        Self {
            nodata: Some(nodata),
            ..self
        }
    }

    fn create_as(path: &Path, layout: Layout, geo: Option<&GeoReference>) -> Result<Self> {
        let (output, file) = OutputFile::create_any(path, &["tif", "tiff"], "GeoTIFFs")?;
        let io = |cause| Error::Io {
            path: path.to_path_buf(),
            cause,
        };
        let cog = geo.is_some_and(|g| g.cloud_optimized);
        let (full, overviews, whole) = if cog {
            let folder = output.scratch_folder();
            let levels = std::iter::once(layout).chain(overview_layouts(layout));
            let mut spools: Vec<Tiles<T>> = levels
                .enumerate()
                .map(|(level, l)| Tiles::spooled(l, &folder, level))
                .collect::<std::io::Result<_>>()
                .map_err(io)?;
            let full = spools.remove(0);
            (full, spools, Some(file))
        } else {
            let header = directory::header(layout.big);
            let mut full = Tiles::new(layout, file, 0);
            full.put(&header).map_err(io)?;
            (full, Vec::new(), None)
        };
        Ok(Self {
            output,
            geo: geo.copied(),
            full,
            overviews,
            row: Vec::new(),
            rows_seen: 0,
            whole,
            nodata: T::NODATA,
        })
    }

    fn io(&self, cause: std::io::Error) -> Error {
        Error::Io {
            path: self.output.path().to_path_buf(),
            cause,
        }
    }

    /// Appends values.
    pub fn write(&mut self, data: &[T]) -> Result<()> {
        if data.len() as u64 > self.remaining() {
            return Err(Error::malformed(format!(
                "{}: more values than the raster holds",
                self.output.path().display()
            )));
        }
        if self.whole.is_none() {
            return self.full.write(data).map_err(|e| self.io(e));
        }
        // Cloud-optimised: whole rows, each also sampled into the overviews.
        let row_values = self.full.layout.row_values();
        let mut data = data;
        while !data.is_empty() {
            let take = (row_values - self.row.len()).min(data.len());
            self.row.extend_from_slice(&data[..take]);
            data = &data[take..];
            if self.row.len() == row_values {
                self.take_row().map_err(|e| self.io(e))?;
            }
        }
        Ok(())
    }

    /// Writes the gathered full row, and the overviews' rows that sample it.
    fn take_row(&mut self) -> std::io::Result<()> {
        let row = std::mem::take(&mut self.row);
        self.full.write(&row)?;
        let (r, full) = (self.rows_seen, self.full.layout);
        let bands = full.bands as usize;
        for (k, level) in self.overviews.iter_mut().enumerate() {
            let l = level.layout;
            while level.remaining() > 0 {
                let j = l.height - (level.remaining() / l.row_values() as u64) as u32;
                if sampled(j, k + 1, full.height) != r {
                    break;
                }
                let samples: Vec<T> = (0..l.width)
                    .flat_map(|i| {
                        let x = sampled(i, k + 1, full.width) as usize * bands;
                        row[x..x + bands].iter().copied()
                    })
                    .collect();
                level.write(&samples)?;
            }
        }
        self.rows_seen += 1;
        self.row = row;
        self.row.clear();
        Ok(())
    }

    /// Finishes the file; every value must have been written.
    pub fn finish(mut self) -> Result<()> {
        let complete = self.full.complete().map_err(|e| self.io(e))?;
        if !complete {
            return self.missing();
        }
        if self.whole.is_some() {
            return self.finish_cloud_optimized();
        }
        let full = &mut self.full;
        let io = |e| Error::Io {
            path: self.output.path().to_path_buf(),
            cause: e,
        };
        if full.at % 2 == 1 {
            full.put(&[0]).map_err(io)?;
        }
        let big = full.layout.big;
        let directory_at = full.at;
        let entries = full
            .layout
            .entries::<T>(&full.tiles, self.geo.as_ref(), self.nodata);
        let bytes = directory::encode(entries, directory_at, big, 0);
        full.put(&bytes).map_err(io)?;
        if !big && full.at > u32::MAX as u64 {
            return Err(Error::Internal(format!(
                "{}: a classic TIFF of {} bytes",
                self.output.path().display(),
                full.at
            )));
        }
        let (pointer, width) = directory::first_directory_at(big);
        let pointed = directory_at.to_le_bytes();
        let writer = &mut full.sink;
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
        drop(self.full);
        self.output.commit()
    }

    /// The cloud-optimised layout, as GDAL's COG driver writes it: the
    /// header, GDAL's structural metadata, every directory (full resolution
    /// first, then the overviews, largest first), then the tiles, the
    /// smallest overview's first and the full resolution's last.
    fn finish_cloud_optimized(mut self) -> Result<()> {
        for level in &mut self.overviews {
            let complete = level.complete().map_err(|e| Error::Io {
                path: self.output.path().to_path_buf(),
                cause: e,
            })?;
            if !complete {
                return Err(Error::Internal("an overview lacks rows".into()));
            }
        }
        let big = self.full.layout.big;
        let ghost = structural_metadata();
        let header = directory::header(big);
        // Directories in file order, and the tiles' order after them.
        let mut levels: Vec<&mut Tiles<T>> = std::iter::once(&mut self.full)
            .chain(self.overviews.iter_mut())
            .collect();
        let entries = |k: usize, level: &Tiles<T>, tiles: &[(u64, u64)]| {
            let geo = if k == 0 { self.geo.as_ref() } else { None };
            let mut entries = level.layout.entries::<T>(tiles, geo, self.nodata);
            if k > 0 {
                entries.push((254, Value::Longs(vec![1]))); // a reduced image
            }
            entries
        };
        // Directory sizes do not depend on the offsets they hold.
        let sizes: Vec<u64> = levels
            .iter()
            .enumerate()
            .map(|(k, l)| directory::encode(entries(k, l, &l.tiles), 0, big, 0).len() as u64)
            .collect();
        // Directories start on a word boundary.
        let first = (header.len() + ghost.len()).next_multiple_of(2) as u64;
        let directories_at: Vec<u64> = sizes
            .iter()
            .scan(first, |at, size| {
                let here = *at;
                *at += size + size % 2;
                Some(here)
            })
            .collect();
        let mut data_at =
            directories_at.last().copied().unwrap_or(first) + sizes.last().map_or(0, |s| s + s % 2);
        let mut bases = vec![0; levels.len()];
        for k in (0..levels.len()).rev() {
            bases[k] = data_at;
            data_at += levels[k].at;
        }
        if !big && data_at > u32::MAX as u64 {
            return Err(Error::Internal(format!(
                "{}: a classic TIFF of {data_at} bytes",
                self.output.path().display()
            )));
        }
        let path = self.output.path().to_path_buf();
        let io = |cause| Error::Io {
            path: path.clone(),
            cause,
        };
        let file = self.whole.take().expect("a cloud-optimised GeoTIFF's file");
        let mut out = BufWriter::new(file);
        let mut bytes = header;
        let (pointer, width) = directory::first_directory_at(big);
        bytes[pointer as usize..pointer as usize + width]
            .copy_from_slice(&first.to_le_bytes()[..width]);
        bytes.extend_from_slice(&ghost);
        bytes.resize(first as usize, 0);
        for (k, level) in levels.iter().enumerate() {
            let tiles: Vec<(u64, u64)> = level
                .tiles
                .iter()
                .map(|&(at, n)| (at + bases[k], n))
                .collect();
            let next = directories_at.get(k + 1).copied().unwrap_or(0);
            bytes.extend(directory::encode(
                entries(k, level, &tiles),
                directories_at[k],
                big,
                next,
            ));
            if bytes.len() % 2 == 1 {
                bytes.push(0);
            }
        }
        out.write_all(&bytes).map_err(io)?;
        for level in levels.iter_mut().rev() {
            level.sink.flush().map_err(io)?;
            let spool = level.sink.get_mut();
            spool.seek(SeekFrom::Start(0)).map_err(io)?;
            std::io::copy(&mut std::io::Read::take(spool, level.at), &mut out).map_err(io)?;
        }
        out.flush().map_err(io)?;
        drop(out);
        drop(levels);
        self.output.commit()
    }

    /// Values the raster still lacks.
    fn remaining(&self) -> u64 {
        self.full.remaining() - self.row.len() as u64
    }

    fn missing(&self) -> Result<()> {
        Err(Error::malformed(format!(
            "{}: {} values missing",
            self.output.path().display(),
            self.remaining()
        )))
    }
}

/// GDAL's structural metadata for a cloud-optimised layout: the directories
/// before the data, tiles row by row, each framed by its size and its last
/// four bytes.
fn structural_metadata() -> Vec<u8> {
    let body = "LAYOUT=IFDS_BEFORE_DATA\nBLOCK_ORDER=ROW_MAJOR\n\
                BLOCK_LEADER=SIZE_AS_UINT4\nBLOCK_TRAILER=LAST_4_BYTES_REPEATED\n\
                KNOWN_INCOMPATIBLE_EDITION=NO\n ";
    format!(
        "GDAL_STRUCTURAL_METADATA_SIZE={:06} bytes\n{body}",
        body.len()
    )
    .into_bytes()
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
        (big, cog): (bool, bool),
        piece: usize,
    ) -> Decoder<File> {
        let path = std::env::temp_dir().join(format!("pixgeo-{}-{name}.tif", std::process::id()));
        let mut layout = Layout::new(width, height, bands as u16, T::BYTES, cog).unwrap();
        layout.big = big;
        let geo = GeoReference {
            left: 10.0,
            top: 20.0,
            pixel_width: 0.5,
            pixel_height: 0.25,
            epsg: Some(6318),
            cloud_optimized: cog,
        };
        let transaction = crate::write::output::TRANSACTION_TESTS.lock();
        let _one = transaction.unwrap_or_else(|e| e.into_inner());
        let mut stream = TiffStream::<T>::create_as(&path, layout, Some(&geo)).unwrap();
        for chunk in values.chunks(piece) {
            stream.write(chunk).unwrap();
        }
        stream.finish().unwrap();
        crate::write::output::finish().unwrap();
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
            let mut d = round_trip(&format!("one-{big}"), size, &labels, (big, false), 777);
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
            let mut d = round_trip(
                &format!("bands-{big}"),
                [17, 9, 3],
                &distances,
                (big, false),
                5,
            );
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
    fn cloud_optimised_tiffs_hold_overviews_after_their_directories() {
        // One tile needs no overview, and is cloud-optimised all the same.
        let small: Vec<u32> = (0..40 * 30).collect();
        let mut d = round_trip("cog-small", [40, 30, 1], &small, (false, true), 7);
        assert!(
            matches!(d.read_image().unwrap(), tiff::decoder::DecodingResult::U32(v) if v == small)
        );
        assert!(!d.more_images());
        use tiff::decoder::DecodingResult;
        // 600 x 520: overviews of 300 x 260 and 150 x 130, nearest samples.
        let (w, h) = (600u32, 520u32);
        let labels: Vec<u32> = (0..w * h).map(|k| k * 7 % 1000).collect();
        for big in [false, true] {
            let mut d = round_trip(&format!("cog-{big}"), [w, h, 1], &labels, (big, true), 999);
            assert!(matches!(d.read_image().unwrap(), DecodingResult::U32(v) if v == labels));
            let first_tile = |d: &mut Decoder<File>| {
                d.find_tag(Tag::TileOffsets)
                    .unwrap()
                    .unwrap()
                    .into_u64_vec()
                    .unwrap()
            };
            let full_tiles = first_tile(&mut d);
            let mut previous_first = full_tiles[0];
            for (level, (lw, lh)) in [(1, (300, 260)), (2, (150, 130))] {
                d.next_image().unwrap();
                assert_eq!(d.dimensions().unwrap(), (lw, lh));
                let kind = d.find_tag(Tag::NewSubfileType).unwrap().unwrap();
                assert_eq!(kind.into_u32().unwrap(), 1);
                let DecodingResult::U32(overview) = d.read_image().unwrap() else {
                    panic!("labels")
                };
                let sample = |j: u32, n: u32| sampled(j, level, n);
                for (k, v) in overview.iter().enumerate() {
                    let (i, j) = (k as u32 % lw, k as u32 / lw);
                    assert_eq!(*v, labels[(sample(j, h) * w + sample(i, w)) as usize]);
                }
                // Smaller overviews' tiles come first.
                let tiles = first_tile(&mut d);
                assert!(tiles[0] < previous_first);
                previous_first = tiles[0];
            }
            assert!(!d.more_images());
        }
    }

    #[test]
    fn the_layout_turns_big_only_past_four_gibibytes() {
        assert!(!Layout::new(16384, 16384, 1, 8, false).unwrap().big); // 2 GiB
        assert!(Layout::new(16384, 16384, 2, 8, false).unwrap().big); // 4 GiB
        assert!(!Layout::new(32000, 32000, 1, 4, false).unwrap().big); // 3.8 GiB
        assert!(Layout::new(32000, 32000, 1, 4, true).unwrap().big); // and a third
        assert!(Layout::new(0, 5, 1, 4, false).is_err());
    }

    #[test]
    fn rasters_whose_rows_run_north_take_a_transformation() {
        let geo = GeoReference {
            left: 0.0,
            top: 0.0,
            pixel_width: 1.0,
            pixel_height: -1.0,
            epsg: Some(4087),
            cloud_optimized: false,
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
