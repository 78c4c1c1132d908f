//! Where the picture lies in the world. Pixel (i, j) is the unit square centred at
//! pixel coordinates (i, j); without a bounding box, world = pixel coordinates.

use crate::memory::Gather;
use glam::DVec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::{
    error::{Error, Result},
    machine::PixelRect,
};

/// A picture of `width` x `height` pixels and the world rectangle it shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// World point at the picture's corner (-0.5, -0.5).
    pub origin: DVec2,
    /// Pixels per world unit (the same along both axes, so distances keep their
    /// shape).
    pub scale: f64,
}

impl Frame {
    /// The longest picture side: pixel coordinates go through float32 on the
    /// device, which holds integers exactly up to 2^24.
    pub const MAX_SIDE: u32 = 1 << 24;

    /// The picture side, in pixels along the longer axis, wherever none is
    /// given: the command line's `--size`, C's `side` 0, Python's defaults.
    pub const DEFAULT_SIDE: u32 = 1024;

    /// `n` points drawn uniformly over the world rectangle the picture shows,
    /// the same for the same `seed` (the command line's `--random N --seed S`),
    /// or the memory error where the process cannot hold them.
    pub fn random_points(&self, n: usize, seed: u64) -> Result<Vec<DVec2>> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let lo = self.to_world(DVec2::splat(-0.5));
        let hi = self.to_world(DVec2::new(
            self.width as f64 - 0.5,
            self.height as f64 - 0.5,
        ));
        (0..n)
            .map(|_| DVec2::new(rng.gen_range(lo.x..hi.x), rng.gen_range(lo.y..hi.y)))
            .gather("random points")
    }

    /// World = pixel coordinates: pixel (i, j) centred at world (i, j).
    pub fn pixels(width: u32, height: u32) -> Result<Self> {
        let frame = Self {
            width,
            height,
            origin: DVec2::splat(-0.5),
            scale: 1.0,
        };
        frame.check()?;
        Ok(frame)
    }

    /// Refuses a picture of this frame holding `bytes_per_pixel` bytes a pixel
    /// at once when the process cannot have them ([`crate::memory::reserve`]).
    pub fn reserve(&self, bytes_per_pixel: u64, what: &str) -> Result<()> {
        crate::memory::reserve_picture(self.width, self.height, bytes_per_pixel, what)
    }

    /// The pixels of `window` in this picture: the whole picture without
    /// one; an error for a window that is empty or leaves the picture.
    pub fn window_rect(&self, window: Option<PixelRect>) -> Result<PixelRect> {
        let Some(w) = window else {
            return Ok(PixelRect::sized(self.width, self.height));
        };
        let inside = |at: u32, len: u32, side: u32| at.checked_add(len).is_some_and(|e| e <= side);
        if w.width == 0
            || w.height == 0
            || !inside(w.x, w.width, self.width)
            || !inside(w.y, w.height, self.height)
        {
            return Err(Error::malformed(format!(
                "window {},{},{},{} (x0,y0,width,height) must be a nonempty rectangle inside the \
                 {}x{} picture",
                w.x, w.y, w.width, w.height, self.width, self.height
            )));
        }
        Ok(w)
    }

    /// Checks the picture size: both sides at least 1 and at most [`Self::MAX_SIDE`],
    /// and a finite, positive scale.
    pub fn check(&self) -> Result<()> {
        let (width, height) = (self.width, self.height);
        if width == 0 || height == 0 {
            return Err(Error::out_of_range(format!(
                "picture size {width}x{height}: both sides must be at least 1"
            )));
        }
        if width > Self::MAX_SIDE || height > Self::MAX_SIDE {
            return Err(Error::PictureTooLarge {
                width,
                height,
                limit: Self::MAX_SIDE,
            });
        }
        if !(self.scale > 0.0 && self.scale.is_finite() && self.origin.is_finite()) {
            return Err(Error::malformed(format!(
                "picture frame with scale {} and origin {}",
                self.scale, self.origin
            )));
        }
        Ok(())
    }

    /// The world rectangle `[xmin, xmax] x [ymin, ymax]` mapped onto the picture,
    /// row 0 at `ymin`. `height` may be omitted (`None`): it then follows from the
    /// rectangle's aspect ratio. A given height must match the aspect ratio to within
    /// one pixel, since pixels are square.
    pub fn with_bbox(width: u32, height: Option<u32>, bbox: [f64; 4]) -> Result<Self> {
        let [xmin, ymin, xmax, ymax] = bbox;
        if !bbox.iter().all(|v| v.is_finite()) || xmax <= xmin || ymax <= ymin {
            return Err(Error::malformed(format!(
                "bbox {xmin:?},{ymin:?},{xmax:?},{ymax:?}: need finite XMIN < XMAX and YMIN < YMAX"
            )));
        }
        if width == 0 {
            return Err(Error::out_of_range(
                "picture width must be at least 1".into(),
            ));
        }
        let (dx, dy) = (xmax - xmin, ymax - ymin);
        if !(dx.is_finite() && dy.is_finite()) {
            return Err(Error::out_of_range(format!(
                "bbox {xmin:?},{ymin:?},{xmax:?},{ymax:?} is wider than the largest float: its sides must be finite"
            )));
        }
        let scale = width as f64 / dx;
        let natural = dy * scale;
        if !(scale.is_normal() && natural.is_finite()) {
            return Err(Error::out_of_range(format!(
                "bbox {xmin:?},{ymin:?},{xmax:?},{ymax:?} cannot be mapped onto {width} pixels: its scale {scale:e} pixels per unit is out of range"
            )));
        }
        if height.is_none() && natural > Self::MAX_SIDE as f64 {
            return Err(Error::out_of_range(format!(
                "bbox {xmin:?},{ymin:?},{xmax:?},{ymax:?} at width {width} gives a height of {natural:.0} pixels, more than {}: give a wider picture or a flatter box",
                Self::MAX_SIDE
            )));
        }
        let height = match height {
            Some(h) => {
                if (h as f64 - natural).abs() > 1.0 {
                    return Err(Error::malformed(format!(
                        "bbox aspect ratio gives a height of {natural:.1} pixels for width {width}, not {h}: \
                         pixels are square, so give a height of {:.0} or only the width",
                        natural.round().max(1.0)
                    )));
                }
                h
            }
            None => natural.round().max(1.0) as u32,
        };
        if height == 0 {
            return Err(Error::out_of_range(
                "picture height must be at least 1".into(),
            ));
        }
        Ok(Self {
            width,
            height,
            origin: DVec2::new(xmin, ymin),
            scale,
        })
    }

    /// The world box `[lo, hi]` on a picture whose longer side has `side`
    /// pixels; the shorter side takes the whole pixels that cover the box, so
    /// every point of the box is within half a pixel's diagonal of a pixel
    /// centre.
    pub fn fitting(side: u32, lo: DVec2, hi: DVec2) -> Result<Self> {
        // Checks the box and the side.
        let checked = Self::with_bbox(side, None, [lo.x, lo.y, hi.x, hi.y])?;
        let size = hi - lo;
        let scale = side as f64 / size.max_element();
        // A side that is whole up to rounding stays whole.
        let cover = |l: f64| ((l * scale * (1.0 - 1e-12)).ceil() as u32).clamp(1, side);
        Ok(Self {
            width: cover(size.x),
            height: cover(size.y),
            scale,
            ..checked
        })
    }

    /// Pixel coordinates of a world point.
    pub fn to_pixel(&self, p: DVec2) -> DVec2 {
        (p - self.origin) * self.scale - 0.5
    }

    /// World coordinates of a point given in pixel coordinates.
    pub fn to_world(&self, p: DVec2) -> DVec2 {
        (p + 0.5) / self.scale + self.origin
    }

    /// Number of pixels.
    pub fn len(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Always false: a frame has at least one pixel.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The rectangle of pixel centres `[0, w-1] x [0, h-1]`, as its corners.
    pub(crate) fn pixel_centres(&self) -> (DVec2, DVec2) {
        let far = DVec2::new((self.width - 1) as f64, (self.height - 1) as f64);
        (DVec2::ZERO, far)
    }

    /// Distance from `p` (pixel coordinates) to the farthest pixel centre.
    pub(crate) fn farthest_pixel(&self, p: DVec2) -> f64 {
        let (lo, hi) = self.pixel_centres();
        farthest2_in_rect(p, lo, hi).sqrt()
    }

    /// Distance from `p` (pixel coordinates) to the nearest pixel centre's
    /// rectangle `[0, w-1] x [0, h-1]` (0 inside).
    pub(crate) fn distance_to_pixels(&self, p: DVec2) -> f64 {
        let (lo, hi) = self.pixel_centres();
        distance2_to_rect(p, lo, hi).sqrt()
    }
}

