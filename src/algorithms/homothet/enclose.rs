//! The smallest enclosing homothet (thesis ch. 4): of points by the furthest
//! envelope's lowest pixel, refined exactly; of weighted and extended sites by
//! a branch and bound on their exact distances.

use super::*;
use crate::memory::Gather;
use crate::{algorithms::higher_order::cpu, Backend};

/// The smallest homothet of `unit` holding at least `k` of `sites` (every
/// site when `k` is 0 or the number of sites). Points are exact, from Welzl's
/// algorithm (circles, all sites) or the points where three of the candidate
/// sites' distance pieces meet. General sites (segments, circles, arcs) are
/// exact where their ends decide (segments under convex units), and refined
/// otherwise by a branch and bound on their farthest gauges to a relative gap
/// of 1e-9.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::algorithms::homothet::{enclose, EncloseOptions, Unit};
///
/// let sites = [DVec2::ZERO, DVec2::new(10.0, 0.0), DVec2::new(5.0, 1.0), DVec2::new(50.0, 50.0)];
/// // The smallest circle holding at least 3 of the 4 sites.
/// let options = EncloseOptions::new(Unit::Circle).k(3);
/// let c = pixgeo::with_default_machine(|m| enclose(&m.into(), &sites, &options))?;
/// assert!((c.exact.scale - 5.0).abs() < 1e-9);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn enclose<'a>(
    backend: &Backend,
    sites: impl Into<Sites<'a>>,
    options: &EncloseOptions,
) -> Result<HomothetAnswer> {
    let EncloseOptions { unit, k, side } = *options;
    match sites.into() {
        Sites::Points(points) => enclose_checked(backend, Checked::new(points)?, unit, k, side),
        Sites::General(sites) => enclose_general(backend, sites, options),
    }
}

/// Which enclosing homothet to find: the unit, how many sites it holds at
/// least (0: all of them), and the picture's side.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct EncloseOptions {
    pub unit: Unit,
    pub k: usize,
    pub side: u32,
}

impl EncloseOptions {
    /// The smallest homothet of `unit` holding every site, on a picture of
    /// [`DEFAULT_SIDE`] pixels.
    pub fn new(unit: Unit) -> Self {
        Self {
            unit,
            k: 0,
            side: DEFAULT_SIDE,
        }
    }

    pub fn k(self, k: usize) -> Self {
        Self { k, ..self }
    }

    pub fn side(self, side: u32) -> Self {
        Self { side, ..self }
    }
}

