//! The settle point refined off the pixel grid: the exact stolen area of a
//! candidate, climbed by compass search.

use super::*;
use crate::cancel::Watch;

/// The refined settle point: a position (pixel coordinates) and the exact area
/// (square pixels) of the region a new site there would win, clipped to the
/// picture and without the own stores' regions.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Refined {
    pub position: [f64; 2],
    pub area: f64,
    /// The exact area at the pixel the search started from.
    pub start_area: f64,
    pub start_pixel: [u32; 2],
}

/// Refines the settle point beyond the pixels (Euclidean metric): from each of
/// the `starts` (row-major pixel indices), a compass search over the exact area
/// of the new site's Voronoi region (`cell::StolenArea`) climbs to a local
/// maximum, halving its step from one pixel to 1e-9 pixels; the best climb wins.
/// The result's area is at least the exact area at its starting pixel. Sites in
/// world coordinates; the result in pixel coordinates.
pub fn refine(rivals: &[DVec2], own: &[DVec2], frame: &Frame, starts: &[usize]) -> Result<Refined> {
    check(rivals, own, frame, Metric::L2)?;
    if starts.is_empty() {
        return Err(Error::degenerate("no pixel to refine from".into()));
    }
    let rivals = to_pixels(&distinct(rivals), frame);
    let own = to_pixels(&distinct(own), frame);
    let picture = cell::Rect {
        lo: DVec2::splat(-0.5),
        hi: DVec2::new(frame.width as f64 - 0.5, frame.height as f64 - 0.5),
    };
    let w = frame.width as usize;
    let watch = Watch::current();
    let climbs: Vec<Refined> = starts
        .par_iter()
        .map(|&k| {
            watch.check()?;
            let pixel = [(k % w) as u32, (k / w) as u32];
            let start = DVec2::new(pixel[0] as f64, pixel[1] as f64);
            let stolen = cell::StolenArea::new(start, &rivals, &own, &picture);
            let area = |t: DVec2| stolen.at(t);
            let (position, best) = compass_search(start, &area, &picture);
            Ok(Refined {
                position: position.to_array(),
                area: best,
                start_area: area(start),
                start_pixel: pixel,
            })
        })
        .collect::<Result<_>>()?;
    climbs
        .into_iter()
        .max_by(|a, b| a.area.total_cmp(&b.area))
        .ok_or_else(|| Error::degenerate("no pixel to refine from".into()))
}

/// Climbs `f` from `start` within `bounds` by compass steps (eight directions),
/// halving the step whenever no direction improves.
fn compass_search(start: DVec2, f: &dyn Fn(DVec2) -> f64, bounds: &cell::Rect) -> (DVec2, f64) {
    let directions = [
        DVec2::new(1.0, 0.0),
        DVec2::new(-1.0, 0.0),
        DVec2::new(0.0, 1.0),
        DVec2::new(0.0, -1.0),
        DVec2::new(1.0, 1.0),
        DVec2::new(1.0, -1.0),
        DVec2::new(-1.0, 1.0),
        DVec2::new(-1.0, -1.0),
    ];
    let (mut x, mut best) = (start, f(start));
    let mut step = 1.0;
    while step > 1e-9 {
        let improved = directions
            .iter()
            .map(|d| (x + *d * step).clamp(bounds.lo, bounds.hi))
            .map(|y| (y, f(y)))
            .filter(|&(_, v)| v > best)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        match improved {
            Some((y, v)) => (x, best) = (y, v),
            None => step *= 0.5,
        }
    }
    (x, best)
}

#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
fn to_pixels(sites: &[DVec2], frame: &Frame) -> Vec<DVec2> {
    sites.iter().map(|&s| frame.to_pixel(s)).collect()
}
