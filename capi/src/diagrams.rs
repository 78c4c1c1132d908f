//! Diagrams: nearest, k nearest and furthest sites per pixel.

use std::{ffi::c_void, ptr};

use super::*;
use pixgeo::algorithms::{
    higher_order::{self, KNearestOptions},
    voronoi::{voronoi, voronoi_bands, Accuracy, Band, VoronoiOptions, VoronoiStats},
};

/// The Voronoi diagram of `count` point sites `xy = {x0, y0, x1, y1, ...}` (world
/// coordinates). Writes the nearest site's index per pixel to `labels` and, if
/// `distances` is not null, its distance (world units) to `distances`; both are
/// caller-owned arrays of `width * height` values (the window's, with one),
/// row-major (`[j * width + i]`).
/// `UINT32_MAX` marks a pixel with no site (never with the default options).
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles; `options` points to
/// valid options; `labels` (and `distances` unless null) have room for
/// `width * height` values.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_voronoi(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    options: *const PixgeoVoronoiOptions,
    labels: *mut u32,
    distances: *mut f32,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if xy.is_null() || options.is_null() || labels.is_null() {
            return Err(invalid("xy, options and labels must not be null"));
        }
        // SAFETY: non-null and valid (caller contract).
        let o = unsafe { read_options(options, "pixgeo_voronoi_options_default") }?;
        let options = voronoi_options(&o, !distances.is_null(), false)?;
        // SAFETY: `xy` holds `2 * count` doubles (caller contract).
        let sites = unsafe { points(xy, count) }?;
        let window = options.window_rect().map_err(failed)?;
        let pixels = window.width as usize * window.height as usize;
        // SAFETY: caller-owned arrays of `width * height` values (caller contract).
        let labels = unsafe { std::slice::from_raw_parts_mut(labels, pixels) };
        let mut distances = (!distances.is_null())
            // SAFETY: as above.
            .then(|| unsafe { std::slice::from_raw_parts_mut(distances, pixels) });
        let width = window.width as usize;
        bands(context, &sites, &options, |band| {
            let start = (band.y0 - window.y) as usize * width;
            labels[start..start + band.labels.len()].copy_from_slice(&band.labels);
            if let Some(d) = distances.as_mut() {
                d[start..start + band.distances.len()].copy_from_slice(&band.distances);
            }
            Ok(())
        })
        .map(|_| ())
    })
}

/// The Voronoi diagram of `count` sites of any shape and weight, like
/// [`pixgeo_voronoi`]: labels (and, unless null, weighted distances in world
/// units) of `width * height` pixels, row-major.
///
/// # Safety
/// `ctx` is a live context; `sites` holds `count` sites; `options` points to
/// valid options; `labels` (and `distances` unless null) have room for
/// `width * height` values.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_voronoi_sites(
    ctx: *mut PixgeoContext,
    sites: *const PixgeoSite,
    count: usize,
    options: *const PixgeoVoronoiOptions,
    labels: *mut u32,
    distances: *mut f32,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if sites.is_null() || options.is_null() || labels.is_null() {
            return Err(invalid("sites, options and labels must not be null"));
        }
        // SAFETY: non-null and valid (caller contract).
        let o = unsafe { read_options(options, "pixgeo_voronoi_options_default") }?;
        let options = voronoi_options(&o, !distances.is_null(), false)?;
        check_count(count, std::mem::size_of::<PixgeoSite>(), "sites")?;
        // SAFETY: `sites` holds `count` sites (caller contract); the count fits.
        let given = unsafe { std::slice::from_raw_parts(sites, count) };
        let sites = sites_of(given)?;
        let need = match options.accuracy == Accuracy::Exact && !options.ties {
            true => Need::DeviceIfAny,
            false => Need::Drawing("fans and counted ties of weighted or extended sites"),
        };
        let d = voronoi(&context.backend_for(need)?, &sites, &options).map_err(failed)?;
        // SAFETY: the caller's arrays have room for the answer (caller contract).
        unsafe { write_diagram(&d.labels, labels, &d.distances, distances) };
        Ok(())
    })
}

/// Every pixel's `k` nearest sites in order (the degree 1..k diagrams, thesis
/// §3.7), equal distances counted with their multiplicity, ties by index. Writes
/// `width * height * k` values to `labels` and, unless null, `distances` (world
/// units): `[(j * width + i) * k + l]` is the (l+1)-th nearest site of pixel
/// (i, j); `UINT32_MAX` (and infinity) where fewer than l+1 sites exist. The
/// order-k diagram is each pixel's k labels as a set. `max_tile` must be 0 (the
/// picture is drawn whole).
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles; `options` points to
/// valid options; `labels` (and `distances` unless null) have room for
/// `width * height * k` values.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_k_nearest(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    options: *const PixgeoVoronoiOptions,
    k: u32,
    labels: *mut u32,
    distances: *mut f32,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if options.is_null() || labels.is_null() {
            return Err(invalid("options and labels must not be null"));
        }
        // SAFETY: non-null and valid (caller contract).
        let o = unsafe { read_options(options, "pixgeo_voronoi_options_default") }?;
        if o.max_tile != 0 {
            return Err(invalid(
                "k nearest sites are drawn whole: max_tile must be 0",
            ));
        }
        let (frame, accuracy, speedup) = picture_of(&o)?;
        // SAFETY: `xy` holds `2 * count` doubles (caller contract).
        let sites = unsafe { points(xy, count) }?;
        let need = match accuracy {
            Accuracy::Exact => Need::DeviceIfAny,
            _ => Need::Drawing("the fast mode's fans"),
        };
        let d = higher_order::k_nearest(
            &context.backend_for(need)?,
            &sites,
            &KNearestOptions::exact(frame, k)
                .metric(metric_of(&o)?)
                .accuracy(accuracy)
                .speedup(speedup),
        )
        .map_err(failed)?;
        // SAFETY: the caller's arrays have room for the answer (caller contract).
        unsafe { write_diagram(&d.labels, labels, &d.distances, distances) };
        Ok(())
    })
}

