//! The pixel algorithms of thesis §3.12 for machines without a GPU driver: every
//! site grows outwards through one table of pixel offsets sorted by length, round
//! robin, and each pixel keeps the first k sites that reach it (§3.12.2; k = 1 is
//! the Voronoi diagram of §3.12.1). Any metric works: the offsets grow by
//! Euclidean length, the pixels compare the metric's keys, and the finishing
//! test scales the horizon by the metric's lower Euclidean bound.
//!
//! The thesis's sites sit on pixel centres. pixgeo's may lie anywhere, so a site
//! grows from its nearest pixel centre, which it misses by at most
//! `SLACK = sqrt(2)/2`: an offset of length r then reaches a pixel at a true
//! distance within `r ± SLACK`. Pixels keep the k smallest *true* keys (squared
//! distance, site index) seen so far, and a pixel is final once its k-th key is
//! nearer than the current offset length minus the slack, because every later
//! arrival is farther. The result is exact: the k nearest sites in order, ties by
//! index, the same as the GPU's.
//!
//! The picture is cut into bands of rows, one per thread; sites are sorted by row
//! so that each offset visits only the sites that land in the band.

use crate::geometry::exact::predicates::convex_hull;
use crate::memory::Gather;
use glam::DVec2;
use rayon::prelude::*;

use crate::{
    cancel::Watch,
    error::{Error, Result},
    geometry::{
        frame::Checked,
        metric::Metric,
        site::{check_general_sites, Site},
        Frame,
    },
};

use super::{
    certify_levels, exactly_furthest, furthest_candidates, with_repeats, Furthest, KNearest,
    KNearestStats, MAX_LEVELS,
};

/// How far a site may lie from the pixel centre it grows from.
const SLACK: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The largest ring radius, in pixels: its square fits in 64 bits with room.
const MAX_RING: f64 = 1e9;

/// Rows per band: enough bands for every thread, few enough to share the sites.
const BAND_ROWS: u32 = 32;

/// The x offsets of ring r (`r - 1 < |(dx, dy)| <= r`) in the row dy, as up to
/// two ranges (the ring's left and right arcs; one range when they meet).
fn ring_row(r: i64, dy: i64) -> [std::ops::Range<i64>; 2] {
    let outer = r * r - dy * dy;
    if outer < 0 {
        return [0..0, 0..0];
    }
    let hi = isqrt(outer);
    // dx² > (r - 1)² - dy², so |dx| >= lo.
    let inner = if r == 0 {
        -1
    } else {
        (r - 1) * (r - 1) - dy * dy
    };
    let lo = if inner < 0 { 0 } else { isqrt(inner) + 1 };
    if lo == 0 {
        [-hi..hi + 1, 0..0]
    } else {
        [-hi..-lo + 1, lo..hi + 1]
    }
}

/// The largest integer whose square is at most `v` (v >= 0).
fn isqrt(v: i64) -> i64 {
    let mut s = (v as f64).sqrt() as i64;
    while s * s > v {
        s -= 1;
    }
    while (s + 1) * (s + 1) <= v {
        s += 1;
    }
    s
}

