//! Higher-order diagrams by their definitions: for every pixel centre, all sites
//! sorted by distance (ties by index), and the furthest site.

use glam::DVec2;
use rayon::prelude::*;

use crate::metric::{distance, pixels};
use pixgeo::geometry::{metric::Metric, Frame};

/// For every pixel (row-major), its `k` nearest sites as `(index, distance)` in
/// pixel units, sorted by distance and then index; fewer where fewer sites exist.
/// Sites are in pixel coordinates.
pub fn k_nearest_brute_force(sites: &[DVec2], frame: &Frame, k: usize) -> Vec<Vec<(u32, f64)>> {
    k_nearest_by_metric(sites, frame, k, Metric::L2)
}

/// [`k_nearest_brute_force`] under another distance function.
pub fn k_nearest_by_metric(
    sites: &[DVec2],
    frame: &Frame,
    k: usize,
    metric: Metric,
) -> Vec<Vec<(u32, f64)>> {
    let w = frame.width as usize;
    (0..pixels(frame))
        .into_par_iter()
        .map(|p| {
            let q = DVec2::new((p % w) as f64, (p / w) as f64);
            let mut all: Vec<(u32, f64)> = sites
                .iter()
                .enumerate()
                .map(|(i, s)| (i as u32, distance(metric, q - *s)))
                .collect();
            all.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
            all.truncate(k);
            all
        })
        .collect()
}

/// For every pixel (row-major), the largest `metric` distance to a site (pixel
/// units) and the lowest index of a site at that distance. Sites are in pixel
/// coordinates.
pub fn furthest_brute_force(
    sites: &[DVec2],
    frame: &Frame,
    metric: Metric,
) -> (Vec<u32>, Vec<f64>) {
    let w = frame.width as usize;
    (0..pixels(frame))
        .into_par_iter()
        .map(|p| {
            let q = DVec2::new((p % w) as f64, (p / w) as f64);
            let mut best = (u32::MAX, f64::NEG_INFINITY);
            for (i, s) in sites.iter().enumerate() {
                let d = distance(metric, q - *s);
                if d > best.1 {
                    best = (i as u32, d);
                }
            }
            best
        })
        .unzip()
}
