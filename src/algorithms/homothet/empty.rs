//! The largest empty homothet in a region (thesis ch. 5): the highest pixel of
//! the lower envelope inside the region, refined exactly.

use super::*;
use crate::geometry::exact::two_difference;
use crate::memory::Gather;

/// Where the centre of the largest empty homothet may lie.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Region {
    /// Closed rings (polygons and their holes, any orientation); a point is inside
    /// when it is inside an odd number of rings. Empty: the sites' bounding box.
    pub rings: Vec<Vec<DVec2>>,
}

impl Region {
    /// Even-odd inside test.
    pub fn contains(&self, p: DVec2) -> bool {
        let mut inside = false;
        for ring in &self.rings {
            for k in 0..ring.len() {
                let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
                if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x)
                {
                    inside = !inside;
                }
            }
        }
        inside
    }

    pub(super) fn edges(&self) -> impl Iterator<Item = (DVec2, DVec2)> + '_ {
        self.rings
            .iter()
            .flat_map(|r| (0..r.len()).map(move |k| (r[k], r[(k + 1) % r.len()])))
    }
}

/// The largest homothet of `unit` containing none of `sites`, its centre in
/// `region` (empty: the sites' bounding box). Plain points without `inside`
/// are exact, from the points where three of the candidate sites' distance
/// pieces or region edges meet. General sites (segments, circles and arcs,
/// with multiplicative weights scaling the clearance each demands, thesis
/// §5.4.2–5.4.3), and any sites with `inside` (the whole homothet inside the
/// region, its boundary added as segment sites, §5.4.1): circles clearing
/// unweighted points and segments take the vertices of their Voronoi diagram;
/// the others a branch and bound on the exact distances around the candidate
/// pixels, to a relative gap of 1e-9 (reported as
/// [`HomothetAnswer::tolerance`]).
///
/// ```
/// use glam::DVec2;
/// use pixgeo::algorithms::homothet::{largest_empty, EmptyOptions, Region, Unit};
///
/// let sites = [DVec2::ZERO, DVec2::new(4.0, 0.0), DVec2::new(0.0, 3.0)];
/// let square = Region { rings: vec![vec![DVec2::ZERO, DVec2::new(4.0, 0.0), DVec2::new(4.0, 4.0), DVec2::new(0.0, 4.0)]] };
/// let options = EmptyOptions::new(Unit::Circle).region(square);
/// let c = pixgeo::with_default_machine(|m| largest_empty(m, &sites, &options))?;
/// // On the top side, as far from (0, 3) as from (4, 0): farther than the corner (4, 4).
/// assert_eq!(c.exact.centre, [3.875, 4.0]);
/// assert!(c.exact.scale > 4.0);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn largest_empty<'a>(
    machine: &Machine,
    sites: impl Into<Sites<'a>>,
    options: &EmptyOptions,
) -> Result<HomothetAnswer> {
    let o = options;
    let general: Vec<Site>;
    let sites = match sites.into() {
        Sites::Points(points) if !o.inside => {
            return empty_of_points(machine, points, o.unit, &o.region, o.side, o.stage);
        }
        // Inside a region, its boundary joins the points as segment sites.
        Sites::Points(points) => {
            check_sites(points)?;
            general = points.iter().map(|&p| Site::point(p)).gather("sites")?;
            &general[..]
        }
        Sites::General(sites) => sites,
    };
    empty_of_sites(machine, sites, o.unit, &o.region, o.inside, o.side, o.stage)
}

/// Which empty homothet to find: the unit, the region its centre lies in
/// (empty: the sites' bounding box), whether the whole homothet lies
/// `inside` the region, the picture's side, and the pixel stage (`None`:
/// the distance transform where it applies, that is circles, unweighted
/// points, every site on the picture or within a pixel of it, a picture
/// the device holds whole, and cones elsewhere; asking for the transform
/// where it does not apply is an error).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct EmptyOptions {
    pub unit: Unit,
    pub region: Region,
    pub inside: bool,
    pub side: u32,
    pub stage: Option<PixelStage>,
}

impl EmptyOptions {
    /// The largest empty homothet of `unit` centred in the sites' bounding
    /// box, on a picture of [`super::DEFAULT_SIDE`] pixels.
    pub fn new(unit: Unit) -> Self {
        Self {
            unit,
            region: Region::default(),
            inside: false,
            side: super::DEFAULT_SIDE,
            stage: None,
        }
    }

    pub fn region(self, region: Region) -> Self {
        Self { region, ..self }
    }

    pub fn inside(self, inside: bool) -> Self {
        Self { inside, ..self }
    }

    pub fn side(self, side: u32) -> Self {
        Self { side, ..self }
    }