/// Every pixel's `k` nearest sites (world coordinates) on `frame`, computed on the
/// CPU by growing the sites (thesis §3.12.2), of sites checked where they
/// entered; `progress(done, total)` as the sites' rings grow (radii in pixels).
pub(crate) fn k_nearest_checked(
    sites: Checked<'_>,
    frame: &Frame,
    k: u32,
    metric: Metric,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<KNearest> {
    with_repeats(sites, frame, metric, k, |sites, k| {
        let mut near = grown_k_nearest(sites, frame, k, metric, progress)?;
        certify_levels(&mut near, sites, metric)?;
        Ok(near)
    })
}

/// [`k_nearest`] as the sites grow, before the exact check.
fn grown_k_nearest(
    sites: &[DVec2],
    frame: &Frame,
    k: u32,
    metric: Metric,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<KNearest> {
    frame.check()?;
    if k == 0 || k > MAX_LEVELS {
        return Err(Error::out_of_range(format!(
            "the number of levels must be 1 to {MAX_LEVELS}, not {k}"
        )));
    }
    frame.reserve(16 * k as u64, "the CPU's nearest sites")?;
    let started = std::time::Instant::now();
    let (w, h) = (frame.width as usize, frame.height as usize);
    let ku = k as usize;
    let pixels: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p)).gather("pixels")?;
    // Sites by the row of the pixel centre they grow from. A site farther than the
    // picture's diagonal from it never needs to grow past that diagonal.
    let mut by_row: Vec<(i64, i64, u32)> = pixels
        .iter()
        .enumerate()
        .map(|(i, p)| (p.y.round() as i64, p.x.round() as i64, i as u32))
        .gather("by row")?;
    by_row.sort_unstable();
    // No pixel is farther than this from the centre a site grows from.
    let reach = pixels
        .iter()
        .map(|p| frame.farthest_pixel(p.round()))
        .fold(0.0, f64::max);
    // Ring radii are squared in 64 bits; farther sites' nearest-site maps take
    // the search by blocks instead.
    if reach > MAX_RING && k == 1 {
        let points: Vec<Site> = sites.iter().map(|&p| Site::point(p)).gather("points")?;
        let (labels, distances) = nearest_by_blocks(&points, frame, metric)?;
        return Ok(levels(frame, k, sites.len(), started, labels, distances));
    }
    if reach > MAX_RING {
        return Err(Error::out_of_range(format!(
            "a site lies {reach:.3e} pixels from the picture; the CPU pixel algorithm \
             grows sites at most {MAX_RING:e} pixels for more than the nearest site"
        )));
    }
    // The rings of radius in [near, far] of a site touch the picture; radii
    // that no site's ring touches are skipped, so a far site costs what a
    // near one does.
    let mut spans: Vec<(i64, i64)> = pixels
        .iter()
        .map(|p| {
            let c = p.round();
            (
                (frame.distance_to_pixels(c).floor() as i64 - 1).max(0),
                frame.farthest_pixel(c).ceil() as i64 + 1,
            )
        })
        .gather("pixel ranges")?;
    spans.sort_unstable();
    let mut keys = crate::memory::filled(w * h * ku, (f64::INFINITY, u32::MAX), "levels' keys")?;
    // A pixel's list can hold at most this many sites.
    let full = ku.min(sites.len());
    let mut done = crate::memory::filled(h.div_ceil(BAND_ROWS as usize), false, "bands done")?;
    let lower = metric.euclidean_bounds().0;
    // Ring r of the offset table holds the offsets of length in (r - 1, r]; the
    // sites visit it row by row of the band.
    let (mut r, mut span) = (0i64, 0usize);
    let mut far = -1i64;
    let watch = Watch::current();
    let last = reach.ceil() as i64 + 1;
    while r <= last {
        watch.check()?;
        progress(r as u64, last as u64);
        while span < spans.len() && spans[span].0 <= r {
            far = far.max(spans[span].1);
            span += 1;
        }
        if r > far {
            // No ring of this radius reaches the picture: on to the next site's.
            match spans.get(span) {
                Some(&(near, _)) => r = near,
                None => break,
            }
            continue;
        }
        keys.par_chunks_mut(BAND_ROWS as usize * w * ku)
            .zip(done.par_iter_mut())
            .enumerate()
            .filter(|(_, (_, done))| !**done)
            .for_each(|(band, (band_keys, done))| {
                let y0 = (band * BAND_ROWS as usize) as i64;
                let rows = (band_keys.len() / (w * ku)) as i64;
                // Sites whose ring r can reach a row of the band.
                let from = by_row.partition_point(|s| s.0 < y0 - r);
                let to = by_row.partition_point(|s| s.0 <= y0 + rows - 1 + r);
                for &(ay, ax, i) in &by_row[from..to] {
                    let site = pixels[i as usize];
                    for y in y0.max(ay - r)..(y0 + rows).min(ay + r + 1) {
                        for dxs in ring_row(r, y - ay) {
                            for x in dxs.map(|dx| ax + dx) {
                                if x < 0 || x >= w as i64 {
                                    continue;
                                }
                                let q = DVec2::new(x as f64, y as f64);
                                let at = ((y - y0) as usize * w + x as usize) * ku;
                                insert(&mut band_keys[at..at + ku], (metric.key(q - site), i));
                            }
                        }
                    }
                }
                // Final once every pixel's list is as full as it can be and its last
                // key beats any later arrival (at least r - SLACK away, Euclidean;
                // at least a times that in the metric).
                let horizon = r as f64 - SLACK;
                let last_key = metric.key_of_distance(lower * horizon.max(0.0));
                *done = horizon > 0.0
                    && band_keys
                        .chunks_exact(ku)
                        .all(|list| list[full - 1].0 <= last_key);
            });
        if done.iter().all(|d| *d) {
            break;
        }
        r += 1;
    }
    let to_world = 1.0 / frame.scale;
    let (labels, distances) = keys
        .par_iter()
        .map(|&(key, i)| {
            if i == u32::MAX {
                (u32::MAX, f32::INFINITY)
            } else {
                (i, (metric.distance_of_key(key) * to_world) as f32)
            }
        })
        .unzip();
    Ok(levels(frame, k, sites.len(), started, labels, distances))
}

