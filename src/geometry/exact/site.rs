//! Exact weighted distances from a pixel's centre to sites beyond points, for
//! the near ties that float bounds cannot order (`algorithms::voronoi::sites::certify`).
//!
//! Everything is measured in the picture's pixels, from the user's doubles: a
//! site's pixel coordinates are `(x - origin) s - 1/2` and a pixel's centre its
//! integer index. Distances under L1, L2 and L∞ to points, segments and whole
//! circles are [`Surd`]s, as are segments' under a polygon's gauge (rational:
//! the gauge is linear between the rays through its corners), and arcs' where
//! the nearest point is clearly inside the arc. An arc's ends lie at angles,
//! transcendental points, and L_p distances to segments and curves have no
//! closed form: those are not decided here.

use std::cmp::Ordering;

use glam::DVec2;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{ToPrimitive, Zero};

use super::precise::{cos_sin, Interval};
use super::surd::Surd;
use super::{exact_key, exact_order, rational};
use crate::geometry::metric::Metric;
use crate::geometry::site::{ArcWedge, Shape, Site};
use crate::geometry::Frame;

type Point = [BigRational; 2];

/// A frame's mapping to pixels in rationals.
pub(crate) struct ExactFrame {
    origin: Point,
    scale: BigRational,
    half: BigRational,
}

impl ExactFrame {
    pub fn new(frame: &Frame) -> Self {
        Self {
            origin: [rational(frame.origin.x), rational(frame.origin.y)],
            scale: rational(frame.scale),
            half: BigRational::new(1.into(), 2.into()),
        }
    }

    fn to_pixel(&self, p: DVec2) -> Point {
        let along = |x: f64, o: &BigRational| (rational(x) - o) * &self.scale - &self.half;
        [along(p.x, &self.origin[0]), along(p.y, &self.origin[1])]
    }

    /// The exact weighted distance (world units) from the centre of `pixel` to
    /// `site` under `metric`; `None` where it cannot be held (see the module).
    pub fn distance(&self, site: &Site, metric: Metric, pixel: [i64; 2]) -> Option<Distance> {
        let q = pixel.map(|i| BigRational::from_integer(BigInt::from(i)));
        let shape = match site.shape {
            Shape::Point(p) => point_distance(metric, &offset(&q, &self.to_pixel(p)))?.into(),
            Shape::Segment(a, b) => {
                segment_distance(metric, &q, &self.to_pixel(a), &self.to_pixel(b))?.into()
            }
            Shape::Circle { center, radius } => circle_distance(
                metric,
                &q,
                &self.to_pixel(center),
                rational(radius) * &self.scale,
            )?
            .into(),
            Shape::Arc {
                center,
                radius,
                start,
                end,
            } => arc_distance(
                metric,
                &q,
                &self.to_pixel(center),
                rational(radius) * &self.scale,
                &ArcWedge::new(DVec2::ZERO, radius, start, end),
                [start, end],
            )?,
        };
        let per_pixel = (&self.scale * rational(site.multiplicative)).recip();
        Some(shape.weighted(&per_pixel, &rational(site.additive)))
    }

    /// The exact order of two sites' weighted distances from `pixel`; `None`
    /// where it cannot be decided.
    pub fn order(&self, a: &Site, b: &Site, metric: Metric, pixel: [i64; 2]) -> Option<Ordering> {
        // Points of equal weights compare by their offsets under every metric.
        if let (Shape::Point(p), Shape::Point(r)) = (a.shape, b.shape) {
            if (a.multiplicative, a.additive) == (b.multiplicative, b.additive) {
                let q = pixel.map(|i| BigRational::from_integer(BigInt::from(i)));
                let (da, db) = (offset(&q, &self.to_pixel(p)), offset(&q, &self.to_pixel(r)));
                return exact_order(metric, &da, &db);
            }
        }
        self.distance(a, metric, pixel)?
            .cmp(&self.distance(b, metric, pixel)?)
    }
}

/// An exact weighted distance: the least of an exact candidate and of arc
/// ends at transcendental points (those not clearly farther).
#[derive(Clone, Debug)]
pub(crate) struct Distance {
    exact: Option<Surd>,
    ends: Vec<ArcEnd>,
}