/// Squared distance from `p` to the rectangle `[lo, hi]` (0 inside).
pub(crate) fn distance2_to_rect(p: DVec2, lo: DVec2, hi: DVec2) -> f64 {
    (p.clamp(lo, hi) - p).length_squared()
}

/// Squared distance from `p` to the farthest point of the rectangle `[lo, hi]`.
pub(crate) fn farthest2_in_rect(p: DVec2, lo: DVec2, hi: DVec2) -> f64 {
    ((p - (lo + hi) * 0.5).abs() + (hi - lo) * 0.5).length_squared()
}

thread_local! {
    static SITE_CHECKS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// How many site lists this thread has checked ([`check_sites`]): a problem
/// checks its input once, where it enters, and the tests count that.
pub fn site_checks() -> u64 {
    SITE_CHECKS.with(std::cell::Cell::get)
}

/// Checks a site list: not empty, every coordinate finite.
pub fn check_sites(sites: &[DVec2]) -> Result<()> {
    SITE_CHECKS.with(|c| c.set(c.get() + 1));
    if sites.is_empty() {
        return Err(Error::too_few(1, 0, "the site list is empty".into()));
    }
    if let Some((i, p)) = sites.iter().enumerate().find(|(_, p)| !p.is_finite()) {
        return Err(Error::not_finite(
            Some(i),
            format!(
                "site {i} has a non-finite coordinate ({:?}, {:?})",
                p.x, p.y
            ),
        ));
    }
    if sites.len() >= u32::MAX as usize {
        return Err(Error::out_of_range(format!(
            "{} sites: ids must fit below u32::MAX",
            sites.len()
        )));
    }
    crate::memory::reserve_sites(sites.len())
}

/// Sites that passed [`check_sites`] where they entered, or that pixgeo made
/// from such (scaled by a power of two, moved to centroids): the problems that
/// call one another hand these on and do not check them again.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Checked<'a>(&'a [DVec2]);

impl<'a> Checked<'a> {
    /// `sites`, checked.
    pub(crate) fn new(sites: &'a [DVec2]) -> Result<Self> {
        check_sites(sites)?;
        Ok(Self(sites))
    }

    /// Sites pixgeo derived from checked ones: as many, each finite.
    pub(crate) fn derived(sites: &'a [DVec2]) -> Self {
        debug_assert!(sites.iter().all(|p| p.is_finite()));
        Self(sites)
    }

    pub(crate) fn sites(self) -> &'a [DVec2] {
        self.0
    }
}

