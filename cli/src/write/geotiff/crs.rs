//! Coordinate systems named by EPSG code, told geographic or projected by
//! EPSG's registry (the `crs-definitions` crate), not by the code's range.

/// What kind of coordinate system a GeoTIFF declares.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CrsKind {
    /// Longitude and latitude in degrees (EPSG:4326, EPSG:6318).
    Geographic,
    /// Projected, in linear units (EPSG:32633, EPSG:4087).
    Projected,
}

/// The kind of EPSG's coordinate system `code`, or why a 2-D raster cannot
/// be placed in it.
pub fn crs_kind(code: u16) -> Result<CrsKind, String> {
    let definition = crs_definitions::from_code(code).ok_or_else(|| {
        format!("EPSG:{code} is not a coordinate system in EPSG's registry as pixgeo knows it")
    })?;
    let projection = definition
        .proj4
        .split_whitespace()
        .find_map(|term| term.strip_prefix("+proj="))
        .unwrap_or("");
    match projection {
        "longlat" | "latlong" | "lonlat" | "latlon" => Ok(CrsKind::Geographic),
        "geocent" => Err(format!(
            "EPSG:{code} is geocentric (x, y, z from the earth's centre), not a map's \
             coordinate system; give a geographic or projected one"
        )),
        _ => Ok(CrsKind::Projected),
    }
}

/// Parses `EPSG:N`: the EPSG code of a geographic or projected coordinate
/// system.
pub fn parse_crs(text: &str) -> Result<u16, String> {
    let code = text
        .strip_prefix("EPSG:")
        .or_else(|| text.strip_prefix("epsg:"))
        .ok_or_else(|| format!("`{text}`: give the coordinate system as EPSG:N"))?;
    let code = match code.parse::<u16>() {
        Ok(n) if (1024..=32766).contains(&n) => n,
        _ => {
            return Err(format!(
                "`{text}`: GeoTIFF keys hold EPSG codes from 1024 to 32766"
            ))
        }
    };
    crs_kind(code)?;
    Ok(code)
}

/// `EPSG:N`, as [`parse_crs`] reads it.
pub fn crs_name(epsg: Option<u16>) -> Option<String> {
    epsg.map(|code| format!("EPSG:{code}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_registry_not_the_range_tells_geographic_from_projected() {
        // EPSG:6318 (NAD83(2011)) is geographic outside 4000–4999, and
        // EPSG:4087 (World Equidistant Cylindrical) projected inside it.
        assert_eq!(crs_kind(4326), Ok(CrsKind::Geographic));
        assert_eq!(crs_kind(6318), Ok(CrsKind::Geographic));
        assert_eq!(crs_kind(4087), Ok(CrsKind::Projected));
        assert_eq!(crs_kind(32633), Ok(CrsKind::Projected));
        assert!(crs_kind(4978).unwrap_err().contains("geocentric"));
        assert_eq!(parse_crs("EPSG:4326"), Ok(4326));
        assert!(parse_crs("4326").is_err());
        assert!(parse_crs("EPSG:900913").is_err());
        assert!(parse_crs("EPSG:1025").unwrap_err().contains("registry"));
    }
}
