//! Distance and feature transforms of a raster: every pixel's distance to the
//! nearest feature pixel, and which pixel that is, exactly, under every metric.
//!
//! The metrics whose distance combines the two axes' offsets by a monotone
//! rule (L2, L1, L∞ and L_p for p >= 1) are separable (Meijster, Roerdink and
//! Hesselink 2000, the pass behind `glsl/euclidean.comp`): a pass down each
//! column finds every pixel's nearest feature row in its column, and a pass
//! along each row takes the lower envelope of the columns' distance curves.
//! Two columns' curves cross once, so a stack of columns with the first pixel
//! each one owns gives the envelope in linear time, each crossing found by a
//! binary search over the row. Sampling may differ between the axes.
//!
//! Polygon metrics and L_p for p < 1 are not separable: their transform is the
//! Voronoi diagram of the feature pixels, grown on the CPU (thesis §3.12), with
//! equal sampling on both axes.
//!
//! Each pixel may also take the connected feature component it is nearest to
//! ([`components`], [`Transform::at_nearest`]): the Voronoi diagram of the
//! obstacles in a raster; and the free space's medial axis ([`medial_axis`]).
//!
//! Rasters are row-major, row 0 first, as NumPy holds them.

use crate::memory::Gather;
use rayon::prelude::*;

mod components;
mod medial_axis;
mod separable;
mod thinning;

pub use components::{components, NO_COMPONENT};
pub use medial_axis::{medial_axis, Pruning};

use separable::{separable, Combine};

use crate::{
    cancel::Watch,
    control::Control,
    error::{Error, Result},
    geometry::{metric::Metric, Frame},
};

/// What to compute. Start from [`TransformOptions::new`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct TransformOptions {
    pub metric: Metric,
    /// The distance between rows and between columns: `[rows, columns]`, as
    /// SciPy's `sampling`.
    pub sampling: [f64; 2],
    /// Progress, reported from any of the passes' threads as they finish
    /// rows, and cancellation.
    pub control: Control,
}

impl TransformOptions {
    /// The Euclidean transform with unit sampling.
    pub fn new() -> Self {
        Self {
            metric: Metric::L2,
            sampling: [1.0, 1.0],
            control: Control::new(),
        }
    }

    pub fn metric(self, metric: Metric) -> Self {
        Self { metric, ..self }
    }

    pub fn sampling(self, sampling: [f64; 2]) -> Self {
        Self { sampling, ..self }
    }

    pub fn control(self, control: Control) -> Self {
        Self { control, ..self }
    }
}

impl Default for TransformOptions {
    fn default() -> Self {
        Self::new()
    }
}

/// A transform of a `width` x `height` raster.
#[derive(Clone, Debug)]
pub struct Transform {
    pub width: u32,
    pub height: u32,
    /// Distance to the nearest feature pixel, row-major; infinity where the
    /// raster has no feature.
    pub distances: Vec<f64>,
    /// That feature pixel's row, row-major; -1 where the raster has no
    /// feature.
    pub feature_rows: Vec<i32>,
    /// And its column.
    pub feature_columns: Vec<i32>,
}

impl Transform {
    /// Each pixel's value of `per_pixel` (row-major, one per pixel) at its
    /// nearest feature pixel; `none` where the raster has no feature. With
    /// [`components`]' labels, every pixel gets the component it is nearest to.
    pub fn at_nearest<T: Copy + Send + Sync>(&self, per_pixel: &[T], none: T) -> Vec<T> {
        let w = self.width as usize;
        self.feature_rows
            .par_iter()
            .zip(&self.feature_columns)
            .map(|(&row, &column)| match row {
                -1 => none,
                row => per_pixel[row as usize * w + column as usize],
            })
            .collect()
    }
}

/// No feature pixel.
const NONE: u32 = u32::MAX;

/// The distance and feature transform of `features` (row-major, `width` x
/// `height`, `true` at feature pixels), reporting progress to `options.control`.
///
/// ```
/// use pixgeo::algorithms::transform::{distance_transform, TransformOptions};
///
/// let mut mask = vec![false; 5 * 4];
/// mask[1 * 5 + 1] = true; // row 1, column 1
/// let t = distance_transform(&mask, 5, 4, &TransformOptions::new())?;
/// assert_eq!(t.distances[3 * 5 + 4], 13f64.sqrt()); // row 3, column 4
/// assert_eq!((t.feature_rows[3 * 5 + 4], t.feature_columns[3 * 5 + 4]), (1, 1));
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn distance_transform(
    features: &[bool],
    width: u32,
    height: u32,
    options: &TransformOptions,
) -> Result<Transform> {
    let (distances, planes) = options.control.run(|| {
        let progress = |done, total| options.control.report(done, total);
        transform(features, width, height, options, true, &progress)
    })?;
    let (feature_rows, feature_columns) = planes.expect("the planes were asked for");
    Ok(Transform {
        width,
        height,
        distances,
        feature_rows,
        feature_columns,
    })
}

/// [`distance_transform`]'s distances alone (row-major), without the
/// feature planes' time and memory.
pub fn distances_only(
    features: &[bool],
    width: u32,
    height: u32,
    options: &TransformOptions,
) -> Result<Vec<f64>> {
    let progress = |done, total| options.control.report(done, total);
    Ok(options
        .control
        .run(|| transform(features, width, height, options, false, &progress))?
        .0)
}

