//! Digital Voronoi diagrams by flooding (Cao, Edelsbrunner and Tan 2015) and
//! by jump flooding.

use super::*;
use pixgeo::algorithms::flooding::{flood, jump_flood, seeds_of};

/// How [`pixgeo_flood`] colours the picture.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixgeoFloodMethod {
    /// Flooding in the paper's total order: every region connected, its dual
    /// a valid triangulation.
    Flood = 0,
    /// Jump flooding (Rong and Tan 2006): fast, a few pixels given a farther
    /// site.
    JumpFlood = 1,
}

/// The digital Voronoi diagram of `count` point sites `xy`, grown from the
/// pixel each lies in: writes `width * height` labels, row-major. Only the
/// picture's size and bounding box of `options` apply (the metric is
/// Euclidean). A site outside the picture, or two in one pixel, is an invalid
/// argument.
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` doubles; `options` points to
/// valid options; `labels` has room for `width * height` values.
#[no_mangle]
pub unsafe extern "C" fn pixgeo_flood(
    ctx: *mut PixgeoContext,
    xy: *const f64,
    count: usize,
    options: *const PixgeoVoronoiOptions,
    method: u32,
    labels: *mut u32,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if labels.is_null() {
            return Err(invalid("labels must not be null"));
        }
        // SAFETY: null or valid (caller contract).
        let o = unsafe { read_options(options, "pixgeo_voronoi_options_default") }?;
        let (frame, _, _) = picture_of(&o)?;
        if o.metric != PixgeoMetric::L2 as u32 {
            return Err(invalid("flooding is Euclidean: the metric must be L2"));
        }
        // SAFETY: `xy` holds `2 * count` doubles (caller contract).
        let sites = unsafe { points(xy, count) }?;
        let seeds = seeds_of(&frame, &sites).map_err(failed)?;
        let (width, height) = (frame.width, frame.height);
        let found = match method {
            0 => flood(context.machine("flooding")?, width, height, &seeds).map(|f| f.labels),
            1 => jump_flood(context.machine("jump flooding")?, width, height, &seeds),
            other => {
                return Err(invalid(format!(
                    "method {other} is not a PixgeoFloodMethod (0 flood, 1 jump flood)"
                )))
            }
        }
        .map_err(failed)?;
        // SAFETY: caller-owned array of `width * height` values.
        unsafe { std::slice::from_raw_parts_mut(labels, found.len()) }.copy_from_slice(&found);
        Ok(())
    })
}
