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

use rayon::prelude::*;

mod components;
mod medial_axis;
mod thinning;

pub use components::{components, NO_COMPONENT};
pub use medial_axis::{medial_axis, Pruning};

use crate::{
    cancel::Watch,
    error::{Error, Result},
    geometry::{metric::Metric, Frame},
};

/// What to compute. Start from [`TransformOptions::new`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct TransformOptions {
    pub metric: Metric,
    /// The distance between rows and between columns: `[rows, columns]`, as
    /// SciPy's `sampling`.
    pub sampling: [f64; 2],
}

impl TransformOptions {
    /// The Euclidean transform with unit sampling.
    pub fn new() -> Self {
        Self {
            metric: Metric::L2,
            sampling: [1.0, 1.0],
        }
    }

    pub fn metric(self, metric: Metric) -> Self {
        Self { metric, ..self }
    }

    pub fn sampling(self, sampling: [f64; 2]) -> Self {
        Self { sampling, ..self }
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
/// `height`, `true` at feature pixels).
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
    distance_transform_with_progress(features, width, height, options, &|_, _| {})
}

/// [`distance_transform`], calling `progress(done, total)` (from any of its
/// threads) as its passes finish rows.
pub fn distance_transform_with_progress(
    features: &[bool],
    width: u32,
    height: u32,
    options: &TransformOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<Transform> {
    let (w, h) = (width as usize, height as usize);
    if width == 0 || height == 0 || w.checked_mul(h) != Some(features.len()) {
        return Err(Error::InvalidInput(format!(
            "a {width} x {height} raster needs {} values and has {}",
            w.saturating_mul(h),
            features.len()
        )));
    }
    if w * h >= u32::MAX as usize || w > i32::MAX as usize || h > i32::MAX as usize {
        return Err(Error::InvalidInput(format!(
            "a raster of {width} x {height} pixels has 2^32 pixels or more, or a side of 2^31"
        )));
    }
    // Outputs of 16 bytes a pixel, and as much again while they are made.
    crate::memory::reserve_picture(width, height, 40, "a distance transform")?;
    let [sy, sx] = options.sampling;
    if !(sy.is_finite() && sx.is_finite() && sy > 0.0 && sx > 0.0) {
        return Err(Error::InvalidInput(format!(
            "sampling {sy},{sx} must be two finite spacings above 0"
        )));
    }
    let metric = options.metric;
    if let Metric::Lp(p) = metric {
        Metric::lp(p).map_err(Error::InvalidInput)?;
    }
    // The longest and the shortest offsets the keys must hold.
    let range = [sy.min(sx), (w as f64 * sx).max(h as f64 * sy)];
    let watch = Watch::current();
    // Bands of columns, then rows twice.
    let tally = Tally::new(w.div_ceil(BAND) + 2 * h, progress);
    let (feature_rows, feature_columns) = match Combine::of(metric, range) {
        Some(combine) => separable(features, w, h, [sy, sx], combine, (&watch, &tally)),
        None if sy == sx => {
            let planes = grown(features, width, height, metric)?;
            tally.add(w.div_ceil(BAND) + h);
            planes
        }
        None => {
            return Err(Error::InvalidInput(format!(
                "the {metric} metric takes equal sampling on both axes: its distance does not \
                 separate into rows and columns"
            )))
        }
    };
    watch.check()?;
    let mut distances = vec![0.0; w * h];
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
                        metric.distance(glam::DVec2::new(dx * sx, dy * sy))
                    }
                };
            }
        });
    watch.check()?;
    Ok(Transform {
        width,
        height,
        distances,
        feature_rows,
        feature_columns,
    })
}

/// How a separable metric combines the two axes' offsets (already sampled,
/// non-negative) into a key that grows with each: the distance is a monotone
/// function of the key.
#[derive(Clone, Copy, Debug)]
enum Combine {
    /// dx² + dy².
    Squares,
    /// dx + dy.
    Sum,
    /// max(dx, dy).
    Max,
    /// dx^p + dy^p, p >= 1.
    Powers(f64),
}

