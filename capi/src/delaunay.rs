//! Delaunay triangulations by flooding (Cao, Edelsbrunner and Tan 2015).

use super::*;
use pixgeo::algorithms::delaunay;

/// The Delaunay triangulation of the `count` points `xy` (`{x0, y0, x1, ...}`),
/// from their digital Voronoi diagram on a texture `grid` pixels along the
/// longer side of their bounding box (0: about one pixel per point). Writes
/// the counter-clockwise triangles as point indices, three per triangle, into
/// `triangles`, which has room for `capacity` triangles (`3 * capacity`
/// values), and their number into `*triangle_count`. A triangulation of n
/// points has fewer than 2n triangles; when `capacity` is less than the
/// answer's, the call returns `PIXGEO_STATUS_BUFFER_TOO_SMALL` with
/// `*triangle_count` set, so it can be repeated with room enough. Repeated
/// points are in
/// no triangle, and `*duplicate_count` (unless null) receives how many there
/// were. Fewer than three distinct points, or all on one line, is an invalid
/// argument.
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles; `triangles` has
/// room for `3 * capacity` values; `triangle_count` points to a writable `size_t`;
/// `duplicate_count` is null or does.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_delaunay(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    grid: u32,
    triangles: *mut u32,
    capacity: usize,
    triangle_count: *mut usize,
    duplicate_count: *mut usize,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if triangles.is_null() || triangle_count.is_null() {
            return Err(invalid("triangles and triangle_count must not be null"));
        }
        // SAFETY: `xy` holds `2 * count` doubles (caller contract).
        let given = unsafe { points(xy, count) }?;
        let options = delaunay::DelaunayOptions::default()
            .grid((grid > 0).then_some(grid))
            .check(false);
        let result =
            delaunay::delaunay(&context.backend_for(Need::CpuUnlessGpu)?, &given, &options)
                .map_err(failed)?;
        // SAFETY: the caller's buffers (caller contract).
        unsafe { write_triangles(&result.triangles, triangles, capacity, triangle_count) }?;
        if !duplicate_count.is_null() {
            // SAFETY: writable when not null (caller contract).
            unsafe { *duplicate_count = result.duplicates.len() };
        }
        Ok(())
    })
}

/// Writes `found`'s count into `*count` and, where `capacity` holds them,
/// the triangles into `out`; else `PIXGEO_STATUS_BUFFER_TOO_SMALL`.
///
/// # Safety
/// `out` has room for `3 * capacity` values; `count` is writable.
pub(super) unsafe fn write_triangles(
    found: &[[u32; 3]],
    out: *mut u32,
    capacity: usize,
    count: *mut usize,
) -> Result<(), (PixgeoStatus, String)> {
    // SAFETY: writable (caller contract).
    unsafe { *count = found.len() };
    if found.len() > capacity {
        return Err((
            PixgeoStatus::BufferTooSmall,
            format!(
                "the triangulation has {} triangles, more than the capacity {capacity}",
                found.len()
            ),
        ));
    }
    let flat: Vec<u32> = found.iter().flatten().copied().collect();
    // SAFETY: room for `3 * capacity` values (caller contract), which hold them.
    unsafe { std::slice::from_raw_parts_mut(out, flat.len()) }.copy_from_slice(&flat);
    Ok(())
}
