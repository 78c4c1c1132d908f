//! The furthest-site diagram proved: each pixel's furthest owner, by doubles
//! where they tell, exactly elsewhere.

use std::cmp::Ordering;

use glam::DVec2;
use rayon::prelude::*;

use super::{Candidate, Certifier, Region};
use crate::{cancel::Watch, error::Result, geometry::metric::Metric};

impl Certifier<'_> {
    /// Proves the proposed furthest sites of every pixel of the frame in
    /// `labels`, mending those that are not the exact furthest of `owners`
    /// (equal distances to the smaller index), and writes every pixel's
    /// distance as [`Certifier::label_distances`] does, so that every route
    /// gives the same bits. Returns the number of pixels mended.
    pub fn furthest(
        &self,
        owners: &[u32],
        labels: &mut [u32],
        distances: &mut [f32],
    ) -> Result<usize> {
        let width = self.frame.width as usize;
        let watch = Watch::current();
        let mended = labels
            .par_chunks_mut(width)
            .enumerate()
            .map(|(y, row)| {
                watch.check()?;
                let mut scratch = crate::memory::room(owners.len(), "owners' scratch")?;
                let mut mended = 0;
                for (x, label) in row.iter_mut().enumerate() {
                    let p = [x as i64, y as i64];
                    let far = match self.clearly_furthest(p, owners) {
                        Some(far) => far,
                        None => self.furthest_of(p, owners, &mut scratch)?,
                    };
                    mended += usize::from(far != *label);
                    *label = far;
                }
                Ok(mended)
            })
            .sum::<Result<usize>>()?;
        let region = Region {
            x0: 0,
            y0: 0,
            width: self.frame.width,
            height: self.frame.height,
            stride: width,
            k: 1,
        };
        self.label_distances(region, labels, distances);
        Ok(mended)
    }

    /// The furthest of `owners` from pixel `p` where doubles show it: under
    /// a norm, each owner's distance in doubles is within `slack` of its
    /// exact one (its place's error and the subtraction's, times the norm's
    /// Euclidean bound, and the key's rounding), so a furthest ahead of the
    /// next by twice that is the furthest. `None` where they cannot tell,
    /// and for metrics that are not norms.
    fn clearly_furthest(&self, p: [i64; 2], owners: &[u32]) -> Option<u32> {
        let norm = match self.metric {
            Metric::L2 | Metric::L1 | Metric::LInf => true,
            Metric::Lp(q) => q >= 1.0,
            Metric::Polygon(_) => false,
        };
        if !norm || owners.len() < 2 {
            return None;
        }
        let at = DVec2::new(p[0] as f64, p[1] as f64);
        let (mut best, mut second) = ((f64::NEG_INFINITY, u32::MAX), f64::NEG_INFINITY);
        for &id in owners {
            let d = (at - self.places[id as usize]).abs();
            let key = self.keys.key(d.x, d.y);
            if key > best.0 {
                second = best.0;
                best = (key, id);
            } else if key > second {
                second = key;
            }
        }
        let far = self.keys.distance(best.0);
        let u = f64::EPSILON;
        let moved = self.largest_error + (far + at.abs().max_element()) * 4.0 * u;
        let bound = self.metric.euclidean_bounds().1;
        let slack = 2.0 * bound * moved + far * (4.0 * self.keys.rounding() + 4.0 * u);
        (far - self.keys.distance(second) > 2.0 * slack).then_some(best.1)
    }

    /// The furthest of `owners` (distinct positions, the first index of
    /// each) from pixel `p`, exactly.
    fn furthest_of(
        &self,
        p: [i64; 2],
        owners: &[u32],
        scratch: &mut Vec<Candidate>,
    ) -> Result<u32> {
        let at = DVec2::new(p[0] as f64, p[1] as f64);
        scratch.clear();
        scratch.extend(owners.iter().map(|&id| self.candidate(at, id)));
        let floor = scratch
            .iter()
            .map(|c| c.lo)
            .fold(f64::NEG_INFINITY, f64::max);
        scratch.retain(|c| c.hi >= floor);
        let mut exact = crate::memory::filled(scratch.len(), None, "exact owners")?;
        let mut best = 0;
        for n in 1..scratch.len() {
            let order = self.compare(p, scratch, &mut exact, best, n)?;
            if order.then(scratch[n].id.cmp(&scratch[best].id)) == Ordering::Less {
                best = n;
            }
        }
        Ok(scratch.get(best).map_or(u32::MAX, |c| c.id))
    }
}
