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

use super::ms;
use crate::geometry::exact::predicates::convex_hull;
use crate::memory::Gather;
use std::{cmp::Ordering, time::Instant};

use glam::DVec2;

use crate::{
    error::{Error, Result},
    geometry::{
        exact::predicates::orient,
        exact::triangle::{area_bounds, compare_areas, convex_ring_area, exact_area, sides_of},
    },
    geometry::{
        frame::{check_sites, first_of_each},
        scale, Frame,
    },
    machine::{
        shaders, Buffer, Clear, ClearColor, Compare, DepthTest, Draw, DrawParams, Format,
        Fragments, GraphicsProgram, Image, Machine, NearExtreme, PixelRect, RasterState, Target,
        Topology,
    },
    Backend, Control,
};

mod exact;
mod roofs;
mod sweep;

pub(crate) use exact::*;
use roofs::*;
use sweep::{extremal_quadrangle_sweep, extremal_triangle_sweep};

/// The picture side (pixels, longer axis) for `n` sites when none is given:
/// about 64 pixels per site, so that few sites share a pixel (those are
/// searched on the CPU), and no more, since every roof's fragments cost.
pub fn default_side(n: usize) -> u32 {
    (8.0 * (n as f64).sqrt()).clamp(64.0, 1024.0) as u32
}

/// An extremal search, [`extremal_triangle`] or [`extremal_quadrangle`].
pub type AreaSearch = fn(&Backend, &[DVec2], &AreaOptions) -> Result<AreaAnswer>;

/// How to search: the extreme, the side of the roofs' picture on a device
/// (`None`: [`default_side`]; the CPU's sweep draws none and takes none), and
/// the work's progress and cancellation.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct AreaOptions {
    pub extreme: Extreme,
    pub side: Option<u32>,
    pub control: Control,
}

impl AreaOptions {
    pub fn new(extreme: Extreme) -> Self {
        Self {
            extreme,
            side: None,
            control: Control::new(),
        }
    }

    pub fn side(self, side: Option<u32>) -> Self {
        Self { side, ..self }
    }

    pub fn control(self, control: Control) -> Self {
        Self { control, ..self }
    }
}

/// The roofs' side on a device; on the CPU, a side is refused.
fn side_on(backend: &Backend, sites: &[DVec2], options: &AreaOptions) -> Result<u32> {
    match (backend, options.side) {
        (Backend::Cpu, Some(_)) => Err(Error::unsupported_option(
            "a side sets the roofs' picture; the CPU's rotational sweep draws none (name a \
             Vulkan device to draw the roofs)"
                .into(),
        )),
        (_, side) => Ok(side.unwrap_or(default_side(sites.len()))),
    }
}

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

/// The best ring of sites offered so far, by exact area: floats decide where
/// their error bounds keep two areas apart, rationals where not; the first
/// offered wins ties.
pub(crate) struct BestRing {
    extreme: Extreme,
    best: Option<(Vec<u32>, (f64, f64))>,
}

impl BestRing {
    pub(crate) fn new(extreme: Extreme) -> Self {
        Self {
            extreme,
            best: None,
        }
    }

    /// Offers the ring `ring` of `sites`.
    pub(crate) fn offer(&mut self, sites: &[DVec2], ring: &[u32]) {
        let bounds = area_bounds(sites, ring);
        let better = match &self.best {
            None => true,
            Some((best, best_bounds)) => {
                let order = compare_areas(sites, (ring, bounds), (best, *best_bounds));
                order
                    == match self.extreme {
                        Extreme::Smallest => Ordering::Less,
                        Extreme::Largest => Ordering::Greater,
                    }
            }
        };
        if better {
            self.best = Some((ring.to_vec(), bounds));
        }
    }

    /// The best ring's area as a float, if any.
    pub(crate) fn estimate(&self) -> Option<f64> {
        self.best.as_ref().map(|(_, (area, _))| *area)
    }

