//! Distance and feature transforms of a raster.

use super::*;
use pixgeo::algorithms::transform::{distance_transform, distances_only, TransformOptions};

/// The distance and feature transform of a `width` x `height` raster (the
/// picture size of `options`): `mask` holds `width * height` bytes, row-major,
/// non-zero at feature pixels. Writes each pixel's distance to the nearest
/// feature pixel (`distances`, infinity where there is none) and that pixel's
/// row and column (`feature_rows`, `feature_columns`, -1 where there is none);
/// any of the three may be null to skip it. The metric of `options` applies,
/// its bounding box does not. `sampling` is null (1, 1) or `{rows, columns}`,
/// the spacing of rows and of columns: any for L2, L1, L-infinity and L_p with
/// p >= 1, equal for the others. Exact; computed on the CPU.
///
/// # Safety
/// `ctx` is a live context; `mask` holds `width * height` bytes; `options`
/// points to valid options; `sampling` is null or holds 2 doubles; each output
/// is null or has room for `width * height` values.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_distance_transform(
    ctx: *mut PixgeoContext,
    mask: *const u8,
    options: *const PixgeoVoronoiOptions,
    sampling: *const f64,
    distances: *mut f64,
    feature_rows: *mut i32,
    feature_columns: *mut i32,
) -> PixgeoStatus {
    with_context(ctx, |_| {
        if mask.is_null() {
            return Err(invalid("mask must not be null"));
        }
        // SAFETY: null or valid (caller contract).
        let o = unsafe { read_options(options, "pixgeo_voronoi_options_default") }?;
        let metric = metric_of(&o)?;
        let pixels = o.width as usize * o.height as usize;
        // SAFETY: `mask` holds `width * height` bytes (caller contract).
        let features: Vec<bool> = unsafe { std::slice::from_raw_parts(mask, pixels) }
            .iter()
            .map(|&m| m != 0)
            .collect();
        let sampling = if sampling.is_null() {
            [1.0, 1.0]
        } else {
            // SAFETY: `sampling` holds 2 doubles (caller contract).
            unsafe { [*sampling, *sampling.add(1)] }
        };
        let options = TransformOptions::new().metric(metric).sampling(sampling);
        // Without the feature planes, their time and memory are saved.
        if feature_rows.is_null() && feature_columns.is_null() {
            let d = distances_only(&features, o.width, o.height, &options).map_err(failed)?;
            // SAFETY: a non-null output has room for `width * height` values
            // (caller contract).
            unsafe { copy_out(distances, &d) };
            return Ok(());
        }
        let t = distance_transform(&features, o.width, o.height, &options).map_err(failed)?;
        // SAFETY: each non-null output has room for `width * height` values
        // (caller contract).
        unsafe {
            copy_out(distances, &t.distances);
            copy_out(feature_rows, &t.feature_rows);
            copy_out(feature_columns, &t.feature_columns);
        }
        Ok(())
    })
}

/// Copies `values` to `out` unless it is null.
///
/// # Safety
/// `out` is null or has room for `values.len()` values.
unsafe fn copy_out<T: Copy>(out: *mut T, values: &[T]) {
    if !out.is_null() {
        // SAFETY: room for `values.len()` values (caller contract).
        unsafe { std::slice::from_raw_parts_mut(out, values.len()) }.copy_from_slice(values);
    }
}
