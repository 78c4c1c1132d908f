//! Label, distance and tie rasters written as NumPy arrays or GeoTIFFs, by the
//! file's name: `.npy` (shape `[height, width]`, or `[height, width, bands]`)
//! or `.tif`/`.tiff` (placed on the earth when a [`GeoReference`] is known).

use std::path::Path;

use super::{
    geotiff::{GeoReference, Sample, TiffStream},
    npy::NpyStream,
    output::{check_extensions, extension_among},
};
use pixgeo::Result;

/// The names a raster may take.
pub const EXTENSIONS: [&str; 3] = ["npy", "tif", "tiff"];

/// Checks that `path` names a raster format, before any work is done.
pub fn check_name(path: &Path, what: &str) -> Result<()> {
    check_extensions(path, &EXTENSIONS, what)
}

/// A raster being written row-major, band by band.
pub enum RasterStream<T: Sample + npyz::Serialize + npyz::AutoSerialize> {
    Npy(NpyStream<T>),
    Tiff(TiffStream<T>),
}

impl<T: Sample + npyz::Serialize + npyz::AutoSerialize> RasterStream<T> {
    /// Creates `path` for a `width` x `height` raster of `bands` values per
    /// pixel, in the format its name gives (a device such as `/dev/stdout`
    /// takes `.npy`).
    pub fn create(
        path: &Path,
        width: u32,
        height: u32,
        bands: u16,
        geo: Option<&GeoReference>,
    ) -> Result<Self> {
        if extension_among(path, &["tif", "tiff"]).is_some() {
            return Ok(Self::Tiff(TiffStream::create(
                path, width, height, bands, geo,
            )?));
        }
        let mut shape = vec![height as u64, width as u64];
        if bands > 1 {
            shape.push(bands as u64);
        }
        Ok(Self::Npy(NpyStream::create(path, &shape)?))
    }

    /// Marks the pixels holding `nodata` as empty, in a GeoTIFF (a `.npy`
    /// has no such mark).
    pub fn with_nodata(self, nodata: &'static str) -> Self {
        match self {
            Self::Tiff(s) => Self::Tiff(s.with_nodata(nodata)),
            npy => npy,
        }
    }

    pub fn write(&mut self, data: &[T]) -> Result<()> {
        match self {
            Self::Npy(s) => s.write(data),
            Self::Tiff(s) => s.write(data),
        }
    }

    pub fn finish(self) -> Result<()> {
        match self {
            Self::Npy(s) => s.finish(),
            Self::Tiff(s) => s.finish(),
        }
    }
}

/// Writes a whole raster (row-major, bands interleaved by pixel).
pub fn write<T: Sample + npyz::Serialize + npyz::AutoSerialize>(
    path: &Path,
    [width, height, bands]: [u32; 3],
    data: &[T],
    geo: Option<&GeoReference>,
) -> Result<()> {
    let bands = u16::try_from(bands).map_err(|_| {
        pixgeo::Error::out_of_range(format!("{bands} bands are more than a raster holds"))
    })?;
    let mut stream = RasterStream::create(path, width, height, bands, geo)?;
    stream.write(data)?;
    stream.finish()
}
