//! Options structs shared by several calls, and how C values become the library's.

use std::ptr;

use glam::DVec2;

use super::*;
use pixgeo::{
    algorithms::voronoi::{Accuracy, Method, Speedup, VoronoiOptions},
    geometry::{
        metric::Metric,
        site::{Shape, Site},
        Frame,
    },
    machine::PixelRect,
};

/// The shape of a [`PixgeoSite`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoSiteKind {
    /// `coords = {x, y}`.
    Point = 0,
    /// `coords = {x1, y1, x2, y2}`.
    Segment = 1,
    /// `coords = {cx, cy, radius}`.
    Circle = 2,
    /// `coords = {cx, cy, radius, start, end}`: counter-clockwise from angle
    /// `start` to `end` (radians).
    Arc = 3,
}

/// A site of any shape with weights (thesis §3.8–3.9): its weighted distance is
/// the distance to the shape divided by `multiplicative` (> 0) plus `additive`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixgeoSite {
    /// A [`PixgeoSiteKind`].
    pub kind: u32,
    /// World coordinates, as [`PixgeoSiteKind`] lays them out; unused ones ignored.
    pub coords: [f64; 5],
    pub multiplicative: f64,
    pub additive: f64,
}

/// How cones are drawn.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoAccuracy {
    /// Exact distance per pixel: every label is a nearest site.
    Exact = 0,
    /// Triangle fans: distances within `epsilon` (or `triangles` per cone).
    Fan = 1,
}

/// The distance function (thesis §3.6).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoMetric {
    /// The Euclidean norm (default).
    L2 = 0,
    L1 = 1,
    LInf = 2,
    /// L_p with `p = metric_p` > 0.
    Lp = 3,
    /// The polygonal distance whose unit ball is `polygon` around `kernel`
    /// (thesis §3.6.5); the polygon must be star-shaped around its kernel.
    Polygon = 4,
}

/// How far cones reach.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoSpeedup {
    /// A radius per site (default).
    Local = 0,
    /// The thesis's quadtree radius with minmax-checked retries.
    Quadtree = 1,
    /// Picture-wide cones.
    None = 2,
}

/// How exact Euclidean labels are found; every way gives the same labels bit
/// for bit.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoVoronoiMethod {
    /// The grid on a software rasterizer, the cones on a GPU (default).
    Auto = 0,
    /// The lower envelope of cones drawn on the device.
    Cones = 1,
    /// A search of a grid of the sites on the CPU, proven like the cones.
    Grid = 2,
}

/// Options of [`pixgeo_voronoi`]; start from [`pixgeo_voronoi_options_default`].
/// Valid options have `polygon` pointing at `2 * polygon_count` doubles when the
/// metric is [`PixgeoMetric::Polygon`].
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PixgeoVoronoiOptions {
    /// `sizeof(PixgeoVoronoiOptions)`, set by [`pixgeo_voronoi_options_default`].
    pub struct_size: u32,
    /// Picture size in pixels.
    pub width: u32,
    pub height: u32,
    /// Map the world rectangle `bbox = {xmin, ymin, xmax, ymax}` onto the picture
    /// (its aspect ratio must match the picture's to within a pixel); otherwise
    /// pixel (i, j) is centred at world point (i, j).
    pub use_bbox: bool,
    pub bbox: [f64; 4],
    /// The distance function, a [`PixgeoMetric`] (both accuracy modes take
    /// every metric). Enumerations are read as integers: a value outside the
    /// enumeration is an invalid argument.
    pub metric: u32,
    /// The exponent of [`PixgeoMetric::Lp`].
    pub metric_p: f64,
    /// The vertices `{x0, y0, x1, y1, ...}` of [`PixgeoMetric::Polygon`]'s unit
    /// ball, `polygon_count` of them, and its kernel point; read during the call.
    pub polygon: *const f64,
    pub polygon_count: usize,
    pub kernel: [f64; 2],
    /// A [`PixgeoAccuracy`].
    pub accuracy: u32,
    /// Distance error bound of fan mode, pixels.
    pub epsilon: f64,
    /// Triangles per fan cone; 0 = the fewest for `epsilon`.
    pub triangles: u32,
    /// A [`PixgeoSpeedup`].
    pub speedup: u32,
    /// Largest tile side in pixels; 0 = as large as the device allows.
    pub max_tile: u32,
    /// `{x0, y0, width, height}`: compute only this window of the picture's
    /// pixels (bit for bit the whole diagram's there), and write `width *
    /// height` values; a width of 0 means the whole picture. Point sites only.
    pub window: [u32; 4],
    /// A [`PixgeoVoronoiMethod`]: how exact Euclidean labels of points are found.
    pub method: u32,
}

