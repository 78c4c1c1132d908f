//! Distance functions (thesis §3.6): the Euclidean norm, L1, L∞, L_p for every
//! p > 0, and the polygonal distance of any polygon star-shaped around its kernel
//! point (§3.6.5). Changing the metric changes the shape of the cones; in exact
//! mode the fragment shader evaluates the metric per pixel, except for polygons,
//! whose distance is piecewise linear, so the fan over the polygon itself is exact.
//!
//! Each metric has a *key*, a monotone function of the distance that the shaders
//! compare instead of the distance itself: the squared distance for L2, the
//! distance itself for the others (for L_p computed as m (Σ (|x_i| / m)^p)^(1/p)
//! with m the larger coordinate, so that no p overflows float32). Keys of integer
//! offsets are exact in float32 for L1, L2 and L∞, so integer ties stay ties.

use std::{
    f64::consts::TAU,
    fmt,
    sync::{Mutex, OnceLock},
};

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
    /// The gauge of a star-shaped polygon around the origin: the t with x / t on
    /// the polygon's boundary. The distance from a site s to a point q is the
    /// gauge of q - s: the cone on s has the base s + polygon.
    Polygon(&'static Gauge),
}

/// A polygon star-shaped around the origin, counter-clockwise, as a unit ball.
#[derive(Debug, PartialEq)]
pub struct Gauge {
    pub vertices: Vec<DVec2>,
    /// The vertices' angles, increasing from the first vertex's.
    angles: Vec<f64>,
    /// The smallest and largest Euclidean distance of the boundary from the origin.
    radii: (f64, f64),
    convex: bool,
}

impl Gauge {
    /// The gauge of `v`.
    pub fn of(&self, v: DVec2) -> f64 {
        if v == DVec2::ZERO {
            return 0.0;
        }
        let n = self.vertices.len();
        if self.convex {
            // Each edge's linear gauge is at most 1 on a convex polygon: the
            // largest is the edge whose sector holds v.
            return (0..n)
                .map(|k| {
                    let (p, q) = (self.vertices[k], self.vertices[(k + 1) % n]);
                    v.perp_dot(q - p) / p.perp_dot(q)
                })
                .fold(0.0, f64::max);
        }
        let a = (v.y.atan2(v.x) - self.angles[0]).rem_euclid(TAU) + self.angles[0];
        // The edge whose sector holds the direction: the last vertex at or before it.
        let k = self.angles.partition_point(|&t| t <= a).saturating_sub(1);
        let (p, q) = (self.vertices[k], self.vertices[(k + 1) % n]);
        (v.perp_dot(q - p) / p.perp_dot(q)).max(0.0)
    }

    /// The gauge's Lipschitz constant: on each edge's sector the gauge is linear
    /// with gradient length 1 / (the edge line's distance from the origin), so
    /// the largest of those.
    pub(crate) fn lipschitz(&self) -> f64 {
        let n = self.vertices.len();
        (0..n)
            .map(|k| {
                let (p, q) = (self.vertices[k], self.vertices[(k + 1) % n]);
                (q - p).length() / p.perp_dot(q).abs()
            })
            .fold(0.0, f64::max)
    }

    /// Whether the polygon is convex (a norm, when also symmetric).
    pub(crate) fn is_convex(&self) -> bool {
        self.convex
    }
}

/// The nearest and farthest a polygon metric's boundary may lie from its kernel.
const POLYGON_SIZES: (f64, f64) = (1e-20, 1e20);

/// Polygons used as metrics live for the whole program (so that [`Metric`] stays
/// a plain copyable value); each distinct polygon is kept once.
fn intern(gauge: Gauge) -> &'static Gauge {
    static GAUGES: OnceLock<Mutex<Vec<&'static Gauge>>> = OnceLock::new();
    let mut kept = GAUGES
        .get_or_init(|| Mutex::new(Vec::new()))
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    if let Some(g) = kept.iter().find(|g| ***g == gauge) {
        return g;
    }
    let g: &'static Gauge = Box::leak(Box::new(gauge));
    kept.push(g);
    g
}

