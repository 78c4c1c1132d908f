//! The transform of a separable metric: a pass down each column finds every
//! pixel's nearest feature row in its column, and a pass along each row takes
//! the lower envelope of the columns' distance curves and writes the
//! distances (and, when asked, each pixel's feature) as it walks the envelope.

use crate::memory::Gather;
use rayon::prelude::*;

use super::{Tally, NONE};
use crate::{cancel::Watch, geometry::metric::Metric, memory, Result};

/// How a separable metric combines the two axes' offsets (already sampled,
/// non-negative) into a key that grows with each: the distance is a monotone
/// function of the key.
#[derive(Clone, Copy, Debug)]
pub(super) enum Combine {
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
    pub(super) fn of(metric: Metric, [shortest, longest]: [f64; 2]) -> Option<Self> {
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

/// A separable transform's outputs: distances, and each pixel's feature
/// (row, column) planes when they were asked for.
pub(super) type Outputs = (Vec<f64>, Option<(Vec<i32>, Vec<i32>)>);

/// The transform of a separable metric. A cancelled transform skips the rest
/// of its rows; its caller returns the error.
pub(super) fn separable(
    features: &[bool],
    (w, h): (usize, usize),
    (metric, combine, [sy, sx]): (Metric, Combine, [f64; 2]),
    planes: bool,
    (watch, tally): (&Watch, &Tally),
) -> Result<Outputs> {
    let mut distances = memory::filled(w * h, 0.0, "distances")?;
    nearest_rows(features, (w, h), &mut distances, (watch, tally))?;
    let plane = || memory::filled(w * h, -1, "feature planes");
    let mut planes = match planes {
        true => Some((plane()?, plane()?)),
        false => None,
    };
    let plane_rows: Vec<Option<(&mut [i32], &mut [i32])>> = match &mut planes {
        Some((rows, columns)) => rows
            .chunks_mut(w)
            .zip(columns.chunks_mut(w))
            .map(Some)
            .gather("plane rows")?,
        None => (0..h).map(|_| None).gather("plane rows")?,
    };
    // Along each row, the lower envelope of the columns' curves
    // key(sx |x - u|, sy |y - row(u)|). Unit Euclidean sampling takes
    // integer keys (Meijster's separator, as glsl/euclidean.comp has it);
    // the rest floats.
    let unit_squares = matches!(combine, Combine::Squares) && sx == 1.0 && sy == 1.0;
    distances
        .par_chunks_mut(w)
        .zip(plane_rows)
        .enumerate()
        .for_each_init(
            || Row::new(w),
            |scratch, (y, (out, planes))| {
                if watch.cancelled() {
                    return;
                }
                tally.add(1);
                for (r, &parked) in scratch.row.iter_mut().zip(&*out) {
                    *r = unpark(parked);
                }
                let Row {
                    row,
                    heights,
                    squares,
                    stack,
                } = scratch;
                let row = &*row;
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
                    let overtakes = |c: usize, u: usize, from: usize| {
                        overtaking(c, u, from, w, (combine, sx, heights), beats)
                    };
                    envelope(row, stack, beats, overtakes);
                }
                write_row(y, row, stack, metric, [sy, sx], out, planes);
            },
        );
    Ok((distances, planes))
}

/// One thread's scratch for the row pass.
struct Row {
    /// The row's nearest feature row in each column.
    row: Vec<u32>,
    heights: Vec<f64>,
    squares: Vec<i64>,
    stack: Vec<(usize, usize)>,
}

impl Row {
    #[expect(
        clippy::disallowed_macros,
        clippy::disallowed_methods,
        reason = "a row's scratch, a thread's, within the transform's picture"
    )]
    fn new(w: usize) -> Self {
        Self {
            row: vec![NONE; w],
            heights: vec![0.0; w],
            squares: vec![0; w],
            stack: Vec::with_capacity(w),
        }
    }
}