/// The distances, and the feature planes where `planes` asks for them.
fn transform(
    features: &[bool],
    width: u32,
    height: u32,
    options: &TransformOptions,
    planes: bool,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<separable::Outputs> {
    let (w, h) = (width as usize, height as usize);
    if width == 0 || height == 0 || w.checked_mul(h) != Some(features.len()) {
        return Err(Error::malformed(format!(
            "a {width} x {height} raster needs {} values and has {}",
            w.saturating_mul(h),
            features.len()
        )));
    }
    if w * h >= u32::MAX as usize || w > i32::MAX as usize || h > i32::MAX as usize {
        return Err(Error::out_of_range(format!(
            "a raster of {width} x {height} pixels has 2^32 pixels or more, or a side of 2^31"
        )));
    }
    // Outputs of 16 bytes a pixel (8 without the planes), and at most one
    // more for the column pass's strips.
    let bytes = if planes { 17 } else { 9 };
    crate::memory::reserve_picture(width, height, bytes, "a distance transform")?;
    let [sy, sx] = options.sampling;
    if !(sy.is_finite() && sx.is_finite() && sy > 0.0 && sx > 0.0) {
        return Err(Error::out_of_range(format!(
            "sampling {sy},{sx} must be two finite spacings above 0"
        )));
    }
    let metric = options.metric;
    if let Metric::Lp(p) = metric {
        Metric::lp(p).map_err(Error::out_of_range)?;
    }
    // The longest and the shortest offsets the keys must hold.
    let range = [sy.min(sx), (w as f64 * sx).max(h as f64 * sy)];
    let watch = Watch::current();
    // The rows of each pass.
    let tally = Tally::new(2 * h, progress);
    let outputs = match Combine::of(metric, range) {
        Some(combine) => separable(
            features,
            (w, h),
            (metric, combine, [sy, sx]),
            planes,
            (&watch, &tally),
        )?,
        None if sy == sx => {
            let (rows, columns) = grown(features, width, height, metric)?;
            tally.add(h);
            let distances = distances_to(&rows, &columns, (w, sx), metric, (&watch, &tally))?;
            (distances, planes.then_some((rows, columns)))
        }
        None => {
            return Err(Error::unsupported_option(format!(
                "the {metric} metric takes equal sampling on both axes: its distance does not \
                 separate into rows and columns"
            )))
        }
    };
    watch.check()?;
    Ok(outputs)
}

/// Each pixel's distance to its feature pixel, from the feature planes, with
/// `spacing` between pixels on both axes.
fn distances_to(
    feature_rows: &[i32],
    feature_columns: &[i32],
    (w, spacing): (usize, f64),
    metric: Metric,
    (watch, tally): (&Watch, &Tally),
) -> Result<Vec<f64>> {
    let mut distances = crate::memory::filled(feature_rows.len(), 0.0, "distances")?;
    distances
        .par_chunks_mut(w)
        .zip(feature_rows.par_chunks(w))
        .zip(feature_columns.par_chunks(w))
        .enumerate()
        .for_each(|(y, ((out, rows), columns))| {
            if watch.cancelled() {
                return;
            }
            tally.add(1);
            for (x, d) in out.iter_mut().enumerate() {
                *d = match rows[x] {
                    -1 => f64::INFINITY,
                    row => {
                        let dy = y as f64 - row as f64;
                        let dx = x as f64 - columns[x] as f64;
                        metric.distance(glam::DVec2::new(dx * spacing, dy * spacing))
                    }
                };
            }
        });
    Ok(distances)
}

/// Pieces of work done of all the passes, told to `progress` every hundredth.
struct Tally<'a> {
    done: std::sync::atomic::AtomicU64,
    total: u64,
    progress: &'a (dyn Fn(u64, u64) + Sync),
}

impl<'a> Tally<'a> {
    fn new(total: usize, progress: &'a (dyn Fn(u64, u64) + Sync)) -> Self {
        Self {
            done: Default::default(),
            total: total as u64,
            progress,
        }
    }

    fn add(&self, pieces: usize) {
        let pieces = pieces as u64;
        let before = self
            .done
            .fetch_add(pieces, std::sync::atomic::Ordering::Relaxed);
        let after = before + pieces;
        if before * 100 / self.total != after * 100 / self.total {
            (self.progress)(after, self.total);
        }
    }
}

/// The feature transform of any metric, as the Voronoi diagram of the feature
/// pixels grown on the CPU.
fn grown(
    features: &[bool],
    width: u32,
    height: u32,
    metric: Metric,
) -> Result<(Vec<i32>, Vec<i32>)> {
    let w = width as usize;
    let pixels: Vec<u32> = (0..features.len() as u32)
        .filter(|&i| features[i as usize])
        .gather("pixels")?;
    if pixels.is_empty() {
        return Ok((
            crate::memory::filled(features.len(), -1, "feature rows")?,
            crate::memory::filled(features.len(), -1, "feature columns")?,
        ));
    }
    let sites: Vec<glam::DVec2> = pixels
        .iter()
        .map(|&i| glam::DVec2::new((i as usize % w) as f64, (i as usize / w) as f64))
        .gather("sites")?;
    let frame = Frame::pixels(width, height)?;
    let sites = crate::geometry::frame::Checked::new(&sites)?;
    let diagram =
        super::higher_order::cpu::k_nearest_checked(sites, &frame, 1, metric, &mut |_, _| {})?;
    let plane = |of: fn(u32, usize) -> i32| {
        diagram
            .labels
            .par_iter()
            .map(|&site| match site {
                NONE => -1,
                s => of(pixels[s as usize], w),
            })
            .collect()
    };
    Ok((
        plane(|p, w| (p as usize / w) as i32),
        plane(|p, w| (p as usize % w) as i32),
    ))
}

#[cfg(test)]
mod tests;
