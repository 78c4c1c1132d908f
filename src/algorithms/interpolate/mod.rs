//! Scattered values interpolated onto a raster: natural-neighbour (Sibson)
//! interpolation, exact or rendered, and the nearest-site and linear
//! interpolants to compare with.
//!
//! - [`Method::Exact`]: Sibson's interpolant, each pixel centre's weights the
//!   areas a new site there would steal from its natural neighbours' Voronoi
//!   regions, from the exact Delaunay triangulation. The natural neighbours
//!   are decided by exact in-circle tests; the value is the double nearest
//!   the exact interpolant, settled by double-double arithmetic with an
//!   error bound, and by rationals where the bound cannot settle it.
//! - [`Method::Linear`]: barycentric interpolation in the exact Delaunay
//!   triangle holding the pixel centre, rounded as exactly (SciPy's
//!   `griddata(method="linear")`).
//! - [`Method::Nearest`]: the value of the exact nearest site (ties to the
//!   lower index), everywhere, as `griddata(method="nearest")`.
//! - [`Method::Discrete`]: the rendered discrete Sibson interpolant
//!   ([`discrete_sibson`]), whose error against the exact one its module
//!   states.
//!
//! Outside the sites' convex hull the natural-neighbour and linear methods
//! give NaN, as MetPy's `natural_neighbor_to_grid` and `griddata` do. On the
//! hull's edges Sibson's interpolant is the linear one along the edge.

mod discrete;
mod formulas;
pub(crate) mod walk;

pub use discrete::discrete_sibson;

use crate::memory::Gather;
use glam::DVec2;
use rayon::prelude::*;

use crate::{
    algorithms::{
        delaunay::{delaunay_checked, DelaunayOptions},
        voronoi::{voronoi_checked, VoronoiOptions},
    },
    cancel::Watch,
    control::Control,
    geometry::{
        exact::bounded::Bounded,
        exact::number::{nearest, Exact},
        frame::Checked,
        scale, Frame,
    },
    machine::PixelRect,
    Backend, Error, Need, Result,
};
use formulas::{centre_offset, linear, on_plane, sibson, slopes, Point};
use walk::{Place, Triangles};

/// How values are interpolated between the sites.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Method {
    /// Sibson's natural-neighbour interpolant, correctly rounded.
    #[default]
    Exact,
    /// The rendered discrete Sibson interpolant.
    Discrete,
    /// Barycentric in the Delaunay triangle, correctly rounded.
    Linear,
    /// The nearest site's value.
    Nearest,
}

impl Method {
    /// What the method needs of a device ([`Backend::choose`]): the CPU's
    /// triangulation and grid beat a software rasterizer; the discrete
    /// method draws its diagram with a margin, faster on a device.
    pub fn need(self) -> Need {
        match self {
            Method::Discrete => Need::DeviceIfAny,
            _ => Need::CpuUnlessGpu,
        }
    }
}

/// An interpolated raster.
#[derive(Clone, Debug)]
pub struct Interpolation {
    /// Row-major values, NaN where the method gives none.
    pub values: Vec<f64>,
    /// Pixels whose rounding the double-double bound left open, settled in
    /// rational arithmetic (exact and linear methods).
    pub decided_exactly: u64,
}

/// Rows interpolated between reports of progress and looks at the cancel
/// flag.
const BAND: usize = 16;

/// Where and how to interpolate: the picture, the method, a window of the
/// picture's pixels (`None`: all of them), and the work's progress (rows done)
/// and cancellation.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct InterpolateOptions {
    pub frame: Frame,
    pub method: Method,
    pub window: Option<PixelRect>,
    pub control: Control,
}

impl InterpolateOptions {
    pub fn new(frame: Frame, method: Method) -> Self {
        Self {
            frame,
            method,
            window: None,
            control: Control::new(),
        }
    }

    /// Only the pixels of `window`, a rectangle of the frame's: the same
    /// values bit for bit, so that windows computed apart tile into the
    /// whole raster. The discrete method takes the whole frame only (its
    /// values depend on the pixels drawn around them).
    pub fn window(self, window: Option<PixelRect>) -> Self {
        Self { window, ..self }
    }

    pub fn control(self, control: Control) -> Self {
        Self { control, ..self }
    }
}

/// `values` (one per site) interpolated at every pixel centre of
/// `options.frame` (or of its window) by `options.method`.
pub fn interpolate(
    backend: &Backend,
    sites: &[DVec2],
    values: &[f64],
    options: &InterpolateOptions,
) -> Result<Interpolation> {
    let progress = &mut |done, total| options.control.report(done, total);
    options
        .control
        .run(|| interpolate_on(backend, sites, values, options, progress))
}