/// The levels' maps as the CPU computed them.
fn levels(
    frame: &Frame,
    k: u32,
    sites: usize,
    started: std::time::Instant,
    labels: Vec<u32>,
    distances: Vec<f32>,
) -> KNearest {
    KNearest {
        width: frame.width,
        height: frame.height,
        frame: *frame,
        k,
        labels,
        distances,
        stats: KNearestStats {
            device: "cpu".into(),
            sites,
            levels: k,
            render_ms: started.elapsed().as_secs_f64() * 1e3,
            ..Default::default()
        },
    }
}

/// Inserts `key` into the sorted list `list` if it is among its smallest.
fn insert(list: &mut [(f64, u32)], key: (f64, u32)) {
    let last = list.len() - 1;
    let smaller = |a: (f64, u32), b: (f64, u32)| a.0 < b.0 || (a.0 == b.0 && a.1 < b.1);
    if !smaller(key, list[last]) {
        return;
    }
    let mut at = last;
    while at > 0 && smaller(key, list[at - 1]) {
        list[at] = list[at - 1];
        at -= 1;
    }
    list[at] = key;
}

/// The furthest-site diagram on the CPU, of sites checked where they entered:
/// every pixel against the convex hull's sites, the only ones that own
/// furthest regions, found as the device's proposals are proved: in doubles
/// where they tell, exactly elsewhere.
pub(crate) fn furthest_checked(
    sites: Checked<'_>,
    frame: &Frame,
    metric: Metric,
) -> Result<Furthest> {
    let sites = sites.sites();
    frame.check()?;
    frame.reserve(16, "the CPU's furthest sites")?;
    let hull = furthest_candidates(sites, &convex_hull(sites), metric);
    let none = crate::memory::filled(frame.len(), u32::MAX, "the furthest sites")?;
    exactly_furthest(sites, frame, metric, none, hull)
}

/// The nearest of general sites to every pixel in f64, by blocks (see
/// `voronoi::sites`), before the exact check: far sites' nearest-site maps
/// here, general sites' there.
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub(crate) fn nearest_by_blocks(
    sites: &[Site],
    frame: &Frame,
    metric: Metric,
) -> Result<(Vec<u32>, Vec<f32>)> {
    check_general_sites(sites)?;
    frame.check()?;
    frame.reserve(16, "the CPU's nearest sites")?;
    let (w, h) = (frame.width as usize, frame.height as usize);
    let pixels: Vec<Site> = sites
        .iter()
        .map(|s| s.to_pixels(|p| frame.to_pixel(p), frame.scale))
        .gather("pixels")?;
    let boxes: Vec<(DVec2, DVec2)> = pixels.iter().map(Site::bounds).gather("boxes")?;
    let lower = metric.euclidean_bounds().0;
    let block = BAND_ROWS as usize;
    let mut best = crate::memory::filled(w * h, (f64::INFINITY, u32::MAX), "nearest keys")?;
    let watch = Watch::current();
    best.par_chunks_mut(block * w)
        .enumerate()
        .for_each(|(band, band_best)| {
            if watch.cancelled() {
                return;
            }
            let y0 = band * block;
            let rows = band_best.len() / w;
            for x0 in (0..w).step_by(block) {
                let cols = block.min(w - x0);
                let lo = DVec2::new(x0 as f64, y0 as f64);
                let hi = lo + DVec2::new(cols as f64 - 1.0, rows as f64 - 1.0);
                // Each site's lower bound over the block, smallest first.
                let mut order: Vec<(f64, usize)> = boxes
                    .iter()
                    .zip(&pixels)
                    .enumerate()
                    .map(|(i, ((a, b), s))| {
                        let gap = (*a - hi).max(lo - *b).max(DVec2::ZERO).length();
                        (
                            lower * gap / (frame.scale * s.multiplicative) + s.additive,
                            i,
                        )
                    })
                    .collect();
                order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                for y in 0..rows {
                    for x in x0..x0 + cols {
                        let q = DVec2::new(x as f64, (y0 + y) as f64);
                        let at = &mut band_best[y * w + x];
                        for &(bound, i) in &order {
                            if bound > at.0 {
                                break;
                            }
                            let s = &pixels[i];
                            let d = s.distance_to_shape(metric, q)
                                / (frame.scale * s.multiplicative)
                                + s.additive;
                            if d < at.0 || (d == at.0 && (i as u32) < at.1) {
                                *at = (d, i as u32);
                            }
                        }
                    }
                }
            }
        });
    watch.check()?;
    Ok(best.into_iter().map(|(d, i)| (i, d as f32)).unzip())
}