impl Metric {
    /// Parses `l2`, `l1`, `linf` or `lp:P` (P a positive number; `lp:1`, `lp:2`
    /// and `lp:inf` name the special cases). `polygon:FILE` names a file, which
    /// `pixgeo_io::sites::parse_metric` reads.
    pub fn parse(text: &str) -> Result<Self, String> {
        if text.trim().starts_with("polygon:") {
            return Err(format!(
                "`{text}` names a file: read it with pixgeo_io::sites::parse_metric"
            ));
        }
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
        let p = t.strip_prefix("lp:").ok_or_else(|| {
            format!("unknown metric `{text}`: use l2, l1, linf, lp:P or polygon:FILE")
        })?;
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
        // The distance of (1, 1) is 2^(1/p): below p = 0.01 a picture's
        // distances pass float32's range.
        if p < 0.01 {
            return Err(format!(
                "L_p takes p of at least 0.01, not {p:?}: the distance of (1, 1) is 2^(1/p), beyond float32's range below that"
            ));
        }
        Ok(match p {
            1.0 => Self::L1,
            2.0 => Self::L2,
            p if p.is_infinite() => Self::LInf,
            p => Self::Lp(p),
        })
    }

    /// The polygonal distance whose unit ball is `vertices` (any orientation)
    /// around `kernel`: an error unless the polygon is star-shaped around it.
    #[expect(clippy::disallowed_methods, reason = "the unit ball's vertices")]
    pub fn polygon(vertices: &[DVec2], kernel: DVec2) -> Result<Self, String> {
        if vertices.len() < 3 {
            return Err(format!(
                "a polygon needs 3 vertices, not {}",
                vertices.len()
            ));
        }
        if vertices.iter().any(|v| !v.is_finite()) || !kernel.is_finite() {
            return Err("polygon coordinates must be finite".into());
        }
        let mut v: Vec<DVec2> = vertices.iter().map(|p| *p - kernel).collect();
        let area: f64 = (0..v.len())
            .map(|k| v[k].perp_dot(v[(k + 1) % v.len()]))
            .sum();
        if area < 0.0 {
            v.reverse();
        }
        let n = v.len();
        // Star-shaped around the origin: every edge sees it strictly on its left,
        // and the vertices turn once around it.
        let mut turn = 0.0;
        for k in 0..n {
            let (p, q) = (v[k], v[(k + 1) % n]);
            if p == DVec2::ZERO || p.perp_dot(q) <= 0.0 {
                return Err(format!(
                    "the polygon is not star-shaped around its kernel point ({}, {}): edge {k} does not face it",
                    kernel.x, kernel.y
                ));
            }
            turn += p.perp_dot(q).atan2(p.dot(q));
        }
        if (turn - TAU).abs() > 1e-9 {
            return Err(format!(
                "the polygon is not star-shaped around its kernel point ({}, {}): it winds {:.3} times around it",
                kernel.x,
                kernel.y,
                turn / TAU
            ));
        }
        let first = v[0].y.atan2(v[0].x);
        let angles = v
            .iter()
            .map(|p| (p.y.atan2(p.x) - first).rem_euclid(TAU) + first)
            .collect();
        let near = (0..n)
            .map(|k| segment_distance(DVec2::ZERO, v[k], v[(k + 1) % n]))
            .fold(f64::INFINITY, f64::min);
        let far = v.iter().map(|p| p.length()).fold(0.0, f64::max);
        // Distances in pixels are then up to 2^24 / near and down to 1 / far, which
        // float32 holds with room to spare in this range.
        if near < POLYGON_SIZES.0 || far > POLYGON_SIZES.1 {
            return Err(format!(
                "the polygon's boundary lies {near:e} to {far:e} from its kernel point; \
                 distances go through float32, which holds polygons from {:e} to {:e} \
                 across: scale the polygon (its distances scale inversely, its diagram \
                 stays the same)",
                POLYGON_SIZES.0, POLYGON_SIZES.1
            ));
        }
        let convex = (0..n)
            .all(|k| (v[(k + 1) % n] - v[k]).perp_dot(v[(k + 2) % n] - v[(k + 1) % n]) >= 0.0);
        Ok(Self::Polygon(intern(Gauge {
            vertices: v,
            angles,
            radii: (near, far),
            convex,
        })))
    }

    /// Whether the distance is convex (its balls are convex): L_p for p >= 1 and
    /// convex polygons. Convex distances obey the triangle inequality, and their
    /// largest value over a polygon is at a corner.
    pub(crate) fn is_convex(self) -> bool {
        match self {
            Self::Lp(p) => p >= 1.0,
            Self::Polygon(g) => g.is_convex(),
            _ => true,
        }
    }

