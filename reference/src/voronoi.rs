//! The Voronoi diagram by its definition: for every pixel centre, the site at the
//! smallest Euclidean distance, found by looking at every site (or, for
//! [`nearest_sites_grid`], every site of the buckets that can hold the nearest).

use glam::DVec2;
use rayon::prelude::*;

use crate::metric::{self, distance, euclidean_bounds, shape_distance, to_world};
use pixgeo::geometry::{
    metric::Metric,
    site::{Shape, Site},
    Frame,
};

/// For every pixel (row-major), the smallest distance to a site (pixel units) and the
/// lowest index of a site at that distance. Sites are in pixel coordinates.
pub fn nearest_sites_brute_force(sites: &[DVec2], frame: &Frame) -> (Vec<u32>, Vec<f64>) {
    let w = frame.width as usize;
    let results: Vec<(u32, f64)> = (0..metric::pixels(frame))
        .into_par_iter()
        .map(|k| {
            let q = DVec2::new((k % w) as f64, (k / w) as f64);
            let mut best = (u32::MAX, f64::INFINITY);
            for (i, s) in sites.iter().enumerate() {
                let d = (*s - q).length_squared();
                if d < best.1 {
                    best = (i as u32, d);
                }
            }
            (best.0, best.1.sqrt())
        })
        .collect();
    results.into_iter().unzip()
}

/// The same labels as [`nearest_sites_brute_force`] (up to ties), computed with a
/// bucket grid and parallel rows: the exact CPU search a user would write instead of
/// rendering. Sites far outside the picture are searched linearly.
pub fn nearest_sites_grid(sites: &[DVec2], frame: &Frame) -> Vec<u32> {
    let (w, h) = (frame.width as usize, frame.height as usize);
    let cell = ((metric::pixels(frame) as f64 / sites.len().max(1) as f64).sqrt() * 1.5).max(2.0);
    let gx = (w as f64 / cell).ceil() as usize;
    let gy = (h as f64 / cell).ceil() as usize;
    let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); gx * gy];
    let mut outside: Vec<u32> = Vec::new();
    for (i, s) in sites.iter().enumerate() {
        let bx = ((s.x + 0.5) / cell).floor();
        let by = ((s.y + 0.5) / cell).floor();
        if bx >= 0.0 && by >= 0.0 && (bx as usize) < gx && (by as usize) < gy {
            buckets[by as usize * gx + bx as usize].push(i as u32);
        } else {
            outside.push(i as u32);
        }
    }
    let mut labels = vec![u32::MAX; w * h];
    labels.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        let by = ((y as f64 + 0.5) / cell) as usize;
        for (x, out) in row.iter_mut().enumerate() {
            let q = DVec2::new(x as f64, y as f64);
            let bx = ((x as f64 + 0.5) / cell) as usize;
            let mut best = (u32::MAX, f64::INFINITY);
            let consider = |best: &mut (u32, f64), i: u32| {
                let d = (sites[i as usize] - q).length_squared();
                if d < best.1 || (d == best.1 && i < best.0) {
                    *best = (i, d);
                }
            };
            for &i in &outside {
                consider(&mut best, i);
            }
            // Rings of buckets until the ring is farther than the best distance.
            let mut ring = 0usize;
            loop {
                let lo_x = bx.saturating_sub(ring);
                let lo_y = by.saturating_sub(ring);
                let hi_x = (bx + ring).min(gx - 1);
                let hi_y = (by + ring).min(gy - 1);
                for cy in lo_y..=hi_y {
                    for cx in lo_x..=hi_x {
                        let on_ring = cx + ring == bx
                            || cx == bx + ring
                            || cy + ring == by
                            || cy == by + ring;
                        if on_ring {
                            for &i in &buckets[cy * gx + cx] {
                                consider(&mut best, i);
                            }
                        }
                    }
                }
                // Any site in a farther ring is at least `ring * cell` away.
                let reach = ring as f64 * cell;
                let all_covered = lo_x == 0 && lo_y == 0 && hi_x == gx - 1 && hi_y == gy - 1;
                if all_covered || (best.1.is_finite() && reach * reach >= best.1) {
                    break;
                }
                ring += 1;
            }
            *out = best.0;
        }
    });
    labels
}

/// For every pixel (row-major), the smallest `metric` distance to a site (pixel
/// units), by looking at every site. Sites are in pixel coordinates.
pub fn nearest_distances_metric(sites: &[DVec2], frame: &Frame, metric: Metric) -> Vec<f64> {
    let w = frame.width as usize;
    (0..metric::pixels(frame))
        .into_par_iter()
        .map(|k| {
            let q = DVec2::new((k % w) as f64, (k / w) as f64);
            sites
                .iter()
                .map(|s| distance(metric, q - *s))
                .fold(f64::INFINITY, f64::min)
        })
        .collect()
}

/// For every pixel (row-major), the smallest weighted distance (world units) to a
/// site of any shape, by looking at every site. Sites are in world coordinates.
/// Circles and arcs under metrics other than L2 are measured at
/// [`CURVE_SAMPLES`] points per turn (and their ends), which overestimates by at
/// most [`curve_sampling_slack`].
pub fn nearest_weighted_distances(sites: &[Site], frame: &Frame, metric: Metric) -> Vec<f64> {
    let w = frame.width as usize;
    let weighted = |s: &Site, d: f64| d / s.multiplicative + s.additive;
    // The curves whose distance is sampled, with their circle; the rest.
    let circle = |s: &Site| match s.shape {
        Shape::Circle { center, radius } | Shape::Arc { center, radius, .. }
            if metric != Metric::L2 =>
        {
            Some((center, radius))
        }
        _ => None,
    };
    let curves: Vec<_> = sites.iter().filter_map(|s| Some((s, circle(s)?))).collect();
    let others: Vec<_> = sites.iter().filter(|s| circle(s).is_none()).collect();
    // A sampled curve is no nearer than a·|‖q − c‖ − r| (a from the metric's
    // Euclidean bounds); one whose bound cannot beat the best is not sampled.
    let slack = 1.0 - 1e-9;
    let (a, _) = euclidean_bounds(metric);
    (0..metric::pixels(frame))
        .into_par_iter()
        .map(|k| {
            let q = to_world(frame, DVec2::new((k % w) as f64, (k / w) as f64));
            let mut best = others
                .iter()
                .map(|s| weighted(s, shape_distance(metric, s.shape, q, CURVE_SAMPLES)))
                .fold(f64::INFINITY, f64::min);
            for &(s, (center, radius)) in &curves {
                let bound = weighted(s, slack * a * ((q - center).length() - radius).abs());
                if bound < best {
                    best = best.min(weighted(
                        s,
                        shape_distance(metric, s.shape, q, CURVE_SAMPLES),
                    ));
                }
            }
            best
        })
        .collect()
}

/// Points per turn at which [`nearest_weighted_distances`] samples curves.
pub const CURVE_SAMPLES: usize = 1 << 11;

/// How much sampling curves can overestimate a weighted distance: half the
/// spacing of the samples, stretched by the metric.
pub fn curve_sampling_slack(sites: &[Site], metric: Metric) -> f64 {
    if metric == Metric::L2 {
        return 0.0;
    }
    let b = euclidean_bounds(metric).1;
    sites
        .iter()
        .map(|s| match s.shape {
            Shape::Circle { radius, .. } | Shape::Arc { radius, .. } => {
                b * radius * std::f64::consts::PI / CURVE_SAMPLES as f64 / s.multiplicative
            }
            _ => 0.0,
        })
        .fold(0.0, f64::max)
}