fn interpolate_on(
    backend: &Backend,
    sites: &[DVec2],
    values: &[f64],
    options: &InterpolateOptions,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<Interpolation> {
    let (frame, method) = (&options.frame, options.method);
    check_values(sites, values)?;
    let checked = Checked::new(sites)?;
    let rect = frame.window_rect(options.window)?;
    let diagram = VoronoiOptions::exact(*frame)
        .distances(false)
        .window(Some(rect));
    // Bytes a pixel: the centres and values, the labels and values, or the
    // discrete method's pictures over the frame and its margins.
    let each = match method {
        Method::Exact | Method::Linear => 24,
        Method::Nearest => 12,
        Method::Discrete => 72,
    };
    crate::memory::reserve_picture(rect.width, rect.height, each, "an interpolated raster")?;
    let values = match method {
        Method::Nearest => {
            let labels = voronoi_checked(backend, checked, &diagram)?.labels;
            labels
                .iter()
                .map(|&l| values[l as usize])
                .gather("labels")?
        }
        Method::Discrete if rect != PixelRect::sized(frame.width, frame.height) => {
            return Err(Error::unsupported_option(
                "the discrete method interpolates whole rasters: a pixel's value depends on \
                 the pixels drawn around it, so windows would not tile into the whole"
                    .into(),
            ))
        }
        Method::Discrete => discrete::of_checked(backend.machine(), checked, values, frame)?,
        Method::Exact | Method::Linear => {
            let centres: Vec<DVec2> = (0..rect.height)
                .flat_map(|j| (0..rect.width).map(move |i| (rect.x + i, rect.y + j)))
                .map(|(i, j)| frame.to_world(DVec2::new(i as f64, j as f64)))
                .gather("centres")?;
            let corners = triangulated(backend, checked, values)?;
            let run = rect.width as usize;
            let sibson = method == Method::Exact;
            return on_triangles(sites, &corners, values, &centres, run, sibson, progress);
        }
    };
    progress(rect.height as u64, rect.height as u64);
    Ok(Interpolation {
        values,
        decided_exactly: 0,
    })
}

/// `values` (one per site) interpolated at each of `points` by the exact or
/// the linear method: the double nearest the interpolant at the doubles
/// given.
pub fn interpolate_points(
    backend: &Backend,
    sites: &[DVec2],
    values: &[f64],
    points: &[DVec2],
    method: Method,
) -> Result<Interpolation> {
    check_values(sites, values)?;
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(Error::not_finite(
            Some(i),
            format!("point {i} ({}, {}) is not finite", points[i].x, points[i].y),
        ));
    }
    if !matches!(method, Method::Exact | Method::Linear) {
        return Err(Error::unsupported_option(format!(
            "the {method:?} method interpolates onto rasters; at points, use the exact or \
             the linear method"
        )));
    }
    let corners = triangulated(backend, Checked::new(sites)?, values)?;
    let sibson = method == Method::Exact;
    on_triangles(sites, &corners, values, points, 256, sibson, &mut |_, _| {})
}

/// The Delaunay triangles of the sites, whose repeated points must agree on
/// their value.
fn triangulated(backend: &Backend, sites: Checked<'_>, values: &[f64]) -> Result<Vec<[u32; 3]>> {
    let mesh = delaunay_checked(backend, sites, &DelaunayOptions::default(), &mut |_, _| {})?;
    let differ =
        |[d, k]: &&[u32; 2]| values[*d as usize].to_bits() != values[*k as usize].to_bits();
    if let Some(&[dropped, kept]) = mesh.duplicates.iter().find(differ) {
        return Err(Error::malformed(format!(
            "sites {kept} and {dropped} lie at the same point with values {} and {}: give one \
             value for each point",
            values[kept as usize], values[dropped as usize]
        )));
    }
    Ok(mesh.triangles)
}

/// Refuses a count of values other than the sites' and values that are not
/// finite.
fn check_values(sites: &[DVec2], values: &[f64]) -> Result<()> {
    if values.len() != sites.len() {
        return Err(Error::malformed(format!(
            "{} values for {} sites: give one value per site",
            values.len(),
            sites.len()
        )));
    }
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(Error::not_finite(
            Some(i),
            format!("value {i} is {}: values are finite", values[i]),
        )),
        None => Ok(()),
    }
}

