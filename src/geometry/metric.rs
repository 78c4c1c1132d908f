//! Distance functions (thesis §3.6): the Euclidean norm, L1, L∞ and L_p for every
//! p > 0. Changing the metric changes the shape of the cones; in exact mode the
//! fragment shader evaluates the metric per pixel.
//!
//! Each metric has a *key*, a monotone function of the distance that the shaders
//! compare instead of the distance itself: the squared distance for L2, the sum of
//! p-th powers for L_p, the distance itself for L1 and L∞. Keys of integer
//! offsets are exact in float32 for L1, L2 and L∞, so integer ties stay ties.

use std::fmt;

use glam::DVec2;

/// A distance function of the plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Metric {
    /// The Euclidean norm.
    L2,
    /// |x| + |y|.
    L1,
    /// max(|x|, |y|).
    LInf,
    /// (|x|^p + |y|^p)^(1/p), any p > 0 (not a norm for p < 1).
    Lp(f64),
}

impl Metric {
    /// Parses `l2`, `l1`, `linf` or `lp:P` (P a positive number; `lp:1`, `lp:2`
    /// and `lp:inf` name the special cases).
    pub fn parse(text: &str) -> Result<Self, String> {
        let t = text.trim().to_ascii_lowercase();
        let named = match t.as_str() {
            "l2" | "euclidean" => Some(Self::L2),
            "l1" | "manhattan" => Some(Self::L1),
            "linf" | "l-inf" | "chebyshev" => Some(Self::LInf),
            _ => None,
        };
        if let Some(m) = named {
            return Ok(m);
        }
        let p = t
            .strip_prefix("lp:")
            .ok_or_else(|| format!("unknown metric `{text}`: use l2, l1, linf or lp:P"))?;
        if p == "inf" {
            return Ok(Self::LInf);
        }
        let p: f64 = p
            .parse()
            .map_err(|_| format!("`{p}` is not a number (lp:P needs P > 0)"))?;
        Self::lp(p)
    }

    /// L_p, with p = 1, 2 and infinity as their named metrics.
    pub fn lp(p: f64) -> Result<Self, String> {
        if p.is_nan() || p <= 0.0 {
            return Err(format!("L_p needs p > 0, not {p}"));
        }
        Ok(match p {
            1.0 => Self::L1,
            2.0 => Self::L2,
            p if p.is_infinite() => Self::LInf,
            p => Self::Lp(p),
        })
    }

    /// The distance of offset `d`.
    pub fn distance(self, d: DVec2) -> f64 {
        self.distance_of_key(self.key(d))
    }

    /// The key of offset `d`: the monotone function of its distance that the
    /// shaders compare (`metric_key_of` in `glsl/metric.glsl`).
    pub fn key(self, d: DVec2) -> f64 {
        let a = d.abs();
        match self {
            Self::L2 => a.length_squared(),
            Self::L1 => a.x + a.y,
            Self::LInf => a.x.max(a.y),
            Self::Lp(p) => a.x.powf(p) + a.y.powf(p),
        }
    }

    /// The key of a distance: the monotone function the shaders compare.
    pub fn key_of_distance(self, r: f64) -> f64 {
        match self {
            Self::L2 => r * r,
            Self::L1 | Self::LInf => r,
            Self::Lp(p) => r.powf(p),
        }
    }

    /// The distance of a key.
    pub fn distance_of_key(self, key: f64) -> f64 {
        match self {
            Self::L2 => key.sqrt(),
            Self::L1 | Self::LInf => key,
            Self::Lp(p) => key.powf(1.0 / p),
        }
    }

    /// `(a, b)` with `a |x|_2 <= |x| <= b |x|_2` for every x, both tight.
    pub fn euclidean_bounds(self) -> (f64, f64) {
        let root2 = std::f64::consts::SQRT_2;
        match self {
            Self::L2 => (1.0, 1.0),
            Self::L1 => (1.0, root2),
            Self::LInf => (1.0 / root2, 1.0),
            Self::Lp(p) if p <= 2.0 => (1.0, 2f64.powf(1.0 / p - 0.5)),
            Self::Lp(p) => (2f64.powf(1.0 / p - 0.5), 1.0),
        }
    }

    /// How far (Euclidean) a point may be from its nearest site under this metric
    /// when some site is within Euclidean distance 1: b / a.
    pub fn stretch(self) -> f64 {
        let (a, b) = self.euclidean_bounds();
        b / a
    }

    /// The shader's code for the metric: (kind, p).
    pub fn shader_code(self) -> (u32, f32) {
        match self {
            Self::L2 => (0, 2.0),
            Self::L1 => (1, 1.0),
            Self::LInf => (2, 0.0),
            Self::Lp(p) => (3, p as f32),
        }
    }
}

impl fmt::Display for Metric {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::L2 => write!(f, "l2"),
            Self::L1 => write!(f, "l1"),
            Self::LInf => write!(f, "linf"),
            Self::Lp(p) => write!(f, "lp:{p}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_names_and_exponents() {
        assert_eq!(Metric::parse("l2"), Ok(Metric::L2));
        assert_eq!(Metric::parse("LINF"), Ok(Metric::LInf));
        assert_eq!(Metric::parse("lp:1"), Ok(Metric::L1));
        assert_eq!(Metric::parse("lp:0.5"), Ok(Metric::Lp(0.5)));
        assert_eq!(Metric::parse("lp:inf"), Ok(Metric::LInf));
        assert!(Metric::parse("lp:0").is_err());
        assert!(Metric::parse("lp:-1").is_err());
        assert!(Metric::parse("lp:x").is_err());
        assert!(Metric::parse("l3").is_err());
    }

    #[test]
    fn bounds_hold_and_keys_invert() {
        let offsets = [
            DVec2::new(3.0, 4.0),
            DVec2::new(-1.0, 0.0),
            DVec2::new(2.0, -2.0),
            DVec2::new(0.3, 7.0),
        ];
        for m in [
            Metric::L2,
            Metric::L1,
            Metric::LInf,
            Metric::Lp(0.5),
            Metric::Lp(1.5),
            Metric::Lp(6.0),
        ] {
            let (a, b) = m.euclidean_bounds();
            for d in offsets {
                let (x, e) = (m.distance(d), d.length());
                assert!(a * e <= x + 1e-12 && x <= b * e + 1e-12, "{m} {d}");
                let back = m.distance_of_key(m.key_of_distance(x));
                assert!((back - x).abs() < 1e-9, "{m}");
            }
        }
        assert_eq!(Metric::L1.distance(DVec2::new(3.0, -4.0)), 7.0);
        assert_eq!(Metric::LInf.distance(DVec2::new(3.0, -4.0)), 4.0);
    }
}
