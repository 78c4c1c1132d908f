//! The settle point (thesis §3.10).

use glam::DVec2;

use super::*;
use pixgeo::{
    algorithms::settle::{self, SettleMethod, SettleOptions},
    geometry::metric::Metric,
};

/// How [`pixgeo_settle`] counts the discs.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoSettleMethod {
    /// Row spans and prefix sums (default).
    Spans = 0,
    /// The thesis's discs, counted by stencil wrap-around and blending.
    Faithful = 1,
}

/// The answer of [`pixgeo_settle`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixgeoSettle {
    /// The settle pixel (the first, row-major, of those tied) and the number of
    /// pixels a new site there would win.
    pub pixel_x: u32,
    pub pixel_y: u32,
    pub area: u32,
    /// How many pixels share the largest potential area.
    pub ties: u32,
    /// The refined position (world coordinates) and the exact area (world units)
    /// it wins; NaN unless the metric is L2.
    pub refined_x: f64,
    pub refined_y: f64,
    pub refined_area: f64,
}

/// The settle point (thesis §3.10): where a new site among the `count` sites
/// `xy` would win the most pixels, not counting pixels already nearest to one
/// of the `own_count` sites `own` (null when 0). The picture's size, bounding
/// box and metric come from `options`. Unless null, `area` receives the
/// potential-area map (`width * height` counts, row-major). With the L2 metric
/// the answer is refined to a real-valued position and its exact area.
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles, `own` `2 *
/// own_count` (or is null when `own_count` is 0); `options` points to valid
/// options; `area` is null or has room for `width * height` values; `out`
/// points to a writable answer.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_settle(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    own: *const f64,
    own_count: usize,
    options: *const PixgeoVoronoiOptions,
    method: u32,
    area: *mut u32,
    out: *mut PixgeoSettle,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if options.is_null() || out.is_null() {
            return Err(invalid("options and out must not be null"));
        }
        // SAFETY: non-null and valid (caller contract).
        let o = unsafe { read_options(options, "pixgeo_voronoi_options_default") }?;
        let (frame, _, _) = picture_of(&o)?;
        let metric = metric_of(&o)?;
        // SAFETY: sizes as documented (caller contract).
        let rivals = unsafe { points(xy, count) }?;
        let own = if own_count == 0 {
            Vec::new()
        } else {
            // SAFETY: as above.
            unsafe { points(own, own_count) }?
        };
        let method = match method {
            0 => SettleMethod::Spans,
            1 => SettleMethod::Faithful,
            other => {
                return Err(invalid(format!(
                    "method {other} is not a PixgeoSettleMethod (0 spans, 1 faithful)"
                )))
            }
        };
        let options = SettleOptions::new(frame).metric(metric).method(method);
        let need = match method {
            SettleMethod::Faithful => Need::Drawing("the faithful method's disc count"),
            SettleMethod::Spans => Need::DeviceIfAny,
        };
        let map = settle::potential_areas(&context.backend_for(need)?, &rivals, &own, &options)
            .map_err(failed)?;
        let refined = if metric == Metric::L2 {
            Some(settle::refine(&rivals, &own, &frame, &map.leaders(8)).map_err(failed)?)
        } else {
            None
        };
        if !area.is_null() {
            // SAFETY: caller-owned array of `width * height` values.
            unsafe { std::slice::from_raw_parts_mut(area, map.area.len()) }
                .copy_from_slice(&map.area);
        }
        let best = map.best[0];
        let world = refined.map(|r| frame.to_world(DVec2::from_array(r.position)));
        let answer = PixgeoSettle {
            pixel_x: (best % frame.width as usize) as u32,
            pixel_y: (best / frame.width as usize) as u32,
            area: map.best_area,
            ties: map.best.len() as u32,
            refined_x: world.map_or(f64::NAN, |p| p.x),
            refined_y: world.map_or(f64::NAN, |p| p.y),
            refined_area: refined.map_or(f64::NAN, |r| r.area / (frame.scale * frame.scale)),
        };
        // SAFETY: non-null and writable (caller contract).
        unsafe { *out = answer };
        Ok(())
    })
}