    pub fn stage(self, stage: Option<PixelStage>) -> Self {
        Self { stage, ..self }
    }
}

/// A corner to move `sites` and `region` by: on each axis where they lie far
/// from the origin beside their extent (more than 2^20 times) and every
/// difference from the corner is exact, the corner's coordinate; 0 on the
/// others.
fn exact_shift(points: &[DVec2]) -> DVec2 {
    let along = |axis: fn(&DVec2) -> f64| {
        let values = || points.iter().map(axis);
        let lo = values().fold(f64::INFINITY, f64::min);
        let hi = values().fold(f64::NEG_INFINITY, f64::max);
        let far = lo.abs().max(hi.abs()) > (hi - lo) * 2f64.powi(20);
        let exact = |v: f64| {
            let (d, e) = two_difference(v, lo);
            e == 0.0 && d + lo == v
        };
        match far && values().all(exact) {
            true => lo,
            false => 0.0,
        }
    };
    DVec2::new(along(|p| p.x), along(|p| p.y))
}

/// More pixels near the largest value than this, and the picture is too coarse
/// for the sites: the exact search would cost more than a finer picture.
const MAX_NEAR_PIXELS: usize = 1024;

/// The side up to which a coarse picture is refined.
const MAX_REFINED_SIDE: u32 = 4096;

/// [`largest_empty`] of points without `inside`.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
fn empty_of_points(
    machine: &Machine,
    sites: &[DVec2],
    unit: Unit,
    region: &Region,
    side: u32,
    stage: Option<PixelStage>,
) -> Result<HomothetAnswer> {
    check_sites(sites)?;
    // Homothets move and scale with their sites, so the sites are placed near
    // the origin and near 1 where that is exact (see `empty_of_sites`).
    let anchors: Vec<DVec2> = sites
        .iter()
        .chain(region.rings.iter().flatten())
        .copied()
        .gather("anchors")?;
    let origin = exact_shift(&anchors);
    let numbers: Vec<f64> = anchors
        .iter()
        .flat_map(|p| [p.x - origin.x, p.y - origin.y])
        .gather("numbers")?;
    let k = exponent_or_refusal(&numbers, REFINED_POINTS)?;
    let t = |x: f64| scale::times_power_of_two(x, k);
    let place = |p: &DVec2| DVec2::new(t(p.x - origin.x), t(p.y - origin.y));
    let sites: Vec<DVec2> = sites.iter().map(place).gather("sites")?;
    let region = Region {
        rings: region
            .rings
            .iter()
            .map(|r| r.iter().map(place).collect())
            .gather("rings")?,
    };
    let placement = Placement { k, origin };
    let (answer, exact) = empty_points(machine, &sites, unit, &region, side, stage, placement)?;
    Ok(placed_back(answer, exact, placement))
}

/// An answer for sites placed by `placement`, in the sites' own coordinates:
/// the exact one, where given, as it was rounded there.
fn placed_back(
    answer: HomothetAnswer,
    exact: Option<Certified>,
    placement: Placement,
) -> HomothetAnswer {
    let mut answer = answer.scaled(-placement.k).moved(placement.origin);
    if let Some(exact) = exact {
        answer.exact = Homothet {
            centre: exact.centre.to_array(),
            scale: exact.radius,
            sites: exact.on,
        };
        answer.tolerance = 0.0;
    }
    answer
}

