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

/// Whether EPSG's coordinate system `code` is geographic (longitude and
/// latitude); why it is no system for maps otherwise.
pub fn is_geographic(code: u16) -> Result<bool, String> {
    crs_kind(code).map(|k| k == CrsKind::Geographic)
}

/// Parses a coordinate system to its EPSG code (which GeoTIFF keys and
/// GeoJSON carry): `EPSG:N`; an OGC URN or URL naming EPSG's N; a WKT string
/// (WKT1, WKT2 or ESRI's) whose outermost AUTHORITY or ID is EPSG's, or an
/// ESRI name for WGS 84, NAD83, their UTM zones or Web Mercator; a PROJ
/// string with the terms of one of EPSG's definitions; or a file (a `.prj`)
/// holding one of these. A definition that names no EPSG code is refused.
pub fn parse_crs(text: &str) -> Result<u16, String> {
    let text = text.trim();
    let code = if let Some(n) = text
        .strip_prefix("EPSG:")
        .or_else(|| text.strip_prefix("epsg:"))
    {
        n.to_string()
    } else if is_definition_file(text) {
        let contents = std::fs::read_to_string(text)
            .map_err(|e| format!("{text}: reading the coordinate system: {e}"))?;
        return parse_crs(&contents).map_err(|e| format!("{text}: {e}"));
    } else if let Some(n) = urn_code(text) {
        n
    } else if text.starts_with('+') {
        proj_code(text)?.to_string()
    } else if text.contains('[') {
        wkt_code(text)?.to_string()
    } else {
        return Err(format!(
            "`{text}`: give the coordinate system as EPSG:N, a WKT or PROJ string, or a .prj file"
        ));
    };
    let code = match code.parse::<u16>() {
        Ok(n) if (1024..=32766).contains(&n) => n,
        _ => {
            return Err(format!(
                "`{code}`: GeoTIFF keys hold EPSG codes from 1024 to 32766"
            ))
        }
    };
    crs_kind(code)?;
    Ok(code)
}

fn is_definition_file(text: &str) -> bool {
    !text.contains('[') && !text.starts_with('+') && std::path::Path::new(text).is_file()
}

/// N from `urn:ogc:def:crs:EPSG::N` or `http://www.opengis.net/def/crs/EPSG/0/N`.
fn urn_code(text: &str) -> Option<String> {
    let upper = text.to_ascii_uppercase();
    let named =
        upper.starts_with("URN:OGC:DEF:CRS:EPSG:") || upper.contains("OPENGIS.NET/DEF/CRS/EPSG/");
    named.then(|| upper.rsplit([':', '/']).next().unwrap_or("").to_string())
}

/// The code of EPSG's definition whose PROJ terms are those of `text`, in
/// any order (the lowest code where several share them: 4326 before 4979).
fn proj_code(text: &str) -> Result<u16, String> {
    if let Some(n) = text.split_whitespace().find_map(|t| {
        t.to_ascii_lowercase()
            .strip_prefix("+init=epsg:")
            .map(str::to_string)
    }) {
        return n
            .parse()
            .map_err(|_| format!("`{text}`: +init names no EPSG code"));
    }
    let terms = proj_terms(text);
    (1024..=32766u16)
        .find(|&code| {
            crs_definitions::from_code(code).is_some_and(|d| proj_terms(d.proj4) == terms)
        })
        .ok_or_else(|| {
            format!(
                "`{text}`: no EPSG definition has these PROJ terms; pixgeo writes coordinate \
                 systems by EPSG code: give EPSG:N (pyproj's CRS.to_epsg() or \
                 `projinfo --identify` finds it)"
            )
        })
}

/// A PROJ string's terms, sorted, without those that change nothing
/// (`+no_defs`, `+type=crs`, `+wktext`, metres as the unit).
fn proj_terms(text: &str) -> Vec<String> {
    let mut terms: Vec<String> = text
        .split_whitespace()
        .map(str::to_ascii_lowercase)
        .filter(|t| {
            !matches!(
                t.as_str(),
                "+no_defs" | "+type=crs" | "+wktext" | "+units=m"
            )
        })
        .collect();
    terms.sort();
    terms
}

/// The EPSG code of a WKT string: its outermost `AUTHORITY["EPSG","N"]` or
/// `ID["EPSG",N]`, else an ESRI name pixgeo knows.
fn wkt_code(text: &str) -> Result<u16, String> {
    // The authority of the outermost node is the last one at depth 1.
    let mut depth = 0;
    let mut outer = None;
    for (at, c) in text.char_indices() {
        match c {
            '[' | '(' => {
                depth += 1;
                let head = text[..at].trim_end();
                let word = head.rsplit([',', '[', '(', ' ']).next().unwrap_or("");
                if depth == 2 && matches!(word.to_ascii_uppercase().as_str(), "AUTHORITY" | "ID") {
                    outer = Some(at + 1);
                }
            }
            ']' | ')' => depth -= 1,
            _ => {}
        }
    }
    let authority = outer.map(|at| {
        let fields: Vec<String> = text[at..]
            .split([',', ']', ')'])
            .take(2)
            .map(|f| f.trim().trim_matches('"').to_string())
            .collect();
        fields
    });
    if let Some(fields) = authority {
        if fields.len() == 2 && fields[0].eq_ignore_ascii_case("EPSG") {
            return fields[1]
                .parse()
                .map_err(|_| format!("the WKT's EPSG code `{}` is not a number", fields[1]));
        }
    }
    let name = text
        .split_once('"')
        .and_then(|(_, rest)| rest.split_once('"'))
        .map(|(name, _)| name)
        .unwrap_or("");
    esri_code(name).ok_or_else(|| {
        format!(
            "the WKT `{name}` names no EPSG code; pixgeo writes coordinate systems by EPSG \
             code: give EPSG:N (pyproj's CRS.to_epsg() or `gdalsrsinfo -e` finds it)"
        )
    })
}