/// [`enclose`] of sites checked where they entered.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
fn enclose_checked(
    backend: &Backend,
    checked: Checked<'_>,
    unit: Unit,
    k: usize,
    side: u32,
) -> Result<HomothetAnswer> {
    let sites = checked.sites();
    // Homothets scale with their sites: far magnitudes are brought near 1 by
    // a power of two, exactly, so that no distance overflows or underflows.
    let shift = scale::predicate_exponent(sites)?;
    if shift != 0 {
        let scaled = scale::scaled(sites, shift);
        let answer = enclose_checked(backend, Checked::derived(&scaled), unit, k, side)?;
        let mut answer = answer.scaled(-shift);
        // Scaled back into the subnormals, a rounded centre would round
        // again: a circle is rounded once, from its sites as given.
        if unit == Unit::Circle {
            answer.exact = circle_through(sites, answer.exact);
        }
        return Ok(answer);
    }
    let n = sites.len();
    let k = if k == 0 { n } else { k };
    if k > n {
        return Err(Error::out_of_range(format!(
            "cannot enclose {k} of {n} sites"
        )));
    }
    if k < n && k > MAX_LEVELS as usize {
        return Err(Error::out_of_range(format!(
            "holding {k} of {n} sites reads the {k}-th nearest site of every pixel, and pixgeo \
             keeps at most {MAX_LEVELS} levels: k takes 1 to {MAX_LEVELS}, or all {n} sites"
        )));
    }
    // Holding every site, a repeat changes nothing but costs an exact test
    // on the circle: the first of each position stands for all.
    if k == n {
        let kept = first_of_each(sites);
        if kept.len() < n {
            let distinct: Vec<DVec2> =
                kept.iter().map(|&i| sites[i as usize]).gather("distinct")?;
            let mut answer = enclose_checked(backend, Checked::derived(&distinct), unit, 0, side)?;
            for homothet in [&mut answer.exact, &mut answer.pixel] {
                for site in &mut homothet.sites {
                    *site = kept[*site as usize];
                }
            }
            return Ok(answer);
        }
    }
    let frame = enclosing_frame(sites, unit, side, k)?;
    let metric = unit.cone_metric()?;
    let bound = half_diagonal(&frame) * unit.lipschitz();
    // The sites drawn in the upper envelope are the only ones that can be
    // furthest (the hull's, for convex units).
    let (pixel, value, near_pixels, owners) = if let (true, None) = (k == n, backend.machine()) {
        // The upper envelope from the CPU's furthest sites: its lowest
        // pixel and those within twice the bound of it.
        let far = cpu::furthest_checked(checked, &frame, metric)?;
        let lowest = lowest_of(&far.distances);
        let value = far.distances[lowest] as f64;
        let near = (0..far.distances.len())
            .filter(|&p| (far.distances[p] as f64) <= value + 2.0 * bound)
            .take(NEAR_PIXELS as usize)
            .gather("near")?;
        (lowest, value, near, far.hull)
    } else if let (true, Some(machine)) = (k == n, backend.machine()) {
        let drawn = draw_furthest(machine, checked, &frame, metric, false)?;
        // Every pixel that could be the optimum's: within twice the bound. L2
        // keys are squared distances (pixels); the others are distances.
        let lowest = machine.depth_extremes(
            &drawn.depth,
            Some(near_extreme(
                metric,
                drawn.scale,
                2.0 * bound * frame.scale,
                false,
            )),
        )?;
        let value = crate::algorithms::higher_order::distance_of_depth(
            metric,
            drawn.scale,
            lowest.min,
            &frame,
        );
        (lowest.at_min, value, lowest.near, drawn.owners)
    } else {
        // The k-th level of the lower envelope, read back: its lowest pixel.
        // Equal optima are many here (on lattices), and which one the
        // search meets depends on the levels' rounding: the device's alone.
        let machine = backend.device_for("the smallest homothet holding k of the sites")?;
        let levels = kth_levels(machine, checked, frame, metric, k)?;
        let kth = levels.level_distances(k as u32 - 1);
        let at = lowest_of(&kth);
        let d = kth[at] as f64;
        let near: Vec<usize> = (0..kth.len())
            .filter(|&p| (kth[p] as f64) <= d + 2.0 * bound)
            .take(NEAR_PIXELS as usize)
            .gather("near")?;
        (at, d, near, Vec::new())
    };
    let centre = pixel_centre(&frame, pixel);
    let pixel_bound = bound + rounding(unit, &frame, value);
    let (exact, checked) = if k == n && unit == Unit::Circle {
        let (around, reach) = surroundings(&frame, &near_pixels);
        let slack = 3.0 * pixel_bound + unit.lipschitz() * reach;
        smallest_circle(sites, around, value, slack)
    } else {
        let goal = Goal::Smallest;
        let eps = rounding(unit, &frame, value);
        let window = (value - 2.0 * bound - eps, value + eps);
        let furthest = |c: DVec2| {
            owners
                .iter()
                .map(|&i| unit.gauge(sites[i as usize] - c))
                .fold(0.0, f64::max)
        };
        let (c, v, checked) = best_of_clusters(&frame, &near_pixels, goal, |around, reach| {
            // A site on the best homothet has its gauge from `around` within
            // the window widened by the reach; the k nearest at any centre in
            // reach lie below its top.
            let spread = unit.lipschitz() * reach;
            let (lo, hi) = (window.0 - spread, window.1 + spread);
            let gauge = |i: &u32| unit.gauge(sites[*i as usize] - around);
            let (near, generators): (Vec<u32>, Vec<u32>) = if k == n {
                let far: Vec<u32> = owners.iter().copied().filter(|i| gauge(i) >= lo).collect();
                (far.clone(), far)
            } else {
                let near: Vec<u32> = (0..n as u32).filter(|i| gauge(i) <= hi).collect();
                let ring = near.iter().copied().filter(|i| gauge(i) >= lo).collect();
                (near, ring)
            };
            let always = |_| true;
            best_vertex(
                sites,
                unit,
                around,
                reach,
                (&near, &generators),
                &[],
                goal,
                k,
                window,
                always,
                furthest,
                None,
            )
        })
        .ok_or_else(|| Error::degenerate("no enclosing homothet found".into()))?;
        // A circle holding k of the sites is decided again exactly from the
        // sites on it.
        let exact = match unit {
            Unit::Circle if k < n => refine::exact_k_circle(sites, k, v, &frame, &near_pixels),
            _ => None,
        };
        (
            exact.unwrap_or_else(|| homothet_at(sites, unit, c, v)),
            checked,
        )
    };
    Ok(answer_of(
        &frame,
        centre,
        value,
        pixel_bound,
        (exact, checked),
    ))
}