/// An arc's end at a double `angle` other than 0: `k d + c` for the distance
/// d under `metric` from `offset` (the pixel less the arc's centre) to the
/// circle's point at that angle.
#[derive(Clone, Debug, PartialEq)]
struct ArcEnd {
    offset: Point,
    radius: BigRational,
    angle: f64,
    metric: Metric,
    k: BigRational,
    c: BigRational,
}

impl From<Surd> for Distance {
    fn from(s: Surd) -> Self {
        Self {
            exact: Some(s),
            ends: Vec::new(),
        }
    }
}

/// Precisions (bits) at which transcendental distances are tried.
const PRECISIONS: [u64; 5] = [64, 128, 256, 512, 1024];

impl Distance {
    #[expect(clippy::disallowed_methods, reason = "one site's arc ends")]
    fn weighted(self, k: &BigRational, c: &BigRational) -> Self {
        Self {
            exact: self.exact.map(|s| s.affine(k, c)),
            ends: self
                .ends
                .into_iter()
                .map(|e| ArcEnd {
                    k: &e.k * k,
                    c: &e.c * k + c,
                    ..e
                })
                .collect(),
        }
    }

    /// An interval holding it, to about 2^-bits of its size.
    fn interval(&self, bits: u64) -> Option<Interval> {
        let exact = self.exact.iter().map(|s| Some(s.interval(bits)));
        let ends = self.ends.iter().map(|e| e.interval(bits));
        exact.chain(ends).reduce(|a, b| Some(a?.min(b?)))?
    }

    /// The exact order; `None` where transcendental ends agree to 1024 bits
    /// without being the same ends.
    fn cmp(&self, other: &Self) -> Option<Ordering> {
        if self.ends.is_empty() && other.ends.is_empty() {
            return Some(self.exact.as_ref()?.cmp(other.exact.as_ref()?));
        }
        let same_exact = match (&self.exact, &other.exact) {
            (None, None) => true,
            (Some(a), Some(b)) => a.cmp(b) == Ordering::Equal,
            _ => false,
        };
        if same_exact && self.ends == other.ends {
            return Some(Ordering::Equal);
        }
        for bits in PRECISIONS {
            let (a, b) = (self.interval(bits)?, other.interval(bits)?);
            if a.hi < b.lo {
                return Some(Ordering::Less);
            }
            if b.hi < a.lo {
                return Some(Ordering::Greater);
            }
        }
        None
    }

    /// Its value to within a few ulps.
    #[cfg(test)]
    pub fn approximate(&self) -> f64 {
        let i = self.interval(64).expect("an interval");
        ((i.lo + i.hi) / BigRational::from_integer(2.into()))
            .to_f64()
            .unwrap_or(f64::NAN)
    }
}

impl ArcEnd {
    fn interval(&self, bits: u64) -> Option<Interval> {
        let (cos, sin) = cos_sin(self.angle, bits + 8)?;
        let zero = BigRational::zero();
        let along =
            |t: &Interval, o: &BigRational| t.affine(&self.radius, &zero).subtracted_from(o).abs();
        let (x, y) = (along(&cos, &self.offset[0]), along(&sin, &self.offset[1]));
        let d = match self.metric {
            Metric::L1 => x.plus(&y),
            Metric::LInf => x.max(y),
            _ => x.square().plus(&y.square()).sqrt_of(bits + 8),
        };
        Some(d.affine(&self.k, &self.c))
    }
}

fn offset(q: &Point, p: &Point) -> Point {
    [&q[0] - &p[0], &q[1] - &p[1]]
}

fn cross(a: &Point, b: &Point) -> BigRational {
    &a[0] * &b[1] - &a[1] * &b[0]
}

fn dot(a: &Point, b: &Point) -> BigRational {
    &a[0] * &b[0] + &a[1] * &b[1]
}

/// The distance of offset `d`: a root for L2, the key itself for the metrics
/// whose key is their distance.
fn point_distance(metric: Metric, d: &Point) -> Option<Surd> {
    match metric {
        Metric::L2 => Some(Surd::new(
            BigRational::zero(),
            BigRational::from_integer(1.into()),
            dot(d, d),
        )),
        Metric::L1 | Metric::LInf | Metric::Polygon(_) => {
            Some(Surd::rational(exact_key(metric, d)?))
        }
        Metric::Lp(_) => None,
    }
}

