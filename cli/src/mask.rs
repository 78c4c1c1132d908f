//! `transform`'s input: a raster whose chosen pixels are the features, read
//! from a `.npy` array, a PNG or a GeoTIFF, which also says where it lies
//! (as `gdal_proximity` reads its source).

use std::{fs::File, io::BufReader, path::Path};

use anyhow::{anyhow, bail, Context, Result};
use pixgeo_io::mask::{read_mask, read_npy_values, Mask, Values};
use tiff::{
    decoder::{Decoder, DecodingResult},
    tags::Tag,
};

use crate::write::{
    geotiff::{crs_kind, GeoReference},
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

/// The first band of a GeoTIFF as doubles, and its placement.
fn read_geotiff(path: &Path) -> Result<(Values, Option<GeoReference>)> {
    pixgeo_io::decoding::decoding(path, "TIFF", || decode_geotiff(path))?
}

fn decode_geotiff(path: &Path) -> Result<(Values, Option<GeoReference>)> {
    let file = File::open(path).with_context(|| format!("{}", path.display()))?;
    let not_tiff = |e: tiff::TiffError| anyhow!("{}: not a TIFF pixgeo reads: {e}", path.display());
    let mut decoder = Decoder::new(BufReader::new(file)).map_err(not_tiff)?;
    let (width, height) = decoder.dimensions().map_err(not_tiff)?;
    pixgeo::memory::reserve_picture(width, height, 24, "a mask")?;
    let bands = decoder
        .find_tag(Tag::SamplesPerPixel)
        .map_err(not_tiff)?
        .map_or(Ok(1), |v| v.into_u16())
        .map_err(not_tiff)?;
    if bands != 1 {
        bail!(
            "{}: a mask has one band; this GeoTIFF has {bands}",
            path.display()
        );
    }
    let placed = placement(&mut decoder).map_err(|e| anyhow!("{}: {e}", path.display()))?;
    let pixels: Vec<f64> = match decoder.read_image().map_err(not_tiff)? {
        DecodingResult::U8(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U16(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U64(v) => v.into_iter().map(|x| x as f64).collect(),
        DecodingResult::I8(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I16(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I64(v) => v.into_iter().map(|x| x as f64).collect(),
        DecodingResult::F32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::F64(v) => v,
        DecodingResult::F16(v) => v.into_iter().map(f64::from).collect(),
    };
    let (width, height) = (width.into(), height.into());
    Ok((
        Values {
            width,
            height,
            values: pixels,
        },
        placed,
    ))
}

/// Where a GeoTIFF lies: from ModelPixelScale and ModelTiepoint, or an
/// axis-aligned ModelTransformation, with the EPSG code of its GeoKeys; none
/// without those tags.
fn placement<R: std::io::Read + std::io::Seek>(
    decoder: &mut Decoder<R>,
) -> Result<Option<GeoReference>> {
    let doubles = |decoder: &mut Decoder<R>, tag: u16| -> Result<Option<Vec<f64>>> {
        match decoder.find_tag(Tag::Unknown(tag))? {
            Some(v) => Ok(Some(v.into_f64_vec()?)),
            None => Ok(None),
        }
    };
    let keys: Vec<u16> = match decoder.find_tag(Tag::GeoKeyDirectoryTag)? {
        Some(v) => v.into_u16_vec()?,
        None => Vec::new(),
    };
    // GeoKeys: a header of four shorts, then (key, location, count, value);
    // location 0 holds the value itself.
    let key = |wanted: u16| {
        keys.get(4..)
            .unwrap_or(&[])
            .chunks_exact(4)
            .find(|k| k[0] == wanted && k[1] == 0)
            .map(|k| k[3])
    };
    let scale = doubles(decoder, 33550)?;
    let tiepoint = doubles(decoder, 33922)?;
    let matrix = doubles(decoder, 34264)?;
    let (mut left, mut top, width, height) = match (scale, tiepoint, matrix) {
        (Some(s), Some(t), _) if s.len() >= 2 && t.len() >= 6 => {
            (t[3] - t[0] * s[0], t[4] + t[1] * s[1], s[0], s[1])
        }
        (_, _, Some(m)) if m.len() >= 16 => {
            if m[1] != 0.0 || m[4] != 0.0 {
                bail!("a rotated or sheared raster (its ModelTransformation) is not one pixgeo places");
            }
            (m[3], m[7], m[0], -m[5])
        }
        _ => return Ok(None),
    };
    if !(width.is_finite() && height.is_finite() && width > 0.0 && height != 0.0) {
        bail!("its pixel size {width} x {height} places no raster");
    }
    // Pixel is point (GTRasterTypeGeoKey 2): the tie point is a pixel's
    // centre, as GDAL reads it.
    if key(1025) == Some(2) {
        left -= width / 2.0;
        top += height / 2.0;
    }
    let epsg = key(3072)
        .or(key(2048))
        .filter(|&code| (1024..32767).contains(&code) && crs_kind(code).is_ok());
    Ok(Some(GeoReference {
        left,
        top,
        pixel_width: width,
        pixel_height: height,
        epsg,
        cloud_optimized: false,
    }))
}
