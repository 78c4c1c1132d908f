//! Distances rounded from their exact values: the float32 nearest the exact
//! distance from a site to a pixel's centre.

use std::cmp::Ordering;

use glam::DVec2;
use num_rational::BigRational;

use super::{exact_key, exact_order, pixel_offset, rational};
use crate::geometry::{metric::Metric, Frame};

/// The exact offset, in pixels, from a site to a pixel's centre (or a whole
/// offset between pixel centres), held for comparisons that floats could not
/// decide.
#[derive(Clone, Debug)]
pub(crate) struct PixelOffset([BigRational; 2]);

impl PixelOffset {
    /// From `site` (world) to the centre of `pixel` of `frame`.
    pub fn of(frame: &Frame, site: DVec2, pixel: [i64; 2]) -> Self {
        Self(pixel_offset(frame, site, pixel))
    }

    /// A whole number of pixels.
    pub fn whole(offset: [i64; 2]) -> Self {
        Self(offset.map(|v| BigRational::from_integer(v.into())))
    }

    /// Whether the site lies on the pixel's centre.
    pub fn is_zero(&self) -> bool {
        self.0.iter().all(num_traits::Zero::is_zero)
    }

    /// The order of the two offsets' lengths under `metric`; `None` where the
    /// kernel cannot decide it (L_p with p no fraction m/n of n up to 64).
    pub fn order(&self, metric: Metric, other: &Self) -> Option<Ordering> {
        exact_order(metric, &self.0, &other.0)
    }

    /// Whether the offset's exact key under `metric` exceeds the integer
    /// `m`; `None` where the metric has no rational key.
    pub fn key_exceeds(&self, metric: Metric, m: i64) -> Option<bool> {
        exact_key(metric, &self.0).map(|key| BigRational::from_integer(m.into()) < key)
    }
}

/// The float32 nearest the distance (world units) from `site` to the centre
/// of `pixel` of `frame` under `metric`, known to lie in `[lo, hi]`; `None`
/// where the metric has no exact key (L_p with p not whole).
pub(crate) fn rounded_pixel_distance(
    metric: Metric,
    frame: &Frame,
    site: DVec2,
    pixel: [i64; 2],
    [lo, hi]: [f32; 2],
) -> Option<f32> {
    let key = exact_key(metric, &pixel_offset(frame, site, pixel))?;
    Some(rounded_root(&key, key_power(metric), frame.scale, lo, hi))
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
