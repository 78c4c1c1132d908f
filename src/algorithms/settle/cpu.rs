//! The potential-area map on the CPU: the same discs, counted by row spans.

use super::*;
use crate::algorithms::certify::{Certifier, Disc};
use crate::memory::Gather;

/// The potential-area map computed on the CPU with the thesis's own variant
/// (§3.12.3): every disc's border is walked row by row, +1 and -1 mark each row
/// span, and prefix sums along the rows give the counts. Threads take bands of
/// target rows: a band's differences stay in cache, and each disc that reaches
/// the band walks only the band's rows. Nearest sites come from
/// the CPU Voronoi diagram (Euclidean) or a search over all sites (other
/// metrics).
pub(crate) fn potential_areas_cpu(
    rivals: &[DVec2],
    own: &[DVec2],
    frame: &Frame,
    metric: Metric,
) -> Result<PotentialAreas> {
    check(rivals, own, frame, metric)?;
    let (rivals, own) = (&distinct(rivals)[..], &distinct(own)[..]);
    let start = Instant::now();
    let rival_labels = nearest_labels_cpu(rivals, frame, metric)?;
    let own_labels = if own.is_empty() {
        None
    } else {
        Some(nearest_labels_cpu(own, frame, metric)?)
    };
    // Each pixel's disc: the positions strictly nearer to it than its nearest
    // rival, decided exactly; none where an own site is at least as near.
    let rival_sites = Certifier::new(rivals, frame, metric)?;
    let own_sites = own_labels
        .as_ref()
        .map(|_| Certifier::new(own, frame, metric))
        .transpose()?;
    let w = frame.width as usize;
    let discs: Vec<Option<Disc>> = (0..frame.len())
        .into_par_iter()
        .map(|k| {
            let pixel = [(k % w) as i64, (k / w) as i64];
            let owned = match (&own_sites, &own_labels) {
                (Some(sites), Some(labels)) => {
                    sites.no_farther(labels[k], &rival_sites, rival_labels[k], pixel)
                }
                _ => false,
            };
            (!owned).then(|| rival_sites.disc(pixel, rival_labels[k]))
        })
        .collect();
    let mut stats = SettleStats {
        device: "cpu".into(),
        rivals: rivals.len(),
        own: own.len(),
        discs: discs.iter().flatten().count(),
        radii_ms: ms(start),
        ..Default::default()
    };
    let start = Instant::now();
    let (w, h) = (frame.width as usize, frame.height as usize);
    // How far each disc reaches along its row and column, and the farthest of
    // each source row.
    let limit = w.max(h) as i64;
    let reaches: Vec<i64> = discs
        .par_iter()
        .map(|disc| disc.map_or(-1, |d| disc_reach(&rival_sites, &d, limit)))
        .collect();
    let row_reach: Vec<i64> = reaches
        .chunks(w)
        .map(|row| row.iter().copied().max().unwrap_or(-1))
        .gather("row reach")?;
    let mut area = crate::memory::filled(w * h, 0i32, "regions' areas")?;
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
                    if let Some(disc) = &discs[source + x] {
                        let reach = reaches[source + x];
                        add_band_spans(band, &rows, w as i64, &rival_sites, (disc, reach));
                    }
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
    let area = area.into_iter().map(|v| v as u32).gather("area")?;
    Ok(PotentialAreas::new(frame, area, stats))
}

/// Target rows per task of the CPU variant.
const BAND_ROWS: usize = 16;

/// The largest offset along a row or column inside `disc`, at most `limit`;
/// -1 when the disc is empty.
fn disc_reach(sites: &Certifier<'_>, disc: &Disc, limit: i64) -> i64 {
    half_width(sites, disc, 0, limit)
}

/// The largest m <= `reach` with offset (m, dy) in `disc` (-1 when none):
/// from a radius that holds the disc, then corrected step by step.
fn half_width(sites: &Certifier<'_>, disc: &Disc, dy: i64, reach: i64) -> i64 {
    let radius = sites.disc_radius(disc);
    let guess = (radius * radius - (dy * dy) as f64).max(0.0).sqrt();
    let mut m = (guess as i64).min(reach);
    while m < reach && sites.in_disc(disc, [m + 1, dy]) {
        m += 1;
    }
    while m >= 0 && !sites.in_disc(disc, [m, dy]) {
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
    sites: &Certifier<'_>,
    (disc, reach): (&Disc, i64),
) {
    let [x, y] = disc.pixel();
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
        let mut m = half_width(sites, disc, first_dy, reach);
        for k in 0..count {
            let dy = first_dy + k;
            while m >= 0 && !sites.in_disc(disc, [m, dy]) {
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

/// Nearest site per pixel on the CPU: the thesis's growing sites (§3.12.1),
/// of the distinct sites of a checked set.
fn nearest_labels_cpu(sites: &[DVec2], frame: &Frame, metric: Metric) -> Result<Vec<u32>> {
    let sites = Checked::derived(sites);
    let near = crate::algorithms::higher_order::cpu::k_nearest_checked(
        sites,
        frame,
        1,
        metric,
        &mut |_, _| {},
    )?;
    Ok(near.labels)
}