/// The distance from `q` to segment `a b`. Under L2 by projection; under L1,
/// L∞ and a polygon's gauge the distance is linear between the parameters
/// where the offset crosses a ray through a corner of the unit ball, so the
/// smallest is at an end or at one of those.
#[expect(clippy::disallowed_methods, reason = "one polyline's vertices")]
fn segment_distance(metric: Metric, q: &Point, a: &Point, b: &Point) -> Option<Surd> {
    let e = offset(b, a);
    let o = offset(q, a);
    let length2 = dot(&e, &e);
    if length2.is_zero() {
        return point_distance(metric, &o);
    }
    if metric == Metric::L2 {
        let along = dot(&o, &e);
        if along <= BigRational::zero() {
            return point_distance(metric, &o);
        }
        if along >= length2 {
            return point_distance(metric, &offset(q, b));
        }
        let c = cross(&o, &e);
        return Some(Surd::new(
            BigRational::zero(),
            BigRational::from_integer(1.into()),
            &c * &c / length2,
        ));
    }
    let rays: Vec<Point> = match metric {
        Metric::L1 => Vec::from([unit(1, 0), unit(0, 1)]),
        Metric::LInf => Vec::from([unit(1, 1), unit(1, -1)]),
        Metric::Polygon(g) => g
            .vertices
            .iter()
            .map(|v| [rational(v.x), rational(v.y)])
            .collect(),
        _ => return None,
    };
    let one = BigRational::from_integer(1.into());
    let zero = BigRational::zero();
    let mut cuts = Vec::from([zero.clone(), one.clone()]);
    for v in &rays {
        // v × (o - t e) = 0.
        let den = cross(v, &e);
        if !den.is_zero() {
            let t = cross(v, &o) / den;
            if t > zero && t < one {
                cuts.push(t);
            }
        }
    }
    cuts.iter()
        .map(|t| {
            let d = [&o[0] - t * &e[0], &o[1] - t * &e[1]];
            exact_key(metric, &d).map(Surd::rational)
        })
        .reduce(|x, y| Some(x?.min(y?)))?
}

fn unit(x: i64, y: i64) -> Point {
    [
        BigRational::from_integer(x.into()),
        BigRational::from_integer(y.into()),
    ]
}

/// The distance from `q` to the circle around `c` of radius `r`: the least of
/// [`circle_candidates`].
fn circle_distance(metric: Metric, q: &Point, c: &Point, r: BigRational) -> Option<Surd> {
    circle_candidates(metric, q, c, r)?
        .into_iter()
        .map(|(d, _)| d)
        .reduce(Surd::min)
}

/// The distance from `q` to the arc of the circle around `c` of radius `r`
/// whose angles `wedge` holds. An end at angle 0 is the rational point
/// c + (r, 0); an end at any other angle (a double) is transcendental, which
/// no exact number here holds: the distance is decided where every candidate
/// lies clearly inside or outside the wedge (or on an end at angle 0) and
/// the nearest is clearly nearer than the transcendental ends; `None`
/// otherwise.
#[expect(clippy::disallowed_methods, reason = "one arc's ends")]
fn arc_distance(
    metric: Metric,
    q: &Point,
    c: &Point,
    r: BigRational,
    wedge: &ArcWedge,
    angles: [f64; 2],
) -> Option<Distance> {
    let e = approximate(&offset(q, c));
    if metric == Metric::L2 && e == DVec2::ZERO {
        // Every point of the arc is r away from its centre.
        return Some(Surd::rational(r).into());
    }
    let radius = r.to_f64()?;
    let mut best: Option<Surd> = None;
    let mut offer = |d: Surd| best = Some(best.take().map_or(d.clone(), |b| b.min(d)));
    for (d, at) in circle_candidates(metric, q, c, r.clone())? {
        let near = DVec2::new(at[0].approximate(), at[1].approximate());
        let on = match wedge.holds(near) {
            Some(on) => on,
            None => holds_precisely(&at, angles[0], angles[1], angles[1] - angles[0])?,
        };
        if on {
            offer(d);
        }
    }
    let mut far = Vec::new();
    if !wedge.is_whole() {
        for ((end, exact), angle) in wedge.ends().into_iter().zip(angles) {
            if exact {
                let at = [&c[0] + &r, c[1].clone()];
                offer(point_distance(metric, &offset(q, &at))?);
            } else {
                far.push((metric.distance(e - radius * end), angle));
            }
        }
    }
    // The transcendental ends that are not clearly farther than the best.
    let slack = 1e-12 * (e.length() + radius);
    let ends = far
        .into_iter()
        .filter(|(d, _)| {
            best.as_ref()
                .is_none_or(|b| *d - slack <= b.approximate() + slack)
        })
        .map(|(_, angle)| ArcEnd {
            offset: offset(q, c),
            radius: r.clone(),
            angle,
            metric,
            k: BigRational::from_integer(1.into()),
            c: BigRational::zero(),
        })
        .collect();
    Some(Distance { exact: best, ends })
}