/// Every pixel's furthest site (thesis §3.7.1), like [`pixgeo_voronoi`]'s
/// outputs: `width * height` labels and, unless null, distances. Only the
/// picture's size, bounding box and metric of `options` apply.
///
/// # Safety
/// As [`pixgeo_voronoi`].
#[no_mangle]
pub unsafe extern "C" fn pixgeo_furthest(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    options: *const PixgeoVoronoiOptions,
    labels: *mut u32,
    distances: *mut f32,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if options.is_null() || labels.is_null() {
            return Err(invalid("options and labels must not be null"));
        }
        // SAFETY: non-null and valid (caller contract).
        let o = &unsafe { read_options(options, "pixgeo_voronoi_options_default") }?;
        let metric = metric_of(o)?;
        let (frame, _, _) = picture_of(o)?;
        // SAFETY: `xy` holds `2 * count` doubles (caller contract).
        let sites = unsafe { points(xy, count) }?;
        let backend = context.backend_for(Need::CpuUnlessGpu)?;
        let f = higher_order::furthest(&backend, &sites, &frame, metric).map_err(failed)?;
        // SAFETY: the caller's arrays have room for the answer (caller contract).
        unsafe { write_diagram(&f.labels, labels, &f.distances, distances) };
        Ok(())
    })
}

/// Rows `y0 .. y0 + height` of a diagram, columns `x0 .. x0 + width` (the
/// whole width, or the window's), row-major, handed to a
/// [`PixgeoBandCallback`]; the arrays are valid during the callback only.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PixgeoBand {
    pub x0: u32,
    pub y0: u32,
    pub width: u32,
    pub height: u32,
    pub labels: *const u32,
    /// Distances in world units; null unless asked for.
    pub distances: *const f32,
    /// How many sites are at the smallest distance from each pixel (thesis
    /// §3.6.4); null unless asked for.
    pub ties: *const u32,
}

/// Receives each band in turn, top to bottom; returns 0 to go on, anything
/// else to stop the call with [`PixgeoStatus::Stopped`].
pub type PixgeoBandCallback =
    Option<unsafe extern "C" fn(band: *const PixgeoBand, user_data: *mut c_void) -> i32>;

/// The Voronoi diagram of [`pixgeo_voronoi`], streamed in bands of rows to
/// `callback`, so that a picture larger than memory can be written as it is
/// made. With `distances` each band carries distances; with `ties` (exact
/// mode) the number of sites tied at each pixel's smallest distance.
/// `user_data` is passed through.
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles; `options` points to
/// valid options; `callback` is safe to call with a band and `user_data`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn pixgeo_voronoi_bands(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    options: *const PixgeoVoronoiOptions,
    distances: bool,
    ties: bool,
    callback: PixgeoBandCallback,
    user_data: *mut c_void,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        let Some(callback) = callback else {
            return Err(invalid("callback must not be null"));
        };
        // SAFETY: null or valid (caller contract).
        let o = unsafe { read_options(options, "pixgeo_voronoi_options_default") }?;
        let options = voronoi_options(&o, distances, ties)?;
        // SAFETY: `xy` holds `2 * count` doubles (caller contract).
        let sites = unsafe { points(xy, count) }?;
        let window = options.window_rect().map_err(failed)?;
        let mut stopped = false;
        let outcome = bands(context, &sites, &options, |band| {
            let view = PixgeoBand {
                x0: window.x,
                y0: band.y0,
                width: window.width,
                height: band.height,
                labels: band.labels.as_ptr(),
                distances: or_null(&band.distances),
                ties: or_null(&band.ties),
            };
            // SAFETY: the callback is safe to call (caller contract); the band's
            // arrays live until it returns.
            if unsafe { callback(&view, user_data) } != 0 {
                stopped = true;
                return Err(Error::malformed("stopped by the band callback".into()));
            }
            Ok(())
        });
        match outcome {
            Ok(_) => Ok(()),
            Err((_, text)) if stopped => Err((PixgeoStatus::Stopped, text)),
            Err(e) => Err(e),
        }
    })
}

/// An array's data, or null for an empty one (an output not asked for).
fn or_null<T>(values: &[T]) -> *const T {
    if values.is_empty() {
        ptr::null()
    } else {
        values.as_ptr()
    }
}

/// The bands of a diagram where the context's rule runs them: the grid on the
/// CPU where the options allow it and no GPU is there, else the device.
fn bands(
    context: &PixgeoContext,
    sites: &[glam::DVec2],
    options: &VoronoiOptions,
    sink: impl FnMut(Band) -> pixgeo::Result<()>,
) -> Result<VoronoiStats, (PixgeoStatus, String)> {
    let need = if options.on_cpu_alone() {
        Need::CpuUnlessGpu
    } else {
        Need::Drawing("this diagram's options (cones, fans or another metric)")
    };
    voronoi_bands(&context.backend_for(need)?, sites, options, sink).map_err(failed)
}
