//! Site files: CSV (`x,y` per line, optional header) and JSON (`[[x, y], ...]`,
//! `[{"x": .., "y": ..}, ...]`, or either under a `"sites"` key), and seeded random
//! sites.

use std::path::Path;

use glam::DVec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::Value;

use crate::{
    error::{Error, Result},
    geometry::Frame,
};

/// Reads point sites from a `.json` file or a CSV file (any other extension).
pub fn read_sites(path: &Path) -> Result<Vec<DVec2>> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let is_json = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let parsed = if is_json {
        parse_json(&text)
    } else {
        parse_csv(&text)
    };
    parsed.map_err(|message| Error::Parse {
        path: path.to_path_buf(),
        message,
    })
}

/// Parses CSV text: two numeric columns per record; a first record that is not
/// numeric is a header. Empty lines and lines starting with `#` are skipped.
pub fn parse_csv(text: &str) -> Result<Vec<DVec2>, String> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .flexible(true)
        .from_reader(text.as_bytes());
    let mut sites = Vec::new();
    for (index, record) in reader.records().enumerate() {
        let record = record.map_err(|e| format!("CSV: {e}"))?;
        let line = record.position().map_or(index as u64 + 1, |p| p.line());
        if record.iter().all(|f| f.is_empty()) {
            continue;
        }
        let numbers: Vec<Result<f64, _>> = record.iter().map(str::parse::<f64>).collect();
        if index == 0 && numbers.iter().any(|n| n.is_err()) {
            continue; // header
        }
        if record.len() != 2 {
            return Err(format!(
                "line {line}: expected 2 columns `x,y`, found {} (weights are not supported for point Voronoi diagrams yet)",
                record.len()
            ));
        }
        let x = numbers[0]
            .clone()
            .map_err(|_| format!("line {line}: x `{}` is not a number", &record[0]))?;
        let y = numbers[1]
            .clone()
            .map_err(|_| format!("line {line}: y `{}` is not a number", &record[1]))?;
        sites.push(DVec2::new(x, y));
    }
    Ok(sites)
}

/// Parses JSON text in one of the accepted shapes.
pub fn parse_json(text: &str) -> Result<Vec<DVec2>, String> {
    let value: Value = serde_json::from_str(text).map_err(|e| format!("JSON: {e}"))?;
    let list = match &value {
        Value::Array(a) => a,
        Value::Object(o) => match o.get("sites") {
            Some(Value::Array(a)) => a,
            _ => return Err("JSON object needs a \"sites\" array".into()),
        },
        _ => return Err("JSON must be an array of sites or an object with \"sites\"".into()),
    };
    list.iter()
        .enumerate()
        .map(|(i, v)| {
            let pair = match v {
                Value::Array(xy) if xy.len() == 2 => (xy[0].as_f64(), xy[1].as_f64()),
                Value::Object(o) => (
                    o.get("x").and_then(Value::as_f64),
                    o.get("y").and_then(Value::as_f64),
                ),
                _ => (None, None),
            };
            match pair {
                (Some(x), Some(y)) => Ok(DVec2::new(x, y)),
                _ => Err(format!(
                    "site {i}: expected [x, y] or {{\"x\": .., \"y\": ..}} with numbers, found {v}"
                )),
            }
        })
        .collect()
}

/// `n` sites uniformly distributed over the world rectangle the frame shows,
/// reproducible from `seed`.
pub fn random_sites(n: usize, seed: u64, frame: &Frame) -> Vec<DVec2> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let lo = frame.to_world(DVec2::splat(-0.5));
    let hi = frame.to_world(DVec2::new(
        frame.width as f64 - 0.5,
        frame.height as f64 - 0.5,
    ));
    (0..n)
        .map(|_| DVec2::new(rng.gen_range(lo.x..hi.x), rng.gen_range(lo.y..hi.y)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_with_and_without_header() {
        let a = parse_csv("x,y\n1,2\n 3.5 , -4\n\n# note\n5e1,6\n").unwrap();
        assert_eq!(
            a,
            vec![
                DVec2::new(1.0, 2.0),
                DVec2::new(3.5, -4.0),
                DVec2::new(50.0, 6.0)
            ]
        );
        assert_eq!(parse_csv("1,2\n").unwrap(), vec![DVec2::new(1.0, 2.0)]);
        assert!(parse_csv("1,2\n3,x\n").unwrap_err().contains("line 2"));
        assert!(parse_csv("1,2,3\n").unwrap_err().contains("3"));
        // NaN parses; the algorithms reject it with the site's index.
        assert!(parse_csv("nan,1\n").unwrap()[0].x.is_nan());
    }

    #[test]
    fn json_shapes() {
        let p = vec![DVec2::new(1.0, 2.0), DVec2::new(3.0, 4.0)];
        assert_eq!(parse_json("[[1,2],[3,4]]").unwrap(), p);
        assert_eq!(
            parse_json(r#"{"sites":[{"x":1,"y":2},{"x":3,"y":4}]}"#).unwrap(),
            p
        );
        assert!(parse_json("[[1]]").is_err());
        assert!(parse_json("{\"points\": []}").is_err());
        assert!(parse_json("[[1,").is_err());
    }
}
