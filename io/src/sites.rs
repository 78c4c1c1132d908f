//! Site files, read by their extension:
//! - `.csv` (or `.txt`): `x,y` per line; weight columns only under a header that
//!   names them (`x,y,m,a`), since a third unnamed column could mean anything;
//! - `.json`: `[[x, y], ...]`, `[{"x": .., "y": ..}, ...]`, sites of every shape
//!   such as `{"segment": [[x1, y1], [x2, y2]], "m": 2}`, any of these under a
//!   `"sites"` key, or GeoJSON;
//! - `.geojson`: Point, MultiPoint, LineString and MultiLineString geometries
//!   (bare, in Features or in a FeatureCollection), weights from the properties
//!   `m` and `a`;
//! - `.npy`: an n×2 (`x, y`), n×3 (`x, y, m`) or n×4 (`x, y, m, a`) array of
//!   floats or integers.
//!
//! Numbers are read bit for bit: the site is the number the file spells.
//! Also: the `--metric` grammar, whose `polygon:FILE` is read here.

use pixgeo::memory::Gather;
use std::path::Path;

use glam::DVec2;
use serde_json::Value;

use pixgeo::{
    error::{Error, Result},
    geometry::{
        metric::Metric,
        site::{Shape, Site},
    },
};

/// The path that names standard input.
pub(crate) const STDIN: &str = "-";

/// The formats a site file may have, told by its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SiteFormat {
    Csv,
    Json,
    GeoJson,
    Npy,
}

impl SiteFormat {
    /// The format of `path` by its extension; an unknown one is an error.
    /// `-`, standard input, is CSV.
    pub fn of(path: &Path) -> Result<Self> {
        if path == Path::new(STDIN) {
            return Ok(Self::Csv);
        }
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("csv" | "txt") => Ok(Self::Csv),
            Some("json") => Ok(Self::Json),
            Some("geojson") => Ok(Self::GeoJson),
            Some("npy") => Ok(Self::Npy),
            _ => Err(Error::Parse {
                path: path.to_path_buf(),
                message: "unknown site file format: name it .csv, .txt, .json, .geojson or .npy"
                    .into(),
            }),
        }
    }
}

/// Reads unweighted point sites; weights and other shapes are an error naming
/// the site.
pub fn read_sites(path: &Path) -> Result<Vec<DVec2>> {
    read_general_sites(path)?
        .iter()
        .enumerate()
        .map(|(i, s)| match s.shape {
            Shape::Point(p) if s.is_plain_point() => Ok(p),
            _ => Err(Error::Parse {
                path: path.to_path_buf(),
                message: format!("site {i}: this command takes unweighted points"),
            }),
        })
        .gather("sites")?
}

/// Reads sites of every shape and weight; a file without sites is an error.
pub fn read_general_sites(path: &Path) -> Result<Vec<Site>> {
    let failed = |message: String| Error::Parse {
        path: path.to_path_buf(),
        message,
    };
    let format = SiteFormat::of(path)?;
    let sites = if format == SiteFormat::Npy {
        let (shape, values) = super::npy::read_numbers(path)?;
        sites_from_array(&shape, &values).map_err(failed)?
    } else {
        let text = read_text(path)?;
        match format {
            SiteFormat::Csv => parse_csv(&text),
            SiteFormat::Json => parse_json(&text),
            _ => parse_geojson(&text),
        }
        .map_err(failed)?
    };
    if sites.is_empty() {
        return Err(failed("the file holds no sites".into()));
    }
    Ok(sites)
}

pub(crate) fn read_text(path: &Path) -> Result<String> {
    let bytes = if path == Path::new(STDIN) {
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut std::io::stdin(), &mut bytes).map(|_| bytes)
    } else {
        std::fs::read(path)
    };
    let bytes = bytes.map_err(|source| Error::Io {
        path: path.to_path_buf(),
        cause: source,
    })?;
    String::from_utf8(bytes).map_err(|e| Error::Parse {
        path: path.to_path_buf(),
        message: format!(
            "not UTF-8 text (byte {}); site files are CSV, JSON, GeoJSON or .npy",
            e.utf8_error().valid_up_to()
        ),
    })
}

