//! The settle point's definition evaluated directly: insert each candidate pixel
//! and count the pixels it would win.

use glam::DVec2;
use rayon::prelude::*;

use crate::metric::{self, key};
use pixgeo::geometry::{metric::Metric, Frame};

/// Potential areas by the definition (thesis Def. 3.4 on pixels): for every
/// candidate pixel t, the number of pixels p that t is strictly nearer to than
/// every existing site, not counting pixels where an `own` site is at least as
/// near as every rival. Sites in pixel coordinates; float64 throughout.
///
/// `slack` widens the comparison: the result is a pair of maps counted with the
/// radius key scaled by `1 - slack` and by `1 + slack`, which bracket every
/// evaluation whose rounding stays within that relative error (pass 0 for an
/// exact count, twice).
pub fn potential_areas_brute_force(
    rivals: &[DVec2],
    own: &[DVec2],
    frame: &Frame,
    metric: Metric,
    slack: f64,
) -> (Vec<u32>, Vec<u32>) {
    let w = frame.width as usize;
    let pixel = |k: usize| DVec2::new((k % w) as f64, (k / w) as f64);
    let nearest = |sites: &[DVec2], p: DVec2| {
        sites
            .iter()
            .map(|s| key(metric, *s - p))
            .fold(f64::INFINITY, f64::min)
    };
    // The radius key of every pixel that counts.
    let pixels: Vec<(DVec2, f64)> = (0..metric::pixels(frame))
        .map(pixel)
        .filter_map(|p| {
            let rival = nearest(rivals, p);
            (nearest(own, p) > rival).then_some((p, rival))
        })
        .collect();
    (0..metric::pixels(frame))
        .into_par_iter()
        .map(|k| {
            let t = pixel(k);
            pixels.iter().fold((0, 0), |(lo, hi), &(p, r)| {
                let key = key(metric, t - p);
                (
                    lo + (key < r * (1.0 - slack)) as u32,
                    hi + (key < r * (1.0 + slack)) as u32,
                )
            })
        })
        .unzip()
}
