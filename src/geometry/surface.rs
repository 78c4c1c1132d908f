//! Fan surfaces of sites of any shape (thesis §3.9): the distance to a site is the
//! lower envelope of the cones standing on its points, so a segment's surface is
//! the cone at each end plus the quads its rulings sweep along the segment (the
//! thesis's roof and half-cones for L2, the Minkowski-sum sweep of Fig. 3.41 for
//! other metrics), and a circle or arc is the polyline of its chords swept the
//! same way (the straw hut and the sliced hut, with the end cones of an arc).
//!
//! Why the sweep is the envelope: along the segment's direction, the height of
//! the translated fan at a fixed point is piecewise linear in the translation; its
//! minimum lies at an end (the end cones) or where the point crosses one of the
//! fan's rulings (the swept quads). For a convex base only the two rulings that
//! are extreme across the segment can give a minimum; a star-shaped base (L_p,
//! p < 1) sweeps all of them. Every drawn triangle lies on some translated cone,
//! so none dips below the envelope.

use glam::{DVec2, DVec3};

use super::{
    chain::{FanMeshes, MetricFan},
    metric::Metric,
    site::{Shape, Site},
};

/// The surface's triangles, three vertices each: picture position (pixels) and
/// the metric distance to the site's shape at that vertex (pixels, unweighted),
/// or on a [folded](FanSurface::folded) surface a signed value whose magnitude
/// is the distance.
pub type Triangles = Vec<[DVec3; 3]>;

/// A site's fan surface ([`fan_surface`]).
pub(crate) struct FanSurface {
    pub triangles: Triangles,
    /// Bound on the error (pixels of shape distance), either way.
    pub error: f64,
    /// How many of the first triangles are folded: their distance is the
    /// magnitude of the interpolated value, taken per fragment (the straw hut
    /// of a circle or arc as one cone whose apex lies r below the plane, see
    /// `straw_hut`). Only they pay for a fragment-written depth.
    pub folded: usize,
}

/// The fan base of one cone: rim vertices relative to the apex and their height.
struct Base {
    rim: Vec<DVec2>,
    height: f64,
    convex: bool,
}

impl Base {
    /// A base covering metric distance `reach` with the accuracy of `fan` (whose
    /// ε is in pixels of shape distance).
    #[expect(clippy::disallowed_methods, reason = "one fan's rim")]
    fn new(meshes: &FanMeshes, fan: MetricFan, reach: f64) -> Self {
        let metric = meshes.metric();
        let b = metric.euclidean_bounds().1;
        let outer = fan.outer_radius(metric, reach / b);
        let mesh = meshes.unit_mesh(fan, outer);
        let rim = mesh[1..mesh.len() - 1]
            .iter()
            .map(|v| DVec2::new(v[0] as f64, v[1] as f64) * outer)
            .collect();
        Self {
            rim,
            height: outer,
            convex: metric.is_convex(),
        }
    }

    fn cone(&self, apex: DVec2, out: &mut Triangles) {
        self.part_cone(apex, None, None, out);
    }

    /// The cone at a vertex of a polyline with the edges `incoming` (towards the
    /// vertex) and `outgoing` (away from it). On a convex base the distance is
    /// linear on each triangle, with a gradient along the rim edge's outward
    /// normal; the cone is only needed where no step along an edge lowers it
    /// (elsewhere the sweeps or another cone are lower), so a segment's ends get
    /// half-cones, the thesis's roof construction.
    fn part_cone(
        &self,
        apex: DVec2,
        incoming: Option<DVec2>,
        outgoing: Option<DVec2>,
        out: &mut Triangles,
    ) {
        let n = self.rim.len();
        let at = |v: DVec2| (apex + v).extend(self.height);
        for k in 0..n {
            let (u, v) = (self.rim[k], self.rim[(k + 1) % n]);
            let d = v - u;
            let normal = DVec2::new(d.y, -d.x);
            let needed = !self.convex
                || (outgoing.is_none_or(|e| normal.dot(e) <= 0.0)
                    && incoming.is_none_or(|e| normal.dot(e) >= 0.0));
            if needed {
                out.push([apex.extend(0.0), at(u), at(v)]);
            }
        }
    }