/// Sites from an n×2, n×3 or n×4 array, row-major: `x, y[, m[, a]]`.
#[expect(
    clippy::disallowed_methods,
    reason = "values of a document already read, fewer than its bytes"
)]
pub fn sites_from_array(shape: &[u64], values: &[f64]) -> Result<Vec<Site>, String> {
    let columns = match shape {
        [_, c @ 2..=4] => *c as usize,
        _ => {
            return Err(format!(
                "an array of shape {shape:?}: site arrays are n×2 (x, y), n×3 (x, y, m) or n×4 (x, y, m, a)"
            ))
        }
    };
    Ok(values
        .chunks_exact(columns)
        .map(|row| {
            let mut site = Site::point(DVec2::new(row[0], row[1]));
            if columns > 2 {
                site.multiplicative = row[2];
            }
            if columns > 3 {
                site.additive = row[3];
            }
            site
        })
        .collect())
}

/// A distance function as the command line's `--metric` names it: what
/// [`Metric::parse`] reads, or `polygon:FILE`, the polygon read by
/// [`read_polygon`].
pub fn parse_metric(text: &str) -> std::result::Result<Metric, String> {
    match text.trim().strip_prefix("polygon:") {
        Some(path) => {
            let (vertices, kernel) = read_polygon(Path::new(path)).map_err(|e| e.to_string())?;
            Metric::polygon(&vertices, kernel)
        }
        None => Metric::parse(text),
    }
}

/// Reads a polygon for `--metric polygon:FILE`: its vertices as a point site
/// file (around the kernel point at the origin), or a `.json` file
/// `{"vertices": [[x, y], ...], "kernel": [x, y]}`. Returns the vertices and
/// the kernel point.
pub fn read_polygon(path: &Path) -> Result<(Vec<DVec2>, DVec2)> {
    let failed = |message: String| Error::Parse {
        path: path.to_path_buf(),
        message,
    };
    let format = SiteFormat::of(path)?;
    let object = if format == SiteFormat::Json {
        match super::json::parse(&read_text(path)?) {
            Ok(Value::Object(o)) if o.contains_key("vertices") => Some(o),
            Ok(_) => None,
            Err(e) => return Err(failed(e)),
        }
    } else {
        None
    };
    let (vertices, kernel) = match object {
        Some(o) => {
            let vertices = match &o["vertices"] {
                Value::Array(a) => json_list(a).map_err(failed)?,
                v => return Err(failed(format!("vertices must be [[x, y], ...], found {v}"))),
            };
            let kernel = match o.get("kernel") {
                None => DVec2::ZERO,
                Some(k) => json_pair(k).map_err(|e| failed(format!("kernel: {e}")))?,
            };
            (vertices, kernel)
        }
        None => (read_general_sites(path)?, DVec2::ZERO),
    };
    let points = vertices
        .iter()
        .map(|s| match s.shape {
            Shape::Point(p) if s.is_plain_point() => Ok(p),
            _ => Err(failed("polygon vertices are points [x, y]".into())),
        })
        .try_gather("polygon vertices")?;
    Ok((points, kernel))
}

/// The columns of a CSV file: where `x`, `y` and the weights `m`, `a` stand.
struct CsvColumns {
    names: Vec<&'static str>,
}

impl CsvColumns {
    /// Columns named by a header line.
    fn from_header(fields: &csv::StringRecord, line: u64) -> Result<Self, String> {
        let mut names = Vec::new();
        for field in fields {
            let name = match field.to_ascii_lowercase().as_str() {
                "x" => "x",
                "y" => "y",
                "m" => "m",
                "a" => "a",
                _ => {
                    return Err(format!(
                        "line {line}: column `{field}` is not one pixgeo reads; name the columns x, y and optionally m (multiplicative weight) and a (additive weight)"
                    ))
                }
            };
            if names.contains(&name) {
                return Err(format!("line {line}: column `{name}` appears twice"));
            }
            names.push(name);
        }
        if !names.contains(&"x") || !names.contains(&"y") {
            return Err(format!("line {line}: the header needs columns x and y"));
        }
        Ok(Self { names })
    }

    /// Columns of a file without a header: `x,y` only.
    fn positional(count: usize, line: u64) -> Result<Self, String> {
        if count != 2 {
            return Err(format!(
                "line {line}: {count} columns without a header; a file without a header has two columns x,y, and weights need a header line naming them, e.g. `x,y,m,a`"
            ));
        }
        Ok(Self {
            names: Vec::from(["x", "y"]),
        })
    }
}