impl Combine {
    /// How `metric` separates, for offsets from `shortest` to `longest`:
    /// L_p's powers of them must stay within f64's range (p up to about
    /// 60 over 2^16 pixels); larger p take the grown diagram, whose keys scale.
    fn of(metric: Metric, [shortest, longest]: [f64; 2]) -> Option<Self> {
        match metric {
            Metric::L2 => Some(Self::Squares),
            Metric::L1 => Some(Self::Sum),
            Metric::LInf => Some(Self::Max),
            Metric::Lp(p) if p >= 1.0 && p * longest.log2() < 1000.0 => {
                (p * shortest.log2() > -1000.0).then_some(Self::Powers(p))
            }
            _ => None,
        }
    }

    /// One axis's share of the key, from its offset (>= 0).
    fn part(self, d: f64) -> f64 {
        match self {
            Self::Squares => d * d,
            Self::Sum | Self::Max => d,
            Self::Powers(p) => d.powf(p),
        }
    }

    /// The key from the two axes' shares.
    fn join(self, a: f64, b: f64) -> f64 {
        match self {
            Self::Max => a.max(b),
            _ => a + b,
        }
    }
}

/// The feature transform of a separable metric.
fn separable(
    features: &[bool],
    w: usize,
    h: usize,
    [sy, sx]: [f64; 2],
    combine: Combine,
    (watch, tally): (&Watch, &Tally),
) -> (Vec<i32>, Vec<i32>) {
    // A cancelled transform skips the rest of its rows; its caller returns
    // the error.
    // Each pixel's nearest feature row in its column (the upper one on a tie),
    // in two sweeps over the rows, bands of columns in parallel.
    let mut rows = vec![NONE; w * h];
    let bands: Vec<(usize, Vec<u32>)> = (0..w)
        .step_by(BAND)
        .collect::<Vec<_>>()
        .into_par_iter()
        .map(|x0| {
            let x1 = (x0 + BAND).min(w);
            let n = x1 - x0;
            let mut band = vec![NONE; n * h];
            if watch.cancelled() {
                return (x0, band);
            }
            tally.add(1);
            let mut above = vec![NONE; n];
            for y in 0..h {
                for (i, a) in above.iter_mut().enumerate() {
                    if features[y * w + x0 + i] {
                        *a = y as u32;
                    }
                }
                band[y * n..(y + 1) * n].copy_from_slice(&above);
            }
            let mut below = vec![NONE; n];
            for y in (0..h).rev() {
                for (i, b) in below.iter_mut().enumerate() {
                    if features[y * w + x0 + i] {
                        *b = y as u32;
                    }
                    let up = band[y * n + i];
                    let nearer_below =
                        *b != NONE && (up == NONE || *b as usize - y < y - up as usize);
                    if nearer_below {
                        band[y * n + i] = *b;
                    }
                }
            }
            (x0, band)
        })
        .collect();
    for (x0, band) in bands {
        let n = band.len() / h;
        for y in 0..h {
            rows[y * w + x0..y * w + x0 + n].copy_from_slice(&band[y * n..(y + 1) * n]);
        }
    }

    // Along each row, the lower envelope of the columns' curves
    // key(sx |x - u|, sy |y - row(u)|). Unit Euclidean sampling takes
    // integer keys (Meijster's separator, as glsl/euclidean.comp has it);
    // the rest floats.
    let unit_squares = matches!(combine, Combine::Squares) && sx == 1.0 && sy == 1.0;
    let mut feature_rows = vec![-1; w * h];
    let mut feature_columns = vec![-1; w * h];
    feature_rows
        .par_chunks_mut(w)
        .zip(feature_columns.par_chunks_mut(w))
        .zip(rows.par_chunks(w))
        .enumerate()
        .for_each_init(
            || (vec![0.0; w], vec![0i64; w], Vec::with_capacity(w)),
            |(heights, squares, stack), (y, ((out_rows, out_columns), row))| {
                if watch.cancelled() {
                    return;
                }
                tally.add(1);
                if unit_squares {
                    for (g, &r) in squares.iter_mut().zip(row) {
                        let dy = y as i64 - r as i64;
                        *g = if r == NONE { 0 } else { dy * dy };
                    }
                    let squares = &*squares;
                    let key = |x: usize, u: usize| {
                        let dx = x as i64 - u as i64;
                        dx * dx + squares[u]
                    };
                    let overtakes = |c: usize, u: usize, _from: usize| {
                        let (c, u) = (c as i64, u as i64);
                        let gap = u * u - c * c + squares[u as usize] - squares[c as usize];
                        (1 + gap.div_euclid(2 * (u - c))).min(w as i64) as usize
                    };
                    envelope(row, stack, |x, u, c| key(x, u) < key(x, c), overtakes);
                } else {
                    for (u, g) in heights.iter_mut().enumerate() {
                        *g = combine.part(sy * (y as f64 - row[u] as f64).abs());
                    }
                    let heights = &*heights;
                    let key = |x: usize, u: usize| {
                        combine.join(combine.part(sx * (x as f64 - u as f64).abs()), heights[u])
                    };
                    let beats = |x: usize, u: usize, c: usize| key(x, u) < key(x, c);
                    // Near where the curves meet, where the metric says, then
                    // settled by the keys themselves, so that rounding never
                    // moves a pixel.
                    let overtakes = |c: usize, u: usize, from: usize| {
                        let beats = |x: usize| beats(x, u, c);
                        let (gc, gu) = (heights[c], heights[u]);
                        let (c, u) = (c as f64, u as f64);
                        let meet = match combine {
                            // Two parabolas of one width always cross.
                            Combine::Squares => {
                                ((u * u - c * c) * sx * sx + gu - gc) / (2.0 * sx * sx * (u - c))
                            }
                            // Past its crossing u stays nearer: if it is not
                            // at the row's end, it never is.
                            _ if !beats(w - 1) => return w,
                            Combine::Sum => ((u + c) * sx + gu - gc) / (2.0 * sx),
                            Combine::Max | Combine::Powers(_) => f64::NAN,
                        };
                        if !meet.is_finite() {
                            let (mut lo, mut hi) = (from, w);
                            while lo < hi {
                                let mid = lo + (hi - lo) / 2;
                                if beats(mid) {
                                    hi = mid;
                                } else {
                                    lo = mid + 1;
                                }
                            }
                            return lo;
                        }
                        let mut x = (meet.floor() + 1.0).clamp(from as f64, w as f64) as usize;
                        while x > from && beats(x - 1) {
                            x -= 1;
                        }
                        while x < w && !beats(x) {
                            x += 1;
                        }
                        x
                    };
                    envelope(row, stack, beats, overtakes);
                }
                let mut k = 0;
                for x in 0..stack.len().min(1) * w {
                    while k + 1 < stack.len() && stack[k + 1].1 <= x {
                        k += 1;
                    }
                    let u = stack[k].0;
                    out_rows[x] = row[u] as i32;
                    out_columns[x] = u as i32;
                }
            },
        );
    (feature_rows, feature_columns)
}

