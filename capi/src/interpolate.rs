//! Scattered values interpolated onto a raster.

use super::*;
use pixgeo::algorithms::interpolate::{interpolate, InterpolateOptions, Method};

/// How [`pixgeo_interpolate`] interpolates.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoInterpolation {
    /// Sibson's natural-neighbour interpolant from the exact Delaunay
    /// triangulation, each value the double nearest the exact one.
    Exact = 0,
    /// The rendered discrete Sibson interpolant.
    Discrete = 1,
    /// Barycentric in the exact Delaunay triangle, correctly rounded.
    Linear = 2,
    /// The nearest site's value.
    Nearest = 3,
}

/// Interpolates `values` (one per site) at the `count` sites `xy` (x, y
/// pairs, world coordinates) at every pixel centre of the picture `options`
/// describes (its size and box; the other options are unused) by `method`, a
/// [`PixgeoInterpolation`]. `raster` receives `width * height` values,
/// row-major, NaN outside the sites' convex hull (all but the nearest
/// method). Unless null, `decided_exactly` receives how many pixels exact
/// rational arithmetic settled where double-double could not.
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles and `values`
/// `count`; `options` points to valid options; `raster` has room for `width
/// * height` doubles; `decided_exactly` is null or writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn pixgeo_interpolate(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    values: *const f64,
    count: usize,
    options: *const PixgeoVoronoiOptions,
    method: u32,
    raster: *mut f64,
    decided_exactly: *mut u64,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if options.is_null() || values.is_null() || raster.is_null() {
            return Err(invalid("options, values and raster must not be null"));
        }
        // SAFETY: non-null and valid (caller contract).
        let o = unsafe { read_options(options, "pixgeo_voronoi_options_default") }?;
        let (frame, _, _) = picture_of(&o)?;
        let method = match method {
            0 => Method::Exact,
            1 => Method::Discrete,
            2 => Method::Linear,
            3 => Method::Nearest,
            other => {
                return Err(invalid(format!(
                    "method {other} is not a PixgeoInterpolation (0 exact, 1 discrete, 2 linear, 3 nearest)"
                )))
            }
        };
        // SAFETY: `2 * count` doubles (caller contract).
        let sites = unsafe { points(xy, count) }?;
        // SAFETY: `count` doubles (caller contract); `points` checked the count.
        let values = unsafe { std::slice::from_raw_parts(values, count) };
        let answer = interpolate(
            &context.backend_for(method.need())?,
            &sites,
            values,
            &InterpolateOptions::new(frame, method),
        )
        .map_err(failed)?;
        // SAFETY: caller-owned array of `width * height` doubles.
        unsafe { std::slice::from_raw_parts_mut(raster, answer.values.len()) }
            .copy_from_slice(&answer.values);
        if !decided_exactly.is_null() {
            // SAFETY: non-null and writable (caller contract).
            unsafe { *decided_exactly = answer.decided_exactly };
        }
        Ok(())
    })
}