/// A header line is names: every field starts with a letter or `_` and is not
/// a number (`nan` and `inf` are numbers).
fn is_header(fields: &csv::StringRecord) -> bool {
    fields.iter().all(|f| {
        f.parse::<f64>().is_err() && f.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
    })
}

/// Parses CSV text: `x,y` per record, or the columns a header names (`x`, `y`,
/// and the multiplicative weight `m` and additive weight `a`). Empty lines and
/// lines starting with `#` are skipped.
pub fn parse_csv(text: &str) -> Result<Vec<Site>, String> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .flexible(true)
        .from_reader(text.as_bytes());
    let mut columns: Option<CsvColumns> = None;
    let mut sites = Vec::new();
    for (index, record) in reader.records().enumerate() {
        let record = record.map_err(|e| format!("CSV: {e}"))?;
        let line = record.position().map_or(index as u64 + 1, |p| p.line());
        if record.iter().all(|f| f.is_empty()) {
            continue;
        }
        let columns = match &columns {
            Some(c) => c,
            None if is_header(&record) => {
                columns = Some(CsvColumns::from_header(&record, line)?);
                continue;
            }
            None => columns.insert(CsvColumns::positional(record.len(), line)?),
        };
        if record.len() != columns.names.len() {
            return Err(format!(
                "line {line}: expected {} columns ({}), found {}",
                columns.names.len(),
                columns.names.join(","),
                record.len()
            ));
        }
        let mut site = Site::point(DVec2::ZERO);
        let mut point = DVec2::ZERO;
        for (k, (field, name)) in record.iter().zip(&columns.names).enumerate() {
            let value: f64 = field.parse().map_err(|_| {
                format!(
                    "line {line}, column {} ({name}): `{field}` is not a number",
                    k + 1
                )
            })?;
            match *name {
                "x" => point.x = value,
                "y" => point.y = value,
                "m" => site.multiplicative = value,
                _ => site.additive = value,
            }
        }
        site.shape = Shape::Point(point);
        sites.push(site);
    }
    Ok(sites)
}

/// Parses GeoJSON text: Point, MultiPoint, LineString (one segment site per
/// edge) and MultiLineString geometries, bare, in a Feature (whose properties
/// `m` and `a` weigh its sites) or in a FeatureCollection.
pub fn parse_geojson(text: &str) -> Result<Vec<Site>, String> {
    Ok(parse_geojson_sources(text)?.0)
}

/// Where a GeoJSON file's sites come from, so that answers about them can be
/// joined back to the input.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GeoJsonSources {
    /// Each site's feature: its index in the FeatureCollection (0 for a lone
    /// Feature or geometry). A MultiPoint's points share their feature.
    pub feature_of_site: Vec<u32>,
    /// Each feature's properties (empty where it has none).
    pub properties: Vec<serde_json::Map<String, Value>>,
    /// The name in the file's `crs` member (GeoJSON 2008, as GDAL writes it
    /// for systems other than WGS 84), if it has one.
    pub crs: Option<String>,
}

/// [`parse_geojson`], with where each site comes from.
pub fn parse_geojson_sources(text: &str) -> Result<(Vec<Site>, GeoJsonSources), String> {
    let value = super::json::parse(text)?;
    let mut sites = Vec::new();
    let mut sources = GeoJsonSources {
        crs: match value.get("crs") {
            None | Some(Value::Null) => None,
            Some(crs) => Some(
                crs.get("properties")
                    .and_then(|p| p.get("name"))
                    .and_then(Value::as_str)
                    .ok_or_else(|| format!("crs {crs}: a named crs, {{\"type\": \"name\", \"properties\": {{\"name\": ...}}}}"))?
                    .to_string(),
            ),
        },
        ..GeoJsonSources::default()
    };
    let mut from = |feature: &Value, sites: &mut Vec<Site>| -> Result<(), String> {
        let before = sites.len();
        geojson_object(feature, (1.0, 0.0), sites)?;
        let index = sources.properties.len() as u32;
        sources
            .feature_of_site
            .extend((before..sites.len()).map(|_| index));
        let properties = match feature.get("properties") {
            Some(Value::Object(p)) => p.clone(),
            _ => serde_json::Map::new(),
        };
        sources.properties.push(properties);
        Ok(())
    };
    match (
        value.get("type").and_then(Value::as_str),
        value.get("features"),
    ) {
        (Some("FeatureCollection"), Some(Value::Array(features))) => {
            for (i, f) in features.iter().enumerate() {
                from(f, &mut sites).map_err(|e| format!("feature {i}: {e}"))?;
            }
        }
        _ => from(&value, &mut sites)?,
    }
    Ok((sites, sources))
}

