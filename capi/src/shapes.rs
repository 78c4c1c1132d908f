//! Shapes of point sets: extremal triangles and quadrangles (thesis §3.11.4),
//! α-hulls (§3.12).

use super::*;
use pixgeo::algorithms::{
    alpha_hull::{self, AlphaMethod, AlphaOptions},
    area::{self, AreaOptions, AreaSearch, Extreme},
};

/// Which extreme [`pixgeo_triangle`] and [`pixgeo_quadrangle`] find.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoExtreme {
    Smallest = 0,
    Largest = 1,
}

/// How [`pixgeo_triangle`] and [`pixgeo_quadrangle`] search.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoAreaMethod {
    /// The exact rotational sweep on the CPU, O(n² log n) (default).
    Sweep = 0,
    /// The thesis's roofs, one per pair of sites, drawn on the context's
    /// device, then an exact search of the pixels' candidates.
    Roofs = 1,
}

/// Options of [`pixgeo_triangle`] and [`pixgeo_quadrangle`]; start from
/// [`pixgeo_area_options_default`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixgeoAreaOptions {
    /// `sizeof(PixgeoAreaOptions)`, set by [`pixgeo_area_options_default`].
    pub struct_size: u32,
    /// A [`PixgeoExtreme`].
    pub extreme: u32,
    /// A [`PixgeoAreaMethod`].
    pub method: u32,
    /// The roofs' picture side in pixels along the longer axis (0: about 8√n).
    pub side: u32,
}

/// The smallest, by the sweep.
#[no_mangle]
pub extern "C" fn pixgeo_area_options_default() -> PixgeoAreaOptions {
    PixgeoAreaOptions {
        struct_size: struct_size::<PixgeoAreaOptions>(),
        extreme: PixgeoExtreme::Smallest as u32,
        method: PixgeoAreaMethod::Sweep as u32,
        side: 0,
    }
}

/// An extremal triangle or quadrangle: its `vertex_count` (3 or 4) vertices as
/// site indices, counter-clockwise, and its exact area (world units squared).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixgeoPolygonAnswer {
    pub sites: [u32; 4],
    pub vertex_count: u32,
    pub area: f64,
}

/// Runs `search` with the caller's arguments (the safety contract of
/// [`pixgeo_triangle`]).
unsafe fn extremal(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    options: *const PixgeoAreaOptions,
    out: *mut PixgeoPolygonAnswer,
    search: AreaSearch,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if out.is_null() {
            return Err(invalid("out must not be null"));
        }
        // SAFETY: null or valid (caller contract).
        let o = unsafe { read_options(options, "pixgeo_area_options_default") }?;
        // SAFETY: `xy` holds `2 * count` doubles (caller contract).
        let sites = unsafe { points(xy, count) }?;
        let extreme = match o.extreme {
            0 => Extreme::Smallest,
            1 => Extreme::Largest,
            other => {
                return Err(invalid(format!(
                    "extreme {other} is not a PixgeoExtreme (0 smallest, 1 largest)"
                )))
            }
        };
        let side = (o.side != 0).then_some(o.side);
        let backend = match o.method {
            0 => Backend::Cpu,
            1 => Backend::Device(context.machine("the extremal shapes' roofs")?),
            other => {
                return Err(invalid(format!(
                    "method {other} is not a PixgeoAreaMethod (0 sweep, 1 roofs)"
                )))
            }
        };
        let answer =
            search(&backend, &sites, &AreaOptions::new(extreme).side(side)).map_err(failed)?;
        let mut polygon = PixgeoPolygonAnswer {
            vertex_count: answer.sites.len() as u32,
            area: answer.area,
            ..Default::default()
        };
        polygon.sites[..answer.sites.len()].copy_from_slice(&answer.sites);
        // SAFETY: non-null and writable (caller contract).
        unsafe { *out = polygon };
        Ok(())
    })
}

/// The smallest or largest triangle with three of the `count` points `xy` as
/// vertices, exact.
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles; `options` points to
/// valid options; `out` points to a writable answer.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_triangle(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    options: *const PixgeoAreaOptions,
    out: *mut PixgeoPolygonAnswer,
) -> PixgeoStatus {
    // SAFETY: the caller's contract is `extremal`'s.
    unsafe { extremal(ctx, xy, count, options, out, area::extremal_triangle) }
}

/// The smallest or largest quadrangle (simple, possibly not convex) with four
/// of the `count` points `xy` as vertices, exact.
///
/// # Safety
/// As [`pixgeo_triangle`].
#[no_mangle]
pub unsafe extern "C" fn pixgeo_quadrangle(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    options: *const PixgeoAreaOptions,
    out: *mut PixgeoPolygonAnswer,
) -> PixgeoStatus {
    // SAFETY: the caller's contract is `extremal`'s.
    unsafe { extremal(ctx, xy, count, options, out, area::extremal_quadrangle) }
}

/// How [`pixgeo_alpha_hull`] computes a hull for α > 0.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoAlphaMethod {
    /// Circles through consecutive points of the convex hull (default).
    Hull = 0,
    /// Two intersections of discs by counting, on the device alone.
    Pixels = 1,
}