    /// The same metric in the world mirrored across the x axis (y to -y), as
    /// a north-up raster computes it: a polygon is mirrored, the other
    /// metrics are symmetric.
    #[expect(clippy::disallowed_methods, reason = "the unit ball's vertices")]
    pub fn mirrored_y(self) -> Self {
        match self {
            Self::Polygon(g) => {
                let mirrored: Vec<DVec2> =
                    g.vertices.iter().map(|v| DVec2::new(v.x, -v.y)).collect();
                Self::polygon(&mirrored, DVec2::ZERO)
                    .expect("a mirrored star-shaped polygon is star-shaped, with the same sizes")
            }
            m => m,
        }
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
            Self::Lp(p) => {
                // Scaled by the larger coordinate: no overflow for large p. The
                // larger term is 1 (as in glsl/metric.glsl, one power fewer).
                let m = a.x.max(a.y);
                if m == 0.0 {
                    0.0
                } else {
                    m * (1.0 + (a.x.min(a.y) / m).powf(p)).powf(1.0 / p)
                }
            }
            Self::Polygon(g) => g.of(d),
        }
    }

    /// The key of a distance: the monotone function the shaders compare.
    pub(crate) fn key_of_distance(self, r: f64) -> f64 {
        match self {
            Self::L2 => r * r,
            Self::L1 | Self::LInf | Self::Lp(_) | Self::Polygon(_) => r,
        }
    }

    /// The power of two that maps the keys of every offset within Euclidean
    /// distance `reach` into the depth range [0, 1]; powers of two keep the
    /// mapping exact, so equal keys stay equal depths.
    pub(crate) fn key_scale(self, reach: f64) -> f64 {
        self.key_of_distance(reach * self.euclidean_bounds().1)
            .log2()
            .ceil()
            .exp2()
            .recip()
    }

    /// The distance of a key.
    pub(crate) fn distance_of_key(self, key: f64) -> f64 {
        match self {
            Self::L2 => key.sqrt(),
            Self::L1 | Self::LInf | Self::Lp(_) | Self::Polygon(_) => key,
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
            // |x| / (largest radius) <= gauge <= |x| / (smallest radius).
            Self::Polygon(g) => (1.0 / g.radii.1, 1.0 / g.radii.0),
        }
    }

    /// The most a distance of at most `reach` grows when its site moves by the
    /// Euclidean `delta`. A norm or a polygon's gauge is Lipschitz; L_p with
    /// p < 1 has no triangle inequality, only d(x + y)^p <= d(x)^p + d(y)^p, so
    /// near its spikes a small move costs more the farther the point is.
    pub(crate) fn displacement_error(self, reach: f64, delta: f64) -> f64 {
        match self {
            Self::Lp(p) if p < 1.0 => {
                let moved = self.euclidean_bounds().1 * delta;
                (reach.powf(p) + moved.powf(p)).powf(1.0 / p) - reach
            }
            Self::Polygon(g) => g.lipschitz() * delta,
            _ => self.euclidean_bounds().1 * delta,
        }
    }

    /// The largest Euclidean move of a site that changes distances near it by
    /// at most `error`: the inverse of the metric's Lipschitz constant (for
    /// L_p with p < 1 that holds at distance 0 only; see
    /// [`Metric::displacement_error`] for farther).
    pub(crate) fn displacement_within(self, error: f64) -> f64 {
        match self {
            Self::Polygon(g) => error / g.lipschitz(),
            _ => error / self.euclidean_bounds().1,
        }
    }

    /// How far (Euclidean) a point may be from its nearest site under this metric
    /// when some site is within Euclidean distance 1: b / a.
    pub fn stretch(self) -> f64 {
        let (a, b) = self.euclidean_bounds();
        b / a
    }

    /// The shader's code for the metric: (kind, p). Polygons have none: they are
    /// drawn as fans over themselves, which are exact.
    pub(crate) fn shader_code(self) -> Option<(u32, f32)> {
        match self {
            Self::L2 => Some((0, 2.0)),
            Self::L1 => Some((1, 1.0)),
            Self::LInf => Some((2, 0.0)),
            Self::Lp(p) => Some((3, p as f32)),
            Self::Polygon(_) => None,
        }
    }
}