fn approximate(p: &Point) -> DVec2 {
    DVec2::new(
        p[0].to_f64().unwrap_or(f64::NAN),
        p[1].to_f64().unwrap_or(f64::NAN),
    )
}

/// Every point of the circle around `c` of radius `r` where the distance
/// from `q` may be least, with that distance and the point's offset from the
/// centre (or a positive multiple of it). Under L2 the point along the ray
/// from the centre, at |√(|q - c|²) - r|. Under L1 and L∞ the points where
/// the offset lies along a corner ray of the unit ball (where a line through
/// q meets the circle, a root of a quadratic) and where a side of the ball
/// touches the circle (at its normals' angles).
fn circle_candidates(
    metric: Metric,
    q: &Point,
    c: &Point,
    r: BigRational,
) -> Option<Vec<(Surd, [Surd; 2])>> {
    let e = offset(q, c);
    let a2 = dot(&e, &e);
    let r2 = &r * &r;
    let zero = BigRational::zero();
    let one = BigRational::from_integer(1.into());
    let half = BigRational::new(1.into(), 2.into());
    let integer = |k: i64| BigRational::from_integer(k.into());
    let rational = |k: i64| Surd::rational(integer(k));
    let mut out = Vec::new();
    match metric {
        Metric::L2 => {
            let along = match a2.is_zero() {
                true => [rational(1), rational(0)],
                false => e.clone().map(Surd::rational),
            };
            out.push((Surd::new(-r, one, a2).abs(), along));
        }
        Metric::L1 => {
            // Where the line through q along axis 1 - k meets the circle, the
            // offset is e_m ∓ √(r² - e_k²) along it.
            for k in 0..2 {
                let rest = &r2 - &e[k] * &e[k];
                if rest >= zero {
                    for sign in [1, -1] {
                        let root = Surd::new(zero.clone(), integer(sign), rest.clone());
                        let mut at = [Surd::rational(e[0].clone()), Surd::rational(e[1].clone())];
                        at[1 - k] = root;
                        let d = Surd::new(e[1 - k].clone(), integer(-sign), rest.clone());
                        out.push((d.abs(), at));
                    }
                }
            }
            // The points r (σx, σy) / √2: offsets e - σ √(r² / 2).
            let h = &r2 * &half;
            for sx in [1, -1] {
                for sy in [1, -1] {
                    let x = Surd::new(e[0].clone(), integer(-sx), h.clone());
                    let y = Surd::new(e[1].clone(), integer(-sy), h.clone());
                    out.push((x.abs().plus(y.abs())?, [rational(sx), rational(sy)]));
                }
            }
        }
        Metric::LInf => {
            // The points e - t (1, σ): 2t² - 2Bt + (|e|² - r²) = 0 with
            // B = e_x + σ e_y, t = (B ± √D) / 2, D = B² - 2(|e|² - r²); the
            // L∞ distance is |t|.
            for sigma in [1, -1] {
                let b = &e[0] + integer(sigma) * &e[1];
                let d = &b * &b - integer(2) * (&a2 - &r2);
                if d >= zero {
                    for sign in [1, -1] {
                        let u = &half * integer(sign);
                        let t = Surd::new(&b * &half, u.clone(), d.clone());
                        let x = Surd::new(&e[0] - &b * &half, -u.clone(), d.clone());
                        let y = Surd::new(
                            &e[1] - integer(sigma) * &b * &half,
                            -u * integer(sigma),
                            d.clone(),
                        );
                        out.push((t.abs(), [x, y]));
                    }
                }
            }
            // The points (±r, 0) and (0, ±r).
            for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                let p = [&c[0] + &r * integer(dx), &c[1] + &r * integer(dy)];
                let d = Surd::rational(exact_key(metric, &offset(q, &p))?);
                out.push((d, [rational(dx), rational(dy)]));
            }
        }
        Metric::Lp(_) | Metric::Polygon(_) => return None,
    }
    Some(out)
}

