//! `transform`'s input: a raster whose chosen pixels are the features, read
//! from a `.npy` array, a PNG or a GeoTIFF, which also says where it lies
//! (as `gdal_proximity` reads its source).

use std::path::Path;

use anyhow::{anyhow, bail, Result};
use pixgeo_io::mask::{read_mask, read_npy_values, Mask};

use crate::write::{
    geotiff::{read_geotiff, GeoReference},
    output::extension_among,
};

/// A mask and, for a GeoTIFF, where it lies.
pub struct Source {
    pub mask: Mask,
    pub placed: Option<GeoReference>,
}

/// Reads the mask at `path`: features are the pixels whose value is among
/// `values`, or (without) those not zero.
pub fn read(path: &Path, values: Option<&[f64]>) -> Result<Source> {
    if values.is_some_and(|v| v.iter().any(|x| x.is_nan())) {
        bail!("--values: NaN equals no pixel value; give the features' values as numbers");
    }
    let (raster, placed) = if extension_among(path, &["tif", "tiff"]).is_some() {
        read_geotiff(path)?
    } else if extension_among(path, &["npy"]).is_some() {
        (read_npy_values(path)?, None)
    } else {
        if values.is_some() {
            bail!("--values picks pixel values of a .npy or .tif mask; a PNG's features are its pixels that are not black");
        }
        return Ok(Source {
            mask: read_mask(path)?,
            placed: None,
        });
    };
    let mask = raster
        .mask(values)
        .map_err(|e| anyhow!("{}: {e}", path.display()))?;
    Ok(Source { mask, placed })
}
