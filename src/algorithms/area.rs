//! The smallest and largest triangles and quadrangles with vertices among the
//! sites (thesis ch. 7).
//!
//! Given two vertices p and q of a triangle, its area is |pq| / 2 times the
//! third vertex's distance to the line pq. A saddle roof over p and q — an
//! upside-down roof whose ridge is that line, with the apex angle §7.3.2
//! chooses — is therefore exactly as high as that area over every point. All
//! pairs' roofs are drawn instanced, in one depth test that keeps, at
//! each site's pixel, the lowest roof (the smallest triangle with that site as
//! a vertex) and the colour names its pair. A roof never marks its own two
//! sites, and covers only the strip beside its own segment: a triangle is
//! found by the roof of its longest edge, onto which the opposite vertex
//! projects. The roofs reach across only as far as an area bound: the thesis's
//! pigeonhole bound (a triangulation of n sites has at least n - 2 triangles in
//! the hull) and the smallest triangle of neighbouring sites (§7.3.3's sample).
//! The largest triangle takes the reversed depth test and, since its vertices
//! are hull vertices, only the hull's roofs.
//!
//! Quadrangles have a diagonal pq with one vertex on each side (§7.3.4): the
//! roofs' fragments keep, per pair and side, the nearest (or farthest) site
//! with 64-bit atomics, which is the thesis's per-diagonal passes with
//! left/right colouring done in one pass.
//!
//! Each roof computes its height from the exact position of the site drawn in
//! the pixel, in double precision, so that the pixel stage is off only by
//! rounding. Its answer is then made exact: every site (or pair) whose pixel
//! value comes within rounding of the best is searched exhaustively in exact
//! arithmetic. A pixel shows one site; sites that share a pixel with another
//! are searched on the CPU: every triangle with such a site as a vertex, and
//! such sites on the sides of every diagonal.
//!
//! The file is long because the triangles and quadrangles, smallest and largest,
//! share the roofs' passes, the exact search of sites that share a pixel, and the
//! answer types.

use super::ms;
use crate::geometry::predicates::convex_hull;
use std::time::Instant;

use glam::DVec2;

use crate::{
    error::{Error, Result},
    geometry::{
        frame::{check_sites, first_of_each},
        scale, Frame,
    },
    geometry::{
        predicates::orient,
        triangle::{sides_of, triangle_area},
    },
    machine::{
        shaders, Buffer, Clear, ClearColor, Compare, DepthTest, Draw, DrawParams, Format,
        Fragments, GraphicsProgram, Image, Machine, NearExtreme, PixelRect, RasterState, Target,
        Topology,
    },
};

/// Push constants of the roof programs (`glsl/roof.glsl`): `[width, height,
/// bound, depth per area, maximum, segment]`.
type RoofWords = [u32; 6];

/// Saddle roofs over pairs of sites (thesis §7.3), one per instance without
/// vertex buffers, reading the sites (`f64` pairs) and the site drawn in each
/// pixel from storage buffers 0 and 1: the area as depth, the pair as colour.
static ROOF: GraphicsProgram = GraphicsProgram::new(
    "Roof",
    shaders::ROOF_VERT,
    Fragments::One(shaders::ROOF_FRAG_TRIANGLE),
    Topology::TriangleStrip,
    &[],
    std::mem::size_of::<RoofWords>(),
);

/// [`ROOF`] keeping per pair and side of its line the nearest (or farthest)
/// site in storage buffer 2; writes no attachment.
static ROOF_SIDES: GraphicsProgram = GraphicsProgram::new(
    "RoofSides",
    shaders::ROOF_VERT,
    Fragments::One(shaders::ROOF_FRAG_SIDES),
    Topology::TriangleStrip,
    &[],
    std::mem::size_of::<RoofWords>(),
);

/// The picture side (pixels, longer axis) for `n` sites when none is given:
/// about 64 pixels per site, so that few sites share a pixel (those are
/// searched on the CPU), and no more, since every roof's fragments cost.
pub fn default_side(n: usize) -> u32 {
    (8.0 * (n as f64).sqrt()).clamp(64.0, 1024.0) as u32
}

/// An extremal search drawn with the roofs: machine, sites, extreme, picture
/// side, progress (`extremal_triangle_with_progress`, `extremal_quadrangle_with_progress`).
pub type RoofSearch =
    fn(&Machine, &[DVec2], Extreme, u32, &mut dyn FnMut(u64, u64)) -> Result<AreaAnswer>;

