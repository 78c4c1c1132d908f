//! The names the options go by, read by one parser for the command line and
//! Python alike: `"exact"`, `"fan:12"`, `"quadtree"`, `"pixels"`, `"l1"`, ...
//! Each option's `FromStr` looks its name up in its own table here.

use std::str::FromStr;

use crate::{
    algorithms::{
        alpha_hull::AlphaMethod, area::Extreme, interpolate::Method as Interpolation,
        settle::SettleMethod, voronoi::Accuracy, voronoi::Method as VoronoiMethod,
        voronoi::Speedup,
    },
    error::{Error, Result},
    geometry::metric::Metric,
};

/// The value `text` names in `table`, or an error that lists the names.
#[expect(clippy::disallowed_methods, reason = "a table's names")]
fn by_name<T: Copy>(what: &str, text: &str, table: &[(&str, T)]) -> Result<T> {
    let key = text.trim().to_ascii_lowercase();
    table
        .iter()
        .find(|(name, _)| *name == key)
        .map(|&(_, value)| value)
        .ok_or_else(|| {
            let names: Vec<&str> = table.iter().map(|(name, _)| *name).collect();
            Error::malformed(format!("unknown {what} `{text}`: use {}", names.join(", ")))
        })
}

const SPEEDUPS: [(&str, Speedup); 3] = [
    ("local", Speedup::Local),
    ("quadtree", Speedup::Quadtree),
    ("none", Speedup::None),
];
const ALPHA_METHODS: [(&str, AlphaMethod); 2] =
    [("hull", AlphaMethod::Hull), ("pixels", AlphaMethod::Pixels)];
const SETTLE_METHODS: [(&str, SettleMethod); 2] = [
    ("spans", SettleMethod::Spans),
    ("faithful", SettleMethod::Faithful),
];
const INTERPOLATIONS: [(&str, Interpolation); 4] = [
    ("exact", Interpolation::Exact),
    ("discrete", Interpolation::Discrete),
    ("linear", Interpolation::Linear),
    ("nearest", Interpolation::Nearest),
];
const VORONOI_METHODS: [(&str, VoronoiMethod); 3] = [
    ("auto", VoronoiMethod::Auto),
    ("cones", VoronoiMethod::Cones),
    ("grid", VoronoiMethod::Grid),
];
const EXTREMES: [(&str, Extreme); 2] = [
    ("smallest", Extreme::Smallest),
    ("largest", Extreme::Largest),
];

impl FromStr for Speedup {
    type Err = Error;
    /// `local`, `quadtree` or `none`.
    fn from_str(text: &str) -> Result<Self> {
        by_name("speedup", text, &SPEEDUPS)
    }
}

impl FromStr for VoronoiMethod {
    type Err = Error;
    /// `auto`, `cones` or `grid`.
    fn from_str(text: &str) -> Result<Self> {
        by_name("Voronoi method", text, &VORONOI_METHODS)
    }
}

impl FromStr for Interpolation {
    type Err = Error;
    /// `exact`, `discrete`, `linear` or `nearest`.
    fn from_str(text: &str) -> Result<Self> {
        by_name("interpolation method", text, &INTERPOLATIONS)
    }
}

impl FromStr for AlphaMethod {
    type Err = Error;
    /// `hull` or `pixels`.
    fn from_str(text: &str) -> Result<Self> {
        by_name("alpha-hull method", text, &ALPHA_METHODS)
    }
}

impl FromStr for SettleMethod {
    type Err = Error;
    /// `spans` or `faithful`.
    fn from_str(text: &str) -> Result<Self> {
        by_name("settle method", text, &SETTLE_METHODS)
    }
}

impl FromStr for Extreme {
    type Err = Error;
    /// `smallest` or `largest`.
    fn from_str(text: &str) -> Result<Self> {
        by_name("extreme", text, &EXTREMES)
    }
}

impl FromStr for Accuracy {
    type Err = Error;
    /// `exact`; `fan` (fans within one pixel); `fan:T` (T triangles a cone).
    fn from_str(text: &str) -> Result<Self> {
        let mode = text.trim().to_ascii_lowercase();
        let accuracy = match mode.as_str() {
            "exact" => Accuracy::Exact,
            "fan" => Accuracy::FAN,
            _ => match mode.strip_prefix("fan:").map(|t| t.trim().parse::<u32>()) {
                Some(Ok(triangles)) => Accuracy::Fan {
                    epsilon: 1.0,
                    triangles: Some(triangles),
                },
                Some(Err(_)) => {
                    return Err(Error::malformed(format!(
                        "`{text}`: a fan has a whole number of triangles"
                    )))
                }
                None => {
                    return Err(Error::malformed(format!(
                        "unknown mode `{text}`: use exact, fan or fan:T"
                    )))
                }
            },
        };
        accuracy.check()?;
        Ok(accuracy)
    }
}

impl FromStr for Metric {
    type Err = Error;
    /// `l2`, `l1`, `linf`, `lp:P` and the other names [`Metric::parse`] reads.
    fn from_str(text: &str) -> Result<Self> {
        Metric::parse(text).map_err(Error::malformed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_reads_back_and_others_are_listed() {
        for (name, speedup) in SPEEDUPS {
            assert_eq!(name.parse::<Speedup>().unwrap(), speedup);
        }
        assert_eq!(
            " Pixels ".parse::<AlphaMethod>().unwrap(),
            AlphaMethod::Pixels
        );
        assert_eq!(
            "faithful".parse::<SettleMethod>().unwrap(),
            SettleMethod::Faithful
        );
        assert_eq!("largest".parse::<Extreme>().unwrap(), Extreme::Largest);
        assert_eq!("exact".parse::<Accuracy>().unwrap(), Accuracy::Exact);
        assert_eq!("fan".parse::<Accuracy>().unwrap(), Accuracy::FAN);
        assert_eq!(
            "fan:12".parse::<Accuracy>().unwrap(),
            Accuracy::Fan {
                epsilon: 1.0,
                triangles: Some(12)
            }
        );
        let message = "quad".parse::<Speedup>().unwrap_err().to_string();
        assert!(message.contains("use local, quadtree, none"), "{message}");
        for bad in ["fan:2", "fan:x", "fan:", "exactly"] {
            assert!(bad.parse::<Accuracy>().is_err(), "{bad}");
        }
    }
}