pub(super) fn answer_of(
    frame: &Frame,
    centre: DVec2,
    value: f64,
    pixel_bound: f64,
    (exact, checked): (Homothet, usize),
) -> HomothetAnswer {
    HomothetAnswer {
        pixel: Homothet {
            centre: centre.to_array(),
            scale: value,
            sites: Vec::new(),
        },
        exact,
        pixel_stage: PixelStage::Cones,
        pixel_bound,
        checked,
        tolerance: 0.0,
        width: frame.width,
        height: frame.height,
        frame: *frame,
    }
}

/// Points per full turn that stand for a circle in the picture of an enclosing
/// homothet; the chords lose at most r (1 − cos(π / 64)).
const CURVE_SAMPLES: usize = 64;

/// The Euclidean distance from `c` to the farthest point of a site's shape.
fn farthest_euclidean(shape: Shape, c: DVec2) -> f64 {
    let at = |o: DVec2, r: f64, a: f64| o + r * DVec2::new(a.cos(), a.sin());
    match shape {
        Shape::Point(p) => c.distance(p),
        Shape::Segment(a, b) => c.distance(a).max(c.distance(b)),
        Shape::Circle { center, radius } => c.distance(center) + radius,
        Shape::Arc {
            center,
            radius,
            start,
            end,
        } => {
            let d = center - c;
            if d == DVec2::ZERO || crate::geometry::site::on_arc(d.y.atan2(d.x), start, end) {
                d.length() + radius
            } else {
                c.distance(at(center, radius, start))
                    .max(c.distance(at(center, radius, end)))
            }
        }
    }
}

/// The gauge of the farthest point of a site's shape from `c` (how large a
/// homothet centred at `c` must be to hold it). In each sector of a polygon the
/// gauge of p − c is linear in p, so over a shape it peaks at an end, where a
/// vertex ray from `c` crosses the shape, or (on a curve) where the curve's
/// tangent is parallel to an edge: those candidates are evaluated exactly.
fn farthest_gauge(unit: Unit, shape: Shape, c: DVec2) -> f64 {
    let Unit::Polygon(g) = unit else {
        return farthest_euclidean(shape, c);
    };
    let at = |o: DVec2, r: f64, a: f64| o + r * DVec2::from_angle(a);
    let mut candidates: Vec<DVec2> = Vec::new();
    match shape {
        Shape::Point(p) => candidates.push(p),
        Shape::Segment(a, b) => {
            candidates.extend([a, b]);
            if !g.is_convex() {
                let d = b - a;
                for v in &g.vertices {
                    // c + t v = a + s d with t ≥ 0, s in [0, 1].
                    let det = v.perp_dot(d);
                    if det != 0.0 {
                        let w = a - c;
                        let (t, s) = (w.perp_dot(d) / det, w.perp_dot(*v) / det);
                        if t >= 0.0 && (0.0..=1.0).contains(&s) {
                            candidates.push(a + d * s);
                        }
                    }
                }
            }
        }
        Shape::Circle { center, radius } | Shape::Arc { center, radius, .. } => {
            let (start, end) = match shape {
                Shape::Arc { start, end, .. } => (start, end),
                _ => (0.0, std::f64::consts::TAU),
            };
            let on = |p: DVec2| {
                let d = p - center;
                crate::geometry::site::on_arc(d.y.atan2(d.x), start, end)
            };
            if matches!(shape, Shape::Arc { .. }) {
                candidates.extend([at(center, radius, start), at(center, radius, end)]);
            }
            let n = g.vertices.len();
            for k in 0..n {
                // The piece of edge k grows along (e.y, −e.x): its peak on the circle.
                let e = g.vertices[(k + 1) % n] - g.vertices[k];
                let peak = center + radius * DVec2::new(e.y, -e.x).normalize();
                if on(peak) {
                    candidates.push(peak);
                }
                if !g.is_convex() {
                    // Where the ray c + t v (t ≥ 0) meets the circle.
                    let v = g.vertices[k];
                    let w = c - center;
                    let roots = quadratic_roots(
                        v.length_squared(),
                        2.0 * v.dot(w),
                        w.length_squared() - radius * radius,
                    );
                    for t in roots {
                        let p = c + v * t;
                        if t >= 0.0 && on(p) {
                            candidates.push(p);
                        }
                    }
                }
            }
        }
    }
    candidates
        .into_iter()
        .map(|p| g.of(p - c))
        .fold(0.0, f64::max)
}