/// [`largest_empty_by`] on sites placed near the origin and near 1 by
/// `placement`: the answer there, and for circles the exact one in the sites'
/// own coordinates.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
fn empty_points(
    machine: &Machine,
    sites: &[DVec2],
    unit: Unit,
    region: &Region,
    side: u32,
    stage: Option<PixelStage>,
    placement: Placement,
) -> Result<(HomothetAnswer, Option<Certified>)> {
    let finer = |side| empty_points(machine, sites, unit, region, side, stage, placement);
    let lo = sites.iter().fold(DVec2::INFINITY, |a, p| a.min(*p));
    let hi = sites.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
    let (region, frame) = region_and_frame(region, (lo, hi), side)?;
    // Fewer pixels than four a site leave many sites near each candidate pixel, and
    // the exact search costs cubic time and memory in them (1000 sites on a
    // 2x2 picture took over 4 GB): the picture is made finer instead.
    if frame.len() < 4 * sites.len() && side < MAX_REFINED_SIDE {
        return finer(side * 2);
    }
    let metric = unit.cone_metric()?;
    let region_mesh = RegionMesh::new(&region, &frame);
    let bound = half_diagonal(&frame) * unit.lipschitz();
    // A gauge of at most g is within Euclidean distance g · rmax.
    let rmax = 1.0 / Metric::from(unit).euclidean_bounds().0;
    let grid = PointGrid::new(sites);
    let nearest = |c: DVec2| {
        let (i, _) = grid.nearest(c).expect("sites exist");
        let upper = unit.gauge(sites[i as usize] - c);
        grid.around(c, upper * rmax)
            .map(|j| unit.gauge(sites[j as usize] - c))
            .fold(upper, f64::min)
    };
    // Per tile: its highest value and the pixels near it, exact at pixel centres.
    let seeds = match stage {
        Some(PixelStage::Cones) => None,
        _ => snapped_seeds(machine, sites, unit, &frame)?,
    };
    if stage == Some(PixelStage::DistanceTransform) && seeds.is_none() {
        return Err(Error::unsupported_option(format!(
            "the distance transform takes circles, sites on the picture (within a pixel) and sides up to {}: use cones",
            flooding::MAX_SIDE.min(machine.max_picture_side())
        )));
    }
    let stage = if seeds.is_some() {
        PixelStage::DistanceTransform
    } else {
        PixelStage::Cones
    };
    let tiles = match seeds {
        Some((seeds, moved)) => {
            // A pixel's value is within `snap` of its clearance (rounding aside),
            // so the best centre's pixel is listed; the exact clearances of the
            // listed centres then keep those within twice the bound.
            let snap = moved * (1.0 + 1e-9) / frame.scale;
            let within = 2.0 * (bound + snap) * frame.scale;
            let listed = listed_of_transform(machine, &seeds, &frame, &region_mesh, within)?;
            let mut exact: Vec<(f64, usize)> = listed
                .into_iter()
                .map(|p| (nearest(pixel_centre(&frame, p)), p))
                .gather("exact")?;
            exact.sort_by(|a, b| b.0.total_cmp(&a.0));
            let top = exact.first().map_or(0.0, |e| e.0);
            exact.retain(|e| e.0 >= top - 2.0 * bound);
            let pixels: Vec<usize> = exact.into_iter().map(|e| e.1).gather("pixels")?;
            if pixels.is_empty() {
                Vec::new()
            } else {
                Vec::from([(top, pixels)])
            }
        }
        None => {
            let options = VoronoiOptions {
                metric,
                speedup: Speedup::Local,
                ..VoronoiOptions::exact(frame)
            };
            let mut tiles: Vec<(f32, Vec<usize>)> = Vec::new();
            let mut keys = None;
            let extras = TileExtras {
                stencil: true,
                ..TileExtras::default()
            };
            draw_point_tiles(machine, sites, &options, extras, |tile| {
                keys = Some(tile.keys);
                let within = 2.0 * bound * frame.scale;
                let near = near_extreme(metric, tile.keys.scale, within, true);
                let picture = (Some(tile.ids), tile.depth, tile.x0, tile.y0, tile.inner);
                tiles.extend(highest_in_region(
                    machine,
                    &frame,
                    &region_mesh,
                    picture,
                    near,
                )?);
                Ok(())
            })?;
            let depth = keys.expect("a picture has a tile");
            tiles
                .into_iter()
                .map(|(z, p)| (depth.distance(z), p))
                .gather("depth")?
        }
    };
    let value = tiles.iter().map(|t| t.0).fold(f64::NEG_INFINITY, f64::max);
    if tiles.is_empty() {
        return Err(Error::degenerate(
            "no pixel centre lies in the region".into(),
        ));
    }
    let near_pixels = near_top(&tiles, value, bound);
    // Sites denser than the picture resolves leave most pixels near the top,
    // and the exact search around each would cost cubic time in the sites
    // there: the picture is made finer instead (the answer does not depend on
    // it), up to a side the device holds.
    if near_pixels.len() > MAX_NEAR_PIXELS && side < MAX_REFINED_SIDE {
        return finer(side * 2);
    }
    let centre = pixel_centre(&frame, near_pixels[0]);
    let eps = rounding(unit, &frame, value);
    let pixel_bound = bound + eps;
    let goal = Goal::Largest;
    let contenders = std::cell::RefCell::new(Vec::new());
    // The best centre's pixel is among the near ones; a pixel left standing
    // outside the region is within the bound of a centre inside it.
    let window = (value - bound - eps, value + 2.0 * bound + eps);
    let (c, v, checked) = best_of_clusters(&frame, &near_pixels, goal, |around, reach| {
        // Every site that can be nearest at a centre in reach, and of them those
        // that can lie on the best homothet.
        let spread = unit.lipschitz() * reach;
        let (lo, hi) = (window.0 - spread, window.1 + spread);
        let gauge = |i: u32| unit.gauge(sites[i as usize] - around);
        let near: Vec<u32> = grid
            .around(around, hi * rmax)
            .filter(|&i| gauge(i) <= hi)
            .collect();
        let generators: Vec<u32> = near.iter().copied().filter(|&i| gauge(i) >= lo).collect();
        let edges: Vec<(DVec2, DVec2)> = region
            .edges()
            .filter(|(a, b)| segment_distance(around, *a, *b) <= reach)
            .collect();
        let allowed = |c: DVec2| {
            let tol = 1e-9 * (1.0 + c.abs().max_element());
            region.contains(c) || edges.iter().any(|(a, b)| segment_distance(c, *a, *b) < tol)
        };
        let sets = (&near[..], &generators[..]);
        let mut kept = contenders.borrow_mut();
        let kept = (unit == Unit::Circle).then_some(&mut *kept);
        best_vertex(
            sites, unit, around, reach, sets, &edges, goal, 1, window, allowed, nearest, kept,
        )
    })
    .ok_or_else(|| Error::degenerate("no empty homothet found".into()))?;
    // Circles: the vertices rounding may put above the best, decided exactly.
    let rounding = 64.0 * f64::EPSILON * (c.abs().max_element() + v);
    let mut contenders = contenders.into_inner();
    contenders
        .retain(|(vertex, value)| *value >= v - CONTENDING * rounding && within(&region, vertex));
    contenders.sort_by(|a, b| b.1.total_cmp(&a.1));
    contenders.truncate(MAX_CONTENDERS);
    let obstacles: Vec<Obstacle> = sites
        .iter()
        .map(|&p| Obstacle::Point(p))
        .gather("obstacles")?;
    let near = |c: DVec2, r: f64| grid.around(c, r).collect();
    let slack = CONTENDING * rounding;
    let certified = certify(&contenders, (&obstacles, &near), slack, placement);
    let exact = homothet_at(sites, unit, c, v);
    let answer = HomothetAnswer {
        pixel_stage: stage,
        ..answer_of(&frame, centre, value, pixel_bound, (exact, checked))
    };
    Ok((answer, certified))
}

