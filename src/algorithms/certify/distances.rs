//! Each label's distance as the float32 nearest the exact one: a double
//! estimate from the site's place and its rest, and exact keys where the
//! estimate's bound straddles a float32 rounding boundary.

use std::cmp::Ordering;

use glam::DVec2;
use num_rational::BigRational;
use rayon::prelude::*;

use super::{Certifier, Region};
use crate::geometry::{
    exact::{exact_key, pixel_offset, rational},
    metric::Metric,
};

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
        let scale = self.frame.scale;
        let at = [pixel.x as i64, pixel.y as i64];
        let Some(key) = exact_key(
            metric,
            &pixel_offset(&self.frame, self.sites[id as usize], at),
        ) else {
            return (estimate * to_world) as f32;
        };
        rounded_root(&key, key_power(metric), scale, lo, hi)
    }
}

/// The power of the distance that [`exact_key`] gives for `metric`: 2 for
/// L2, p for L_p with p whole, 1 for L1, L∞ and polygons.
fn key_power(metric: Metric) -> u32 {
    match metric {
        Metric::L2 => 2,
        Metric::Lp(p) => p as u32,
        _ => 1,
    }
}

/// The float32 nearest `d = key^(1/power) / scale` (ties to even), known to
/// lie in `[lo, hi]` (non-negative): a binary search over the float32s
/// between, each step comparing `d` exactly with the midpoint above a
/// float32 as `(midpoint · scale)^power` against `key`.
fn rounded_root(key: &BigRational, power: u32, scale: f64, lo: f32, hi: f32) -> f32 {
    let scale = rational(scale);
    // Whether d lies beyond the midpoint of r and the float32 above it (on
    // it, towards the even one).
    let above = |r: f32| {
        let up = f32::from_bits(r.to_bits() + 1);
        // Past the largest float32, the overflow threshold.
        let mid = match up.is_finite() {
            true => (r as f64 + up as f64) / 2.0,
            false => f32::MAX as f64 + 2f64.powi(103),
        };
        match num_traits::pow(rational(mid) * &scale, power as usize).cmp(key) {
            Ordering::Less => true,
            Ordering::Equal => r.to_bits() % 2 == 1,
            Ordering::Greater => false,
        }
    };
    let (mut a, mut b) = (lo.to_bits(), hi.to_bits());
    while a < b {
        let m = a + (b - a) / 2;
        if above(f32::from_bits(m)) {
            a = m + 1;
        } else {
            b = m;
        }
    }
    f32::from_bits(a)
}
