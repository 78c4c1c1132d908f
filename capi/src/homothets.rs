//! Smallest enclosing and largest empty homothets (thesis ch. 4–5).

use glam::DVec2;

use super::*;
use pixgeo::{
    algorithms::homothet::{
        self, EmptyOptions, EncloseOptions, HomothetAnswer, Region, Unit, DEFAULT_SIDE,
    },
    geometry::metric::Metric,
};

/// The shape and picture of [`pixgeo_enclose`] and [`pixgeo_empty`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixgeoHomothetOptions {
    /// `sizeof(PixgeoHomothetOptions)`, set by [`pixgeo_homothet_options_default`].
    pub struct_size: u32,
    /// The polygon's vertices `{x0, y0, x1, y1, ...}` around `kernel`, star-shaped
    /// around it; null for circles.
    pub polygon: *const f64,
    pub polygon_count: usize,
    pub kernel: [f64; 2],
    /// Picture side in pixels along the longer axis (0: 1024).
    pub side: u32,
}

/// Circles on a picture of the default side.
#[no_mangle]
pub extern "C" fn pixgeo_homothet_options_default() -> PixgeoHomothetOptions {
    PixgeoHomothetOptions {
        struct_size: struct_size::<PixgeoHomothetOptions>(),
        polygon: std::ptr::null(),
        polygon_count: 0,
        kernel: [0.0; 2],
        side: 0,
    }
}

/// A homothet `centre + scale · Q`: the exact one, the picture's candidate, the
/// bound between them, and the gap left where a branch and bound decided.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixgeoHomothet {
    pub centre: [f64; 2],
    pub scale: f64,
    pub pixel_centre: [f64; 2],
    pub pixel_scale: f64,
    pub pixel_bound: f64,
    pub tolerance: f64,
}

/// The unit and picture side that homothet options describe.
///
/// # Safety
/// `options` is null or valid, its `polygon` null or holding `2 *
/// polygon_count` doubles.
unsafe fn homothet_options(
    options: *const PixgeoHomothetOptions,
) -> Result<(Unit, u32), (PixgeoStatus, String)> {
    // SAFETY: null or valid (caller contract).
    let o = unsafe { read_options(options, "pixgeo_homothet_options_default") }?;
    let unit = if o.polygon.is_null() {
        Unit::Circle
    } else {
        // SAFETY: as documented.
        let vertices = unsafe { points(o.polygon, o.polygon_count) }?;
        match Metric::polygon(&vertices, DVec2::from(o.kernel)).map_err(invalid)? {
            Metric::Polygon(g) => Unit::Polygon(g),
            _ => unreachable!("a polygon metric"),
        }
    };
    let side = if o.side == 0 { DEFAULT_SIDE } else { o.side };
    Ok((unit, side))
}

fn homothet_into(
    out: *mut PixgeoHomothet,
    answer: &HomothetAnswer,
) -> Result<(), (PixgeoStatus, String)> {
    // SAFETY: null or writable (caller contract of the public functions).
    let Some(slot) = (unsafe { out.as_mut() }) else {
        return Err(invalid("the answer pointer is null"));
    };
    *slot = PixgeoHomothet {
        centre: answer.exact.centre,
        scale: answer.exact.scale,
        pixel_centre: answer.pixel.centre,
        pixel_scale: answer.pixel.scale,
        pixel_bound: answer.pixel_bound,
        tolerance: answer.tolerance,
    };
    Ok(())
}

/// The smallest homothet of a circle or polygon (thesis ch. 4) holding every
/// one of the `count` sites (points, segments, circles, arcs; unweighted), or
/// with `k` > 0 at least `k` of them (points only, §4.4.1).
///
/// # Safety
/// `ctx` is a live context; `sites` holds `count` sites; `options` points to
/// valid options; `out` points to a writable answer.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_enclose(
    ctx: *mut PixgeoContext,
    sites: *const PixgeoSite,
    count: usize,
    options: *const PixgeoHomothetOptions,
    k: usize,
    out: *mut PixgeoHomothet,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if sites.is_null() {
            return Err(invalid("sites must not be null"));
        }
        // SAFETY: as documented (caller contract).
        let (unit, side) = unsafe { homothet_options(options) }?;
        check_count(count, std::mem::size_of::<PixgeoSite>(), "sites")?;
        // SAFETY: `sites` holds `count` sites (caller contract); the count fits.
        let given = sites_of(unsafe { std::slice::from_raw_parts(sites, count) })?;
        let need = match k == 0 || k == count {
            true => Need::CpuUnlessGpu,
            false => Need::Drawing("the smallest homothet holding k of the sites"),
        };
        let answer = homothet::enclose(
            &context.backend_for(need)?,
            &given,
            &EncloseOptions::new(unit).k(k).side(side),
        )
        .map_err(failed)?;
        homothet_into(out, &answer)
    })
}

/// The largest homothet of a circle or polygon (thesis ch. 5) meeting none of
/// the `count` sites (points, segments, circles, arcs; multiplicative weights
/// scale the clearance each demands), its centre in the region: `ring_count`
/// rings of `ring_sizes[r]` points each, concatenated in `rings` as `{x0, y0,
/// ...}` (holes by even-odd; `ring_count` 0: the sites' bounding box). With
/// `inside`, the whole homothet stays inside the region.
///
/// # Safety
/// `ctx` is a live context; `sites` holds `count` sites; `rings` holds twice
/// the sum of the `ring_count` sizes in `ring_sizes` (both may be null when
/// `ring_count` is 0); `options` points to valid options; `out` points to a
/// writable answer.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn pixgeo_empty(
    ctx: *mut PixgeoContext,
    sites: *const PixgeoSite,
    count: usize,
    rings: *const f64,
    ring_sizes: *const usize,
    ring_count: usize,
    inside: bool,
    options: *const PixgeoHomothetOptions,
    out: *mut PixgeoHomothet,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if sites.is_null() {
            return Err(invalid("sites must not be null"));
        }
        // SAFETY: as documented (caller contract).
        let (unit, side) = unsafe { homothet_options(options) }?;
        check_count(count, std::mem::size_of::<PixgeoSite>(), "sites")?;
        // SAFETY: `sites` holds `count` sites (caller contract); the count fits.
        let given = sites_of(unsafe { std::slice::from_raw_parts(sites, count) })?;
        let mut region = Region::default();
        if ring_count > 0 {
            if ring_sizes.is_null() {
                return Err(invalid("ring_sizes must not be null"));
            }
            // SAFETY: `ring_sizes` holds `ring_count` sizes (caller contract).
            let sizes = unsafe { std::slice::from_raw_parts(ring_sizes, ring_count) };
            let total = sizes
                .iter()
                .try_fold(0usize, |a, n| a.checked_add(*n))
                .ok_or_else(|| invalid("ring sizes overflow"))?;
            // SAFETY: `rings` holds `2 * total` doubles (caller contract).
            let all = unsafe { points(rings, total) }?;
            let mut at = 0;
            for n in sizes {
                region.rings.push(all[at..at + n].to_vec());
                at += n;
            }
        }
        let answer = homothet::largest_empty(
            context.machine("a largest empty homothet")?,
            &given,
            &EmptyOptions::new(unit)
                .region(region)
                .inside(inside)
                .side(side),
        )
        .map_err(failed)?;
        homothet_into(out, &answer)
    })
}
