//! Sample files, points that carry a value to interpolate, read by their
//! extension:
//! - `.csv` (or `.txt`, `-` for standard input): a header naming `x`, `y` and
//!   the value's column (other columns are skipped), or three unnamed
//!   columns `x,y,value`;
//! - `.json`: `[[x, y, value], ...]` or `[{"x": .., "y": .., "<column>": ..}]`;
//! - `.geojson`: Point and MultiPoint features whose property `<column>` is
//!   the value, or, without it, the coordinates' third number (elevation);
//! - `.npy`: an n×3 array `x, y, value`.
//!
//! Numbers are read bit for bit, as site files are.

use std::path::Path;

use glam::DVec2;
use serde_json::Value;

use super::sites::{read_text, SiteFormat};
use pixgeo::error::{Error, Result};

/// Points and their values, in file order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Samples {
    pub points: Vec<DVec2>,
    pub values: Vec<f64>,
}

impl Samples {
    fn push(&mut self, x: f64, y: f64, value: f64) {
        self.points.push(DVec2::new(x, y));
        self.values.push(value);
    }
}

/// Reads the samples of `path`, their values from `column` (a CSV column,
/// a JSON key or a GeoJSON property).
pub fn read_samples(path: &Path, column: &str) -> Result<Samples> {
    let failed = |message: String| Error::Parse {
        path: path.to_path_buf(),
        message,
    };
    let samples = match SiteFormat::of(path)? {
        SiteFormat::Npy => {
            let (shape, values) = super::npy::read_numbers(path)?;
            match shape[..] {
                [_, 3] => {
                    let mut samples = Samples::default();
                    for row in values.chunks(3) {
                        samples.push(row[0], row[1], row[2]);
                    }
                    samples
                }
                _ => {
                    return Err(failed(format!(
                        "a {shape:?} array: samples are n×3 (x, y, value)"
                    )))
                }
            }
        }
        SiteFormat::Csv => parse_csv(&read_text(path)?, column).map_err(failed)?,
        SiteFormat::Json => parse_json(&read_text(path)?, column).map_err(failed)?,
        SiteFormat::GeoJson => parse_geojson(&read_text(path)?, column).map_err(failed)?,
    };
    if samples.points.is_empty() {
        return Err(failed("the file holds no samples".into()));
    }
    if let Some(i) = samples.points.iter().position(|p| !p.is_finite()) {
        return Err(failed(format!("sample {i}: its point is not finite")));
    }
    if let Some(i) = samples.values.iter().position(|v| !v.is_finite()) {
        return Err(failed(format!(
            "sample {i}: its value {} is not finite",
            samples.values[i]
        )));
    }
    Ok(samples)
}

/// CSV text: a header naming `x`, `y` and `column`, or `x,y,value` rows.
pub fn parse_csv(text: &str, column: &str) -> std::result::Result<Samples, String> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let mut at: Option<[usize; 3]> = None;
    let mut samples = Samples::default();
    for record in reader.records() {
        let record = record.map_err(|e| format!("CSV: {e}"))?;
        let line = record.position().map_or(0, |p| p.line());
        let at = match at {
            Some(at) => at,
            None if record.iter().all(|f| f.parse::<f64>().is_err()) => {
                let find = |name: &str| {
                    record
                        .iter()
                        .position(|f| f.eq_ignore_ascii_case(name))
                        .ok_or_else(|| {
                            format!("line {line}: the header has no column `{name}`; it needs x, y and {column}")
                        })
                };
                at = Some([find("x")?, find("y")?, find(column)?]);
                continue;
            }
            None if record.len() == 3 => *at.insert([0, 1, 2]),
            None => {
                return Err(format!(
                    "line {line}: {} columns without a header; name the columns (x,y,{column}) or give three, x,y,value",
                    record.len()
                ))
            }
        };
        let number = |k: usize| {
            let field = record.get(k).unwrap_or("");
            field
                .parse::<f64>()
                .map_err(|_| format!("line {line}, column {}: `{field}` is not a number", k + 1))
        };
        samples.push(number(at[0])?, number(at[1])?, number(at[2])?);
    }
    Ok(samples)
}

fn number(v: &Value, what: &str) -> std::result::Result<f64, String> {
    v.as_f64()
        .ok_or_else(|| format!("{what}: {v} is not a number"))
}