/// The lower envelope of one row's column curves (those of the columns with a
/// feature, `row[u] != NONE`) into `stack`: each column on it, with the first
/// pixel it owns. `beats(x, u, c)`: column u is strictly nearer than c at
/// pixel x; `overtakes(c, u, from)`: the first pixel from `from` on where u
/// beats c (c < u), or the row's width. Ties go to the left column.
fn envelope(
    row: &[u32],
    stack: &mut Vec<(usize, usize)>,
    beats: impl Fn(usize, usize, usize) -> bool,
    overtakes: impl Fn(usize, usize, usize) -> usize,
) {
    let w = row.len();
    stack.clear();
    for u in (0..w).filter(|&u| row[u] != NONE) {
        while let Some(&(c, start)) = stack.last() {
            if beats(start, u, c) {
                stack.pop();
            } else {
                break;
            }
        }
        match stack.last() {
            None => stack.push((u, 0)),
            Some(&(c, from)) => {
                let start = overtakes(c, u, from);
                if start < w {
                    stack.push((u, start));
                }
            }
        }
    }
}

/// Columns a thread sweeps at once in the first pass.
const BAND: usize = 256;

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
        .collect();
    if pixels.is_empty() {
        return Ok((vec![-1; features.len()], vec![-1; features.len()]));
    }
    let sites: Vec<glam::DVec2> = pixels
        .iter()
        .map(|&i| glam::DVec2::new((i as usize % w) as f64, (i as usize / w) as f64))
        .collect();
    let frame = Frame::pixels(width, height)?;
    let diagram = super::cpu::k_nearest(&sites, &frame, 1, metric)?;
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