/// The magnitudes the refinement among segments, shapes or `inside` a region
/// holds in doubles: it forms products of four coordinates.
const REFINED_SITES: (f64, f64) = (1e-75, 1e75);

/// The magnitudes the refinement among points holds: squared distances.
const REFINED_POINTS: (f64, f64) = (1e-150, 1e150);

/// [`largest_empty`] of general sites, with the options taken apart.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
fn empty_of_sites(
    machine: &Machine,
    sites: &[Site],
    unit: Unit,
    region: &Region,
    inside: bool,
    side: u32,
    stage: Option<PixelStage>,
) -> Result<HomothetAnswer> {
    check_general_sites(sites)?;
    if !inside && sites.iter().all(Site::is_plain_point) {
        let points: Vec<DVec2> = sites
            .iter()
            .map(|s| match s.shape {
                Shape::Point(p) => p,
                _ => unreachable!("plain points"),
            })
            .gather("points")?;
        return empty_of_points(machine, &points, unit, region, side, stage);
    }
    if stage == Some(PixelStage::DistanceTransform) {
        return Err(Error::unsupported_option(
            "the distance transform takes unweighted points without `inside`: use cones".into(),
        ));
    }
    // Homothets move and scale with their sites: far from the origin, a set's
    // digits are in its offsets, so it is moved to the origin where that is
    // exact; far magnitudes are brought near 1 by a power of two where that
    // is exact, so that the picture's depths and the refinement's products
    // neither overflow nor underflow. The exact answer is rounded once, in
    // the sites' own coordinates.
    let anchors: Vec<DVec2> = sites
        .iter()
        .flat_map(Site::anchors)
        .chain(region.rings.iter().flatten().copied())
        .gather("anchors")?;
    let origin = exact_shift(&anchors);
    let placed = |sites: Vec<Site>, region: Region, f: &dyn Fn(DVec2) -> DVec2| {
        let rings = region
            .rings
            .iter()
            .map(|r| r.iter().map(|p| f(*p)).collect());
        (
            sites,
            Region {
                rings: rings.collect(),
            },
        )
    };
    let (sites, region) = placed(
        sites.iter().map(|s| s.moved_back(origin)).gather("rings")?,
        region.clone(),
        &|p| p - origin,
    );
    let k = exponent_or_refusal(&numbers_of(&sites, &region), REFINED_SITES)?;
    let t = |x: f64| scale::times_power_of_two(x, k);
    let (sites, region) = placed(
        sites.iter().map(|s| s.scaled(k)).gather("scaled sites")?,
        region,
        &|p| DVec2::new(t(p.x), t(p.y)),
    );
    let placement = Placement { k, origin };
    let (answer, exact) = refine_empty(machine, &sites, unit, &region, inside, side, placement)?;
    Ok(placed_back(answer, exact, placement))
}