/// JSON: `[[x, y, value], ...]` or objects with `x`, `y` and `column`.
fn parse_json(text: &str, column: &str) -> std::result::Result<Samples, String> {
    let value = super::json::parse(text)?;
    let items = value
        .as_array()
        .ok_or("a JSON array of samples: [[x, y, value], ...]")?;
    let mut samples = Samples::default();
    for (i, item) in items.iter().enumerate() {
        let at = |key: &str| -> std::result::Result<f64, String> {
            let v = item.get(key).ok_or(format!("sample {i}: no `{key}`"))?;
            number(v, &format!("sample {i}"))
        };
        match item {
            Value::Array(xs) if xs.len() == 3 => {
                let n = |k: usize| number(&xs[k], &format!("sample {i}"));
                samples.push(n(0)?, n(1)?, n(2)?);
            }
            Value::Object(_) => samples.push(at("x")?, at("y")?, at(column)?),
            _ => return Err(format!("sample {i}: {item} is not [x, y, value]")),
        }
    }
    Ok(samples)
}

/// GeoJSON: Point and MultiPoint geometries, bare or in Features, in a
/// FeatureCollection or alone.
fn parse_geojson(text: &str, column: &str) -> std::result::Result<Samples, String> {
    let value = super::json::parse(text)?;
    let features = match value.get("features") {
        Some(Value::Array(f)) => f.clone(),
        _ => Vec::from([value]),
    };
    let mut samples = Samples::default();
    for (i, feature) in features.iter().enumerate() {
        let geometry = feature.get("geometry").unwrap_or(feature);
        let property = feature.get("properties").and_then(|p| p.get(column));
        let kind = geometry.get("type").and_then(Value::as_str).unwrap_or("");
        let coordinates = geometry.get("coordinates");
        let points = match (kind, coordinates) {
            ("Point", Some(c)) => Vec::from([c.clone()]),
            ("MultiPoint", Some(Value::Array(cs))) => cs.clone(),
            _ => {
                return Err(format!(
                    "feature {i}: a {kind:?} geometry; samples are Points or MultiPoints"
                ))
            }
        };
        for p in points {
            let xs = p
                .as_array()
                .ok_or(format!("feature {i}: coordinates {p}"))?;
            let n = |k: usize| number(&xs[k], &format!("feature {i}"));
            let value = match (property, xs.len()) {
                (Some(v), 2 | 3) => number(v, &format!("feature {i}, property {column}"))?,
                (None, 3) => n(2)?,
                _ => {
                    return Err(format!(
                        "feature {i}: no property `{column}` and no third coordinate to take the value from"
                    ))
                }
            };
            samples.push(n(0)?, n(1)?, value);
        }
    }
    Ok(samples)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_each_format() {
        let want = Samples {
            points: vec![DVec2::new(0.1, 2.0), DVec2::new(3.0, -4.5)],
            values: vec![7.0, -0.25],
        };
        assert_eq!(
            parse_csv("x,y,t\n0.1,2,7\n3,-4.5,-0.25\n", "t").unwrap(),
            want
        );
        assert_eq!(parse_csv("0.1,2,7\n3,-4.5,-0.25\n", "z").unwrap(), want);
        assert_eq!(
            parse_csv("name,y,x,z\na,2,0.1,7\nb,-4.5,3,-0.25\n", "z").unwrap(),
            want
        );
        assert!(parse_csv("x,y\n1,2\n", "z")
            .unwrap_err()
            .contains("no column `z`"));
        assert!(parse_csv("1,2\n", "z").is_err());
        assert_eq!(
            parse_json("[[0.1, 2, 7], [3, -4.5, -0.25]]", "z").unwrap(),
            want
        );
        let objects = r#"[{"x": 0.1, "y": 2, "v": 7}, {"x": 3, "y": -4.5, "v": -0.25}]"#;
        assert_eq!(parse_json(objects, "v").unwrap(), want);
        let geojson = r#"{"type": "FeatureCollection", "features": [
            {"type": "Feature", "properties": {"t": 7}, "geometry": {"type": "Point", "coordinates": [0.1, 2]}},
            {"type": "Feature", "properties": {}, "geometry": {"type": "Point", "coordinates": [3, -4.5, -0.25]}}]}"#;
        assert_eq!(parse_geojson(geojson, "t").unwrap(), want);
        assert!(parse_geojson(r#"{"type": "Point", "coordinates": [1, 2]}"#, "t").is_err());
    }
}
