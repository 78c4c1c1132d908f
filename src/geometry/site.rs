//! Sites beyond points (thesis §3.8–3.9): segments, circles and circular arcs,
//! each with a multiplicative and an additive weight. A site's weighted distance
//! from q is `dist(q, site) / m + a`, where `dist` is the metric's distance to the
//! nearest point of the site.
//!
//! Every shape works with every metric: the distance to a segment is the smallest
//! norm on the segment of offsets (`super::chain::norm_range_on_segment`); to a
//! circle or arc it is closed-form for L2, the least of a few candidates under
//! L1 and L∞ (`polygonal_curve_distance`), and found by `curve_distance`
//! otherwise. Circles and arcs are
//! Euclidean circles whatever the metric.

use std::f64::consts::TAU;

use glam::DVec2;

use super::{chain::norm_range_on_segment, metric::segment_distance, metric::Metric};
use crate::error::{Error, Result};

/// The geometric part of a site, in world coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    Point(DVec2),
    Segment(DVec2, DVec2),
    Circle {
        center: DVec2,
        radius: f64,
    },
    /// The arc of the circle counter-clockwise from angle `start` to `end`
    /// (radians); a span of 2π or more is the whole circle.
    Arc {
        center: DVec2,
        radius: f64,
        start: f64,
        end: f64,
    },
}

/// The sites a problem takes: plain points, or general sites (segments,
/// circles, arcs, weights). Problems that take both take either through
/// `impl Into<Sites>`, so `&[DVec2]`, `&Vec<Site>` and arrays of either pass
/// as they are.
#[derive(Clone, Copy, Debug)]
pub enum Sites<'a> {
    Points(&'a [DVec2]),
    General(&'a [Site]),
}

macro_rules! sites_from {
    ($item:ty, $variant:ident) => {
        impl<'a> From<&'a [$item]> for Sites<'a> {
            fn from(sites: &'a [$item]) -> Self {
                Self::$variant(sites)
            }
        }
        impl<'a> From<&'a Vec<$item>> for Sites<'a> {
            fn from(sites: &'a Vec<$item>) -> Self {
                Self::$variant(sites)
            }
        }
        impl<'a, const N: usize> From<&'a [$item; N]> for Sites<'a> {
            fn from(sites: &'a [$item; N]) -> Self {
                Self::$variant(sites)
            }
        }
    };
}
sites_from!(DVec2, Points);
sites_from!(Site, General);

/// A site: a shape with its weights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Site {
    pub shape: Shape,
    /// Multiplicative weight m > 0: distances are divided by it (a steeper or
    /// flatter cone, thesis §3.8).
    pub multiplicative: f64,
    /// Additive weight a: added to distances (a raised apex).
    pub additive: f64,
}

impl Site {
    /// The site scaled by 2^k about the origin: its distances, and so its
    /// additive weight, scale with it (exact where the results are normal).
    pub fn scaled(self, k: i32) -> Self {
        let t = |x: f64| crate::geometry::scale::times_power_of_two(x, k);
        Self {
            additive: t(self.additive),
            ..self.mapped(|p| DVec2::new(t(p.x), t(p.y)), t)
        }
    }

    /// The site moved by `-by`, weights kept.
    pub fn moved_back(self, by: DVec2) -> Self {
        self.mapped(|p| p - by, |r| r)
    }

    /// The points of the shape through `point`, its radius through `length`.
    fn mapped(self, point: impl Fn(DVec2) -> DVec2, length: impl Fn(f64) -> f64) -> Self {
        let shape = match self.shape {
            Shape::Point(p) => Shape::Point(point(p)),
            Shape::Segment(a, b) => Shape::Segment(point(a), point(b)),
            Shape::Circle { center, radius } => Shape::Circle {
                center: point(center),
                radius: length(radius),
            },
            Shape::Arc {
                center,
                radius,
                start,
                end,
            } => Shape::Arc {
                center: point(center),
                radius: length(radius),
                start,
                end,
            },
        };
        Self { shape, ..self }
    }