/// The Sibson (`sibson_weights`) or linear interpolant at each query
/// point, from the Delaunay triangles, in runs of `run` points (the rows of a
/// raster) that walk from each point to the next.
fn on_triangles(
    sites: &[DVec2],
    corners: &[[u32; 3]],
    values: &[f64],
    queries: &[DVec2],
    run: usize,
    sibson_weights: bool,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<Interpolation> {
    let mut out = crate::memory::filled(queries.len(), f64::NAN, "interpolated values")?;
    let runs = queries.len().div_ceil(run) as u64;
    if corners.is_empty() {
        // Sites on one line: the hull has no inside.
        progress(runs, runs);
        return Ok(Interpolation {
            values: out,
            decided_exactly: 0,
        });
    }
    let exact = Triangles::new(sites, corners);
    // Double-double sees coordinates scaled near 1 (by a power of two, which
    // changes no interpolant), so that its products neither overflow nor
    // underflow; on them the predicates need no scaling of their own.
    let k = scale::incircle_exponent(sites)?;
    let scaled_sites = scale::scaled(sites, k);
    let scaled = exact.scaled(&scaled_sites);
    let largest = scaled_sites
        .iter()
        .fold(0.0f64, |m, p| m.max(p.abs().max_element()));
    let triangles = 0..corners.len() as u32;
    let mesh = Mesh {
        offsets: match sibson_weights {
            true => triangles
                .clone()
                .into_par_iter()
                .map(|t| centre_offset(&scaled, t))
                .collect(),
            false => Vec::new(),
        },
        slopes: triangles
            .into_par_iter()
            .map(|t| slopes(&scaled, t, values))
            .collect(),
        exact,
        scaled,
        k,
        largest,
    };
    let watch = Watch::current();
    let mut decided_exactly = 0;
    let band = run * BAND;
    for (b, (outs, queries)) in out.chunks_mut(band).zip(queries.chunks(band)).enumerate() {
        watch.check()?;
        decided_exactly += outs
            .par_chunks_mut(run)
            .zip(queries.par_chunks(run))
            .map(|(outs, queries)| {
                let mut exactly = 0;
                let mut start = 0;
                for (out, &q) in outs.iter_mut().zip(queries) {
                    let (value, rational) = mesh.at(q, values, sibson_weights, &mut start)?;
                    *out = value;
                    exactly += u64::from(rational);
                }
                Ok(exactly)
            })
            .collect::<Result<Vec<u64>>>()?
            .iter()
            .sum::<u64>();
        progress((((b + 1) * BAND) as u64).min(runs), runs);
    }
    Ok(Interpolation {
        values: out,
        decided_exactly,
    })
}

/// The Delaunay triangles over the sites as given, and scaled for
/// double-double arithmetic and direct predicates.
struct Mesh<'a> {
    exact: Triangles<'a>,
    scaled: Triangles<'a>,
    /// Each scaled triangle's [`centre_offset`] (for Sibson's weights) and
    /// [`slopes`].
    offsets: Vec<Point<Bounded>>,
    slopes: Vec<[Bounded; 2]>,
    /// The scaling, 2^k, and the largest scaled coordinate.
    k: i32,
    largest: f64,
}

impl Mesh<'_> {
    /// `q` scaled, where the scaling is exact and leaves it in the range in
    /// which the scaled sites' predicates are exact as they are.
    fn scaled_point(&self, q: DVec2) -> Option<DVec2> {
        let sq = q.map(|x| scale::times_power_of_two(x, self.k));
        let floor = self.largest * 2f64.powi(-170);
        let fits = |x: f64| x == 0.0 || (floor..=self.largest).contains(&x.abs());
        (sq.map(|x| scale::times_power_of_two(x, -self.k)) == q && fits(sq.x) && fits(sq.y))
            .then_some(sq)
    }

    /// The interpolant at `q` (NaN outside the hull) and whether rationals
    /// settled it; `start` is where the walk begins, and is left where it
    /// ended.
    fn at(
        &self,
        q: DVec2,
        values: &[f64],
        sibson_weights: bool,
        start: &mut u32,
    ) -> Result<(f64, bool)> {
        let scaled = self.scaled_point(q);
        let (walk, p) = match scaled {
            Some(sq) => (&self.scaled, sq),
            None => (&self.exact, q),
        };
        let (t, inside) = match walk.locate(p, *start)? {
            Place::Outside(t) => {
                *start = t;
                return Ok((f64::NAN, false));
            }
            Place::Inside(t) => (t, true),
            Place::Boundary(t) => (t, false),
        };
        *start = t;
        let mut cavity = Vec::new();
        let sibson_weights = sibson_weights && inside;
        if sibson_weights {
            walk.cavity(p, t, &mut cavity);
        }
        let exact = &self.exact;
        let by_rationals = || -> Exact {
            match sibson_weights {
                true => sibson(q, exact, &cavity, |t| centre_offset(exact, t), values),
                false => linear(q, exact, t, values),
            }
        };
        // A point the scaling would move is settled in rationals at once.
        let Some(sq) = scaled else {
            return Ok((by_rationals().nearest(), true));
        };
        let offset = |t: u32| self.offsets[t as usize].clone();
        Ok(nearest(
            || -> Bounded {
                match sibson_weights {
                    true => sibson(sq, &self.scaled, &cavity, offset, values),
                    false => on_plane(sq, &self.scaled, t, &self.slopes[t as usize], values),
                }
            },
            by_rationals,
        ))
    }
}
