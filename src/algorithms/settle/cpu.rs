//! The potential-area map on the CPU: the same discs, counted by row spans.

use super::*;

/// The potential-area map computed on the CPU with the thesis's own variant
/// (§3.12.3): every disc's border is walked row by row, +1 and -1 mark each row
/// span, and prefix sums along the rows give the counts. Threads take bands of
/// target rows: a band's differences stay in cache, and each disc that reaches
/// the band walks only the band's rows. Nearest sites come from
/// the CPU Voronoi diagram (Euclidean) or a search over all sites (other
/// metrics).
pub fn potential_areas_cpu(
    rivals: &[DVec2],
    own: &[DVec2],
    frame: &Frame,
    metric: Metric,
) -> Result<PotentialAreas> {
    check(rivals, own, frame, metric)?;
    let start = Instant::now();
    let rivals_px = to_pixels(rivals, frame);
    let own_px = to_pixels(own, frame);
    let rival_labels = nearest_labels_cpu(rivals, frame, metric)?;
    let own_labels = if own.is_empty() {
        None
    } else {
        Some(nearest_labels_cpu(own, frame, metric)?)
    };
    let keys = disc_radius_keys(
        frame,
        metric,
        &rivals_px,
        &rival_labels,
        &own_px,
        own_labels.as_deref(),
    );
    let mut stats = SettleStats {
        device: "cpu".into(),
        rivals: rivals.len(),
        own: own.len(),
        discs: keys.iter().filter(|&&k| k > 0.0).count(),
        radii_ms: ms(start),
        ..Default::default()
    };
    let start = Instant::now();
    let (w, h) = (frame.width as usize, frame.height as usize);
    // How far each disc reaches along its row and column, and the farthest of
    // each source row.
    let limit = w.max(h) as i64;
    let reaches: Vec<i64> = keys
        .par_iter()
        .map(|&key| disc_reach(metric, key, limit))
        .collect();
    let row_reach: Vec<i64> = reaches
        .chunks(w)
        .map(|row| row.iter().copied().max().unwrap_or(-1))
        .collect();
    let mut area = vec![0i32; w * h];
    area.par_chunks_mut(BAND_ROWS * w)
        .enumerate()
        .for_each(|(b, band)| {
            let rows = (b * BAND_ROWS) as i64..((b + 1) * BAND_ROWS).min(h) as i64;
            for (py, reach) in row_reach.iter().enumerate() {
                let py = py as i64;
                if py + reach < rows.start || py - reach >= rows.end {
                    continue;
                }
                let source = py as usize * w;
                for x in 0..w {
                    let disc = (keys[source + x], reaches[source + x]);
                    add_band_spans(band, &rows, w as i64, metric, (x as i64, py), disc);
                }
            }
            for row in band.chunks_mut(w) {
                let mut sum = 0;
                for v in row {
                    sum += *v;
                    *v = sum;
                }
            }
        });
    stats.count_ms = ms(start);
    let area = area.into_iter().map(|v| v as u32).collect();
    Ok(PotentialAreas::new(frame, area, stats))
}

/// Target rows per task of the CPU variant.
const BAND_ROWS: usize = 16;

/// Whether offset (dx, dy) lies in the disc of radius key `key` (as
/// `in_disc` of `glsl/settle.glsl`, in float64).
fn in_disc(metric: Metric, dx: i64, dy: i64, key: f32) -> bool {
    match metric {
        // The same squared distance, exact in integers.
        Metric::L2 => ((dx * dx + dy * dy) as f64) < key as f64,
        _ => metric.key(DVec2::new(dx as f64, dy as f64)) < key as f64,
    }
}

/// The largest offset along a row or column inside the disc of `key`, at most
/// `limit`; -1 when the disc is empty.
fn disc_reach(metric: Metric, key: f32, limit: i64) -> i64 {
    if key.is_nan() || key <= 0.0 {
        return -1;
    }
    let mut m = metric.distance_of_key(key as f64).min(limit as f64) as i64;
    while m < limit && in_disc(metric, m + 1, 0, key) {
        m += 1;
    }
    while m >= 0 && !in_disc(metric, m, 0, key) {
        m -= 1;
    }
    m
}

/// The largest m <= `reach` with offset (m, dy) in the disc of `key` (-1 when
/// none): from the metric's closed form, then corrected step by step.
fn half_width(metric: Metric, dy: i64, key: f32, reach: i64) -> i64 {
    let (k, y) = (key as f64, dy as f64);
    let guess = match metric {
        Metric::L2 => (k - y * y).max(0.0).sqrt(),
        Metric::L1 => k - y,
        Metric::Lp(p) => (k.powf(p) - y.powf(p)).max(0.0).powf(1.0 / p),
        _ => k,
    };
    let mut m = (guess.max(0.0) as i64).min(reach);
    while m < reach && in_disc(metric, m + 1, dy, key) {
        m += 1;
    }
    while m >= 0 && !in_disc(metric, m, dy, key) {
        m -= 1;
    }
    m
}

/// Adds the row spans of the disc of pixel (x, y), of radius key `key` and
/// reach `reach` ([`disc_reach`]), on the target rows `rows` of a picture `w`
/// pixels wide to `band`, the differences of those rows. Rows are visited by
/// growing distance from the disc's centre row, where the span only shrinks.
fn add_band_spans(
    band: &mut [i32],
    rows: &std::ops::Range<i64>,
    w: i64,
    metric: Metric,
    (x, y): (i64, i64),
    (key, reach): (f32, i64),
) {
    if reach < 0 || y + reach < rows.start || y - reach >= rows.end {
        return;
    }
    let mut add = |row: i64, m: i64| {
        let base = ((row - rows.start) * w) as usize;
        band[base + (x - m).max(0) as usize] += 1;
        if x + m + 1 < w {
            band[base + (x + m + 1) as usize] -= 1;
        }
    };
    // Rows at and below the centre, then above it, each by growing distance.
    let below = rows.start.max(y)..rows.end.min(y + reach + 1);
    let above = rows.start.max(y - reach)..rows.end.min(y);
    let mut walk = |first_dy: i64, count: i64, row_of: &dyn Fn(i64) -> i64| {
        let mut m = half_width(metric, first_dy, key, reach);
        for k in 0..count {
            let dy = first_dy + k;
            while m >= 0 && !in_disc(metric, m, dy, key) {
                m -= 1;
            }
            if m < 0 {
                break;
            }
            add(row_of(dy), m);
        }
    };
    if !below.is_empty() {
        walk(below.start - y, below.end - below.start, &|dy| y + dy);
    }
    if !above.is_empty() {
        walk(y - (above.end - 1), above.end - above.start, &|dy| y - dy);
    }
}

/// Nearest site per pixel on the CPU: the thesis's growing sites (§3.12.1).
fn nearest_labels_cpu(sites: &[DVec2], frame: &Frame, metric: Metric) -> Result<Vec<u32>> {
    Ok(crate::algorithms::cpu::k_nearest(sites, frame, 1, metric)?.labels)
}