/// The EPSG code of an ESRI coordinate system name (as `.prj` files have
/// them, without an authority): WGS 84 and NAD83, their UTM zones, and Web
/// Mercator.
fn esri_code(name: &str) -> Option<u16> {
    let fixed = match name {
        "GCS_WGS_1984" => Some(4326),
        "GCS_North_American_1983" => Some(4269),
        "WGS_1984_Web_Mercator_Auxiliary_Sphere" => Some(3857),
        _ => None,
    };
    let utm = |prefix: &str, north: u16, south: Option<u16>| {
        let zone = name.strip_prefix(prefix)?;
        let (number, hemisphere) = zone.split_at(zone.len().checked_sub(1)?);
        let number: u16 = number.parse().ok().filter(|z| (1..=60).contains(z))?;
        match hemisphere {
            "N" => Some(north + number),
            "S" => south.map(|s| s + number),
            _ => None,
        }
    };
    fixed
        .or_else(|| utm("WGS_1984_UTM_Zone_", 32600, Some(32700)))
        .or_else(|| utm("NAD_1983_UTM_Zone_", 26900, None))
}

/// `EPSG:N`, as [`parse_crs`] reads it.
pub fn crs_name(epsg: Option<u16>) -> Option<String> {
    epsg.map(|code| format!("EPSG:{code}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wkt_proj_and_urns_name_their_epsg_code() {
        let wgs84 = r#"GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563,AUTHORITY["EPSG","7030"]],AUTHORITY["EPSG","6326"]],PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433],AUTHORITY["EPSG","4326"]]"#;
        assert_eq!(parse_crs(wgs84), Ok(4326));
        // WKT2 as PROJ writes it: the outermost ID, not the datum's.
        let utm = r#"PROJCRS["WGS 84 / UTM zone 33N",BASEGEOGCRS["WGS 84",DATUM["World Geodetic System 1984",ELLIPSOID["WGS 84",6378137,298.257223563]],ID["EPSG",4326]],CONVERSION["UTM zone 33N",METHOD["Transverse Mercator",ID["EPSG",9807]]],CS[Cartesian,2],ID["EPSG",32633]]"#;
        assert_eq!(parse_crs(utm), Ok(32633));
        // ESRI's .prj: no authority, a name.
        let esri = r#"PROJCS["WGS_1984_UTM_Zone_33S",GEOGCS["GCS_WGS_1984",DATUM["D_WGS_1984",SPHEROID["WGS_1984",6378137.0,298.257223563]],PRIMEM["Greenwich",0.0],UNIT["Degree",0.0174532925199433]],PROJECTION["Transverse_Mercator"],UNIT["Meter",1.0]]"#;
        assert_eq!(parse_crs(esri), Ok(32733));
        assert_eq!(
            parse_crs(r#"GEOGCS["GCS_WGS_1984",DATUM["D_WGS_1984"]]"#),
            Ok(4326)
        );
        let unknown = parse_crs(r#"PROJCS["My_Local_Grid",PROJECTION["Transverse_Mercator"]]"#);
        assert!(unknown.unwrap_err().contains("names no EPSG code"));
        assert_eq!(parse_crs("+proj=longlat +datum=WGS84 +no_defs"), Ok(4326));
        assert_eq!(parse_crs("+proj=utm +zone=33 +datum=WGS84"), Ok(32633));
        assert_eq!(
            parse_crs("+datum=WGS84 +proj=utm +zone=33 +units=m +type=crs"),
            Ok(32633)
        );
        assert_eq!(parse_crs("+init=epsg:3857"), Ok(3857));
        assert!(parse_crs("+proj=utm +zone=33 +ellps=intl +towgs84=1,2,3").is_err());
        assert_eq!(parse_crs("urn:ogc:def:crs:EPSG::32633"), Ok(32633));
        assert_eq!(
            parse_crs("http://www.opengis.net/def/crs/EPSG/0/4326"),
            Ok(4326)
        );
        let prj = std::env::temp_dir().join(format!("pixgeo-crs-{}.prj", std::process::id()));
        std::fs::write(&prj, esri).unwrap();
        assert_eq!(parse_crs(prj.to_str().unwrap()), Ok(32733));
        std::fs::remove_file(prj).unwrap();
    }

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
        assert!(parse_crs("EPSG:4326x").is_err());
        assert!(parse_crs("EPSG:900913").is_err());
        assert!(parse_crs("EPSG:1025").unwrap_err().contains("registry"));
    }
}
