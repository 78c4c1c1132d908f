//! The settle point's discs: the positions strictly nearer to a pixel than
//! its nearest site, their float32 radii for the shaders and their exact
//! membership, and sites tied at a pixel.

use std::cmp::Ordering;

use glam::DVec2;

use super::{Certifier, FloatKey};
use crate::geometry::{
    exact::{distance::PixelOffset, exact_float_key},
    metric::Metric,
};

/// The disc of one pixel in a settle count: the positions strictly nearer
/// to the pixel than its nearest site, whose key lies in `[lo, hi]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Disc {
    pixel: [i64; 2],
    site: u32,
    lo: f64,
    hi: f64,
}

impl Disc {
    /// The pixel whose disc this is.
    pub fn pixel(&self) -> [i64; 2] {
        self.pixel
    }
}

impl Certifier<'_> {
    /// The disc of `pixel` (picture pixels) whose nearest site is `site`.
    pub fn disc(&self, pixel: [i64; 2], site: u32) -> Disc {
        let c = self.candidate(DVec2::new(pixel[0] as f64, pixel[1] as f64), site);
        Disc {
            pixel,
            site,
            lo: c.lo,
            hi: c.hi,
        }
    }

    /// A Euclidean radius (pixels) that holds the disc.
    pub fn disc_radius(&self, disc: &Disc) -> f64 {
        let (lower, _) = self.metric.euclidean_bounds();
        self.keys.distance(disc.hi) / lower
    }

    /// The shader's code (`glsl/metric.glsl`) for the keys a disc's radius is
    /// given in: sums of powers for integer p from 3 to 16, whose integer
    /// offsets' keys are integers, the metric's own keys otherwise.
    pub fn shader_code(metric: Metric) -> (u32, f32) {
        match FloatKey::of(metric) {
            FloatKey::PowerSum(p) => (4, p as f32),
            _ => metric.shader_code().unwrap_or((0, 2.0)),
        }
    }

    /// A float32 key above that of every offset between two pixels of the
    /// frame: a disc of a larger radius covers the picture as this one does,
    /// and its bounds stay within the shaders' integers.
    pub fn covering_radius(&self) -> f32 {
        let (w, h) = (self.frame.width as f64, self.frame.height as f64);
        let reach = w.hypot(h) * self.metric.euclidean_bounds().1 * 2.0 + 2.0;
        round_up_f32(self.keys.of_distance(reach))
    }

    /// The float32 radius for a strict `key < radius` test of the float32
    /// keys of integer offsets that holds exactly the disc's positions: where
    /// those keys are integers that float32 holds (L1, L2, L∞ and integer p
    /// up to 16, below 2^24),
    /// a float32 between the largest integer key strictly below the disc's
    /// exact key and the next integer; elsewhere the disc's float key rounded
    /// up.
    pub fn disc_radius_f32(&self, disc: &Disc) -> f32 {
        let integer_keys = matches!(self.metric, Metric::L1 | Metric::L2 | Metric::LInf)
            || matches!(self.keys, FloatKey::PowerSum(_));
        if !integer_keys || disc.hi.is_nan() || disc.hi >= (1u32 << 24) as f64 {
            // A pixel centred on its site holds no disc; any other holds at
            // least itself, and a float32 key too small for a normal number
            // would reach a device flushed to zero.
            let site = self.sites[disc.site as usize];
            let centred =
                disc.lo == 0.0 && PixelOffset::of(&self.frame, site, disc.pixel).is_zero();
            return match centred {
                true => 0.0,
                false => round_up_f32(disc.hi).max(f32::MIN_POSITIVE),
            };
        }
        // The largest integer below the exact key: below the interval's low
        // end surely, and each integer in the interval decided exactly.
        let mut exact = None;
        let mut below = |m: f64| {
            if disc.lo == disc.hi {
                return m < disc.lo;
            }
            let offset = exact.get_or_insert_with(|| {
                PixelOffset::of(&self.frame, self.sites[disc.site as usize], disc.pixel)
            });
            offset
                .key_exceeds(self.metric, m as i64)
                .expect("L1, L2, L∞ and integer p keys are rational")
        };
        let mut largest = disc.lo.ceil() - 1.0;
        while largest + 1.0 <= disc.hi && below(largest + 1.0) {
            largest += 1.0;
        }
        if largest < 0.0 {
            return 0.0;
        }
        // Halfway to the next integer where float32 holds it (no subnormal
        // that a device might flush to zero), else the next float32 up.
        match largest < (1u32 << 23) as f64 {
            true => (largest + 0.5) as f32,
            false => f32::from_bits((largest as f32).to_bits() + 1),
        }
    }

    /// Whether the pixel centre `offset` pixels from the disc's pixel is
    /// strictly nearer to it than the disc's site, exactly (L_p with p no
    /// fraction m/n of n up to 64: by floats where they cannot tell).
    pub fn in_disc(&self, disc: &Disc, offset: [i64; 2]) -> bool {
        let (dx, dy) = (offset[0] as f64, offset[1] as f64);
        let (lo, hi) = match exact_float_key(self.metric, dx, dy) {
            Some(key) if matches!(self.keys, FloatKey::Metric(_)) => (key, key),
            _ => self.keys.bounds(dx, dy),
        };
        if hi < disc.lo {
            return true;
        }
        if lo > disc.hi || (lo == hi && disc.lo == disc.hi) {
            return lo < disc.lo;
        }
        let to_site = PixelOffset::of(&self.frame, self.sites[disc.site as usize], disc.pixel);
        let order = PixelOffset::whole(offset).order(self.metric, &to_site);
        order.map_or(lo < disc.lo, |o| o == Ordering::Less)
    }

    /// The sites exactly as near pixel `pixel` (picture pixels) as `nearest`,
    /// itself included.
    #[expect(clippy::disallowed_methods, reason = "the sites tied at one pixel")]
    pub fn tied_with(&self, pixel: [i64; 2], nearest: u32) -> Vec<u32> {
        let p = DVec2::new(pixel[0] as f64, pixel[1] as f64);
        let reach = self.reach(p, &[nearest]);
        let within = reach * reach * (1.0 + 1e-12);
        self.grid
            .around(p, reach)
            .filter(|&id| self.places[id as usize].distance_squared(p) <= within)
            .filter(|&id| {
                id == nearest
                    || (self.no_farther(id, self, nearest, pixel)
                        && self.no_farther(nearest, self, id, pixel))
            })
            .collect()
    }

    /// Whether this certifier's site `a` is at most as far from `pixel` as
    /// `other`'s site `b`, exactly (as [`Certifier::in_disc`]).
    pub fn no_farther(&self, a: u32, other: &Certifier<'_>, b: u32, pixel: [i64; 2]) -> bool {
        let at = DVec2::new(pixel[0] as f64, pixel[1] as f64);
        let (ca, cb) = (self.candidate(at, a), other.candidate(at, b));
        if ca.hi < cb.lo {
            return true;
        }
        if ca.lo > cb.hi {
            return false;
        }
        let oa = PixelOffset::of(&self.frame, self.sites[a as usize], pixel);
        let ob = PixelOffset::of(&other.frame, other.sites[b as usize], pixel);
        let order = oa.order(self.metric, &ob);
        order.map_or(ca.lo <= cb.lo, |o| o != Ordering::Greater)
    }
}

/// The smallest float32 at least `x`.
fn round_up_f32(x: f64) -> f32 {
    let f = x as f32;
    // For finite positive f the next float up has the next bit pattern.
    if (f as f64) < x && f.is_finite() && f >= 0.0 {
        f32::from_bits(f.to_bits() + 1)
    } else {
        f
    }
}