/// Each pixel's nearest feature row in its column (the upper one on a tie),
/// `NONE` where its column has none, parked in `out` (see [`park`]). Strips
/// of rows run in parallel: each first notes its columns' first and last
/// feature rows, which tell every strip what lies above and below it; then
/// each sweeps down and up its own rows.
fn nearest_rows(
    features: &[bool],
    (w, h): (usize, usize),
    out: &mut [f64],
    (watch, tally): (&Watch, &Tally),
) -> Result<()> {
    // Four strips a thread, of 16 rows at least: the strips' four rows of
    // answers (16 bytes a column) stay within a byte a pixel.
    let strip = h.div_ceil(4 * rayon::current_num_threads()).max(16);
    let rows_of = |k: usize| &features[k * strip * w..((k + 1) * strip).min(h) * w];
    let strips = h.div_ceil(strip);
    // Each strip's first and last feature row in each column.
    let columns = || memory::filled(w, NONE, "a strip's feature rows");
    let ends: Vec<(Vec<u32>, Vec<u32>)> = (0..strips)
        .into_par_iter()
        .map(|k| {
            let (mut first, mut last) = (columns()?, columns()?);
            for (i, features) in rows_of(k).chunks_exact(w).enumerate() {
                let y = (k * strip + i) as u32;
                for ((f, l), &feature) in first.iter_mut().zip(&mut last).zip(features) {
                    if feature {
                        *l = y;
                        *f = (*f).min(y);
                    }
                }
            }
            Ok((first, last))
        })
        .collect::<Result<_>>()?;
    // The nearest feature row above each strip, and below it.
    let mut above = memory::filled(strips, columns()?, "feature rows above strips")?;
    let mut below = memory::filled(strips, columns()?, "feature rows below strips")?;
    for k in 1..strips {
        let (done, rest) = above.split_at_mut(k);
        for ((a, &before), &last) in rest[0].iter_mut().zip(&done[k - 1]).zip(&ends[k - 1].1) {
            *a = if last == NONE { before } else { last };
        }
    }
    for k in (0..strips - 1).rev() {
        let (rest, done) = below.split_at_mut(k + 1);
        for ((b, &after), &first) in rest[k].iter_mut().zip(&done[0]).zip(&ends[k + 1].0) {
            *b = first.min(after);
        }
    }
    out.par_chunks_mut(strip * w)
        .zip(above)
        .zip(below)
        .enumerate()
        .for_each(|(k, ((out, mut above), mut below))| {
            if watch.cancelled() {
                return;
            }
            let (y0, features) = (k * strip, rows_of(k));
            let lines = || features.chunks_exact(w);
            for (i, (out, features)) in out.chunks_exact_mut(w).zip(lines()).enumerate() {
                let y = (y0 + i) as u32;
                for ((a, &f), o) in above.iter_mut().zip(features).zip(out) {
                    if f {
                        *a = y;
                    }
                    *o = park(*a);
                }
            }
            for (i, (out, features)) in out.chunks_exact_mut(w).zip(lines()).enumerate().rev() {
                let y = y0 + i;
                for ((b, &f), o) in below.iter_mut().zip(features).zip(out) {
                    if f {
                        *b = y as u32;
                    }
                    let up = unpark(*o);
                    let nearer_below =
                        *b != NONE && (up == NONE || *b as usize - y < y - up as usize);
                    if nearer_below {
                        *o = park(*b);
                    }
                }
            }
            tally.add(features.len() / w);
        });
    Ok(())
}

/// A row index held in an `f64`'s bits: the column pass's answers live in
/// the distances' own memory until the row pass replaces them.
fn park(row: u32) -> f64 {
    f64::from_bits(u64::from(row))
}

/// The row index [`park`] held.
fn unpark(parked: f64) -> u32 {
    parked.to_bits() as u32
}

/// The first pixel from `from` on where column u's curve beats c's (c < u),
/// or the row's width `w`: near where the curves meet, where the metric
/// says, then settled by the keys themselves, so that rounding never moves a
/// pixel.
fn overtaking(
    c: usize,
    u: usize,
    from: usize,
    w: usize,
    (combine, sx, heights): (Combine, f64, &[f64]),
    beats: impl Fn(usize, usize, usize) -> bool,
) -> usize {
    let beats = |x: usize| beats(x, u, c);
    let (gc, gu) = (heights[c], heights[u]);
    let (cf, uf) = (c as f64, u as f64);
    let meet = match combine {
        // Two parabolas of one width always cross.
        Combine::Squares => ((uf * uf - cf * cf) * sx * sx + gu - gc) / (2.0 * sx * sx * (uf - cf)),
        // Past its crossing u stays nearer: if it is not at the row's end,
        // it never is.
        _ if !beats(w - 1) => return w,
        Combine::Sum => ((uf + cf) * sx + gu - gc) / (2.0 * sx),
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
}

/// Row `y`'s distances, and its features into `planes`, from the envelope
/// `stack`; infinity and -1 where the raster has no feature.
fn write_row(
    y: usize,
    row: &[u32],
    stack: &[(usize, usize)],
    metric: Metric,
    [sy, sx]: [f64; 2],
    out: &mut [f64],
    planes: Option<(&mut [i32], &mut [i32])>,
) {
    if stack.is_empty() {
        out.fill(f64::INFINITY);
        return;
    }
    // Each envelope column owns the run from its start to the next's.
    let ends = stack.iter().skip(1).map(|&(_, start)| start);
    let runs = stack.iter().zip(ends.chain([out.len()]));
    let mut planes = planes;
    for (&(u, start), end) in runs {
        let dy = (y as f64 - row[u] as f64) * sy;
        for (x, d) in out[start..end].iter_mut().enumerate() {
            let dx = ((start + x) as f64 - u as f64) * sx;
            *d = metric.distance(glam::DVec2::new(dx, dy));
        }
        if let Some((rows, columns)) = &mut planes {
            rows[start..end].fill(row[u] as i32);
            columns[start..end].fill(u as i32);
        }
    }
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