/// [`largest_empty`] on general sites placed near the origin and near 1 by
/// `placement`: the answer there, and the exact one in the sites' own
/// coordinates where the exact refinement decides it.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
fn refine_empty(
    machine: &Machine,
    sites: &[Site],
    unit: Unit,
    region: &Region,
    inside: bool,
    side: u32,
    placement: Placement,
) -> Result<(HomothetAnswer, Option<Certified>)> {
    let bounds = sites
        .iter()
        .map(Site::bounds)
        .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(a, b), (l, h)| {
            (a.min(l), b.max(h))
        });
    let (region, frame) = region_and_frame(region, bounds, side)?;
    let metric = unit.cone_metric()?;
    let mut all = sites.to_vec();
    if inside {
        all.extend(region.edges().map(|(a, b)| Site::new(Shape::Segment(a, b))));
    }
    let options = VoronoiOptions {
        metric,
        speedup: Speedup::Quadtree,
        distances: false,
        ..VoronoiOptions::exact(frame)
    };
    let region_mesh = RegionMesh::new(&region, &frame);
    let least_m = all
        .iter()
        .map(|s| s.multiplicative)
        .fold(f64::INFINITY, f64::min);
    let lipschitz = unit.lipschitz() / least_m;
    let bound = half_diagonal(&frame) * lipschitz;
    let mut tiles: Vec<(f64, Vec<usize>)> = Vec::new();
    let (stats, _) = draw_sites(machine, &all, &options, |tile| {
        let near = NearExtreme {
            maximum: true,
            within: (2.0 * bound * tile.keys.scale) as f32,
            squared_scale: 0.0,
            capacity: NEAR_PIXELS,
        };
        let picture = (Some(tile.ids), tile.depth, tile.x0, tile.y0, tile.inner);
        if let Some((z, pixels)) = highest_in_region(machine, &frame, &region_mesh, picture, near)?
        {
            tiles.push((tile.keys.distance(z), pixels));
        }
        Ok(())
    })?;
    let value = tiles.iter().map(|t| t.0).fold(f64::NEG_INFINITY, f64::max);
    if tiles.is_empty() {
        return Err(Error::degenerate(
            "no pixel centre lies in the region".into(),
        ));
    }
    // Fans (polygons, curves under other metrics) add their own error.
    let bound = bound + stats.distance_error_bound;
    let near_pixels = near_top(&tiles, value, bound);
    let centre = pixel_centre(&frame, near_pixels[0]);
    let pixel_bound = bound + 1e-5 * value.abs();
    let clearance = |c: DVec2, set: &[Site]| {
        set.iter()
            .map(|s| s.distance(metric, c))
            .fold(f64::INFINITY, f64::min)
    };
    let edges: Vec<(DVec2, DVec2)> = region.edges().gather("edges")?;
    // Whether the disc of radius r around c meets the region.
    let meets = |c: DVec2, r: f64| {
        region.contains(c) || edges.iter().any(|(a, b)| segment_distance(c, *a, *b) <= r)
    };
    let mut best: Option<(DVec2, f64, f64, usize)> = None;
    // Vertices in doubles near the best of their cluster, and how far from
    // their clearance a site may be and still decide them.
    let mut contenders: Vec<(Vertex, f64)> = Vec::new();
    let mut decided_within: f64 = 0.0;
    for cluster in clusters(&frame, &near_pixels) {
        let (around, reach) = surroundings(&frame, &cluster);
        let slack = 3.0 * pixel_bound + lipschitz * reach;
        let near: Vec<Site> = all
            .iter()
            .filter(|s| s.distance(metric, around) <= value + slack)
            .copied()
            .gather("near")?;
        let allowed = |c: DVec2| {
            let tol = 1e-9 * (1.0 + c.abs().max_element());
            region.contains(c) || edges.iter().any(|(a, b)| segment_distance(c, *a, *b) < tol)
        };
        let found = if unit == Unit::Circle && near.iter().all(is_plain_point_or_segment) {
            // Exact: the best centre is a vertex of the diagram of points and
            // segments, or where its edges meet the region's boundary.
            let mut points = Vec::new();
            let mut lines = Vec::new();
            for site in &near {
                match site.shape {
                    Shape::Point(p) => points.push(p),
                    Shape::Segment(a, b) => {
                        points.extend([a, b]);
                        if a != b {
                            lines.push((a, b));
                        }
                    }
                    _ => unreachable!("points and segments"),
                }
            }
            let walls: Vec<(DVec2, DVec2)> = edges
                .iter()
                .filter(|(a, b)| segment_distance(around, *a, *b) <= reach)
                .copied()
                .gather("walls")?;
            let mut candidates = clearing_vertices(&points, &lines, &walls, |_| true);
            let given = walls
                .iter()
                .flat_map(|(a, b)| [*a, *b])
                .chain(points.iter().copied());
            candidates.extend(given.map(Vertex::at));
            candidates.retain(|v| {
                v.centre.is_finite() && v.centre.distance(around) <= reach && allowed(v.centre)
            });
            let cells = candidates.len();
            let mut bounded: Vec<(Vertex, f64)> = candidates
                .into_iter()
                .map(|v| (v, clearance(v.centre, &near)))
                .gather("bounded")?;
            bounded.sort_by(|a, b| b.1.total_cmp(&a.1));
            let mut best: Option<(DVec2, f64)> = None;
            for &(v, upper) in &bounded {
                if best.is_some_and(|b| upper <= b.1) {
                    break;
                }
                let value = clearance(v.centre, &all);
                if best.is_none_or(|b| value > b.1) {
                    best = Some((v.centre, value));
                }
            }
            // The vertices are computed in doubles, so the best one is proven
            // by a branch and bound that starts from it and stops at the
            // rounding of the clearances it evaluates.
            match best {
                None => None,
                Some((c, v)) => {
                    // Centres and the sites that decide them lie within about
                    // this of the origin.
                    let magnitude = around.abs().max_element() + 2.0 * reach + v.abs();
                    let rounding = 64.0 * f64::EPSILON * magnitude;
                    let found = branch_and_bound(
                        around,
                        reach,
                        |c, h| clearance_over_square(&points, &lines, c, h) + rounding,
                        |c| clearance(c, &all) - rounding,
                        allowed,
                        meets,
                        (Some((c, v - rounding)), |_| 4.0 * rounding),
                    )?
                    .map(|(c, _, gap, checked)| {
                        // The optimum lies between the value less its rounding
                        // and that plus the gap.
                        (c, clearance(c, &all), gap + rounding, cells + checked)
                    });
                    // The vertices that rounding may put above the best, for
                    // the exact decision.
                    let window = found.map_or(0.0, |f| f.2) + CONTENDING * rounding;
                    contenders.extend(
                        bounded
                            .iter()
                            .take_while(|b| b.1 >= v - window)
                            .take(MAX_CONTENDERS)
                            .map(|&(vertex, _)| (vertex, clearance(vertex.centre, &all))),
                    );
                    decided_within = decided_within.max(window);
                    found
                }
            }
        } else {
            branch_and_bound(
                around,
                reach,
                |c, h| clearance(c, &near) + lipschitz * h * std::f64::consts::SQRT_2,
                |c| clearance(c, &all),
                allowed,
                meets,
                (None, |best: f64| 1e-9 * (1.0 + best.abs())),
            )?
        };
        if let Some((c, v, gap, cells)) = found {
            if best.is_none_or(|b| v > b.1) {
                best = Some((c, v, gap, cells));
            }
        }
    }
    let (c, v, gap, cells) =
        best.ok_or_else(|| Error::degenerate("no empty homothet found".into()))?;
    let certified = if unit == Unit::Circle && all.iter().all(is_plain_point_or_segment) {
        contenders.retain(|(vertex, value)| {
            *value >= v - gap - decided_within && within(&region, vertex)
        });
        contenders.sort_by(|a, b| b.1.total_cmp(&a.1));
        let obstacles: Vec<Obstacle> = all.iter().map(obstacle).gather("obstacles")?;
        let near = |c: DVec2, r: f64| {
            let near =
                (0..obstacles.len() as u32).filter(|&i| obstacles[i as usize].distance(c) <= r);
            near.collect()
        };
        certify(&contenders, (&obstacles, &near), decided_within, placement)
    } else {
        None
    };
    // The gap bounds how far the optimum is; a search that closed it fully
    // leaves rounding.
    let tol = if gap > 0.0 {
        gap
    } else {
        1e-9 * (1.0 + v.abs())
    };
    let on: Vec<u32> = (0..all.len() as u32)
        .filter(|&i| (all[i as usize].distance(metric, c) - v).abs() <= tol)
        .gather("on")?;
    let homothet = Homothet {
        centre: c.to_array(),
        scale: v,
        sites: on,
    };
    let mut answer = answer_of(&frame, centre, value, pixel_bound, (homothet, cells));
    answer.tolerance = gap;
    Ok((answer, certified))
}