    /// The points that place the shape: a point, a segment's ends, a
    /// circle's or arc's centre.
    pub fn anchors(&self) -> Vec<DVec2> {
        match self.shape {
            Shape::Point(p) => Vec::from([p]),
            Shape::Segment(a, b) => Vec::from([a, b]),
            Shape::Circle { center, .. } | Shape::Arc { center, .. } => Vec::from([center]),
        }
    }

    /// The site mirrored across the x axis (y to -y), weights kept. An arc
    /// keeps running counter-clockwise: from -end to -start.
    pub fn mirrored_y(self) -> Self {
        let mut site = self.mapped(|p| DVec2::new(p.x, -p.y), |r| r);
        if let Shape::Arc { start, end, .. } = &mut site.shape {
            (*start, *end) = (-*end, -*start);
        }
        site
    }

    /// An unweighted site.
    pub fn new(shape: Shape) -> Self {
        Self {
            shape,
            multiplicative: 1.0,
            additive: 0.0,
        }
    }

    /// An unweighted point.
    pub fn point(p: DVec2) -> Self {
        Self::new(Shape::Point(p))
    }

    /// Whether the site is an unweighted point, which the point machinery draws.
    pub fn is_plain_point(&self) -> bool {
        matches!(self.shape, Shape::Point(_)) && self.multiplicative == 1.0 && self.additive == 0.0
    }

    /// The `metric` distance from `q` to the nearest point of the shape.
    pub fn distance_to_shape(&self, metric: Metric, q: DVec2) -> f64 {
        match self.shape {
            Shape::Point(p) => metric.distance(q - p),
            Shape::Segment(a, b) if metric == Metric::L2 => segment_distance(q, a, b),
            Shape::Segment(a, b) => norm_range_on_segment(metric, q - a, q - b).0,
            Shape::Circle { center, radius } if piecewise_linear(metric) => {
                polygonal_curve_distance(metric, q - center, radius, None)
            }
            Shape::Arc {
                center,
                radius,
                start,
                end,
            } if piecewise_linear(metric) => {
                let wedge = ArcWedge::new(center, radius, start, end);
                polygonal_curve_distance(metric, q - center, radius, Some(&wedge))
            }
            Shape::Circle { center, radius } if metric != Metric::L2 => {
                curve_distance(metric, q, center, radius, 0.0, TAU)
            }
            Shape::Arc {
                center,
                radius,
                start,
                end,
            } if metric != Metric::L2 => {
                curve_distance(metric, q, center, radius, start, (end - start).min(TAU))
            }
            Shape::Circle { center, radius } => ((q - center).length() - radius).abs(),
            Shape::Arc {
                center,
                radius,
                start,
                end,
            } => {
                let d = q - center;
                if on_arc(d.y.atan2(d.x), start, end) || d == DVec2::ZERO {
                    (d.length() - radius).abs()
                } else {
                    let at = |a: f64| center + radius * DVec2::new(a.cos(), a.sin());
                    (q - at(start)).length().min((q - at(end)).length())
                }
            }
        }
    }

    /// The weighted distance from `q`: `dist / m + a`.
    pub fn distance(&self, metric: Metric, q: DVec2) -> f64 {
        self.distance_to_shape(metric, q) / self.multiplicative + self.additive
    }

    /// The site in pixel coordinates of a frame that maps world point `w` to
    /// `(w - origin) * scale - 0.5`; weights stay in world units.
    pub fn to_pixels(&self, mut to_pixel: impl FnMut(DVec2) -> DVec2, scale: f64) -> Self {
        let shape = match self.shape {
            Shape::Point(p) => Shape::Point(to_pixel(p)),
            Shape::Segment(a, b) => Shape::Segment(to_pixel(a), to_pixel(b)),
            Shape::Circle { center, radius } => Shape::Circle {
                center: to_pixel(center),
                radius: radius * scale,
            },
            Shape::Arc {
                center,
                radius,
                start,
                end,
            } => Shape::Arc {
                center: to_pixel(center),
                radius: radius * scale,
                start,
                end,
            },
        };
        Self { shape, ..*self }
    }