/// Reads a `.geojson` file's sites and where each comes from; a file without
/// sites is an error.
pub fn read_geojson_sources(path: &Path) -> Result<(Vec<Site>, GeoJsonSources)> {
    let failed = |message: String| Error::Parse {
        path: path.to_path_buf(),
        message,
    };
    let (sites, sources) = parse_geojson_sources(&read_text(path)?).map_err(failed)?;
    if sites.is_empty() {
        return Err(failed("the file holds no sites".into()));
    }
    Ok((sites, sources))
}

#[expect(
    clippy::disallowed_methods,
    reason = "values of a document already read, fewer than its bytes"
)]
fn geojson_object(v: &Value, weights: (f64, f64), out: &mut Vec<Site>) -> Result<(), String> {
    let kind = v.get("type").and_then(Value::as_str).unwrap_or_default();
    let coordinates = || {
        v.get("coordinates")
            .ok_or_else(|| format!("a {kind} needs \"coordinates\""))
    };
    let positions = |v: &Value| -> Result<Vec<DVec2>, String> {
        match v {
            Value::Array(a) => a.iter().map(geojson_position).collect(),
            _ => Err(format!("{kind} coordinates must be an array of positions")),
        }
    };
    let weigh = |shape| Site {
        shape,
        multiplicative: weights.0,
        additive: weights.1,
    };
    let line = |points: Vec<DVec2>, out: &mut Vec<Site>| {
        if points.len() < 2 {
            return Err(format!("a {kind} needs at least two positions"));
        }
        out.extend(points.windows(2).map(|w| weigh(Shape::Segment(w[0], w[1]))));
        Ok(())
    };
    match kind {
        "FeatureCollection" => match v.get("features") {
            Some(Value::Array(features)) => features.iter().enumerate().try_for_each(|(i, f)| {
                geojson_object(f, weights, out).map_err(|e| format!("feature {i}: {e}"))
            }),
            _ => Err("a FeatureCollection needs a \"features\" array".into()),
        },
        "Feature" => {
            let property = |name: &str, default: f64| {
                match v.get("properties").and_then(|p| p.get(name)) {
                    None | Some(Value::Null) => Ok(default),
                    Some(p) => p
                        .as_f64()
                        .ok_or_else(|| format!("property {name} must be a number, found {p}")),
                }
            };
            let weights = (property("m", 1.0)?, property("a", 0.0)?);
            match v.get("geometry") {
                Some(g) if !g.is_null() => geojson_object(g, weights, out),
                _ => Err("a Feature without a geometry".into()),
            }
        }
        "GeometryCollection" => match v.get("geometries") {
            Some(Value::Array(gs)) => gs.iter().try_for_each(|g| geojson_object(g, weights, out)),
            _ => Err("a GeometryCollection needs a \"geometries\" array".into()),
        },
        "Point" => {
            out.push(weigh(Shape::Point(geojson_position(coordinates()?)?)));
            Ok(())
        }
        "MultiPoint" => {
            out.extend(positions(coordinates()?)?.into_iter().map(|p| weigh(Shape::Point(p))));
            Ok(())
        }
        "LineString" => line(positions(coordinates()?)?, out),
        "MultiLineString" => match coordinates()? {
            Value::Array(lines) => lines.iter().try_for_each(|l| line(positions(l)?, out)),
            _ => Err("MultiLineString coordinates must be an array of lines".into()),
        },
        "" => Err("a GeoJSON object needs a \"type\"".into()),
        other => Err(format!(
            "GeoJSON {other} is not a site geometry pixgeo reads (Point, MultiPoint, LineString, MultiLineString)"
        )),
    }
}

/// A GeoJSON position `[x, y]` or `[x, y, z]`; the plane takes x and y.
fn geojson_position(v: &Value) -> Result<DVec2, String> {
    match v {
        Value::Array(c) if c.len() == 2 || c.len() == 3 => {
            json_pair(&Value::Array(c[..2].to_vec()))
        }
        _ => Err(format!("a position must be [x, y] or [x, y, z], found {v}")),
    }
}