/// An extremal search by the rotational sweep: sites, extreme, progress
/// (`extremal_triangle_sweep`, `extremal_quadrangle_sweep`).
pub type SweepSearch = fn(&[DVec2], Extreme, &mut dyn FnMut(u64, u64)) -> Result<AreaAnswer>;

/// Which extreme to find.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Extreme {
    Smallest,
    Largest,
}

impl Extreme {
    pub(crate) fn improves(self, area: f64, best: Option<f64>) -> bool {
        match (best, self) {
            (None, _) => true,
            (Some(b), Extreme::Smallest) => area < b,
            (Some(b), Extreme::Largest) => area > b,
        }
    }
}

/// An extremal triangle or quadrangle.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct AreaAnswer {
    pub extreme: Extreme,
    /// The vertices (site indices), counter-clockwise.
    pub sites: Vec<u32>,
    /// The exact area (world units squared).
    pub area: f64,
    /// The best area the pixels proposed, before the exact search.
    pub pixel_area: Option<f64>,
    /// Roofs drawn: one per pair of the sites searched.
    pub roofs: usize,
    /// The area the roofs reached across to (world units squared); `None`: the
    /// whole picture.
    pub bound: Option<f64>,
    /// Sites (triangles) or pairs (quadrangles) searched exhaustively.
    pub checked: usize,
    /// Sites that shared a pixel with another.
    pub shared: usize,
    pub width: u32,
    pub height: u32,
    /// The roofs' picture; `None` where none was drawn (the sweep, or an
    /// answer decided before drawing).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub frame: Option<Frame>,
    /// What decided the answer: `pixels`, `neighbours` (a triangle of
    /// neighbouring sites has area 0), `duplicates` (two sites coincide) or
    /// `collinear` (all sites on a line).
    pub decided_by: &'static str,
    /// Milliseconds: bounds and buffers on the CPU, drawing the roofs, the
    /// reduction and readback, the exact search.
    pub prepare_ms: f64,
    pub draw_ms: f64,
    pub reduce_ms: f64,
    pub exact_ms: f64,
}

/// The smallest or largest triangle with three of `sites` as vertices.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::algorithms::area::{extremal_triangle, Extreme};
///
/// let sites = [DVec2::ZERO, DVec2::new(4.0, 0.0), DVec2::new(0.0, 3.0), DVec2::new(1.0, 1.0)];
/// // The thesis's roofs, on a 64-pixel picture.
/// let t = pixgeo::with_default_machine(|m| extremal_triangle(m, &sites, Extreme::Smallest, 64))?;
/// assert_eq!(t.area, 1.5); // (0, 0), (0, 3), (1, 1)
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn extremal_triangle(
    machine: &Machine,
    sites: &[DVec2],
    extreme: Extreme,
    side: u32,
) -> Result<AreaAnswer> {
    extremal_triangle_with_progress(machine, sites, extreme, side, &mut |_, _| {})
}