/// Whether direction `v` lies on the arc from angle `start` to `end`
/// (`span` apart), its sides against the ends decided exactly at an end at
/// angle 0 and else by intervals of the ends' cosines and sines: a direction
/// of surds is never parallel to one at another double angle.
fn holds_precisely(v: &[Surd; 2], start: f64, end: f64, span: f64) -> Option<bool> {
    // After the start: start × v >= 0; before the end: v × end >= 0.
    let side = |angle: f64, after: bool| -> Option<bool> {
        let flip = |o: Ordering| if after { o } else { o.reverse() };
        if angle == 0.0 {
            return Some(flip(v[1].sign()) != Ordering::Less);
        }
        // The end's direction × v, whose sign is the side's (flipped for the
        // end).
        for bits in PRECISIONS {
            let (cos, sin) = cos_sin(angle, bits)?;
            let (x, y) = (v[0].interval(bits), v[1].interval(bits));
            let cross = cos.times(&y).minus(&sin.times(&x));
            let zero = BigRational::zero();
            if cross.lo > zero || cross.hi < zero {
                let sign = if cross.lo > zero {
                    Ordering::Greater
                } else {
                    Ordering::Less
                };
                return Some(flip(sign) == Ordering::Greater);
            }
        }
        None
    };
    let (after_start, before_end) = (side(start, true)?, side(end, false)?);
    Some(match span <= std::f64::consts::PI {
        true => after_start && before_end,
        false => after_start || before_end,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn exact_distances_agree_with_the_float_ones() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let frame = Frame::pixels(40, 30).unwrap();
        let exact = ExactFrame::new(&frame);
        let triangle = [
            DVec2::new(2.0, 0.0),
            DVec2::new(-1.0, 1.5),
            DVec2::new(-0.5, -1.0),
        ];
        let polygon = Metric::polygon(&triangle, DVec2::ZERO).unwrap();
        let p =
            |rng: &mut ChaCha8Rng| DVec2::new(rng.gen_range(-5.0..45.0), rng.gen_range(-5.0..35.0));
        for _ in 0..400 {
            let shapes = [
                Shape::Point(p(&mut rng)),
                Shape::Segment(p(&mut rng), p(&mut rng)),
                Shape::Circle {
                    center: p(&mut rng),
                    radius: rng.gen_range(0.0..20.0),
                },
            ];
            let pixel = [rng.gen_range(0..40), rng.gen_range(0..30)];
            let q = frame.to_world(DVec2::new(pixel[0] as f64, pixel[1] as f64));
            for (k, shape) in shapes.into_iter().enumerate() {
                let site = Site {
                    shape,
                    multiplicative: rng.gen_range(0.5..3.0),
                    additive: rng.gen_range(-2.0..2.0),
                };
                for metric in [Metric::L2, Metric::L1, Metric::LInf, polygon] {
                    let Some(d) = exact.distance(&site, metric, pixel) else {
                        assert!(k == 2 && matches!(metric, Metric::Polygon(_)));
                        continue;
                    };
                    let float = site.distance(metric, q);
                    assert!(
                        (d.approximate() - float).abs() <= 1e-9 * (1.0 + float.abs()),
                        "{shape:?} {metric}: exact {} float {float}",
                        d.approximate()
                    );
                }
            }
        }
    }
}