/// Default Voronoi options for a `width` x `height` picture: Euclidean, exact,
/// local radii, no bounding box, tiles as large as the device allows.
#[no_mangle]
pub extern "C" fn pixgeo_voronoi_options_default(width: u32, height: u32) -> PixgeoVoronoiOptions {
    PixgeoVoronoiOptions {
        struct_size: struct_size::<PixgeoVoronoiOptions>(),
        width,
        height,
        use_bbox: false,
        bbox: [0.0; 4],
        metric: PixgeoMetric::L2 as u32,
        metric_p: 2.0,
        polygon: ptr::null(),
        polygon_count: 0,
        kernel: [0.0; 2],
        accuracy: PixgeoAccuracy::Exact as u32,
        epsilon: 1.0,
        triangles: 0,
        speedup: PixgeoSpeedup::Local as u32,
        max_tile: 0,
        window: [0; 4],
        method: PixgeoVoronoiMethod::Auto as u32,
    }
}

/// The window of the options, if any (width 0: the whole picture).
pub(super) fn window_of(o: &PixgeoVoronoiOptions) -> Option<PixelRect> {
    let [x, y, width, height] = o.window;
    (width > 0).then_some(PixelRect {
        x,
        y,
        width,
        height,
    })
}

/// The library's sites for the C ones.
pub(super) fn sites_of(given: &[PixgeoSite]) -> Result<Vec<Site>, (PixgeoStatus, String)> {
    let mut sites = Vec::new();
    reserve(&mut sites, given.len(), "sites")?;
    for (i, s) in given.iter().enumerate() {
        let c = s.coords;
        let shape = match s.kind {
            0 => Shape::Point(DVec2::new(c[0], c[1])),
            1 => Shape::Segment(DVec2::new(c[0], c[1]), DVec2::new(c[2], c[3])),
            2 => Shape::Circle {
                center: DVec2::new(c[0], c[1]),
                radius: c[2],
            },
            3 => Shape::Arc {
                center: DVec2::new(c[0], c[1]),
                radius: c[2],
                start: c[3],
                end: c[4],
            },
            other => {
                return Err(invalid(format!(
                    "site {i}: kind {other} is not a PixgeoSiteKind \
                     (0 point, 1 segment, 2 circle, 3 arc)"
                )))
            }
        };
        sites.push(Site {
            shape,
            multiplicative: s.multiplicative,
            additive: s.additive,
        });
    }
    Ok(sites)
}

/// The frame, accuracy and speedup that `options` describe.
pub(super) fn picture_of(
    o: &PixgeoVoronoiOptions,
) -> Result<(Frame, Accuracy, Speedup), (PixgeoStatus, String)> {
    let frame = if o.use_bbox {
        Frame::with_bbox(o.width, Some(o.height), o.bbox)
    } else {
        Frame::pixels(o.width, o.height)
    }
    .map_err(failed)?;
    let accuracy = match o.accuracy {
        0 => Accuracy::Exact,
        1 => Accuracy::Fan {
            epsilon: o.epsilon,
            triangles: (o.triangles > 0).then_some(o.triangles),
        },
        other => {
            return Err(invalid(format!(
                "accuracy {other} is not a PixgeoAccuracy (0 exact, 1 fan)"
            )))
        }
    };
    let speedup = match o.speedup {
        0 => Speedup::Local,
        1 => Speedup::Quadtree,
        2 => Speedup::None,
        other => {
            return Err(invalid(format!(
                "speedup {other} is not a PixgeoSpeedup (0 local, 1 quadtree, 2 none)"
            )))
        }
    };
    Ok((frame, accuracy, speedup))
}

/// The distance function that `options` name.
pub(super) fn metric_of(o: &PixgeoVoronoiOptions) -> Result<Metric, (PixgeoStatus, String)> {
    Ok(match o.metric {
        0 => Metric::L2,
        1 => Metric::L1,
        2 => Metric::LInf,
        3 => Metric::lp(o.metric_p).map_err(invalid)?,
        4 => {
            // SAFETY: `polygon` is null or holds `2 * polygon_count` doubles
            // (caller contract of every call taking options).
            let vertices = unsafe { points(o.polygon, o.polygon_count) }?;
            Metric::polygon(&vertices, DVec2::from(o.kernel)).map_err(invalid)?
        }
        other => {
            return Err(invalid(format!(
                "metric {other} is not a PixgeoMetric (0 L2, 1 L1, 2 L-infinity, 3 L_p, 4 polygon)"
            )))
        }
    })
}

/// `count` points from `xy = {x0, y0, x1, y1, ...}`.
///
/// # Safety
/// `xy` is null or holds `2 * count` doubles.
pub(super) unsafe fn points(
    xy: *const f64,
    count: usize,
) -> Result<Vec<DVec2>, (PixgeoStatus, String)> {
    if xy.is_null() {
        return Err(invalid("a point array is null"));
    }
    check_count(count, 16, "points")?;
    // The work on the points, asked for before their copy takes its share.
    pixgeo::memory::reserve_sites(count).map_err(failed)?;
    // SAFETY: `xy` holds `2 * count` doubles (caller contract); the count
    // was checked to fit.
    let coords = unsafe { std::slice::from_raw_parts(xy, 2 * count) };
    let mut points = Vec::new();
    reserve(&mut points, count, "points")?;
    points.extend(coords.chunks_exact(2).map(|p| DVec2::new(p[0], p[1])));
    Ok(points)
}