/// The key an exact point cone writes as its depth (`metric_key_of` in
/// `glsl/metric.glsl`): the metric's own key, or, for L_p whose 2p is a whole
/// number up to `DepthKey::MAX_DOUBLED_P`, the sum of the coordinates' p-th
/// powers (shader kind 4). That takes products and at most a square root per
/// coordinate where the distance takes three powers, which on lavapipe are
/// polynomials, and for integer p it is exact for integer offsets while below
/// 2^24, so that ties between integer sites are exact ties.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DepthKey {
    Metric(Metric),
    PowerSum(f64),
}

impl DepthKey {
    /// The largest 2p with power-sum keys: their products grow with it, and
    /// keys of offsets up to 2^30 stay below float32's largest.
    pub(crate) const MAX_DOUBLED_P: u32 = 8;

    /// The key of exact cones of `metric` that reach no farther than Euclidean
    /// `reach`: power sums where they apply.
    pub(crate) fn for_cones(metric: Metric, reach: f64) -> Self {
        match metric {
            Metric::Lp(p)
                if (2.0 * p).fract() == 0.0
                    && 2.0 * p <= Self::MAX_DOUBLED_P as f64
                    && reach < (1u64 << 30) as f64 =>
            {
                Self::PowerSum(p)
            }
            _ => Self::Metric(metric),
        }
    }

    /// The key of offset `d`, as the shaders compute it.
    pub(crate) fn of_offset(self, d: DVec2) -> f64 {
        match self {
            Self::Metric(m) => m.key(d),
            // |x|^p as the square root's 2p-th power, as glsl/metric.glsl makes it.
            Self::PowerSum(p) => {
                let k = (2.0 * p) as i32;
                d.x.abs().sqrt().powi(k) + d.y.abs().sqrt().powi(k)
            }
        }
    }

    /// The shader's code: (kind, p).
    pub(crate) fn shader_code(self) -> Option<(u32, f32)> {
        match self {
            Self::Metric(m) => m.shader_code(),
            Self::PowerSum(p) => Some((4, p as f32)),
        }
    }

    /// The distance of a key.
    pub fn distance(self, key: f64) -> f64 {
        match self {
            Self::Metric(m) => m.distance_of_key(key),
            Self::PowerSum(p) => key.max(0.0).powf(p.recip()),
        }
    }

    /// The power of two that maps the keys of every offset within Euclidean
    /// distance `reach` into the depth range [0, 1] (see `Metric::key_scale`).
    pub fn scale(self, reach: f64) -> f64 {
        match self {
            Self::Metric(m) => m.key_scale(reach),
            // Each coordinate is at most the reach.
            Self::PowerSum(p) => (2.0 * reach.powf(p)).log2().ceil().exp2().recip(),
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
            Self::Polygon(g) => write!(f, "polygon ({} vertices)", g.vertices.len()),
        }
    }
}

/// The Euclidean distance from `p` to the segment `a b` (a point where a = b).
pub(crate) fn segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let e = b - a;
    let t = if e == DVec2::ZERO {
        0.0
    } else {
        ((p - a).dot(e) / e.length_squared()).clamp(0.0, 1.0)
    };
    (p - a - e * t).length()
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
        // A polygon equal to the L1 diamond, listed clockwise around a shifted
        // kernel, measures like L1.
        let k = DVec2::new(5.0, 5.0);
        let diamond: Vec<DVec2> = [(0.0, 1.0), (1.0, 0.0), (0.0, -1.0), (-1.0, 0.0)]
            .iter()
            .map(|&(x, y)| k + DVec2::new(x, y))
            .collect();
        let m = Metric::polygon(&diamond, k).unwrap();
        for d in offsets {
            assert!(
                (m.distance(d) - Metric::L1.distance(d)).abs() < 1e-12,
                "{d}"
            );
        }
        let (a, b) = m.euclidean_bounds();
        assert!((a - 1.0).abs() < 1e-12 && (b - 2f64.sqrt()).abs() < 1e-12);
        assert!(m.is_convex());
        // Not star-shaped around the kernel: a clear error.
        let bent = [
            DVec2::new(1.0, 0.0),
            DVec2::new(-1.0, 1.0),
            DVec2::new(-1.0, -1.0),
            DVec2::new(-2.0, 0.0),
        ];
        assert!(Metric::polygon(&bent, DVec2::ZERO)
            .unwrap_err()
            .contains("star-shaped"));
        assert!(Metric::polygon(&diamond, DVec2::new(9.0, 9.0)).is_err());
        assert_eq!(Metric::LInf.distance(DVec2::new(3.0, -4.0)), 4.0);
    }
}
