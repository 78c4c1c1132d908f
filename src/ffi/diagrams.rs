//! Diagrams: nearest, k nearest and furthest sites per pixel.

use super::*;
use crate::algorithms::{
    higher_order::{self, KNearestOptions},
    sites::voronoi_sites,
    voronoi::{voronoi_bands, VoronoiOptions},
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
        let o = unsafe { *options };
        let (frame, accuracy, speedup) = picture_of(&o)?;
        let metric = metric_of(&o)?;
        // SAFETY: `xy` holds `2 * count` doubles (caller contract).
        let sites = unsafe { points(xy, count) }?;
        let options = VoronoiOptions {
            frame,
            metric,
            accuracy,
            speedup,
            distances: !distances.is_null(),
            ties: false,
            max_tile: (o.max_tile > 0).then_some(o.max_tile),
            window: window_of(&o),
        };
        let window = options.window_rect().map_err(failed)?;
        let pixels = window.width as usize * window.height as usize;
        // SAFETY: caller-owned arrays of `width * height` values (caller contract).
        let labels = unsafe { std::slice::from_raw_parts_mut(labels, pixels) };
        let mut distances = (!distances.is_null())
            // SAFETY: as above.
            .then(|| unsafe { std::slice::from_raw_parts_mut(distances, pixels) });
        let width = window.width as usize;
        voronoi_bands(&context.machine, &sites, &options, |band| {
            let start = (band.y0 - window.y) as usize * width;
            labels[start..start + band.labels.len()].copy_from_slice(&band.labels);
            if let Some(d) = distances.as_mut() {
                d[start..start + band.distances.len()].copy_from_slice(&band.distances);
            }
            Ok(())
        })
        .map(|_| ())
        .map_err(failed)
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
        let o = unsafe { *options };
        let (frame, accuracy, speedup) = picture_of(&o)?;
        // SAFETY: `sites` holds `count` sites (caller contract).
        let given = unsafe { std::slice::from_raw_parts(sites, count) };
        let sites = sites_of(given)?;
        let options = VoronoiOptions {
            frame,
            metric: metric_of(&o)?,
            accuracy,
            speedup,
            distances: !distances.is_null(),
            ties: false,
            max_tile: (o.max_tile > 0).then_some(o.max_tile),
            window: window_of(&o),
        };
        let d = voronoi_sites(&context.machine, &sites, &options).map_err(failed)?;
        // SAFETY: caller-owned arrays of `width * height` values.
        unsafe { std::slice::from_raw_parts_mut(labels, d.labels.len()) }
            .copy_from_slice(&d.labels);
        if !distances.is_null() {
            // SAFETY: as above.
            unsafe { std::slice::from_raw_parts_mut(distances, d.distances.len()) }
                .copy_from_slice(&d.distances);
        }
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
        let o = unsafe { *options };
        if o.max_tile != 0 {
            return Err(invalid(
                "k nearest sites are drawn whole: max_tile must be 0",
            ));
        }
        let (frame, accuracy, speedup) = picture_of(&o)?;
        // SAFETY: `xy` holds `2 * count` doubles (caller contract).
        let sites = unsafe { points(xy, count) }?;
        let d = higher_order::k_nearest(
            &context.machine,
            &sites,
            &KNearestOptions {
                frame,
                k,
                metric: metric_of(&o)?,
                accuracy,
                speedup,
            },
        )
        .map_err(failed)?;
        // SAFETY: caller-owned arrays of `width * height * k` values.
        unsafe { std::slice::from_raw_parts_mut(labels, d.labels.len()) }
            .copy_from_slice(&d.labels);
        if !distances.is_null() {
            // SAFETY: as above.
            unsafe { std::slice::from_raw_parts_mut(distances, d.distances.len()) }
                .copy_from_slice(&d.distances);
        }
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
        let o = unsafe { &*options };
        let metric = metric_of(o)?;
        let (frame, _, _) = picture_of(o)?;
        // SAFETY: `xy` holds `2 * count` doubles (caller contract).
        let sites = unsafe { points(xy, count) }?;
        let f = higher_order::furthest(&context.machine, &sites, &frame, metric).map_err(failed)?;
        // SAFETY: caller-owned arrays of `width * height` values.
        unsafe { std::slice::from_raw_parts_mut(labels, f.labels.len()) }
            .copy_from_slice(&f.labels);
        if !distances.is_null() {
            // SAFETY: as above.
            unsafe { std::slice::from_raw_parts_mut(distances, f.distances.len()) }
                .copy_from_slice(&f.distances);
        }
        Ok(())
    })
}
