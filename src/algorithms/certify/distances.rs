//! Each label's distance as the float32 nearest the exact one: a double
//! estimate from the site's place and its rest, and exact keys where the
//! estimate's bound straddles a float32 rounding boundary.

use glam::DVec2;
use rayon::prelude::*;

use super::{Certifier, Region};
use crate::geometry::exact::distance::rounded_pixel_distance;

impl Certifier<'_> {
    /// Each label's distance in `region` (world units, float32, every level) to
    /// its site, from the label alone, so that tiles, windows and devices
    /// agree to the bit: the float32 nearest the exact distance from the
    /// site given to the pixel's centre (L_p with p not whole: within a few
    /// units of the double's last place of it).
    pub fn label_distances(&self, region: Region, labels: &[u32], distances: &mut [f32]) {
        let (k, to_world) = (region.k, 1.0 / self.frame.scale);
        distances
            .par_chunks_mut(region.stride * k)
            .zip(labels.par_chunks(region.stride * k))
            .take(region.height as usize)
            .enumerate()
            .for_each(|(row, (d, l))| {
                let y = (region.y0 as usize + row) as f64;
                let row = d.iter_mut().zip(l).take(region.width as usize * k);
                for (at, (d, &id)) in row.enumerate() {
                    let column = at / k;
                    let x = (region.x0 as usize + column) as f64;
                    *d = self.rounded_distance(id, DVec2::new(x, y), to_world);
                }
            });
    }

    /// The float32 nearest the distance (world units) from site `id` to the
    /// centre of `pixel` (integer pixel coordinates); infinite for no site.
    /// The double estimate from the site's place and rest settles it unless
    /// its error bound straddles a float32 rounding boundary; then the exact
    /// key does, where the metric has one.
    fn rounded_distance(&self, id: u32, pixel: DVec2, to_world: f64) -> f32 {
        let Some(&place) = self.places.get(id as usize) else {
            return f32::INFINITY;
        };
        let (rest, bound) = (self.rests[id as usize], self.errors[id as usize]);
        // Within ε of the offset and of the rest, which the slack takes in.
        let offset = (pixel - place) - rest;
        let metric = self.metric;
        let estimate = metric.distance_of_key(metric.key(offset));
        // The offset within 4ε of itself and the place's bound; the
        // metric's arithmetic (powers and roots for L_p) within 64ε.
        let u = f64::EPSILON;
        let slack = 64.0 * u * estimate
            + 8.0 * (u * (offset.abs().max_element() + bound) + 4.0 * f64::MIN_POSITIVE);
        if !estimate.is_finite() {
            return (estimate * to_world) as f32;
        }
        // to_world is 1 / scale within ε, and each product within ε more.
        // + 0.0: a negative zero's bits would order it above every float.
        let lo = ((estimate - slack).max(0.0) * to_world * (1.0 - 4.0 * u) + 0.0) as f32;
        let hi = ((estimate + slack) * to_world * (1.0 + 4.0 * u)) as f32;
        if lo == hi {
            return lo;
        }
        let at = [pixel.x as i64, pixel.y as i64];
        rounded_pixel_distance(metric, &self.frame, self.sites[id as usize], at, [lo, hi])
            .unwrap_or((estimate * to_world) as f32)
    }
}