    /// The half of the cone at `apex` that faces `back`: the rim triangles whose
    /// outward normal has a component along `back` of zero or more, and one more
    /// on each side. The rim vertex where the normals turn lies within half a rim
    /// step of the line through the apex across `back`, so with the extra
    /// triangles the half-disc {d · back >= 0} is covered up to that line. A
    /// star-shaped base keeps its whole cone.
    fn half_cone(&self, apex: DVec2, back: DVec2, out: &mut Triangles) {
        let n = self.rim.len();
        let faces = |k: usize| {
            let d = self.rim[(k + 1) % n] - self.rim[k];
            DVec2::new(d.y, -d.x).dot(back) >= 0.0
        };
        let at = |v: DVec2| (apex + v).extend(self.height);
        for k in 0..n {
            if !self.convex || faces((k + n - 1) % n) || faces(k) || faces((k + 1) % n) {
                let (u, v) = (self.rim[k], self.rim[(k + 1) % n]);
                out.push([apex.extend(0.0), at(u), at(v)]);
            }
        }
    }

    /// The quads the rulings sweep along the segment `a b` (no end cones).
    #[expect(clippy::disallowed_methods, reason = "two extreme points")]
    fn sweep(&self, a: DVec2, b: DVec2, out: &mut Triangles) {
        let e = b - a;
        if e == DVec2::ZERO {
            return;
        }
        let across = |v: &DVec2| e.perp_dot(*v);
        let rulings: Vec<DVec2> = if self.convex {
            let max = self
                .rim
                .iter()
                .copied()
                .max_by(|u, v| across(u).total_cmp(&across(v)));
            let min = self
                .rim
                .iter()
                .copied()
                .min_by(|u, v| across(u).total_cmp(&across(v)));
            max.into_iter().chain(min).collect()
        } else {
            self.rim.clone()
        };
        let h = self.height;
        for v in rulings {
            let (a0, b0) = (a.extend(0.0), b.extend(0.0));
            let (a1, b1) = ((a + v).extend(h), (b + v).extend(h));
            out.push([a0, b0, b1]);
            out.push([a0, b1, a1]);
        }
    }
}

/// The fan surface of `site` (pixel coordinates) out to shape distance `reach`,
/// with a bound on its error: the fan's own overestimate, plus the chords'
/// deviation for circles and arcs, which may err either way. For a chain fan
/// of error ε the chords get half of ε.
pub(crate) fn fan_surface(
    site: &Site,
    meshes: &FanMeshes,
    fan: MetricFan,
    reach: f64,
) -> FanSurface {
    let metric = meshes.metric();
    let b = metric.euclidean_bounds().1;
    let curved = matches!(site.shape, Shape::Circle { .. } | Shape::Arc { .. });
    if let (true, Metric::L2, MetricFan::Chain { epsilon }) = (curved, metric, fan) {
        let (triangles, folded) = straw_hut(site, meshes, reach, epsilon);
        return FanSurface {
            triangles,
            error: epsilon,
            folded,
        };
    }
    // The chords' Euclidean deviation from the curve moves the nearest point of
    // the site; what that costs in distance depends on the metric: for a norm
    // or a polygon's gauge the chords take half of ε, while for L_p with p < 1
    // the cost grows with the reach (see `Metric::displacement_error`) and the
    // bound reported is the one that holds, above ε.
    let (fan, chord) = match fan {
        MetricFan::Chain { epsilon } if curved => (
            MetricFan::Chain {
                epsilon: epsilon / 2.0,
            },
            metric.displacement_within(epsilon / 2.0),
        ),
        MetricFan::Chain { .. } => (fan, 0.0),
        MetricFan::Uniform { .. } => (fan, 0.5 / b),
    };
    let outer = reach + chord * b;
    let base = Base::new(meshes, fan, outer);
    let fan_error = fan.error_bound(metric, outer / b);
    let chord_error = metric.displacement_error(outer, chord);
    let mut out = Triangles::new();
    let polyline = match site.shape {
        Shape::Point(p) => Vec::from([p]),
        Shape::Segment(a, b) => Vec::from([a, b]),
        Shape::Circle { center, radius } => {
            chords(center, radius, 0.0, std::f64::consts::TAU, chord)
        }
        Shape::Arc {
            center,
            radius,
            start,
            end,
        } => chords(center, radius, start, end - start, chord),
    };
    // A closed polyline's last point repeats its first.
    let closed = polyline.len() > 2 && polyline[0].distance(polyline[polyline.len() - 1]) < 1e-9;
    let vertices = polyline.len() - usize::from(closed);
    for i in 0..vertices {
        let edge = |from: usize, to: usize| {
            let e = polyline[to] - polyline[from];
            (e != DVec2::ZERO).then_some(e)
        };
        let incoming = match i {
            0 if closed => edge(vertices - 1, 0),
            0 => None,
            _ => edge(i - 1, i),
        };
        let outgoing = (i + 1 < polyline.len()).then(|| edge(i, i + 1)).flatten();
        base.part_cone(polyline[i], incoming, outgoing, &mut out);
    }
    for w in polyline.windows(2) {
        base.sweep(w[0], w[1], &mut out);
    }
    FanSurface {
        triangles: out,
        error: fan_error + chord_error,
        folded: 0,
    }
}

