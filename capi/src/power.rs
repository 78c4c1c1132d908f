//! Power diagrams and regular triangulations of weighted points.

use super::*;
use pixgeo::{
    algorithms::power::{power_diagram, regular_triangulation, PowerOptions},
    geometry::power::Weighted,
};

/// The `count` weighted sites from `xy` and `weights`.
///
/// # Safety
/// `xy` holds `2 * count` doubles and `weights` `count`, unless null.
unsafe fn weighted(
    xy: *const f64,
    weights: *const f64,
    count: usize,
) -> Result<Vec<Weighted>, (PixgeoStatus, String)> {
    if weights.is_null() {
        return Err(invalid("weights must not be null"));
    }
    // SAFETY: `2 * count` doubles (caller contract).
    let at = unsafe { points(xy, count) }?;
    // SAFETY: `count` doubles (caller contract); `points` checked the count.
    let w = unsafe { std::slice::from_raw_parts(weights, count) };
    Ok(Weighted::zip(&at, w))
}

/// Marks the hidden sites: `hidden[i]` becomes 1 when site `i`'s power cell
/// is empty, else 0.
///
/// # Safety
/// `hidden` is null or has room for `count` bytes.
unsafe fn mark_hidden(hidden: *mut u8, count: usize, which: &[u32]) {
    if hidden.is_null() {
        return;
    }
    // SAFETY: room for `count` bytes (caller contract).
    let flags = unsafe { std::slice::from_raw_parts_mut(hidden, count) };
    flags.fill(0);
    for &h in which {
        flags[h as usize] = 1;
    }
}

/// The regular (weighted Delaunay) triangulation of the `count` points `xy`
/// with power weights `weights`, exactly: counter-clockwise triangles into
/// `triangles` (room for `capacity` of them, `3 * capacity` values; fewer
/// than 2n), their number into `*triangle_count`, and unless null one byte
/// per point into `hidden`: 1 where the point's power cell is empty. Too
/// small a capacity returns `PIXGEO_STATUS_BUFFER_TOO_SMALL` with the count
/// set; points all on one line are an invalid argument.
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles and `weights`
/// `count`; `triangles` has room for `3 * capacity` values;
/// `triangle_count` points to a writable `size_t`; `hidden` is null or has
/// room for `count` bytes.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn pixgeo_regular_triangulation(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    weights: *const f64,
    count: usize,
    triangles: *mut u32,
    capacity: usize,
    triangle_count: *mut usize,
    hidden: *mut u8,
) -> PixgeoStatus {
    with_context(ctx, |_| {
        if triangles.is_null() || triangle_count.is_null() {
            return Err(invalid("triangles and triangle_count must not be null"));
        }
        // SAFETY: the arrays' sizes (caller contract).
        let sites = unsafe { weighted(xy, weights, count) }?;
        let result = regular_triangulation(&sites).map_err(failed)?;
        // SAFETY: the caller's buffers (caller contract).
        unsafe {
            super::delaunay::write_triangles(&result.triangles, triangles, capacity, triangle_count)
        }?;
        // SAFETY: null or `count` bytes (caller contract).
        unsafe { mark_hidden(hidden, count, &result.hidden) };
        Ok(())
    })
}

/// The power diagram of the `count` points `xy` with power weights
/// `weights` on the picture `options` describes (its size and box): every
/// pixel's site of least power `|p - s|² - w` into `labels` (ties to the
/// lower index), unless null each power into `powers` (the double nearest
/// the exact one), and unless null one byte per site into `hidden` (1 where
/// its cell is empty). Exact, on the CPU.
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles and `weights`
/// `count`; `options` points to valid options; `labels` (and `powers`,
/// unless null) has room for `width * height` values; `hidden` is null or
/// has room for `count` bytes.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn pixgeo_power_diagram(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    weights: *const f64,
    count: usize,
    options: *const PixgeoVoronoiOptions,
    labels: *mut u32,
    powers: *mut f64,
    hidden: *mut u8,
) -> PixgeoStatus {
    with_context(ctx, |_| {
        if options.is_null() || labels.is_null() {
            return Err(invalid("options and labels must not be null"));
        }
        // SAFETY: non-null and valid (caller contract).
        let o = unsafe { read_options(options, "pixgeo_voronoi_options_default") }?;
        let (frame, _, _) = picture_of(&o)?;
        // SAFETY: the arrays' sizes (caller contract).
        let sites = unsafe { weighted(xy, weights, count) }?;
        let d = power_diagram(&sites, &PowerOptions::new(frame)).map_err(failed)?;
        // SAFETY: room for `width * height` values (caller contract).
        unsafe { std::slice::from_raw_parts_mut(labels, d.labels.len()) }
            .copy_from_slice(&d.labels);
        if !powers.is_null() {
            // SAFETY: room for `width * height` values (caller contract).
            unsafe { std::slice::from_raw_parts_mut(powers, d.powers.len()) }
                .copy_from_slice(&d.powers);
        }
        // SAFETY: null or `count` bytes (caller contract).
        unsafe { mark_hidden(hidden, count, &d.regular.hidden) };
        Ok(())
    })
}