/// [`extremal_triangle`], calling `progress(done, total)` as the roofs are drawn.
pub fn extremal_triangle_with_progress(
    machine: &Machine,
    sites: &[DVec2],
    extreme: Extreme,
    side: u32,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<AreaAnswer> {
    in_range(sites, |sites| {
        triangle_in_range(machine, sites, extreme, side, progress)
    })
}

/// Runs `answer` on the sites scaled by a power of two into the range where
/// areas (products of coordinates) neither overflow nor underflow, and scales
/// its areas back: the vertices are the same and the area exact to rounding;
/// an area beyond the largest float is refused.
pub(crate) fn in_range(
    sites: &[DVec2],
    answer: impl FnOnce(&[DVec2]) -> Result<AreaAnswer>,
) -> Result<AreaAnswer> {
    check_sites(sites)?;
    let k = scale::predicate_exponent(sites)?;
    if k == 0 {
        return answer(sites);
    }
    let mut found = answer(&scale::scaled(sites, k))?;
    // Areas are products of two coordinates: 2^k each.
    let back = -2 * k;
    found.area = scale::times_power_of_two(found.area, back);
    found.pixel_area = found.pixel_area.map(|a| scale::times_power_of_two(a, back));
    found.bound = found.bound.map(|a| scale::times_power_of_two(a, back));
    if !found.area.is_finite() {
        return Err(Error::InvalidInput(format!(
            "the {}'s area is beyond the largest float ({:e})",
            if found.sites.len() == 3 {
                "triangle"
            } else {
                "quadrangle"
            },
            f64::MAX
        )));
    }
    Ok(found)
}

fn triangle_in_range(
    machine: &Machine,
    sites: &[DVec2],
    extreme: Extreme,
    side: u32,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<AreaAnswer> {
    let started = Instant::now();
    if let Some(answer) = degenerate_triangle(sites, extreme)? {
        return Ok(answer);
    }
    let distinct = first_of_each(sites);
    let ordered = |v: [u32; 3]| counter_clockwise(sites, v.to_vec());
    let hull = convex_hull(sites);
    let chosen = match extreme {
        Extreme::Smallest => distinct,
        Extreme::Largest => hull.clone(),
    };
    let mut best: Option<(Vec<u32>, f64)> = None;
    let mut offer = |v: Vec<u32>, area: f64| {
        if extreme.improves(area, best.as_ref().map(|b| b.1)) {
            best = Some((v, area));
        }
    };
    let bound = match extreme {
        Extreme::Smallest => {
            let (triple, area, bound) = neighbour_triangle(sites, &chosen, hull.len());
            if area == 0.0 {
                return Ok(decided(extreme, ordered(triple), 0.0, "neighbours"));
            }
            offer(triple.to_vec(), area);
            Some(bound)
        }
        Extreme::Largest => None,
    };
    let roofs = Roofs::new(machine, sites, &chosen, side, extreme, bound, &hull)?;
    let frame = roofs.frame;
    let prepare_ms = ms(started);
    let started = Instant::now();
    let (depth, pairs) = roofs.draw_triangles(progress)?;
    let draw_ms = ms(started);
    let started = Instant::now();
    let near = machine.depth_extremes(
        &depth,
        Some(NearExtreme {
            maximum: extreme == Extreme::Largest,
            within: 1e-6,
            squared_scale: 0.0,
            capacity: 4096,
        }),
    )?;
    let extreme_depth = match extreme {
        Extreme::Smallest => near.min,
        Extreme::Largest => near.max,
    };
    let drawn = match extreme {
        Extreme::Smallest => near.min < 1.0,
        Extreme::Largest => near.max > 0.0,
    };
    // The pixels to search: those near the extreme (all site pixels when the
    // list overflowed).
    let pixels: Vec<usize> = if !drawn {
        Vec::new()
    } else if near.near_count > near.near.len() {
        roofs.owned_pixels()
    } else {
        std::iter::once(extreme_at(&near, extreme))
            .chain(near.near.iter().copied())
            .collect()
    };
    let pair_ids = roofs.pairs_at(machine, &pairs, &pixels)?;
    let reduce_ms = ms(started);
    let started = Instant::now();
    // The pixels' own triangles first, for the best so far.
    for (&at, &pair) in pixels.iter().zip(&pair_ids) {
        let s = roofs.owner[at];
        if s == NO_SITE || pair == NO_SITE {
            continue;
        }
        let (i, j) = pair_of(pair);
        let (i, j) = (chosen[i as usize], chosen[j as usize]);
        let s = chosen[s as usize];
        offer(
            vec![i, j, s],
            triangle_area(sites[i as usize], sites[j as usize], sites[s as usize]),
        );
    }
    // Then every triangle at every searched site, and at every site that shares
    // a pixel (the roof of a triangle's longest edge finds it at the opposite
    // vertex only if that vertex shows), exactly.
    let shared: Vec<u32> = roofs.shared.iter().map(|&k| chosen[k as usize]).collect();
    let searched: Vec<u32> = pixels
        .iter()
        .filter(|&&at| roofs.owner[at] != NO_SITE)
        .map(|&at| chosen[roofs.owner[at] as usize])
        .chain(shared.iter().copied())
        .collect();
    for &s in &searched {
        for (a, &i) in chosen.iter().enumerate() {
            for &j in &chosen[a + 1..] {
                if i != s && j != s {
                    offer(
                        vec![i, j, s],
                        triangle_area(sites[i as usize], sites[j as usize], sites[s as usize]),
                    );
                }
            }
        }
    }
    let checked = searched.len();
    let (vertices, area) = best.ok_or_else(|| Error::Internal("no triangle was found".into()))?;
    Ok(AreaAnswer {
        extreme,
        sites: counter_clockwise(sites, vertices),
        area,
        pixel_area: drawn.then(|| roofs.area_of_depth(extreme_depth)),
        roofs: roofs.count(),
        bound,
        checked,
        shared: shared.len(),
        width: frame.width,
        height: frame.height,
        frame: Some(frame),
        decided_by: "pixels",
        prepare_ms,
        draw_ms,
        reduce_ms,
        exact_ms: ms(started),
    })
}

/// The smallest or largest quadrangle with four of `sites` as vertices: a
/// diagonal with one vertex strictly on each side (sites on the diagonal's
/// line make no quadrangle with it).
pub fn extremal_quadrangle(
    machine: &Machine,
    sites: &[DVec2],
    extreme: Extreme,
    side: u32,
) -> Result<AreaAnswer> {
    extremal_quadrangle_with_progress(machine, sites, extreme, side, &mut |_, _| {})
}

/// [`extremal_quadrangle`], calling `progress(done, total)` as the roofs are
/// drawn and their sides reduced.
pub fn extremal_quadrangle_with_progress(
    machine: &Machine,
    sites: &[DVec2],
    extreme: Extreme,
    side: u32,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<AreaAnswer> {
    in_range(sites, |sites| {
        quadrangle_in_range(machine, sites, extreme, side, progress)
    })
}

fn quadrangle_in_range(
    machine: &Machine,
    sites: &[DVec2],
    extreme: Extreme,
    side: u32,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<AreaAnswer> {
    let started = Instant::now();
    let (chosen, hull) = quadrangle_candidates(sites, extreme)?;
    let points: Vec<DVec2> = chosen.iter().map(|&i| sites[i as usize]).collect();
    let bound = match extreme {
        Extreme::Smallest => neighbour_quadrangle(&points),
        Extreme::Largest => None,
    };
    let roofs = Roofs::new(machine, sites, &chosen, side, extreme, bound, &hull)?;
    let frame = roofs.frame;
    let px2 = frame.scale * frame.scale;
    let prepare_ms = ms(started);
    let started = Instant::now();
    let pairs = roofs.count();
    // Half the work is drawing, half reducing the sides.
    let total = 2 * pairs as u64;
    let keys = roofs.draw_sides(&mut |done, _| progress(done, total))?;
    let draw_ms = ms(started);
    let started = Instant::now();
    // Per pair: the best site on each side, from the pixels and from the sites
    // that share a pixel (exactly).
    let to_area = |key: u64| roofs.area_of_depth(f32::from_bits((key >> 32) as u32));
    let empty = match extreme {
        Extreme::Smallest => u64::MAX,
        Extreme::Largest => 0,
    };
    let mut sums: Vec<(f64, u32)> = Vec::new();
    for k in 0..pairs as u32 {
        if k % (1 << 16) == 0 {
            progress((pairs + k as usize) as u64, total);
        }
        let (i, j) = pair_of(k);
        let (p, q) = (points[i as usize], points[j as usize]);
        let mut side_best = [0usize, 1].map(|s| {
            let key = keys[2 * k as usize + s];
            (key != empty).then(|| to_area(key))
        });
        for &t in &roofs.shared {
            if t == i || t == j {
                continue;
            }
            let c = orient(p, q, points[t as usize]);
            if c != 0.0 {
                let s = usize::from(c < 0.0);
                let area = 0.5 * c.abs();
                if extreme.improves(area, side_best[s]) {
                    side_best[s] = Some(area);
                }
            }
        }
        if let [Some(a), Some(b)] = side_best {
            sums.push((a + b, k));
        }
    }
    // Pairs in the order of their pixel sums, searched exactly over every site
    // until no pair's sum, less its rounding, can beat the best exact one. A
    // pixel sum may be too good (a site on the diagonal's line, which makes
    // no quadrangle, rounds to a sliver on one side), never worse by more than
    // rounding, so the pair that wins is always reached.
    match extreme {
        Extreme::Smallest => sums.sort_by(|a, b| a.0.total_cmp(&b.0)),
        Extreme::Largest => sums.sort_by(|a, b| b.0.total_cmp(&a.0)),
    }
    let pixel_best = sums
        .first()
        .map(|s| s.0)
        .ok_or_else(|| Error::Internal("no diagonal has sites on both sides".into()))?;
    let reduce_ms = ms(started);
    let started = Instant::now();
    let slack = |sum: f64| 1e-6 * sum.abs() + 1e-9 / px2;
    let mut best: Option<(Vec<u32>, f64)> = None;
    let mut checked = 0;
    for &(sum, k) in &sums {
        if let Some((_, area)) = &best {
            let hopeless = match extreme {
                Extreme::Smallest => sum - slack(sum) > *area,
                Extreme::Largest => sum + slack(sum) < *area,
            };
            if hopeless {
                break;
            }
        }
        checked += 1;
        let (i, j) = pair_of(k);
        if let [Some((l, a)), Some((r, b))] =
            sides_of(&points, i as usize, j as usize, extreme == Extreme::Largest)
        {
            if extreme.improves(a + b, best.as_ref().map(|b| b.1)) {
                let v = [i, r, j, l].map(|x| chosen[x as usize]).to_vec();
                best = Some((v, a + b));
            }
        }
    }
    let (vertices, area) =
        best.ok_or_else(|| Error::Internal("no diagonal has sites strictly on both sides".into()))?;
    Ok(AreaAnswer {
        extreme,
        sites: vertices,
        area,
        pixel_area: Some(pixel_best),
        roofs: pairs,
        bound,
        checked,
        shared: roofs.shared.len(),
        width: frame.width,
        height: frame.height,
        frame: Some(frame),
        decided_by: "pixels",
        prepare_ms,
        draw_ms,
        reduce_ms,
        exact_ms: ms(started),
    })
}

/// The sites a quadrangle's vertices are searched among (the distinct ones;
/// for the largest, the hull's vertices where there are four), and the hull; an
/// error for fewer than four distinct sites or all on a line.
pub(crate) fn quadrangle_candidates(
    sites: &[DVec2],
    extreme: Extreme,
) -> Result<(Vec<u32>, Vec<u32>)> {
    check_sites(sites)?;
    let distinct = first_of_each(sites);
    let hull = convex_hull(sites);
    if distinct.len() < 4 || hull.len() < 3 {
        return Err(Error::InvalidInput(format!(
            "a quadrangle needs four distinct sites, not all on a line; there are {} distinct",
            distinct.len()
        )));
    }
    let chosen = match extreme {
        Extreme::Largest if hull.len() >= 4 => hull.clone(),
        _ => distinct,
    };
    Ok((chosen, hull))
}

/// The answer when two sites coincide (the smallest triangle) or all sites lie
/// on a line: area 0 either way; an error for bad sites or fewer than three.
pub(crate) fn degenerate_triangle(sites: &[DVec2], extreme: Extreme) -> Result<Option<AreaAnswer>> {
    check_sites(sites)?;
    if sites.len() < 3 {
        return Err(Error::InvalidInput(format!(
            "a triangle needs three sites; there are {}",
            sites.len()
        )));
    }
    if extreme == Extreme::Smallest {
        if let Some((a, b)) = duplicate_pair(sites, &first_of_each(sites)) {
            let c = (0..sites.len() as u32)
                .find(|&c| c != a && c != b)
                .expect("n >= 3");
            return Ok(Some(decided(extreme, vec![a, b, c], 0.0, "duplicates")));
        }
    }
    let hull = convex_hull(sites);
    if hull.len() < 3 {
        let mut v = hull.clone();
        v.extend(
            (0..sites.len() as u32)
                .filter(|c| !hull.contains(c))
                .take(3 - v.len()),
        );
        return Ok(Some(decided(extreme, v, 0.0, "collinear")));
    }
    Ok(None)
}

pub(crate) fn decided(
    extreme: Extreme,
    sites: Vec<u32>,
    area: f64,
    by: &'static str,
) -> AreaAnswer {
    AreaAnswer {
        extreme,
        sites,
        area,
        pixel_area: None,
        roofs: 0,
        bound: None,
        checked: 0,
        shared: 0,
        width: 0,
        height: 0,
        frame: None,
        decided_by: by,
        prepare_ms: 0.0,
        draw_ms: 0.0,
        reduce_ms: 0.0,
        exact_ms: 0.0,
    }
}

/// Two sites at one position, if any.
fn duplicate_pair(sites: &[DVec2], distinct: &[u32]) -> Option<(u32, u32)> {
    if distinct.len() == sites.len() {
        return None;
    }
    let mut seen = std::collections::HashMap::new();
    for (i, p) in sites.iter().enumerate() {
        if let Some(&j) = seen.get(&(p.x.to_bits(), p.y.to_bits())) {
            return Some((j, i as u32));
        }
        seen.insert((p.x.to_bits(), p.y.to_bits()), i as u32);
    }
    None
}

/// The vertices sorted counter-clockwise around their centroid, starting at the
/// smallest index.
pub(crate) fn counter_clockwise(sites: &[DVec2], mut v: Vec<u32>) -> Vec<u32> {
    let c = v.iter().map(|&i| sites[i as usize]).sum::<DVec2>() / v.len() as f64;
    v.sort_by(|&a, &b| {
        let angle = |i: u32| {
            let d = sites[i as usize] - c;
            d.y.atan2(d.x)
        };
        angle(a).total_cmp(&angle(b))
    });
    let first = (0..v.len()).min_by_key(|&k| v[k]).expect("vertices");
    v.rotate_left(first);
    v
}

fn polygon_area(sites: &[DVec2], ring: &[u32]) -> f64 {
    let p = |k: usize| sites[ring[k % ring.len()] as usize];
    0.5 * (0..ring.len())
        .map(|k| p(k).perp_dot(p(k + 1)))
        .sum::<f64>()
        .abs()
}

/// Neighbouring sites along rows of square cells (boustrophedon), whose
/// consecutive triples and quadruples are small shapes: the sample of §7.3.3.
fn neighbour_order(points: &[DVec2]) -> Vec<usize> {
    let lo = points.iter().fold(DVec2::INFINITY, |a, p| a.min(*p));
    let hi = points.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
    let extent = (hi - lo).max_element().max(f64::MIN_POSITIVE);
    let cell = extent / (points.len() as f64).sqrt().max(1.0);
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by_cached_key(|&k| {
        let p = points[k] - lo;
        let row = (p.y / cell) as i64;
        let x = (p.x / cell * 1024.0) as i64;
        (row, if row % 2 == 0 { x } else { -x })
    });
    order
}

/// The smallest triangle of consecutive neighbours and its area, and an upper
/// bound on the smallest triangle: that area or the pigeonhole bound (the
/// hull's area over the 2n - h - 2 triangles of any triangulation, at least
/// n - 2), whichever is smaller.
fn neighbour_triangle(sites: &[DVec2], chosen: &[u32], hull: usize) -> ([u32; 3], f64, f64) {
    let points: Vec<DVec2> = chosen.iter().map(|&i| sites[i as usize]).collect();
    let order = neighbour_order(&points);
    let mut best = ([0, 1, 2].map(|k| chosen[order[k]]), f64::INFINITY);
    for w in order.windows(4) {
        for t in [[w[0], w[1], w[2]], [w[0], w[1], w[3]], [w[0], w[2], w[3]]] {
            let area = triangle_area(points[t[0]], points[t[1]], points[t[2]]);
            if area < best.1 {
                best = (t.map(|k| chosen[k]), area);
            }
        }
    }
    if order.len() == 3 {
        let t = [order[0], order[1], order[2]];
        best = (
            t.map(|k| chosen[k]),
            triangle_area(points[t[0]], points[t[1]], points[t[2]]),
        );
    }
    let hull_ring = convex_hull(&points);
    let triangles = (2 * points.len()).saturating_sub(hull + 2).max(1);
    let pigeonhole = polygon_area(&points, &hull_ring) / triangles as f64;
    (best.0, best.1, best.1.min(pigeonhole))
}

/// The smallest quadrangle of four consecutive neighbours, if any is one.
fn neighbour_quadrangle(points: &[DVec2]) -> Option<f64> {
    let order = neighbour_order(points);
    let mut best: Option<f64> = None;
    for w in order.windows(4) {
        // The three ways to choose a diagonal among four points.
        for (p, q, a, b) in [(0, 1, 2, 3), (0, 2, 1, 3), (0, 3, 1, 2)] {
            let (p, q) = (points[w[p]], points[w[q]]);
            let (ca, cb) = (orient(p, q, points[w[a]]), orient(p, q, points[w[b]]));
            if ca * cb < 0.0 {
                let area = 0.5 * (ca.abs() + cb.abs());
                if best.is_none_or(|x| area < x) {
                    best = Some(area);
                }
            }
        }
    }
    best
}

/// "No site" in a pixel, "no pair" in the pair picture.
const NO_SITE: u32 = u32::MAX;

/// Instance k's pair (i, j), i < j: k = j (j - 1) / 2 + i (`glsl/roof.glsl`).
fn pair_of(k: u32) -> (u32, u32) {
    let k = k as u64;
    let mut j = ((1.0 + (1.0 + 8.0 * k as f64).sqrt()) / 2.0).floor() as u64;
    while j * (j - 1) / 2 > k {
        j -= 1;
    }
    while (j + 1) * j / 2 <= k {
        j += 1;
    }
    ((k - j * (j - 1) / 2) as u32, j as u32)
}

/// The roofs of every pair of the chosen sites on one picture.
struct Roofs<'m> {
    machine: &'m Machine,
    frame: Frame,
    /// The chosen sites in picture pixels, `[x, y]` as f64.
    sites: Buffer,
    /// The chosen site drawn in each pixel (an index into the chosen ones).
    owners: Buffer,
    owner: Vec<u32>,
    /// Chosen sites whose pixel shows another.
    shared: Vec<u32>,
    chosen: usize,
    extreme: Extreme,
    /// How far the roofs reach across (an area in pixels squared), if bounded.
    bound_px: Option<f64>,
    /// Depth per unit of area (world units squared).
    depth_per_area: f64,
}

impl<'m> Roofs<'m> {
    /// The roofs of the `chosen` sites' pairs reaching across as far as `bound`
    /// (an area; `None`: the whole picture), for sites whose hull is `hull`.
    fn new(
        machine: &'m Machine,
        sites: &[DVec2],
        chosen: &[u32],
        side: u32,
        extreme: Extreme,
        bound: Option<f64>,
        hull: &[u32],
    ) -> Result<Self> {
        if !machine.has_float64() || !machine.has_fragment_atomics64() {
            return Err(Error::InvalidInput(format!(
                "{} lacks double precision or 64-bit atomics in shaders, which the saddle roofs need",
                machine.device_name()
            )));
        }
        if chosen.len() > 65535 {
            return Err(Error::InvalidInput(format!(
                "{} sites make more pairs than one draw can number; at most 65535",
                chosen.len()
            )));
        }
        if side == 0 || side > machine.max_picture_side() {
            return Err(Error::InvalidInput(format!(
                "picture side {side}: it must be between 1 and {} on this device",
                machine.max_picture_side()
            )));
        }
        let points: Vec<DVec2> = chosen.iter().map(|&i| sites[i as usize]).collect();
        let lo = points.iter().fold(DVec2::INFINITY, |a, p| a.min(*p));
        let hi = points.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
        let pad = DVec2::splat(0.01 * (hi - lo).max_element());
        let frame = Frame::fitting(side, lo - pad, hi + pad)?;
        let (w, h) = (frame.width as usize, frame.height as usize);
        let mut owner = vec![NO_SITE; w * h];
        let mut shared = Vec::new();
        let mut position: Vec<[f64; 2]> = Vec::with_capacity(points.len());
        for (k, p) in points.iter().enumerate() {
            let c = frame.to_pixel(*p);
            position.push([c.x, c.y]);
            let (i, j) = (c.x.round(), c.y.round());
            let inside = i >= 0.0 && j >= 0.0 && (i as usize) < w && (j as usize) < h;
            let at = j as usize * w + i as usize;
            if inside && owner[at] == NO_SITE {
                owner[at] = k as u32;
            } else {
                shared.push(k as u32);
            }
        }
        let mut sites_buffer = machine.storage_buffer((position.len() * 16) as u64)?;
        sites_buffer.write(&position);
        let mut owners = machine.storage_buffer((owner.len() * 4) as u64)?;
        owners.write(&owner);
        // Widened a little: the shaders take the bound in float32.
        let bound = bound.map(|b| b * (1.0 + 1e-5));
        // Depths: areas up to the bound map into [0, 1/2] (the clear value 1
        // stays clear of the near list); the largest triangle in the hull has at
        // least 3√3/(4π) of its area, so the hull's area keeps it well inside
        // [0, 1].
        let depth_per_area = match bound {
            Some(b) => 0.5 / b,
            None => 1.0 / (polygon_area(sites, hull) * 1.001),
        };
        let px2 = frame.scale * frame.scale;
        Ok(Self {
            machine,
            frame,
            sites: sites_buffer,
            owners,
            owner,
            shared,
            chosen: points.len(),
            extreme,
            bound_px: bound.map(|b| b * px2),
            depth_per_area,
        })
    }

    /// The area (world units squared) of a roof's depth.
    fn area_of_depth(&self, z: f32) -> f64 {
        z as f64 / self.depth_per_area
    }

    fn count(&self) -> usize {
        self.chosen * (self.chosen - 1) / 2
    }

    /// The roof programs' push constants (`glsl/roof.glsl`): areas there are in
    /// pixels squared.
    fn push(&self, segment: bool) -> RoofWords {
        let depth_per_pixel_area = self.depth_per_area / (self.frame.scale * self.frame.scale);
        [
            (self.frame.width as f32).to_bits(),
            (self.frame.height as f32).to_bits(),
            (self.bound_px.unwrap_or(0.0) as f32).to_bits(),
            (depth_per_pixel_area as f32).to_bits(),
            u32::from(self.extreme == Extreme::Largest),
            u32::from(segment),
        ]
    }

    /// Every pair's roof (`segment`: only over the segment's strip) into
    /// `target`, the fragment shader reading `buffers`: instanced, in about 64
    /// submissions so that `progress(done, total)` can tell how far it is.
    #[allow(clippy::too_many_arguments)]
    fn draw_roofs(
        &self,
        program: &'static GraphicsProgram,
        state: &RasterState,
        target: Target<'_>,
        clear: Clear,
        buffers: &[&Buffer],
        segment: bool,
        progress: &mut dyn FnMut(u64, u64),
    ) -> Result<()> {
        let push = self.push(segment);
        let count = self.count() as u32;
        let chunk = count.div_ceil(64).max(1 << 14);
        // At least one submission, which clears the target.
        for first in (0..count.max(1)).step_by(chunk as usize) {
            let last = (first + chunk).min(count);
            self.machine.run(|pass| {
                pass.bind_fragment_buffers(buffers, None)?;
                pass.begin(target, if first == 0 { clear } else { Clear::default() })?;
                pass.draw(
                    state,
                    &DrawParams::default(),
                    &Draw {
                        program,
                        variant: 0,
                        push: bytemuck::bytes_of(&push),
                        vertex_buffers: &[],
                        vertices: 0..4,
                        instances: first..last,
                    },
                )?;
                pass.end()
            })?;
            progress(last as u64, count as u64);
        }
        Ok(())
    }

    /// Every pair's roof with the depth test keeping the extreme: the depth
    /// ([`Roofs::area_of_depth`]) and the pair picture.
    fn draw_triangles(&self, progress: &mut dyn FnMut(u64, u64)) -> Result<(Image, Image)> {
        let machine = self.machine;
        let (w, h) = (self.frame.width, self.frame.height);
        let depth = machine.image(Format::Depth, w, h)?;
        let pairs = machine.image(Format::R32Uint, w, h)?;
        let (compare, clear) = match self.extreme {
            Extreme::Smallest => (Compare::Less, 1.0),
            Extreme::Largest => (Compare::Greater, 0.0),
        };
        let state = RasterState::OVERWRITE.with_depth(DepthTest {
            compare,
            write: true,
        });
        // A triangle is found by its longest edge's roof: the segment's strip.
        self.draw_roofs(
            &ROOF,
            &state,
            Target {
                color: Some(&pairs),
                depth_stencil: Some(&depth),
            },
            Clear {
                color: Some(ClearColor::Uint([NO_SITE; 4])),
                depth: Some(clear),
                stencil: None,
            },
            &[&self.sites, &self.owners],
            true,
            progress,
        )?;
        Ok((depth, pairs))
    }

    /// Every pair's roof keeping, per pair and side, the extreme (area bits,
    /// site) key; returns the keys, two per pair (left, right).
    fn draw_sides(&self, progress: &mut dyn FnMut(u64, u64)) -> Result<Vec<u64>> {
        let machine = self.machine;
        let (w, h) = (self.frame.width, self.frame.height);
        let slots = 2 * self.count();
        let mut best = machine.storage_buffer((slots * 8) as u64)?;
        best.fill(match self.extreme {
            Extreme::Smallest => 0xFF,
            Extreme::Largest => 0,
        });
        let depth = machine.image(Format::Depth, w, h)?;
        // A quadrangle's diagonal need not be its longest edge: the whole line.
        self.draw_roofs(
            &ROOF_SIDES,
            &RasterState::OVERWRITE,
            Target {
                color: None,
                depth_stencil: Some(&depth),
            },
            Clear {
                depth: Some(1.0),
                ..Clear::default()
            },
            &[&self.sites, &self.owners, &best],
            false,
            progress,
        )?;
        Ok(best.read(slots))
    }

    /// The pixels that show a site.
    fn owned_pixels(&self) -> Vec<usize> {
        (0..self.owner.len())
            .filter(|&k| self.owner[k] != NO_SITE)
            .collect()
    }

    /// The pair picture at `pixels`: one pixel at a time for a few, the whole
    /// picture for many.
    fn pairs_at(&self, machine: &Machine, pairs: &Image, pixels: &[usize]) -> Result<Vec<u32>> {
        let w = self.frame.width as usize;
        if pixels.len() > 16 {
            let all = machine.read_u32(pairs, PixelRect::of(pairs))?;
            return Ok(pixels.iter().map(|&k| all[k]).collect());
        }
        pixels
            .iter()
            .map(|&k| {
                let rect = PixelRect {
                    x: (k % w) as u32,
                    y: (k / w) as u32,
                    width: 1,
                    height: 1,
                };
                Ok(machine.read_u32(pairs, rect)?[0])
            })
            .collect()
    }
}

fn extreme_at(near: &crate::machine::DepthExtremes, extreme: Extreme) -> usize {
    match extreme {
        Extreme::Smallest => near.at_min,
        Extreme::Largest => near.at_max,
    }
}