/// `[x, y]` of two numbers.
fn json_pair(v: &Value) -> Result<DVec2, String> {
    match v {
        Value::Array(xy) if xy.len() == 2 => match (xy[0].as_f64(), xy[1].as_f64()) {
            (Some(x), Some(y)) => Ok(DVec2::new(x, y)),
            _ => Err(format!("[x, y] must hold two numbers, found {v}")),
        },
        _ => Err(format!("expected [x, y], found {v}")),
    }
}

/// Parses JSON text in one of the accepted shapes.
pub fn parse_json(text: &str) -> Result<Vec<Site>, String> {
    let value = super::json::parse(text)?;
    let list = match &value {
        Value::Array(a) => a,
        Value::Object(o) if o.contains_key("type") => {
            let mut sites = Vec::new();
            geojson_object(&value, (1.0, 0.0), &mut sites)?;
            return Ok(sites);
        }
        Value::Object(o) => match o.get("sites") {
            Some(Value::Array(a)) => a,
            _ => return Err("JSON object needs a \"sites\" array (or a GeoJSON \"type\")".into()),
        },
        _ => return Err("JSON must be an array of sites or an object with \"sites\"".into()),
    };
    json_list(list)
}

#[expect(
    clippy::disallowed_methods,
    reason = "values of a document already read, fewer than its bytes"
)]
fn json_list(list: &[Value]) -> Result<Vec<Site>, String> {
    list.iter()
        .enumerate()
        .map(|(i, v)| json_site(v).map_err(|e| format!("site {i}: {e}, found {v}")))
        .collect()
}