/// The power of two that brings the largest of `numbers` within 2^±16 of 1,
/// where one is needed and every number scales exactly.
fn unit_exponent(numbers: &[f64]) -> Option<i32> {
    let largest = numbers.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if largest == 0.0 || (2f64.powi(-16)..2f64.powi(16)).contains(&largest) {
        return None;
    }
    let k = -(largest.log2().floor() as i32);
    let t = scale::times_power_of_two;
    numbers.iter().all(|&x| t(t(x, k), -k) == x).then_some(k)
}

/// [`unit_exponent`], or 0 where the numbers are within `range`, or a
/// refusal that names it: the refinement's products would overflow or
/// underflow.
fn exponent_or_refusal(numbers: &[f64], (lo, hi): (f64, f64)) -> Result<i32> {
    if let Some(k) = unit_exponent(numbers) {
        return Ok(k);
    }
    let largest = numbers.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if largest == 0.0 || (lo..=hi).contains(&largest) {
        return Ok(0);
    }
    let smallest = numbers
        .iter()
        .map(|x| x.abs())
        .filter(|&x| x > 0.0)
        .fold(f64::INFINITY, f64::min);
    Err(Error::out_of_range(format!(
        "coordinates reach {largest:e}: the largest empty homothet is refined in doubles, \
         which hold its products of coordinates from about {lo:e} to {hi:e}, and no power \
         of two brings these coordinates there exactly (the smallest, {smallest:e}, would \
         fall below the normal doubles); round the smallest to 0 or scale the input into \
         that range"
    )))
}

