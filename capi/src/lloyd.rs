//! Lloyd's iterations: centroidal Voronoi tessellations and stippling.

use super::*;
use pixgeo::algorithms::lloyd::{self, LloydOptions};

/// The answer of [`pixgeo_lloyd`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixgeoLloyd {
    /// Iterations run.
    pub iterations: u32,
    /// Whether the last largest move was within the tolerance.
    pub converged: bool,
    /// Sites whose region holds no weight (they stayed put).
    pub idle: u32,
    /// The last iteration's largest move (world units; 0 without one).
    pub largest_move: f64,
    /// The energy of the final sites: Σ density · squared distance from each
    /// pixel's centre to its nearest site.
    pub energy: f64,
}

/// Lloyd's iterations from the `count` sites `xy` (x, y pairs, world
/// coordinates), which receive where the iterations leave them: each
/// iteration takes the exact Voronoi diagram on the picture `options`
/// describes (its metric must be L2), sums every region's pixels weighted
/// by `density` (`width * height` values, row-major, finite and not
/// negative; null for a uniform one) and moves each site to its region's
/// centroid, exact for the digital region (whole-number sums, rounded
/// once). At most `iterations`; stops once no site moves farther than
/// `tolerance` (world units; negative for a hundredth of a pixel; NaN is an
/// invalid argument). Unless
/// null, `labels` receives every pixel's nearest final site.
///
/// # Safety
/// `ctx` is a live context; `xy` holds `2 * count` writable doubles;
/// `options` points to valid options; `density` is null or holds `width *
/// height` doubles; `labels` is null or has room for `width * height`
/// values; `out` points to a writable answer.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn pixgeo_lloyd(
    ctx: *mut PixgeoContext,
    xy: *mut f64,
    count: usize,
    options: *const PixgeoVoronoiOptions,
    iterations: u32,
    tolerance: f64,
    density: *const f64,
    labels: *mut u32,
    out: *mut PixgeoLloyd,
) -> PixgeoStatus {
    with_context(ctx, |context| {
        if options.is_null() || out.is_null() {
            return Err(invalid("options and out must not be null"));
        }
        // SAFETY: non-null and valid (caller contract).
        let o = unsafe { read_options(options, "pixgeo_voronoi_options_default") }?;
        let (frame, _, _) = picture_of(&o)?;
        if metric_of(&o)? != pixgeo::geometry::metric::Metric::L2 {
            return Err(invalid("Lloyd's iterations take the L2 metric"));
        }
        // SAFETY: `2 * count` doubles (caller contract).
        let sites = unsafe { points(xy, count) }?;
        let density = if density.is_null() {
            None
        } else {
            // SAFETY: `width * height` doubles (caller contract).
            Some(unsafe { std::slice::from_raw_parts(density, frame.len()) })
        };
        let mut lloyd_options = LloydOptions::new(frame).iterations(iterations);
        // Negative asks for the default; NaN is refused with the rest.
        if tolerance.is_nan() || tolerance >= 0.0 {
            lloyd_options = lloyd_options.tolerance(tolerance);
        }
        let answer = lloyd::lloyd(
            &context.backend_for(Need::DeviceIfAny)?,
            &sites,
            density,
            &lloyd_options,
        )
        .map_err(failed)?;
        // SAFETY: `2 * count` writable doubles (caller contract).
        let moved = unsafe { std::slice::from_raw_parts_mut(xy, 2 * count) };
        for (pair, p) in moved.chunks_exact_mut(2).zip(&answer.sites) {
            pair.copy_from_slice(&[p.x, p.y]);
        }
        if !labels.is_null() {
            // SAFETY: caller-owned array of `width * height` values.
            unsafe { std::slice::from_raw_parts_mut(labels, answer.labels.len()) }
                .copy_from_slice(&answer.labels);
        }
        let result = PixgeoLloyd {
            iterations: answer.steps.len() as u32,
            converged: answer.converged,
            idle: answer.idle as u32,
            largest_move: answer.steps.last().map_or(0.0, |s| s.largest_move),
            energy: answer.energy,
        };
        // SAFETY: non-null and writable (caller contract).
        unsafe { *out = result };
        Ok(())
    })
}
