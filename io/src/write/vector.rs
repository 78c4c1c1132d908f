//! Cells as vector files: GeoJSON FeatureCollections (RFC 7946) for GIS
//! tools and shapely, and SVG pictures.

use std::path::Path;

use glam::DVec2;
use serde_json::{json, Map, Value};

use super::output::write_text;
use pixgeo::{geometry::predicates::ring_turn, Result};

/// Polygons, each an outer ring and then its holes; rings are open (the
/// first corner is not repeated).
pub type Polygons = Vec<Vec<Vec<DVec2>>>;

/// One feature: its polygons (none: a null geometry) and its properties.
#[derive(Clone, Debug, Default)]
pub struct Feature {
    pub polygons: Polygons,
    pub properties: Map<String, Value>,
}

/// Whether a simple ring turns counter-clockwise (y up): by the exact turn
/// at its least corner (far from the origin, a float area would cancel
/// away), else by the area about its first corner.
fn counter_clockwise(ring: &[DVec2]) -> bool {
    let turn = ring_turn(ring);
    if turn != 0.0 {
        return turn > 0.0;
    }
    let o = ring.first().copied().unwrap_or_default();
    let n = ring.len();
    (0..n)
        .map(|k| (ring[k] - o).perp_dot(ring[(k + 1) % n] - o))
        .sum::<f64>()
        > 0.0
}

/// A ring as GeoJSON wants it: closed, counter-clockwise when `outer`,
/// clockwise when a hole (RFC 7946 §3.1.6).
fn ring_json(ring: &[DVec2], outer: bool) -> Value {
    let mut points: Vec<DVec2> = ring.to_vec();
    if counter_clockwise(&points) != outer {
        points.reverse();
    }
    points.push(points[0]);
    Value::Array(points.iter().map(|p| json!([p.x, p.y])).collect())
}

fn geometry_json(polygons: &Polygons) -> Value {
    let polygon = |rings: &Vec<Vec<DVec2>>| {
        Value::Array(
            rings
                .iter()
                .enumerate()
                .map(|(k, r)| ring_json(r, k == 0))
                .collect(),
        )
    };
    match &polygons[..] {
        [] => Value::Null,
        [one] => json!({"type": "Polygon", "coordinates": polygon(one)}),
        many => json!({
            "type": "MultiPolygon",
            "coordinates": many.iter().map(polygon).collect::<Vec<_>>(),
        }),
    }
}

/// Writes `features` as a GeoJSON FeatureCollection, one feature at a time (a
/// million cells never stand as one JSON tree). With an EPSG code other than
/// 4326 (GeoJSON's own), the collection names it in a `crs` member, as GDAL
/// reads it. Members are in the order serde_json sorts them.
pub fn write_geojson(
    path: &Path,
    features: impl IntoIterator<Item = Feature>,
    epsg: Option<u16>,
) -> Result<()> {
    let json = |out: &mut dyn std::io::Write, value: &Value| {
        serde_json::to_writer(&mut *out, value).map_err(std::io::Error::other)
    };
    write_text(path, "geojson", "GeoJSON files", |out| {
        write!(out, "{{")?;
        if let Some(code) = epsg.filter(|&c| c != 4326) {
            let crs = json!({
                "type": "name",
                "properties": {"name": format!("urn:ogc:def:crs:EPSG::{code}")},
            });
            write!(out, "\"crs\":")?;
            json(out, &crs)?;
            write!(out, ",")?;
        }
        write!(out, "\"features\":[")?;
        for (k, f) in features.into_iter().enumerate() {
            if k > 0 {
                write!(out, ",")?;
            }
            let feature = json!({
                "type": "Feature",
                "geometry": geometry_json(&f.polygons),
                "properties": f.properties,
            });
            json(out, &feature)?;
        }
        writeln!(out, "],\"type\":\"FeatureCollection\"}}")
    })
}

/// Writes an SVG picture `width` x `height` pixels: each shape's polygons
/// filled in its colour (holes left open), and a dot at each site. Points are
/// in picture coordinates: x right, y down, pixel (0, 0) from (0, 0) to (1, 1).
pub fn write_svg(
    path: &Path,
    width: u32,
    height: u32,
    shapes: &[(Polygons, [u8; 3])],
    sites: &[DVec2],
) -> Result<()> {
    write_text(path, "svg", "SVG pictures", |out| {
        writeln!(
            out,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" \
             viewBox=\"0 0 {width} {height}\">"
        )?;
        let line = (width.max(height) as f64 / 800.0).max(0.5);
        writeln!(
            out,
            "<g stroke=\"white\" stroke-width=\"{line}\" stroke-linejoin=\"round\" fill-rule=\"evenodd\">"
        )?;
        for (polygons, [r, g, b]) in shapes {
            let mut d = String::new();
            for ring in polygons.iter().flatten() {
                for (k, p) in ring.iter().enumerate() {
                    d.push_str(&format!(
                        "{}{} {} ",
                        if k == 0 { 'M' } else { 'L' },
                        p.x,
                        p.y
                    ));
                }
                d.push_str("Z ");
            }
            if !d.is_empty() {
                writeln!(
                    out,
                    "<path fill=\"rgb({r},{g},{b})\" d=\"{}\"/>",
                    d.trim_end()
                )?;
            }
        }
        writeln!(out, "</g>\n<g fill=\"black\">")?;
        let dot = 2.0 * line;
        for p in sites {
            writeln!(out, "<circle cx=\"{}\" cy=\"{}\" r=\"{dot}\"/>", p.x, p.y)?;
        }
        writeln!(out, "</g>\n</svg>")
    })
}
