//! The exact Euclidean bisector of two sites over a frame's pixels. Which of
//! two sites is nearer to pixel (i, j) is the sign of one linear function,
//! `A i + B j + C`, whose integer coefficients are found once per pair: near
//! ties between sites within rounding of each other (one ulp apart, or
//! scaled to 1e-300) are then decided at the cost of two small products a
//! pixel, not of rational arithmetic.

use std::{
    cmp::Ordering,
    collections::HashMap,
    sync::{Arc, Mutex},
};

use glam::DVec2;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::Signed;

use super::rational;
use crate::geometry::Frame;

/// Pairs kept before the cache starts over, so that its memory stays small.
const KEPT: usize = 1 << 16;

/// `key(a) - key(b) = A i + B j + C` at pixel (i, j), up to a positive factor.
struct Bisector {
    a: BigInt,
    b: BigInt,
    c: BigInt,
}

impl Bisector {
    /// For sites `a` and `b` (world coordinates) on `frame`: with `P` a
    /// site's exact pixel position, `|p - P_a|² - |p - P_b|²` is
    /// `-2 p·(P_a - P_b) + |P_a|² - |P_b|²`.
    fn new(frame: &Frame, a: DVec2, b: DVec2) -> Self {
        let scale = rational(frame.scale);
        let half = BigRational::new(1.into(), 2.into());
        let along = |x: f64, o: f64| (rational(x) - rational(o)) * &scale - &half;
        let place = |s: DVec2| [along(s.x, frame.origin.x), along(s.y, frame.origin.y)];
        let (pa, pb) = (place(a), place(b));
        let two = BigRational::from_integer(2.into());
        let alpha = -(&pa[0] - &pb[0]) * &two;
        let beta = -(&pa[1] - &pb[1]) * &two;
        let square = |p: &[BigRational; 2]| &p[0] * &p[0] + &p[1] * &p[1];
        let gamma = square(&pa) - square(&pb);
        // Over a common denominator, which is positive.
        let d = alpha.denom() * beta.denom() * gamma.denom();
        let whole = |r: &BigRational| r.numer() * (&d / r.denom());
        Self {
            a: whole(&alpha),
            b: whole(&beta),
            c: whole(&gamma),
        }
    }

    fn side(&self, pixel: [i64; 2]) -> Ordering {
        let value = &self.a * pixel[0] + &self.b * pixel[1] + &self.c;
        match (value.is_negative(), value.is_positive()) {
            (true, _) => Ordering::Less,
            (_, true) => Ordering::Greater,
            _ => Ordering::Equal,
        }
    }
}

/// The bisectors met so far on one frame, shared by the threads that
/// certify it.
#[derive(Default)]
pub(crate) struct Bisectors {
    known: Mutex<HashMap<(u32, u32), Arc<Bisector>>>,
}

impl Bisectors {
    /// The order of sites `a` and `b` (ids into `sites`) by exact Euclidean
    /// distance from `pixel`.
    pub fn order(
        &self,
        frame: &Frame,
        sites: &[DVec2],
        a: u32,
        b: u32,
        pixel: [i64; 2],
    ) -> Ordering {
        if a > b {
            return self.order(frame, sites, b, a, pixel).reverse();
        }
        let lock = || self.known.lock().unwrap_or_else(|e| e.into_inner());
        let found = lock().get(&(a, b)).cloned();
        let bisector = found.unwrap_or_else(|| {
            let made = Arc::new(Bisector::new(frame, sites[a as usize], sites[b as usize]));
            let mut known = lock();
            if known.len() >= KEPT {
                known.clear();
            }
            known.insert((a, b), made.clone());
            made
        });
        bisector.side(pixel)
    }
}
