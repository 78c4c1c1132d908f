//! Site files: CSV (`x,y` per line, optional header, optional weight columns
//! `m,a`) and JSON (`[[x, y], ...]`, `[{"x": .., "y": ..}, ...]`, sites of every
//! shape such as `{"segment": [[x1, y1], [x2, y2]], "m": 2}`, or any of these under
//! a `"sites"` key), and seeded random sites.

use std::path::Path;

use glam::DVec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::Value;

use crate::{
    error::{Error, Result},
    geometry::{
        site::{Shape, Site},
        Frame,
    },
};

/// Reads unweighted point sites from a `.json` file or a CSV file (any other
/// extension); weights and other shapes are an error naming the site.
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
        .collect()
}

/// Reads sites of every shape and weight from a `.json` or CSV file.
pub fn read_general_sites(path: &Path) -> Result<Vec<Site>> {
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

/// Reads a polygon for `--metric polygon:FILE`: its vertices as a point site
/// file (around the kernel point at the origin), or JSON `{"vertices": [[x, y],
/// ...], "kernel": [x, y]}`. Returns the vertices and the kernel point.
pub fn read_polygon(path: &Path) -> Result<(Vec<DVec2>, DVec2)> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let failed = |message: String| Error::Parse {
        path: path.to_path_buf(),
        message,
    };
    let value: Option<Value> = serde_json::from_str(&text).ok();
    let (vertices, kernel) = match value {
        Some(Value::Object(o)) if o.contains_key("vertices") => {
            let vertices =
                serde_json::to_string(&o["vertices"]).map_err(|e| failed(e.to_string()))?;
            let kernel = match o.get("kernel") {
                None => DVec2::ZERO,
                Some(Value::Array(k)) if k.len() == 2 => DVec2::new(
                    k[0].as_f64()
                        .ok_or_else(|| failed("kernel x is not a number".into()))?,
                    k[1].as_f64()
                        .ok_or_else(|| failed("kernel y is not a number".into()))?,
                ),
                Some(k) => return Err(failed(format!("kernel must be [x, y], found {k}"))),
            };
            (parse_json(&vertices).map_err(failed)?, kernel)
        }
        Some(_) => (parse_json(&text).map_err(failed)?, DVec2::ZERO),
        None => (parse_csv(&text).map_err(failed)?, DVec2::ZERO),
    };
    let points = vertices
        .iter()
        .map(|s| match s.shape {
            Shape::Point(p) if s.is_plain_point() => Ok(p),
            _ => Err(failed("polygon vertices are points [x, y]".into())),
        })
        .collect::<Result<_>>()?;
    Ok((points, kernel))
}

/// Parses CSV text: `x,y` and optionally the multiplicative weight `m` and the
/// additive weight `a` per record; a first record that is not numeric is a
/// header. Empty lines and lines starting with `#` are skipped.
pub fn parse_csv(text: &str) -> Result<Vec<Site>, String> {
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
        if !(2..=4).contains(&record.len()) {
            return Err(format!(
                "line {line}: expected 2 to 4 columns `x,y[,m[,a]]`, found {}",
                record.len()
            ));
        }
        let column = |k: usize, name: &str| {
            numbers[k]
                .clone()
                .map_err(|_| format!("line {line}: {name} `{}` is not a number", &record[k]))
        };
        let mut site = Site::point(DVec2::new(column(0, "x")?, column(1, "y")?));
        if record.len() > 2 {
            site.multiplicative = column(2, "m")?;
        }
        if record.len() > 3 {
            site.additive = column(3, "a")?;
        }
        sites.push(site);
    }
    Ok(sites)
}

/// Parses JSON text in one of the accepted shapes.
pub fn parse_json(text: &str) -> Result<Vec<Site>, String> {
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
        let pt = |x, y| Site::point(DVec2::new(x, y));
        let a = parse_csv("x,y\n1,2\n 3.5 , -4\n\n# note\n5e1,6\n").unwrap();
        assert_eq!(a, vec![pt(1.0, 2.0), pt(3.5, -4.0), pt(50.0, 6.0)]);
        assert_eq!(parse_csv("1,2\n").unwrap(), vec![pt(1.0, 2.0)]);
        assert!(parse_csv("1,2\n3,x\n").unwrap_err().contains("line 2"));
        assert!(parse_csv("1,2,3,4,5\n").unwrap_err().contains("5"));
        // Weight columns.
        let w = parse_csv("x,y,m,a\n1,2,3,-4\n5,6,0.5\n").unwrap();
        assert_eq!((w[0].multiplicative, w[0].additive), (3.0, -4.0));
        assert_eq!((w[1].multiplicative, w[1].additive), (0.5, 0.0));
        // NaN parses; the algorithms reject it with the site's index.
        assert!(matches!(parse_csv("nan,1\n").unwrap()[0].shape, Shape::Point(p) if p.x.is_nan()));
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