/// Points of the circle of `radius` around `center` from angle `start` over
/// `span` (clamped to a full turn), close enough that every chord stays within
/// `deviation` of the arc (Euclidean).
#[expect(clippy::disallowed_methods, reason = "one chord fan")]
fn chords(center: DVec2, radius: f64, start: f64, span: f64, deviation: f64) -> Vec<DVec2> {
    let span = span.clamp(0.0, std::f64::consts::TAU);
    if radius == 0.0 || span == 0.0 {
        let p = center + radius * DVec2::new(start.cos(), start.sin());
        return Vec::from([p]);
    }
    // A chord over angle 2t deviates by r (1 - cos t).
    let step = if deviation >= radius {
        std::f64::consts::PI
    } else {
        2.0 * (1.0 - deviation / radius).acos()
    };
    let pieces = (span / step).ceil().max(1.0) as usize;
    (0..=pieces)
        .map(|k| {
            let a = start + span * k as f64 / pieces as f64;
            center + radius * DVec2::new(a.cos(), a.sin())
        })
        .collect()
}

/// The thesis's straw hut (L2), folded: over the arc's wedge the distance is
/// |ρ − r|, the magnitude of one cone over the centre whose apex lies r below
/// the plane, so each piece of the wedge is one triangle instead of the
/// thesis's three (a cone rising inwards to the centre and a ring rising
/// outwards); lavapipe's time goes with the triangles (docs/tuning.md,
/// "Measured choices"). The pieces' angles keep the chords at
/// the outer radius within ε, so the fan's ρ exceeds the true one by at most
/// ε everywhere, and |ρ − r| moves by no more than ρ does: the hut errs by at
/// most ε either way. An arc adds the cones of its two ends, which
/// serve the pixels outside its wedge (the sliced hut of §3.9); their values
/// are never negative.
fn straw_hut(site: &Site, meshes: &FanMeshes, reach: f64, epsilon: f64) -> (Triangles, usize) {
    let (center, r, start, span) = match site.shape {
        Shape::Circle { center, radius } => (center, radius, 0.0, std::f64::consts::TAU),
        Shape::Arc {
            center,
            radius,
            start,
            end,
        } => (
            center,
            radius,
            start,
            (end - start).min(std::f64::consts::TAU),
        ),
        _ => unreachable!("only circles and arcs have huts"),
    };
    let outer = r + reach + epsilon;
    let full = super::cone::triangles_for_distance_error(outer, epsilon) as f64;
    let pieces = (full * span / std::f64::consts::TAU).ceil().max(1.0) as usize;
    let at = |k: usize, radius: f64| {
        let a = start + span * k as f64 / pieces as f64;
        center + radius * DVec2::new(a.cos(), a.sin())
    };
    let mut out = Triangles::new();
    if span > 0.0 && r > 0.0 {
        for k in 0..pieces {
            let (o0, o1) = (
                at(k, outer).extend(outer - r),
                at(k + 1, outer).extend(outer - r),
            );
            out.push([center.extend(-r), o0, o1]);
        }
    }
    let folded = out.len();
    if span < std::f64::consts::TAU || r == 0.0 {
        let base = Base::new(meshes, MetricFan::Chain { epsilon }, reach);
        if r == 0.0 {
            base.cone(center, &mut out);
        } else {
            // An end serves only the pixels beyond its radial line, where the
            // offset from it runs against the arc's direction at the start and
            // along it at the end.
            let tangent = |a: f64| DVec2::new(-a.sin(), a.cos());
            base.half_cone(at(0, r), -tangent(start), &mut out);
            base.half_cone(at(pieces, r), tangent(start + span), &mut out);
        }
    }
    (out, folded)
}