/// Refuses a count of items of `bytes` each that no array of the host's, nor
/// pixgeo's 32-bit ids, can hold.
pub(super) fn check_count(
    count: usize,
    bytes: usize,
    what: &str,
) -> Result<(), (PixgeoStatus, String)> {
    let fits = count < u32::MAX as usize && count.saturating_mul(bytes) <= isize::MAX as usize;
    match fits {
        true => Ok(()),
        false => Err(invalid(format!(
            "{count} {what}: pixgeo takes fewer than 2^32 - 1 (ids are 32-bit)"
        ))),
    }
}

/// Room for `count` items in `v`, or a message saying how much memory they
/// need, in place of an abort.
pub(super) fn reserve<T>(
    v: &mut Vec<T>,
    count: usize,
    what: &str,
) -> Result<(), (PixgeoStatus, String)> {
    v.try_reserve_exact(count).map_err(|_| {
        let error = pixgeo::Error::HostMemory {
            what: format!("{count} {what}"),
            bytes: (count as u64).saturating_mul(std::mem::size_of::<T>() as u64),
        };
        (super::status_of(&error), error.to_string())
    })
}

/// The size C's `sizeof` gives an options struct: its `struct_size`.
pub(super) fn struct_size<T>() -> u32 {
    std::mem::size_of::<T>() as u32
}

/// Options a caller made with `default_fn` (and then changed), checked by the
/// `struct_size` they start with. Only this version's size exists so far; when
/// a struct grows, the sizes of its older versions will be read as a prefix of
/// it over the defaults.
///
/// # Safety
/// `options` is null or points to a `T` whose first field is its `u32`
/// `struct_size`, readable for `struct_size` bytes.
pub(super) unsafe fn read_options<T: Copy>(
    options: *const T,
    default_fn: &str,
) -> Result<T, (PixgeoStatus, String)> {
    if options.is_null() {
        return Err(invalid("options must not be null"));
    }
    // SAFETY: every options struct starts with its `u32` struct_size (caller
    // contract), and the pointer is non-null.
    let size = unsafe { options.cast::<u32>().read_unaligned() };
    let expected = struct_size::<T>();
    if size == 0 {
        return Err(invalid(format!(
            "options have struct_size 0: start them from {default_fn}()"
        )));
    }
    if size != expected {
        return Err(invalid(format!(
            "options have struct_size {size}, but this library's are {expected} bytes: the \
             header and the library come from different pixgeo versions (compare \
             PIXGEO_VERSION_* with pixgeo_version())"
        )));
    }
    // SAFETY: non-null, and `size` matches `T` (caller contract).
    Ok(unsafe { options.read() })
}

/// The library's options for the diagram `o` describes, with distances and
/// ties as asked.
pub(super) fn voronoi_options(
    o: &PixgeoVoronoiOptions,
    distances: bool,
    ties: bool,
) -> Result<VoronoiOptions, (PixgeoStatus, String)> {
    let (frame, accuracy, speedup) = picture_of(o)?;
    let method = match o.method {
        0 => Method::Auto,
        1 => Method::Cones,
        2 => Method::Grid,
        other => {
            return Err(invalid(format!(
                "method {other} is not a PixgeoVoronoiMethod (0 auto, 1 cones, 2 grid)"
            )))
        }
    };
    Ok(VoronoiOptions::exact(frame)
        .method(method)
        .metric(metric_of(o)?)
        .accuracy(accuracy)
        .speedup(speedup)
        .distances(distances)
        .ties(ties)
        .max_tile((o.max_tile > 0).then_some(o.max_tile))
        .window(window_of(o)))
}

/// Copies a diagram's labels to `to_labels`, and its distances to
/// `to_distances` unless that is null.
///
/// # Safety
/// `to_labels` has room for `labels.len()` values; `to_distances` is null or
/// has room for `distances.len()`.
pub(super) unsafe fn write_diagram(
    labels: &[u32],
    to_labels: *mut u32,
    distances: &[f32],
    to_distances: *mut f32,
) {
    // SAFETY: room for `labels.len()` values (caller contract).
    unsafe { std::slice::from_raw_parts_mut(to_labels, labels.len()) }.copy_from_slice(labels);
    if !to_distances.is_null() {
        // SAFETY: room for `distances.len()` values (caller contract).
        unsafe { std::slice::from_raw_parts_mut(to_distances, distances.len()) }
            .copy_from_slice(distances);
    }
}
