//! The GeoTIFF reader: a raster's first band as doubles and where it lies,
//! as `gdal_proximity` reads its source. The `tiff` crate decodes it, isolated
//! ([`crate::decoding`]) so that a panic inside it is an error naming the file.

use std::{fs::File, io::BufReader, path::Path};

use pixgeo::{Error, Result};
use tiff::{
    decoder::{Decoder, DecodingResult},
    tags::Tag,
};

use super::{crs_kind, GeoReference};
use crate::mask::Values;

/// The first band of the GeoTIFF at `path` as doubles, and its placement
/// (none where it has no georeferencing tags).
pub fn read_geotiff(path: &Path) -> Result<(Values, Option<GeoReference>)> {
    crate::decoding::decoding(path, "TIFF", || decode(path))?
}

fn decode(path: &Path) -> Result<(Values, Option<GeoReference>)> {
    let parse = |message: String| Error::Parse {
        path: path.to_path_buf(),
        message,
    };
    let not_tiff = |e: tiff::TiffError| parse(format!("not a TIFF pixgeo reads: {e}"));
    let file = File::open(path).map_err(|cause| Error::Io {
        path: path.to_path_buf(),
        cause,
    })?;
    let mut decoder = Decoder::new(BufReader::new(file)).map_err(not_tiff)?;
    let (width, height) = decoder.dimensions().map_err(not_tiff)?;
    pixgeo::memory::reserve_picture(width, height, 24, "a mask")?;
    let bands = decoder
        .find_tag(Tag::SamplesPerPixel)
        .map_err(not_tiff)?
        .map_or(Ok(1), |v| v.into_u16())
        .map_err(not_tiff)?;
    if bands != 1 {
        return Err(parse(format!(
            "a mask has one band; this GeoTIFF has {bands}"
        )));
    }
    let placed = placement(&mut decoder).map_err(parse)?;
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
    let values = Values {
        width: width.into(),
        height: height.into(),
        values: pixels,
    };
    Ok((values, placed))
}

/// Where a GeoTIFF lies: from ModelPixelScale and ModelTiepoint, or an
/// axis-aligned ModelTransformation, with the EPSG code of its GeoKeys; none
/// without those tags.
fn placement<R: std::io::Read + std::io::Seek>(
    decoder: &mut Decoder<R>,
) -> std::result::Result<Option<GeoReference>, String> {
    let tag_error = |e: tiff::TiffError| format!("its georeferencing tags: {e}");
    let doubles = |decoder: &mut Decoder<R>, tag: u16| -> std::result::Result<_, String> {
        match decoder.find_tag(Tag::Unknown(tag)).map_err(tag_error)? {
            Some(v) => Ok(Some(v.into_f64_vec().map_err(tag_error)?)),
            None => Ok(None),
        }
    };
    let keys: Vec<u16> = match decoder
        .find_tag(Tag::GeoKeyDirectoryTag)
        .map_err(tag_error)?
    {
        Some(v) => v.into_u16_vec().map_err(tag_error)?,
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
                return Err("a rotated or sheared raster (its ModelTransformation) is not one pixgeo places".into());
            }
            (m[3], m[7], m[0], -m[5])
        }
        _ => return Ok(None),
    };
    if !(width.is_finite() && height.is_finite() && width > 0.0 && height != 0.0) {
        return Err(format!(
            "its pixel size {width} x {height} places no raster"
        ));
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