/// [`enclose`] of general sites: segments, circles and arcs (thesis §4.4:
/// the minimum enclosing circle of circles). Points and segments under convex
/// units are exact through the points' route (a segment's ends decide); the
/// rest are drawn as points on them and refined by a branch and bound on their
/// farthest gauges, to a relative gap of 1e-9.
fn enclose_general(
    backend: &Backend,
    sites: &[Site],
    options: &EncloseOptions,
) -> Result<HomothetAnswer> {
    let EncloseOptions { unit, k, .. } = *options;
    check_general_sites(sites)?;
    if sites
        .iter()
        .any(|s| s.multiplicative != 1.0 || s.additive != 0.0)
    {
        return Err(Error::unsupported_option(
            "enclosing homothets take unweighted sites".into(),
        ));
    }
    let curved = sites
        .iter()
        .any(|s| matches!(s.shape, Shape::Circle { .. } | Shape::Arc { .. }));
    let points_only = sites.iter().all(|s| matches!(s.shape, Shape::Point(_)));
    if !points_only && k != 0 && k != sites.len() {
        return Err(Error::unsupported_option(
            "the smallest k-enclosing homothet takes point sites".into(),
        ));
    }
    let convex = match unit {
        Unit::Polygon(g) => g.is_convex(),
        Unit::Circle => true,
    };
    // Points standing for each site, and whose site they are.
    let mut samples = Vec::new();
    let mut owner = Vec::new();
    for (i, s) in sites.iter().enumerate() {
        let mut add = |p: DVec2| {
            samples.push(p);
            owner.push(i as u32);
        };
        match s.shape {
            Shape::Point(p) => add(p),
            // A convex homothet holds a segment when it holds its ends; others
            // see its inside too.
            Shape::Segment(a, b) => {
                let steps = if convex { 1 } else { CURVE_SAMPLES };
                for j in 0..=steps {
                    add(a + (b - a) * (j as f64 / steps as f64));
                }
            }
            Shape::Circle { center, radius } => {
                for j in 0..CURVE_SAMPLES {
                    let a = std::f64::consts::TAU * j as f64 / CURVE_SAMPLES as f64;
                    add(center + radius * DVec2::new(a.cos(), a.sin()));
                }
            }
            Shape::Arc {
                center,
                radius,
                start,
                end,
            } => {
                let span = (end - start).min(std::f64::consts::TAU);
                let steps =
                    ((span / std::f64::consts::TAU * CURVE_SAMPLES as f64).ceil() as usize).max(1);
                for j in 0..=steps {
                    let a = start + span * j as f64 / steps as f64;
                    add(center + radius * DVec2::new(a.cos(), a.sin()));
                }
            }
        }
    }
    let mut answer = enclose(backend, &samples, options)?;
    // The picture saw chords of the curves.
    let chord_loss = sites
        .iter()
        .map(|s| match s.shape {
            Shape::Circle { radius, .. } | Shape::Arc { radius, .. } => {
                radius * (1.0 - (std::f64::consts::PI / CURVE_SAMPLES as f64).cos())
            }
            _ => 0.0,
        })
        .fold(0.0, f64::max);
    answer.pixel_bound += chord_loss * unit.lipschitz();
    let mut named: Vec<u32> = answer
        .exact
        .sites
        .iter()
        .map(|&s| owner[s as usize])
        .gather("named")?;
    named.dedup();
    answer.exact.sites = named;
    if !curved && (convex || points_only) {
        return Ok(answer);
    }
    // The samples' circle is a start; the sites' farthest distances decide.
    let start = DVec2::from(answer.exact.centre);
    let farthest = |c: DVec2| {
        sites
            .iter()
            .map(|s| farthest_gauge(unit, s.shape, c))
            .fold(0.0, f64::max)
    };
    // Convex units have one basin: search around the samples' answer. Others
    // search every centre whose homothet of the scale at the sites' middle holds
    // all the samples.
    let (start, mut reach) = if convex {
        (
            start,
            0.1 * answer.exact.scale + 8.0 * half_diagonal(&answer.frame),
        )
    } else {
        let lo = samples.iter().fold(DVec2::INFINITY, |a, p| a.min(*p));
        let hi = samples.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
        let (qlo, qhi) = unit_box(unit);
        let scale0 = farthest((lo + hi) / 2.0);
        let (blo, bhi) = (hi - qhi * scale0, lo - qlo * scale0);
        (
            (blo + bhi) / 2.0,
            (bhi - blo).max_element() / 2.0 * 1.01 + 1e-9,
        )
    };
    loop {
        let (c, v, gap, cells) = branch_and_bound(
            start,
            reach,
            |c, h| -farthest(c) + unit.lipschitz() * h * std::f64::consts::SQRT_2,
            |c| -farthest(c),
            |_| true,
            |_, _| true,
            (None, |best: f64| 1e-9 * (1.0 + best.abs())),
        )?
        .ok_or_else(|| Error::degenerate("no enclosing circle found".into()))?;
        // The optimum is inside the square searched, or (convex units) the
        // square was too small.
        if !convex || (c - start).abs().max_element() < reach * 0.99 {
            let tol = 1e-9 * (1.0 + v.abs());
            answer.exact = Homothet {
                centre: c.to_array(),
                scale: -v,
                sites: (0..sites.len() as u32)
                    .filter(|&i| {
                        (farthest_gauge(unit, sites[i as usize].shape, c) + v).abs() <= tol.max(gap)
                    })
                    .gather("sites")?,
            };
            answer.tolerance = gap;
            answer.checked += cells;
            return Ok(answer);
        }
        reach *= 4.0;
    }
}