/// One JSON site: `[x, y]`, `{"x", "y"}`, or one of the keys `point`,
/// `segment`, `circle`, `arc`, each with optional weights `m` and `a`.
fn json_site(v: &Value) -> Result<Site, String> {
    let number = |v: Option<&Value>, what: &str| {
        v.and_then(Value::as_f64)
            .ok_or_else(|| format!("{what} must be a number"))
    };
    let pair = |v: Option<&Value>, what: &str| -> Result<DVec2, String> {
        match v {
            Some(Value::Array(xy)) if xy.len() == 2 => Ok(DVec2::new(
                number(xy.first(), what)?,
                number(xy.get(1), what)?,
            )),
            _ => Err(format!("{what} must be [x, y]")),
        }
    };
    let o = match v {
        Value::Array(_) => return Ok(Site::point(pair(Some(v), "a point")?)),
        Value::Object(o) => o,
        _ => return Err("expected [x, y] or an object".into()),
    };
    let shape = if let Some(p) = o.get("point") {
        Shape::Point(pair(Some(p), "point")?)
    } else if let Some(seg) = o.get("segment") {
        match seg {
            Value::Array(ends) if ends.len() == 2 => Shape::Segment(
                pair(ends.first(), "segment end")?,
                pair(ends.get(1), "segment end")?,
            ),
            _ => return Err("segment must be [[x1, y1], [x2, y2]]".into()),
        }
    } else if let Some(c) = o.get("circle") {
        Shape::Circle {
            center: pair(c.get("center"), "circle center")?,
            radius: number(c.get("radius"), "circle radius")?,
        }
    } else if let Some(a) = o.get("arc") {
        Shape::Arc {
            center: pair(a.get("center"), "arc center")?,
            radius: number(a.get("radius"), "arc radius")?,
            start: number(a.get("start"), "arc start")?,
            end: number(a.get("end"), "arc end")?,
        }
    } else if o.contains_key("x") || o.contains_key("y") {
        Shape::Point(DVec2::new(
            number(o.get("x"), "x")?,
            number(o.get("y"), "y")?,
        ))
    } else {
        return Err("expected a point, segment, circle or arc".into());
    };
    Ok(Site {
        shape,
        multiplicative: o.get("m").map_or(Ok(1.0), |m| number(Some(m), "m"))?,
        additive: o.get("a").map_or(Ok(0.0), |a| number(Some(a), "a"))?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn metrics_are_named_or_read_from_a_polygon_file() {
        assert_eq!(parse_metric("l1"), Ok(Metric::L1));
        assert_eq!(parse_metric(" lp:3 "), Ok(Metric::Lp(3.0)));
        let path = std::env::temp_dir().join(format!("pixgeo-diamond-{}.json", std::process::id()));
        std::fs::write(
            &path,
            r#"{"vertices": [[2, 1], [1, 2], [0, 1], [1, 0]], "kernel": [1, 1]}"#,
        )
        .unwrap();
        let named = format!("polygon:{}", path.display());
        let diamond = parse_metric(&named).unwrap();
        // The unit ball is the L1 ball: the same distances.
        for d in [DVec2::new(3.0, -1.5), DVec2::new(-0.25, 2.0)] {
            assert!((diamond.distance(d) - Metric::L1.distance(d)).abs() < 1e-12);
        }
        assert!(Metric::parse(&named).unwrap_err().contains("parse_metric"));
        std::fs::remove_file(&path).unwrap();
        assert!(parse_metric(&format!("polygon:{}", path.display())).is_err());
    }

    #[test]
    fn csv_with_and_without_header() {
        let pt = |x, y| Site::point(DVec2::new(x, y));
        let a = parse_csv("x,y\n1,2\n 3.5 , -4\n\n# note\n5e1,6\n").unwrap();
        assert_eq!(a, vec![pt(1.0, 2.0), pt(3.5, -4.0), pt(50.0, 6.0)]);
        assert_eq!(parse_csv("1,2\n").unwrap(), vec![pt(1.0, 2.0)]);
        assert!(parse_csv("1,2\n3,x\n").unwrap_err().contains("line 2"));
        assert!(parse_csv("x,y\n1,2,3,4,5\n").unwrap_err().contains("5"));
        // Weight columns by their names, in any order.
        let w = parse_csv("x,y,m,a\n1,2,3,-4\n").unwrap();
        assert_eq!((w[0].multiplicative, w[0].additive), (3.0, -4.0));
        let w = parse_csv("a,Y,x\n-4,2,1\n").unwrap();
        assert_eq!(
            (w[0].shape, w[0].additive),
            (Shape::Point(DVec2::new(1.0, 2.0)), -4.0)
        );
        // NaN parses; the algorithms reject it with the site's index.
        assert!(matches!(parse_csv("nan,1\n").unwrap()[0].shape, Shape::Point(p) if p.x.is_nan()));
    }

    #[test]
    fn csv_never_guesses() {
        // A column pixgeo does not read is named, not taken for a weight.
        assert!(parse_csv("x,y,id\n1,2,3\n").unwrap_err().contains("`id`"));
        // A third column without a header is ambiguous.
        assert!(parse_csv("1,2,3\n").unwrap_err().contains("header"));
        // A malformed first row is an error, not a header.
        let e = parse_csv("1,2x\n3,4\n5,6\n").unwrap_err();
        assert!(e.contains("line 1, column 2 (y): `2x`"), "{e}");
        assert!(parse_csv("x,x\n1,2\n").unwrap_err().contains("twice"));
        assert!(parse_csv("x,m\n1,2\n").unwrap_err().contains("x and y"));
    }

    #[test]
    fn numbers_are_read_bit_for_bit() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        for _ in 0..2000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let v = f64::from_bits(state);
            if !v.is_finite() {
                continue;
            }
            let text = format!("{v:?}");
            let csv = parse_csv(&format!("{text},{text}\n")).unwrap();
            let json = parse_json(&format!("[[{text}, {text}]]")).unwrap();
            let geo = parse_geojson(&format!(
                r#"{{"type":"Point","coordinates":[{text},{text}]}}"#
            ))
            .unwrap();
            for site in [&csv[0], &json[0], &geo[0]] {
                assert!(matches!(site.shape, Shape::Point(p) if p.x.to_bits() == v.to_bits()));
            }
        }
        // The case that once moved by one unit in the last place.
        let json = parse_json("[[3.7974166882130675, 0]]").unwrap();
        assert!(matches!(json[0].shape, Shape::Point(p) if p.x == 3.7974166882130675));
    }

    #[test]
    fn geojson_sources_name_each_sites_feature_and_its_properties() {
        let text = r#"{"type": "FeatureCollection",
            "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32633"}},
            "features": [
                {"type": "Feature", "properties": {"name": "a"}, "geometry": {"type": "Point", "coordinates": [1, 2]}},
                {"type": "Feature", "properties": null, "geometry": {"type": "MultiPoint", "coordinates": [[3, 4], [5, 6]]}},
                {"type": "Feature", "properties": {"name": "c", "m": 2}, "geometry": {"type": "Point", "coordinates": [7, 8]}}
            ]}"#;
        let (sites, sources) = parse_geojson_sources(text).unwrap();
        assert_eq!(sites.len(), 4);
        assert_eq!(sources.feature_of_site, [0, 1, 1, 2]);
        assert_eq!(sources.properties[0]["name"], "a");
        assert!(sources.properties[1].is_empty());
        assert_eq!(sites[3].multiplicative, 2.0);
        assert_eq!(sources.crs.as_deref(), Some("urn:ogc:def:crs:EPSG::32633"));
        let (_, lone) =
            parse_geojson_sources(r#"{"type": "Point", "coordinates": [0, 0]}"#).unwrap();
        assert_eq!((lone.feature_of_site, lone.crs), (vec![0], None));
    }

    #[test]
    fn geojson_geometries() {
        let sites = parse_geojson(
            r#"{"type": "FeatureCollection", "features": [
                {"type": "Feature", "properties": {"m": 2}, "geometry": {"type": "Point", "coordinates": [1, 2]}},
                {"type": "Feature", "properties": null, "geometry": {"type": "MultiPoint", "coordinates": [[3, 4], [5, 6, 7]]}},
                {"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[0, 0], [1, 0], [1, 1]]}}]}"#,
        )
        .unwrap();
        assert_eq!(sites.len(), 5);
        assert_eq!(sites[0].multiplicative, 2.0);
        assert!(matches!(sites[2].shape, Shape::Point(p) if p == DVec2::new(5.0, 6.0)));
        assert!(matches!(sites[4].shape, Shape::Segment(a, b) if a == DVec2::X && b == DVec2::ONE));
        assert!(parse_geojson(r#"{"type": "Polygon", "coordinates": []}"#)
            .unwrap_err()
            .contains("Polygon"));
        assert!(parse_geojson(r#"{"type": "LineString", "coordinates": [[0, 0]]}"#).is_err());
        // GeoJSON in a .json file is read as GeoJSON.
        assert_eq!(
            parse_json(r#"{"type": "Point", "coordinates": [1, 2]}"#)
                .unwrap()
                .len(),
            1
        );
    }

    #[test]
    fn arrays_of_two_to_four_columns() {
        let s = sites_from_array(&[2, 3], &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]).unwrap();
        assert_eq!(s[1].multiplicative, 6.0);
        assert!(sites_from_array(&[2, 5], &[0.0; 10]).is_err());
        assert!(sites_from_array(&[4], &[0.0; 4]).is_err());
    }

    #[test]
    fn formats_by_extension() {
        assert_eq!(
            SiteFormat::of(Path::new("a.GeoJSON")).unwrap(),
            SiteFormat::GeoJson
        );
        assert_eq!(SiteFormat::of(Path::new("a.npy")).unwrap(), SiteFormat::Npy);
        assert!(SiteFormat::of(Path::new("a.xlsx")).is_err());
        assert!(SiteFormat::of(Path::new("sites")).is_err());
    }

    #[test]
    fn json_shapes() {
        let p = vec![
            Site::point(DVec2::new(1.0, 2.0)),
            Site::point(DVec2::new(3.0, 4.0)),
        ];
        assert_eq!(parse_json("[[1,2],[3,4]]").unwrap(), p);
        assert_eq!(
            parse_json(r#"{"sites":[{"x":1,"y":2},{"x":3,"y":4}]}"#).unwrap(),
            p
        );
        assert!(parse_json("[[1]]").is_err());
        assert!(parse_json("{\"points\": []}").is_err());
        assert!(parse_json("[[1,").is_err());
        let shapes = parse_json(
            r#"[{"point": [1, 2], "m": 2, "a": -1},
                {"segment": [[0, 0], [3, 4]]},
                {"circle": {"center": [5, 5], "radius": 2}},
                {"arc": {"center": [0, 0], "radius": 1, "start": 0, "end": 2.5}}]"#,
        )
        .unwrap();
        assert_eq!((shapes[0].multiplicative, shapes[0].additive), (2.0, -1.0));
        assert!(matches!(shapes[1].shape, Shape::Segment(..)));
        assert!(matches!(shapes[2].shape, Shape::Circle { radius, .. } if radius == 2.0));
        assert!(matches!(shapes[3].shape, Shape::Arc { end, .. } if end == 2.5));
        assert!(parse_json(r#"[{"circle": {"center": [5, 5]}}]"#)
            .unwrap_err()
            .contains("radius"));
    }
}