/// A key that orders finite coordinates as numbers, with −0.0 equal to 0.0,
/// so that equal points sort together.
pub(crate) fn lexicographic(p: DVec2) -> (i64, i64) {
    let key = |x: f64| {
        let bits = (x + 0.0).to_bits() as i64;
        // Negative numbers: flip the magnitude bits so that they order downward.
        bits ^ (((bits >> 63) as u64) >> 1) as i64
    };
    (key(p.x), key(p.y))
}

/// The first index of each distinct point of `points`, in increasing order.
pub(crate) fn first_of_each(points: &[DVec2]) -> Vec<u32> {
    // Equal points already sort together by the tie-break's key.
    let mut kept = distinct_by(points, 0..points.len() as u32, |_| ()).0;
    kept.sort_unstable();
    kept
}

/// The distinct points among `indices`: sorted by `key`, the first index of
/// each run of equal points kept (−0.0 equals 0.0). Returns the kept indices in
/// key order, and the others as (dropped, kept), sorted.
#[expect(
    clippy::disallowed_methods,
    reason = "the distinct keys, at most the sites given"
)]
pub(crate) fn distinct_by<K: Ord + Send>(
    points: &[DVec2],
    indices: impl IntoIterator<Item = u32>,
    key: impl Fn(DVec2) -> K + Sync,
) -> (Vec<u32>, Vec<[u32; 2]>) {
    use rayon::prelude::*;
    let mut keys: Vec<(K, (i64, i64), u32)> = indices
        .into_iter()
        .collect::<Vec<u32>>()
        .into_par_iter()
        .map(|i| {
            let p = points[i as usize];
            (key(p), lexicographic(p), i)
        })
        .collect();
    keys.par_sort_unstable();
    let mut kept = Vec::with_capacity(keys.len());
    let mut repeats = Vec::new();
    for w in 0..keys.len() {
        let i = keys[w].2;
        if w > 0 && keys[w - 1].1 == keys[w].1 && keys[w - 1].0 == keys[w].0 {
            repeats.push([i, *kept.last().expect("a run starts with a kept point")]);
        } else {
            kept.push(i);
        }
    }
    repeats.sort_unstable();
    (kept, repeats)
}