    /// An arc's wedge, made once for many distance queries.
    pub(crate) fn wedge(&self) -> Option<ArcWedge> {
        match self.shape {
            Shape::Arc {
                center,
                radius,
                start,
                end,
            } => Some(ArcWedge::new(center, radius, start, end)),
            _ => None,
        }
    }

    /// The smallest box holding the shape: (lo, hi).
    pub fn bounds(&self) -> (DVec2, DVec2) {
        match self.shape {
            Shape::Point(p) => (p, p),
            Shape::Segment(a, b) => (a.min(b), a.max(b)),
            Shape::Circle { center, radius } | Shape::Arc { center, radius, .. } => {
                (center - radius, center + radius)
            }
        }
    }
}

/// Samples of a curve distance per full turn, brackets refined, and golden-section
/// steps per bracket.
const CURVE_SAMPLES: usize = 64;
const CURVE_BRACKETS: usize = 4;
const CURVE_REFINEMENTS: usize = 40;

/// The `metric` distance from `q` to the arc of the circle around `center` from
/// angle `start` over `span` (L_p and polygons; L1 and L∞ take
/// [`polygonal_curve_distance`]): the smallest of samples at equal angles, the
/// four best refined by golden-section search between their neighbours. Along the circle
/// a norm's distance has a valley on each side of `q`; star-shaped balls
/// (p < 1, star polygons) may add valleys at their spikes, which the extra
/// brackets cover. The tests compare it with dense sampling.
#[expect(clippy::disallowed_methods, reason = "one curve's samples")]
pub(crate) fn curve_distance(
    metric: Metric,
    q: DVec2,
    center: DVec2,
    radius: f64,
    start: f64,
    span: f64,
) -> f64 {
    let at = |a: f64| metric.distance(q - center - radius * DVec2::new(a.cos(), a.sin()));
    if radius == 0.0 || span <= 0.0 {
        return at(start);
    }
    let on_arc = |a: &f64| (a - start).rem_euclid(TAU) <= span;
    let cusps = ray_crossings(metric, q - center, radius);
    let n = ((CURVE_SAMPLES as f64 * span / TAU).ceil() as usize).max(2);
    let step = span / n as f64;
    let samples: Vec<f64> = (0..=n).map(|k| at(start + step * k as f64)).collect();
    let mut order: Vec<usize> = (0..=n).collect();
    order.sort_by(|&i, &j| samples[i].total_cmp(&samples[j]));
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let mut best = samples[order[0]];
    // Cusps: where the offset to the curve lies along a ray through a corner of
    // the unit ball (the axes for p < 1, where the valleys are too narrow for any
    // sampling).
    for a in cusps.into_iter().filter(on_arc) {
        best = best.min(at(a));
    }
    for &k in order.iter().take(CURVE_BRACKETS) {
        let mut lo = start + step * (k as f64 - 1.0).max(0.0);
        let mut hi = start + step * (k as f64 + 1.0).min(n as f64);
        for _ in 0..CURVE_REFINEMENTS {
            let (m1, m2) = (hi - g * (hi - lo), lo + g * (hi - lo));
            if at(m1) <= at(m2) {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        best = best.min(at(0.5 * (lo + hi)));
    }
    best
}

fn piecewise_linear(metric: Metric) -> bool {
    matches!(metric, Metric::L1 | Metric::LInf)
}

/// The L1 or L∞ distance from offset `e` (from the centre) to the circle of
/// `radius`, or to the arc of it that `wedge` holds, without angles: the
/// smallest over the circle's points where the offset lies along a corner
/// ray of the unit ball (where a line through the pixel meets the circle),
/// where a side of the ball touches the circle (its normals' directions), and
/// the arc's ends. Each candidate is computed stably (products of sums for the
/// differences of squares), so its error is a few ulps of the sizes involved;
/// `geometry::exact::site` computes the same candidates exactly.
pub(crate) fn polygonal_curve_distance(
    metric: Metric,
    e: DVec2,
    radius: f64,
    wedge: Option<&ArcWedge>,
) -> f64 {
    let r = radius;
    let mut best = f64::INFINITY;
    let mut offer = |on_circle: DVec2, distance: f64| {
        if wedge.is_none_or(|w| w.contains(on_circle)) {
            best = best.min(distance);
        }
    };
    match metric {
        Metric::L1 => {
            // On the line through the pixel along axis m: the other coordinate
            // equal to the pixel's.
            for k in 0..2 {
                let rest = (r - e[k].abs()) * (r + e[k].abs());
                if rest >= 0.0 {
                    let root = rest.sqrt();
                    for sign in [1.0, -1.0] {
                        let mut p = DVec2::ZERO;
                        p[k] = e[k];
                        p[1 - k] = sign * root;
                        offer(p, (e[1 - k] - p[1 - k]).abs());
                    }
                }
            }
            let h = r * std::f64::consts::FRAC_1_SQRT_2;
            for p in [(h, h), (h, -h), (-h, h), (-h, -h)] {
                let p = DVec2::from(p);
                offer(p, metric.distance(e - p));
            }
        }
        _ => {
            // Points e - t (1, σ): t = (B ± √D) / 2 with B = e_x + σ e_y and
            // D = 2r² - (e_x - σ e_y)².
            for sigma in [1.0, -1.0] {
                let b = e.x + sigma * e.y;
                let w = (e.x - sigma * e.y).abs();
                let r2 = r * std::f64::consts::SQRT_2;
                let d = (r2 - w) * (r2 + w);
                if d >= 0.0 {
                    for sign in [1.0, -1.0] {
                        let t = (b + sign * d.sqrt()) / 2.0;
                        offer(e - t * DVec2::new(1.0, sigma), t.abs());
                    }
                }
            }
            for p in [(r, 0.0), (-r, 0.0), (0.0, r), (0.0, -r)] {
                let p = DVec2::from(p);
                offer(p, metric.distance(e - p));
            }
        }
    }
    if let Some(w) = wedge.filter(|w| w.span < TAU) {
        for end in [w.start, w.end] {
            best = best.min(metric.distance(e - r * end));
        }
    }
    best
}

/// The rays along which the metric's distance has a kink: the corners of L1,
/// L∞ and polygon balls, and the axes for p < 1.
pub(crate) fn kink_rays(metric: Metric) -> Vec<DVec2> {
    match metric {
        Metric::L1 => Vec::from([DVec2::X, DVec2::Y]),
        Metric::Lp(p) if p < 1.0 => Vec::from([DVec2::X, DVec2::Y]),
        Metric::LInf => Vec::from([DVec2::ONE, DVec2::new(1.0, -1.0)]),
        Metric::Polygon(g) => g.vertices.clone(),
        _ => Vec::new(),
    }
}

/// The angles a at which the offset `d - radius (cos a, sin a)` from a circle
/// point lies on the line of a kink ray.
pub fn ray_crossings(metric: Metric, d: DVec2, radius: f64) -> Vec<f64> {
    let mut out = Vec::new();
    for v in kink_rays(metric) {
        // v × (d − r u(a)) = 0  ⇔  |v| sin(a − φ) = (v × d) / r.
        let s = v.perp_dot(d) / (radius * v.length());
        if s.abs() <= 1.0 {
            let phi = v.y.atan2(v.x);
            out.extend([phi + s.asin(), phi + std::f64::consts::PI - s.asin()]);
        }
    }
    out
}

/// A Euclidean arc made ready for many distance queries: the directions of its
/// ends, so that the side of each that a query lies on tells whether it faces the
/// arc, with no angle per query (as `glsl/site_distance.glsl` does).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcWedge {
    center: DVec2,
    radius: f64,
    span: f64,
    start: DVec2,
    end: DVec2,
}

impl ArcWedge {
    pub fn new(center: DVec2, radius: f64, start: f64, end: f64) -> Self {
        let direction = |a: f64| DVec2::new(a.cos(), a.sin());
        Self {
            center,
            radius,
            span: end - start,
            start: direction(start),
            end: direction(end),
        }
    }

    /// Whether direction `v` (from the centre) lies within the arc's angles.
    pub fn contains(&self, v: DVec2) -> bool {
        let after_start = self.start.perp_dot(v) >= 0.0;
        let before_end = v.perp_dot(self.end) >= 0.0;
        // Both sides for a span up to a half turn, either beyond.
        self.span >= TAU
            || if self.span <= std::f64::consts::PI {
                after_start && before_end
            } else {
                after_start || before_end
            }
    }

    /// Whether direction `v` lies within the arc's angles, where the sides of
    /// its ends are clear by far more than their rounding; `None` where not.
    pub(crate) fn holds(&self, v: DVec2) -> Option<bool> {
        let margin = 1e-12 * v.length();
        // On an end's ray counts as on the arc where that end is exact (angle
        // 0, direction (1, 0)) and the side is exactly 0.
        let side = |s: f64, exact: bool| match s.abs() > margin {
            true => Some(s > 0.0),
            false => (exact && s == 0.0).then_some(true),
        };
        if self.span >= TAU {
            return Some(true);
        }
        let after_start = side(self.start.perp_dot(v), self.start == DVec2::X)?;
        let before_end = side(v.perp_dot(self.end), self.end == DVec2::X)?;
        Some(if self.span <= std::f64::consts::PI {
            after_start && before_end
        } else {
            after_start || before_end
        })
    }

    /// Whether the arc is the whole circle.
    pub(crate) fn is_whole(&self) -> bool {
        self.span >= TAU
    }

    /// The directions of its ends, each with whether it is exact: the end
    /// at angle 0, (1, 0); every other double angle's point is transcendental.
    pub(crate) fn ends(&self) -> [(DVec2, bool); 2] {
        [self.start, self.end].map(|d| (d, d == DVec2::X))
    }

    /// The Euclidean distance from `q` to the arc.
    pub fn distance(&self, q: DVec2) -> f64 {
        let v = q - self.center;
        if self.contains(v) || v == DVec2::ZERO {
            (v.length() - self.radius).abs()
        } else {
            let r = self.radius;
            (v - r * self.start)
                .length()
                .min((v - r * self.end).length())
        }
    }
}

/// Whether the direction of angle `angle` lies on the arc from `start`
/// counter-clockwise to `end`.
pub(crate) fn on_arc(angle: f64, start: f64, end: f64) -> bool {
    let span = end - start;
    if span >= TAU {
        return true;
    }
    (angle - start).rem_euclid(TAU) <= span.rem_euclid(TAU)
}

/// Checks a site list: not empty, finite, weights m > 0, radii >= 0, arcs that
/// end after they start.
pub(crate) fn check_general_sites(sites: &[Site]) -> Result<()> {
    if sites.is_empty() {
        return Err(Error::too_few(1, 0, "the site list is empty".into()));
    }
    if sites.len() >= u32::MAX as usize {
        return Err(Error::out_of_range(format!(
            "{} sites: ids must fit below u32::MAX",
            sites.len()
        )));
    }
    for (i, s) in sites.iter().enumerate() {
        let bad = |what: &str| Err(Error::malformed(format!("site {i}: {what}")));
        let numbers: Vec<f64> = match s.shape {
            Shape::Point(p) => Vec::from([p.x, p.y]),
            Shape::Segment(a, b) => Vec::from([a.x, a.y, b.x, b.y]),
            Shape::Circle { center, radius } => Vec::from([center.x, center.y, radius]),
            Shape::Arc {
                center,
                radius,
                start,
                end,
            } => Vec::from([center.x, center.y, radius, start, end]),
        };
        if numbers
            .iter()
            .chain([&s.multiplicative, &s.additive])
            .any(|v| !v.is_finite())
        {
            return bad("has a non-finite coordinate or weight");
        }
        if s.multiplicative <= 0.0 {
            return bad(&format!(
                "multiplicative weight {} must be positive",
                s.multiplicative
            ));
        }
        match s.shape {
            Shape::Circle { radius, .. } | Shape::Arc { radius, .. } if radius < 0.0 => {
                return bad(&format!("radius {radius} is negative"));
            }
            Shape::Arc { start, end, .. } if end < start => {
                return bad(&format!("arc end {end} is before its start {start}"));
            }
            _ => {}
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arc_wedges_measure_as_the_definition() {
        // Spans from none to more than a full turn, starts all around, queries
        // near and far, on the ends' rays and at the centre.
        let center = DVec2::new(1.5, -2.0);
        for s in 0..12 {
            let start = -7.0 + 1.3 * s as f64;
            for span in [
                0.0,
                0.4,
                1.5,
                3.0,
                std::f64::consts::PI,
                3.3,
                5.0,
                TAU - 1e-9,
                TAU,
                7.5,
            ] {
                let end = start + span;
                let radius = 3.0;
                let wedge = ArcWedge::new(center, radius, start, end);
                let arc = Site::new(Shape::Arc {
                    center,
                    radius,
                    start,
                    end,
                });
                let mut queries = vec![center];
                for k in 0..40 {
                    let a = 0.17 * k as f64;
                    for r in [0.5, 2.9, 3.0, 4.0, 9.0] {
                        queries.push(center + r * DVec2::new(a.cos(), a.sin()));
                    }
                }
                for a in [start, end] {
                    queries.push(center + 5.0 * DVec2::new(a.cos(), a.sin()));
                }
                for q in queries {
                    let (fast, exact) = (wedge.distance(q), arc.distance(Metric::L2, q));
                    assert!(
                        (fast - exact).abs() <= 1e-9,
                        "start {start} span {span} at {q}: {fast} vs {exact}"
                    );
                }
            }
        }
    }

    #[test]
    fn distances_of_each_shape() {
        let q = DVec2::new(3.0, 4.0);
        let l2 = Metric::L2;
        assert_eq!(Site::point(DVec2::ZERO).distance(l2, q), 5.0);
        let seg = Site::new(Shape::Segment(DVec2::new(-1.0, 0.0), DVec2::new(10.0, 0.0)));
        assert!((seg.distance(l2, q) - 4.0).abs() < 1e-9);
        assert!((seg.distance(Metric::L1, DVec2::new(12.0, 1.0)) - 3.0).abs() < 1e-9);
        let circle = Site::new(Shape::Circle {
            center: DVec2::ZERO,
            radius: 2.0,
        });
        assert!((circle.distance(l2, q) - 3.0).abs() < 1e-12);
        // The upper half circle: q below it is nearest an end point.
        let arc = Site::new(Shape::Arc {
            center: DVec2::ZERO,
            radius: 2.0,
            start: 0.0,
            end: std::f64::consts::PI,
        });
        assert!((arc.distance(l2, q) - 3.0).abs() < 1e-12);
        let below = DVec2::new(0.0, -3.0);
        assert!((arc.distance(l2, below) - 13f64.sqrt()).abs() < 1e-12);
        let weighted = Site {
            multiplicative: 2.0,
            additive: 1.0,
            ..Site::point(DVec2::ZERO)
        };
        assert_eq!(weighted.distance(l2, q), 3.5);
    }

    #[test]
    fn bad_sites_are_named() {
        let mut s = Site::point(DVec2::ZERO);
        s.multiplicative = 0.0;
        assert!(check_general_sites(&[s])
            .unwrap_err()
            .to_string()
            .contains("site 0"));
        let c = Site::new(Shape::Circle {
            center: DVec2::ZERO,
            radius: 1.0,
        });
        assert!(check_general_sites(&[c]).is_ok());
        assert!(check_general_sites(&[]).is_err());
    }
}