/// Options of [`pixgeo_alpha_hull`]; start from [`pixgeo_alpha_options_default`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixgeoAlphaOptions {
    /// `sizeof(PixgeoAlphaOptions)`, set by [`pixgeo_alpha_options_default`].
    pub struct_size: u32,
    /// α: 0 the convex hull, > 0 discs of radius 1/α holding every site, < 0
    /// discs of radius 1/|α| holding none.
    pub alpha: f64,
    /// A [`PixgeoAlphaMethod`].
    pub method: u32,
    /// Picture side in pixels along the longer axis (0: 1024); the picture is
    /// fitted to where the hull can be.
    pub side: u32,
}

/// The convex hull (α = 0) by the hull method on a picture of the default side.
#[no_mangle]
pub extern "C" fn pixgeo_alpha_options_default() -> PixgeoAlphaOptions {
    PixgeoAlphaOptions {
        struct_size: struct_size::<PixgeoAlphaOptions>(),
        alpha: 0.0,
        method: PixgeoAlphaMethod::Hull as u32,
        side: 0,
    }
}

/// What a pixel of an α-hull's picture is.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoAlphaClass {
    Outside = 0,
    Inside = 1,
    /// α < 0: at least 1/|α| from every site. α > 0 with the pixels method: the
    /// centre of a disc holding every site.
    Centre = 2,
    /// α < 0: erased by a disc around the rim of the centres.
    Disc = 3,
}

/// The picture of an α-hull and what was found on it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixgeoAlphaHull {
    pub width: u32,
    pub height: u32,
    /// World point at the picture's corner (-0.5, -0.5), and pixels per world unit.
    pub origin: [f64; 2],
    pub scale: f64,
    /// 1/|α| in world units; NaN for the convex hull.
    pub radius: f64,
    /// Pixels inside the hull.
    pub inside: usize,
    /// α > 0 by the hull method, and α = 0: the number of sites on the hull's
    /// boundary.
    pub boundary_count: usize,
    /// α < 0: pixels within this distance (world units) of the border may be
    /// inside only because discs centred beyond it are not drawn; `uncertain`
    /// of the inside pixels lie there.
    pub border_band: f64,
    pub uncertain: usize,
}

/// The α-hull of the `count` points `xy` (thesis §3.12). `*out` always gets the
/// picture's size and the counts. Unless null, `pixels` receives a
/// [`PixgeoAlphaClass`] per pixel (`width * height`, row-major) and `boundary`
/// the boundary's site indices, counter-clockwise; when either's capacity is
/// too small the call returns [`PixgeoStatus::BufferTooSmall`] with `*out`
/// filled in, to be repeated with room enough.
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles; `options` points to
/// valid options; `out` points to a writable answer; `pixels` is null or has
/// room for `pixels_capacity` bytes, `boundary` null or room for
/// `boundary_capacity` values.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn pixgeo_alpha_hull(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    options: *const PixgeoAlphaOptions,
    out: *mut PixgeoAlphaHull,
    pixels: *mut u8,
    pixels_capacity: usize,
    boundary: *mut u32,
    boundary_capacity: usize,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if out.is_null() {
            return Err(invalid("out must not be null"));
        }
        // SAFETY: null or valid (caller contract).
        let o = unsafe { read_options(options, "pixgeo_alpha_options_default") }?;
        let method = match o.method {
            0 => AlphaMethod::Hull,
            1 => AlphaMethod::Pixels,
            other => {
                return Err(invalid(format!(
                    "method {other} is not a PixgeoAlphaMethod (0 hull, 1 pixels)"
                )))
            }
        };
        let side = if o.side == 0 {
            alpha_hull::DEFAULT_SIDE
        } else {
            o.side
        };
        // SAFETY: `xy` holds `2 * count` doubles (caller contract).
        let sites = unsafe { points(xy, count) }?;
        let hull = alpha_hull::alpha_hull(
            context.machine("an alpha hull")?,
            &sites,
            &AlphaOptions::new(o.alpha).method(method).side(side),
        )
        .map_err(failed)?;
        let answer = PixgeoAlphaHull {
            width: hull.width,
            height: hull.height,
            origin: hull.origin,
            scale: hull.scale,
            radius: hull.radius.unwrap_or(f64::NAN),
            inside: hull.inside,
            boundary_count: hull.boundary_sites.len(),
            border_band: hull.border_band,
            uncertain: hull.uncertain,
        };
        // SAFETY: non-null and writable (caller contract).
        unsafe { *out = answer };
        // SAFETY: null or with room for their capacities (caller contract).
        unsafe {
            copy_out(&hull.pixels, pixels, pixels_capacity, "pixels")?;
            copy_out(
                &hull.boundary_sites,
                boundary,
                boundary_capacity,
                "boundary",
            )
        }
    })
}

/// Copies `values` to `to` unless it is null, refusing a capacity too small.
///
/// # Safety
/// `to` is null or has room for `capacity` values.
unsafe fn copy_out<T: Copy>(
    values: &[T],
    to: *mut T,
    capacity: usize,
    what: &str,
) -> Result<(), (PixgeoStatus, String)> {
    if to.is_null() {
        return Ok(());
    }
    if capacity < values.len() {
        return Err((
            PixgeoStatus::BufferTooSmall,
            format!(
                "{what} has room for {capacity} values, the answer has {}",
                values.len()
            ),
        ));
    }
    // SAFETY: room for `capacity` >= `values.len()` values (caller contract).
    unsafe { std::slice::from_raw_parts_mut(to, values.len()) }.copy_from_slice(values);
    Ok(())
}