/// The k nearest sites of every pixel, exact.
pub(super) fn kth_levels(
    machine: &Machine,
    sites: Checked<'_>,
    frame: Frame,
    metric: Metric,
    k: usize,
) -> Result<crate::algorithms::higher_order::KNearest> {
    let options = KNearestOptions::exact(frame, k as u32)
        .metric(metric)
        .speedup(Speedup::Quadtree);
    k_nearest_checked(machine, sites, &options)
}

/// The first pixel of least distance.
fn lowest_of(distances: &[f32]) -> usize {
    distances
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0, |(at, _)| at)
}

/// The circle through the sites that determine `circle` (its `sites`, one to
/// three), its centre and radius rounded once from the exact ones.
fn circle_through(sites: &[DVec2], circle: Homothet) -> Homothet {
    let at = |k: usize| sites[circle.sites[k] as usize];
    let index = |k: usize| circle.sites[k] as usize;
    let exact = match circle.sites.len() {
        2 => crate::geometry::exact::circle::through_two(at(0), at(1), index(0), index(1)),
        3 => crate::geometry::exact::circle::through_three(
            [at(0), at(1), at(2)],
            [0, 1, 2].map(index),
        ),
        _ => return circle,
    };
    Homothet {
        centre: exact.centre.to_array(),
        scale: exact.radius,
        ..circle
    }
}