    /// The best ring and its exact area rounded to the nearest double.
    pub(crate) fn exact(self, sites: &[DVec2]) -> Option<(Vec<u32>, f64)> {
        self.best.map(|(ring, _)| {
            let area = exact_area(sites, &ring);
            (ring, area)
        })
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
    /// What decided the answer.
    pub decided_by: Decided,
    /// Milliseconds: bounds and buffers on the CPU, drawing the roofs, the
    /// reduction and readback, the exact search.
    pub prepare_ms: f64,
    pub draw_ms: f64,
    pub reduce_ms: f64,
    pub exact_ms: f64,
}

/// What decided an extremal shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Decided {
    /// The roofs' pixels proposed it, an exact search settled it.
    Pixels,
    /// The rotational sweep.
    Sweep,
    /// A triangle of neighbouring sites has area 0.
    Neighbours,
    /// Two sites coincide.
    Duplicates,
    /// All sites lie on a line.
    Collinear,
}

impl std::fmt::Display for Decided {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Decided::Pixels => "pixels",
            Decided::Sweep => "sweep",
            Decided::Neighbours => "neighbours",
            Decided::Duplicates => "duplicates",
            Decided::Collinear => "collinear",
        })
    }
}

/// The smallest or largest triangle with three of `sites` as vertices: on a
/// device by the thesis's roofs, on the CPU by the rotational sweep
/// (`sweep.rs`); both exact, the same triangle.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::algorithms::area::{extremal_triangle, AreaOptions, Extreme};
///
/// let sites = [DVec2::ZERO, DVec2::new(4.0, 0.0), DVec2::new(0.0, 3.0), DVec2::new(1.0, 1.0)];
/// let options = AreaOptions::new(Extreme::Smallest);
/// let t = extremal_triangle(&pixgeo::Backend::Cpu, &sites, &options)?;
/// assert_eq!(t.area, 1.5); // (0, 0), (0, 3), (1, 1)
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn extremal_triangle(
    backend: &Backend,
    sites: &[DVec2],
    options: &AreaOptions,
) -> Result<AreaAnswer> {
    let side = side_on(backend, sites, options)?;
    let (extreme, progress) = (options.extreme, &mut |d, t| options.control.report(d, t));
    options.control.run(|| match backend {
        Backend::Device(machine) => in_range(sites, |sites| {
            triangle_in_range(machine, sites, extreme, side, progress)
        }),
        Backend::Cpu => extremal_triangle_sweep(sites, extreme, progress),
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
        return Err(Error::out_of_range(format!(
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
    let mut best = BestRing::new(extreme);
    let bound = match extreme {
        Extreme::Smallest => {
            let (triple, area, bound) = neighbour_triangle(sites, &chosen, hull.len());
            if area == 0.0 {
                return Ok(decided(extreme, ordered(triple), 0.0, Decided::Neighbours));
            }
            best.offer(sites, &triple);
            Some(bound)
        }
        Extreme::Largest => None,
    };
    let roofs = Roofs::new(machine, sites, &chosen, side, extreme, bound, &hull)?;
    // Pixels within twice the depths' error of the extreme hold a vertex of
    // the best triangle; where that band is most of the depth range (nearly
    // collinear sites, whose areas vanish against the picture's), the exact
    // sweep decides instead.
    let within = (2.0 * roofs.depth_error()).max(1e-6);
    if within > 0.25 {
        return extremal_triangle_sweep(sites, extreme, progress);
    }
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
            within: within as f32,
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
            .gather("pixels")?
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
        best.offer(sites, &[i, j, s]);
    }
    // Then every triangle at every searched site, and at every site that shares
    // a pixel (the roof of a triangle's longest edge finds it at the opposite
    // vertex only if that vertex shows), exactly.
    let shared: Vec<u32> = roofs
        .shared
        .iter()
        .map(|&k| chosen[k as usize])
        .gather("shared")?;
    let searched: Vec<u32> = pixels
        .iter()
        .filter(|&&at| roofs.owner[at] != NO_SITE)
        .map(|&at| chosen[roofs.owner[at] as usize])
        .chain(shared.iter().copied())
        .gather("searched")?;
    for &s in &searched {
        for (a, &i) in chosen.iter().enumerate() {
            for &j in &chosen[a + 1..] {
                if i != s && j != s {
                    best.offer(sites, &[i, j, s]);
                }
            }
        }
    }
    let checked = searched.len();
    let (vertices, area) = best
        .exact(sites)
        .ok_or_else(|| Error::Internal("no triangle was found".into()))?;
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
        decided_by: Decided::Pixels,
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
    backend: &Backend,
    sites: &[DVec2],
    options: &AreaOptions,
) -> Result<AreaAnswer> {
    let side = side_on(backend, sites, options)?;
    let (extreme, progress) = (options.extreme, &mut |d, t| options.control.report(d, t));
    options.control.run(|| match backend {
        Backend::Device(machine) => in_range(sites, |sites| {
            quadrangle_in_range(machine, sites, extreme, side, progress)
        }),
        Backend::Cpu => extremal_quadrangle_sweep(sites, extreme, progress),
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
    let points: Vec<DVec2> = chosen.iter().map(|&i| sites[i as usize]).gather("points")?;
    let bound = match extreme {
        Extreme::Smallest => neighbour_quadrangle(&points),
        Extreme::Largest => None,
    };
    let roofs = Roofs::new(machine, sites, &chosen, side, extreme, bound, &hull)?;
    // As for triangles: sites too nearly collinear for the picture's depths
    // go to the exact sweep.
    if 2.0 * roofs.depth_error() > 0.25 {
        return extremal_quadrangle_sweep(sites, extreme, progress);
    }
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
    let depth_slack = 2.0 * roofs.depth_error() / roofs.depth_per_area;
    let mut sums: Vec<(f64, u32)> = Vec::new();
    // Pairs with a site within rounding of their line.
    let mut lined = 0;
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
        // A site within rounding of the diagonal's line goes to both sides
        // (it may belong to either): where a side's best is such a site, the
        // other side's best may be it too, so the sum stays below the pair's
        // exact best for the smallest.
        let near = |v: f64| v <= depth_slack;
        lined += usize::from(side_best.iter().flatten().any(|&v| near(v)));
        let sum = match side_best {
            [Some(a), Some(b)] => Some(match extreme {
                Extreme::Smallest => {
                    let own = |v: f64, other: f64| if near(other) { 0.0 } else { v };
                    own(a, b) + own(b, a)
                }
                Extreme::Largest => a + b,
            }),
            _ => None,
        };
        if let Some(sum) = sum {
            sums.push((sum, k));
        }
    }
    // Where many pairs have a site on their line (lattices, decimal ones
    // nearly), the pixels cannot order them: the exact sweep decides.
    if extreme == Extreme::Smallest && lined > pairs / 16 {
        return extremal_quadrangle_sweep(sites, extreme, progress);
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
    let slack = |sum: f64| 1e-6 * sum.abs() + 1e-9 / px2 + depth_slack;
    let mut best = BestRing::new(extreme);
    let mut checked = 0;
    for &(sum, k) in &sums {
        if let Some(area) = best.estimate() {
            let hopeless = match extreme {
                Extreme::Smallest => sum - slack(sum) > area,
                Extreme::Largest => sum + slack(sum) < area,
            };
            if hopeless {
                break;
            }
        }
        checked += 1;
        let (i, j) = pair_of(k);
        if let [Some((l, _)), Some((r, _))] =
            sides_of(&points, i as usize, j as usize, extreme == Extreme::Largest)
        {
            best.offer(sites, &[i, r, j, l].map(|x| chosen[x as usize]));
        }
    }
    let (vertices, area) = best
        .exact(sites)
        .ok_or_else(|| Error::Internal("no diagonal has sites strictly on both sides".into()))?;
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
        decided_by: Decided::Pixels,
        prepare_ms,
        draw_ms,
        reduce_ms,
        exact_ms: ms(started),
    })
}