/// The coordinates, radii and weights of `sites` and `region`.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
fn numbers_of(sites: &[Site], region: &Region) -> Vec<f64> {
    let of_sites = sites.iter().flat_map(|s| {
        let radius = match s.shape {
            Shape::Circle { radius, .. } | Shape::Arc { radius, .. } => radius,
            _ => 0.0,
        };
        let anchors = s.anchors().into_iter().flat_map(|p| [p.x, p.y]);
        anchors.chain([radius, s.additive])
    });
    of_sites
        .chain(region.rings.iter().flatten().flat_map(|p| [p.x, p.y]))
        .collect()
}

/// Whether a candidate centre may be decided exactly: one solved on a wall
/// (which the exact solution checks it lies on) or given, or one inside the
/// region. Candidates near the boundary are let in by a tolerance; those that
/// are no wall's may lie just outside, and where they lie on the boundary
/// exactly a wall's candidate is the same centre.
fn within(region: &Region, vertex: &Vertex) -> bool {
    let on_wall = |pieces: [Piece; 3]| pieces.iter().any(|p| matches!(p, Piece::Wall(..)));
    vertex.pieces.is_none_or(on_wall) || region.contains(vertex.centre)
}

/// How many roundings of the best clearance in doubles a vertex may fall
/// short of it and still be decided exactly.
const CONTENDING: f64 = 1024.0;

/// Vertices decided exactly per cluster, at most.
const MAX_CONTENDERS: usize = 64;

fn obstacle(site: &Site) -> Obstacle {
    match site.shape {
        Shape::Point(p) => Obstacle::Point(p),
        Shape::Segment(a, b) => Obstacle::Segment(a, b),
        _ => unreachable!("points and segments"),
    }
}

fn is_plain_point_or_segment(s: &Site) -> bool {
    matches!(s.shape, Shape::Point(_) | Shape::Segment(..))
        && s.multiplicative == 1.0
        && s.additive == 0.0
}

/// The region to search (the box `bounds` when none is given, checked
/// otherwise) and the frame that shows it.
fn region_and_frame(
    region: &Region,
    (lo, hi): (DVec2, DVec2),
    side: u32,
) -> Result<(Region, Frame)> {
    let defaulted = region.rings.is_empty();
    let region = if defaulted {
        Region {
            rings: Vec::from([Vec::from([
                lo,
                DVec2::new(hi.x, lo.y),
                hi,
                DVec2::new(lo.x, hi.y),
            ])]),
        }
    } else {
        check_region(region)?;
        region.clone()
    };
    let (lo, hi) = region
        .rings
        .iter()
        .flatten()
        .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(a, b), p| {
            (a.min(*p), b.max(*p))
        });
    if !(hi - lo).cmpgt(DVec2::ZERO).all() {
        return Err(Error::degenerate(if defaulted {
            "the sites' bounding box has no area (one site, or all on a line along an axis): give a region".into()
        } else {
            "the region has no area".into()
        }));
    }
    let frame = Frame::fitting(side, lo, hi)?;
    Ok((region, frame))
}

/// A drawn tile: ids, depth, its corner in the picture, the part that is
/// picture.
type Tile<'a> = (
    Option<&'a crate::machine::Image>,
    &'a crate::machine::Image,
    u32,
    u32,
    crate::machine::PixelRect,
);

/// A tile's highest depth inside the region (its `triangles`, the rest masked)
/// and the picture pixels near it (the highest first), unless the whole tile
/// is masked.
#[expect(clippy::disallowed_methods, reason = "the pixels near one maximum")]
fn highest_in_region(
    machine: &Machine,
    frame: &Frame,
    region_mesh: &RegionMesh,
    (ids, depth, x0, y0, inner): Tile<'_>,
    near: NearExtreme,
) -> Result<Option<(f32, Vec<usize>)>> {
    mask_outside(machine, ids, depth, region_mesh, x0, y0)?;
    let mut highest = machine.depth_extremes(depth, Some(near))?;
    if highest.near_count > highest.near.len() {
        // The list overflowed: ask again with room for every near pixel.
        let capacity = highest.near_count as u32;
        highest = machine.depth_extremes(depth, Some(NearExtreme { capacity, ..near }))?;
    }
    let w = depth.width() as usize;
    let to_picture = |at: usize| {
        let (i, j) = ((at % w) as u32, (at / w) as u32);
        (i < inner.width && j < inner.height)
            .then(|| (y0 + j) as usize * frame.width as usize + (x0 + i) as usize)
    };
    if highest.max <= 0.0 {
        return Ok(None);
    }
    Ok(to_picture(highest.at_max).map(|at| {
        let near = highest.near.iter().filter_map(|&a| to_picture(a));
        (highest.max, std::iter::once(at).chain(near).collect())
    }))
}

/// The sites' pixels (each once) and the farthest any site moved to its pixel
/// (in pixels), when the largest empty circle may take its pixel stage from
/// the distance transform: the device holds the picture whole and every site
/// lies on it or within a pixel of it (the frame fits the box's shorter side
/// to whole pixels). A pixel's distance to the snapped sites is within that
/// move of its true clearance.
fn snapped_seeds(
    machine: &Machine,
    sites: &[DVec2],
    unit: Unit,
    frame: &Frame,
) -> Result<Option<(Vec<Seed>, f64)>> {
    let (w, h) = (frame.width, frame.height);
    let side = flooding::MAX_SIDE.min(machine.max_picture_side());
    if unit != Unit::Circle || w > side || h > side {
        return Ok(None);
    }
    let far = DVec2::new((w - 1) as f64, (h - 1) as f64);
    let mut taken = crate::memory::filled(w as usize * h as usize, false, "the sites' pixels")?;
    let mut seeds = Vec::new();
    let mut moved2: f64 = 0.0;
    for p in sites {
        let q = frame.to_pixel(*p);
        let pixel = q.round().clamp(DVec2::ZERO, far);
        moved2 = moved2.max(q.distance_squared(pixel));
        if moved2 > 1.0 {
            return Ok(None);
        }
        let (i, j) = (pixel.x as u32, pixel.y as u32);
        if !std::mem::replace(&mut taken[(j * w + i) as usize], true) {
            seeds.push([i as i32, j as i32]);
        }
    }
    Ok(Some((seeds, moved2.sqrt())))
}

/// The pixel stage of the largest empty circle by the exact Euclidean distance
/// transform of the snapped sites (compute passes instead of cones): the
/// region's pixels within `within` pixels of its highest value, the highest
/// first.
fn listed_of_transform(
    machine: &Machine,
    seeds: &[Seed],
    frame: &Frame,
    region_mesh: &RegionMesh,
    within: f64,
) -> Result<Vec<usize>> {
    let (w, h) = (frame.width, frame.height);
    let depth = machine.image(Format::DepthStencil, w, h)?;
    // Squared distances in pixels plus one, scaled into [0, 1]; the listing
    // window on their roots is then a little wider than asked.
    let scale = (1.0 / (w as f64 * w as f64 + h as f64 * h as f64)) as f32;
    flooding::euclidean_depth(machine, seeds, &depth, scale)?;
    let near = near_extreme(Metric::L2, scale as f64, within, true);
    let picture = (None, &depth, 0, 0, PixelRect::of(&depth));
    let highest = highest_in_region(machine, frame, region_mesh, picture, near)?;
    Ok(highest.map(|(_, p)| p).unwrap_or_default())
}

/// The pixels of the tiles whose highest value is within `2 bound` of the
/// highest of all, `value`.
#[expect(
    clippy::disallowed_methods,
    reason = "per-pixel values of a picture whose room was reserved where it was placed"
)]
fn near_top(tiles: &[(f64, Vec<usize>)], value: f64, bound: f64) -> Vec<usize> {
    tiles
        .iter()
        .filter(|t| t.0 >= value - 2.0 * bound)
        .flat_map(|t| t.1.iter().copied())
        .collect()
}

fn check_region(region: &Region) -> Result<()> {
    for (r, ring) in region.rings.iter().enumerate() {
        if ring.len() < 3 {
            return Err(Error::malformed(format!(
                "region ring {r} has {} vertices; it needs 3",
                ring.len()
            )));
        }
        if ring.iter().any(|p| !p.is_finite()) {
            return Err(Error::not_finite(
                Some(r),
                format!("region ring {r} has a coordinate that is not finite"),
            ));
        }
    }
    Ok(())
}
