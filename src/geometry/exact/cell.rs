//! Voronoi and power cells clipped to a rectangle with every decision exact:
//! a cell is the rectangle clipped by the bisectors (radical axes, for
//! weighted sites) with its site's neighbours (Sutherland–Hodgman), each
//! corner known by the two lines that meet there, each side test decided in
//! floats with an error bound or else in rationals, and each corner written as the double nearest the exact point.
//! Cells that share a corner therefore write the same double for it, however
//! each found it: a vertex of four co-circular sites, a bisector through a
//! frame corner and a crossing of the frame come out once, identical in every
//! cell that has them.

use std::{cmp::Ordering, collections::HashMap};

use glam::DVec2;
use num_rational::BigRational;
use num_traits::Zero;

use super::bounded::Bounded;
use super::{nearest_double, rational};
use crate::geometry::cell::Rect;

/// A line that bounds the cell of site `s`, as `normal . (p - s) = offset`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Line {
    /// x = lo.x, y = lo.y, x = hi.x, y = hi.y.
    Side(u8),
    /// The bisector (radical axis) of `s` and this site.
    Bisector(u32),
}

/// A corner of a cell: where the line of the edge before it meets the line
/// of the edge after it; `q` approximates `p - s`.
#[derive(Clone, Copy, Debug)]
struct Corner {
    before: Line,
    after: Line,
    q: [Bounded; 2],
}

/// The exact point a corner names, the same for every cell that has it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Point {
    Corner(u8, u8),
    Crossing(u8, u32, u32),
    Centre([u32; 3]),
}

/// Cells built between looks at the cancel flag and reports of progress.
const CELLS_PER_LOOK: usize = 1 << 14;

/// Builds exact cells of `sites` in `rect`, remembering the doubles of the
/// points already placed. Every corner is the double nearest an exact
/// point, whichever cell finds it, so builders may work apart.
#[derive(Clone)]
pub(crate) struct CellBuilder<'a> {
    sites: &'a [DVec2],
    /// Power weights: a point's power from site `s` is `|p - s|² - w[s]`.
    weights: Option<&'a [f64]>,
    rect: Rect,
    placed: HashMap<Point, DVec2>,
}

impl<'a> CellBuilder<'a> {
    pub fn new(sites: &'a [DVec2], rect: Rect) -> Self {
        Self {
            sites,
            weights: None,
            rect,
            placed: HashMap::new(),
        }
    }

    /// Builds power cells: `weights[s]` is site `s`'s.
    pub fn weighted(sites: &'a [DVec2], weights: &'a [f64], rect: Rect) -> Self {
        Self {
            weights: Some(weights),
            ..Self::new(sites, rect)
        }
    }

    /// `w[s] - w[k]`, zero without weights.
    fn weight_gap(&self, s: u32, k: u32) -> Bounded {
        match self.weights {
            Some(w) => Bounded::difference(w[s as usize], w[k as usize]),
            None => Bounded::exact(0.0),
        }
    }

    /// [`Self::weight_gap`] exactly.
    fn exact_weight_gap(&self, s: u32, k: u32) -> BigRational {
        match self.weights {
            Some(w) => rational(w[s as usize]) - rational(w[k as usize]),
            None => BigRational::zero(),
        }
    }

    /// The cells of `jobs` (each a site and its neighbours), in order, built
    /// in parallel in blocks; before each block the cancel flag is looked at
    /// and the cells built reported to `control`.
    pub fn cells(
        &self,
        jobs: &[(u32, &[u32])],
        control: &crate::Control,
    ) -> crate::Result<Vec<Vec<DVec2>>> {
        use rayon::prelude::*;
        let (watch, total) = (crate::cancel::Watch::current(), jobs.len() as u64);
        let mut cells = crate::memory::room(jobs.len(), "exact cells")?;
        for part in jobs.chunks(CELLS_PER_LOOK) {
            watch.check()?;
            control.report(cells.len() as u64, total);
            let built: Vec<Vec<DVec2>> = part
                .par_iter()
                .map_init(|| self.clone(), |b, &(s, around)| b.cell(s, around))
                .collect();
            cells.extend(built);
        }
        control.report(total, total);
        super::snap::keep_rings_simple(&mut cells)?;
        Ok(cells)
    }

    /// The cell of site `s` bounded by the lines with `neighbours`: its
    /// corners counter-clockwise, each the double nearest the exact corner;
    /// empty where the exact cell has no area in the rectangle.
    #[expect(clippy::disallowed_methods, reason = "one cell's corners")]
    pub fn cell(&mut self, s: u32, neighbours: &[u32]) -> Vec<DVec2> {
        let site = self.sites[s as usize];
        let (lo, hi) = (self.rect.lo, self.rect.hi);
        let corner = |x: f64, y: f64, before: u8, after: u8| Corner {
            before: Line::Side(before),
            after: Line::Side(after),
            q: [
                Bounded::difference(x, site.x),
                Bounded::difference(y, site.y),
            ],
        };
        let mut corners = Vec::from([
            corner(lo.x, lo.y, 0, 1),
            corner(hi.x, lo.y, 1, 2),
            corner(hi.x, hi.y, 2, 3),
            corner(lo.x, hi.y, 3, 0),
        ]);
        // Nearer neighbours first: they clip the most.
        let mut order: Vec<u32> = neighbours.to_vec();
        order.sort_by(|&a, &b| {
            let d = |k: u32| self.sites[k as usize].distance_squared(site);
            d(a).total_cmp(&d(b))
        });
        for k in order {
            corners = self.clip(s, &corners, k);
            if corners.len() < 3 {
                return Vec::new();
            }
        }
        let mut ring: Vec<DVec2> = Vec::with_capacity(corners.len());
        for c in &corners {
            let p = self.place(s, c);
            if ring.last() != Some(&p) {
                ring.push(p);
            }
        }
        while ring.len() > 1 && ring.first() == ring.last() {
            ring.pop();
        }
        if ring.len() < 3 {
            ring.clear();
        }
        ring
    }

    /// Keeps the part of the cell of no more power from `s` than from `k`:
    /// the exact intersection, with no corner repeated.
    #[expect(clippy::disallowed_methods, reason = "one cell's corners")]
    fn clip(&self, s: u32, corners: &[Corner], k: u32) -> Vec<Corner> {
        let sides: Vec<Ordering> = corners.iter().map(|c| self.side(s, c, k)).collect();
        if sides.iter().all(|&o| o != Ordering::Greater) {
            return corners.to_vec();
        }
        let cut = Line::Bisector(k);
        let n = corners.len();
        let mut out = Vec::with_capacity(n + 1);
        for i in 0..n {
            let a = corners[i];
            let (sa, sb) = (sides[i], sides[(i + 1) % n]);
            let edge = a.after;
            if sa != Ordering::Greater {
                let after = match (sa, sb) {
                    (Ordering::Equal, Ordering::Greater) => cut,
                    _ => edge,
                };
                out.push(Corner { after, ..a });
            }
            let crossing = |before, after| Corner {
                before,
                after,
                q: self.meet(s, edge, cut),
            };
            match (sa, sb) {
                (Ordering::Less, Ordering::Greater) => out.push(crossing(edge, cut)),
                (Ordering::Greater, Ordering::Less) => out.push(crossing(cut, edge)),
                _ => {}
            }
        }
        // A kept corner on the cut that follows a cut-off one starts after it.
        let m = out.len();
        for i in 0..m {
            if out[(i + m - 1) % m].after == cut {
                out[i].before = cut;
            }
        }
        out
    }

    /// Where corner `c` of the cell of `s` lies against the line with `k`:
    /// less power from `s` (Less), on it, or less from `k`.
    fn side(&self, s: u32, c: &Corner, k: u32) -> Ordering {
        let (site, other) = (self.sites[s as usize], self.sites[k as usize]);
        let n = [
            Bounded::difference(other.x, site.x),
            Bounded::difference(other.y, site.y),
        ];
        // 2 q . n - |n|² - (w[s] - w[k]), the difference of the powers.
        let two = Bounded::exact(2.0);
        let f = two * (c.q[0] * n[0] + c.q[1] * n[1])
            - (n[0] * n[0] + n[1] * n[1])
            - self.weight_gap(s, k);
        if let Some(o) = f.sign() {
            return o;
        }
        let q = self.exact_q(s, c);
        let n = [
            rational(other.x) - rational(site.x),
            rational(other.y) - rational(site.y),
        ];
        let two = BigRational::from_integer(2.into());
        let f = two * (&q[0] * &n[0] + &q[1] * &n[1])
            - (&n[0] * &n[0] + &n[1] * &n[1])
            - self.exact_weight_gap(s, k);
        f.cmp(&BigRational::zero())
    }

    /// `normal . q = offset` for line `l` of the cell of `s`, in floats.
    fn line(&self, s: u32, l: Line) -> ([Bounded; 2], Bounded) {
        let site = self.sites[s as usize];
        let (zero, one) = (Bounded::exact(0.0), Bounded::exact(1.0));
        match l {
            Line::Side(i) => {
                let (axis, at) = self.side_line(i);
                let normal = if axis == 0 { [one, zero] } else { [zero, one] };
                (normal, Bounded::difference(at, site[axis]))
            }
            Line::Bisector(k) => {
                let o = self.sites[k as usize];
                let n = [
                    Bounded::difference(o.x, site.x),
                    Bounded::difference(o.y, site.y),
                ];
                let half = Bounded::exact(0.5);
                (
                    n,
                    half * (n[0] * n[0] + n[1] * n[1] + self.weight_gap(s, k)),
                )
            }
        }
    }

    /// `normal . q = offset` for line `l` of the cell of `s`, exactly.
    fn exact_line(&self, s: u32, l: Line) -> ([BigRational; 2], BigRational) {
        let site = self.sites[s as usize];
        let (zero, one) = (BigRational::zero(), BigRational::from_integer(1.into()));
        match l {
            Line::Side(i) => {
                let (axis, at) = self.side_line(i);
                let normal = if axis == 0 { [one, zero] } else { [zero, one] };
                (normal, rational(at) - rational(site[axis]))
            }
            Line::Bisector(k) => {
                let o = self.sites[k as usize];
                let n = [
                    rational(o.x) - rational(site.x),
                    rational(o.y) - rational(site.y),
                ];
                let offset = (&n[0] * &n[0] + &n[1] * &n[1] + self.exact_weight_gap(s, k))
                    / BigRational::from_integer(2.into());
                (n, offset)
            }
        }
    }

    /// Side `i`'s axis (0 for x) and coordinate.
    fn side_line(&self, i: u8) -> (usize, f64) {
        let (lo, hi) = (self.rect.lo, self.rect.hi);
        match i {
            0 => (0, lo.x),
            1 => (1, lo.y),
            2 => (0, hi.x),
            _ => (1, hi.y),
        }
    }

    /// Where lines `a` and `b` of the cell of `s` meet, in floats (Cramer).
    fn meet(&self, s: u32, a: Line, b: Line) -> [Bounded; 2] {
        let ((n, c), (m, d)) = (self.line(s, a), self.line(s, b));
        let det = n[0] * m[1] - n[1] * m[0];
        [(c * m[1] - d * n[1]) / det, (n[0] * d - m[0] * c) / det]
    }

    /// `p - s` for corner `c` of the cell of `s`, exactly.
    fn exact_q(&self, s: u32, c: &Corner) -> [BigRational; 2] {
        let ((n, c0), (m, d)) = (self.exact_line(s, c.before), self.exact_line(s, c.after));
        let det = &n[0] * &m[1] - &n[1] * &m[0];
        debug_assert!(!det.is_zero(), "a corner of parallel lines");
        [
            (&c0 * &m[1] - &d * &n[1]) / &det,
            (&n[0] * &d - &m[0] * &c0) / &det,
        ]
    }

    /// The double nearest corner `c` of the cell of `s`.
    fn place(&mut self, s: u32, c: &Corner) -> DVec2 {
        let key = match (c.before, c.after) {
            (Line::Side(a), Line::Side(b)) => Point::Corner(a.min(b), a.max(b)),
            (Line::Side(i), Line::Bisector(k)) | (Line::Bisector(k), Line::Side(i)) => {
                Point::Crossing(i, s.min(k), s.max(k))
            }
            (Line::Bisector(j), Line::Bisector(k)) => {
                let mut t = [s, j, k];
                t.sort_unstable();
                Point::Centre(t)
            }
        };
        if let Some(&p) = self.placed.get(&key) {
            return p;
        }
        let site = self.sites[s as usize];
        let nearest = |axis: usize| {
            let fast = c.q[axis].nearest_plus(site[axis]);
            fast.unwrap_or_else(|| {
                let q = self.exact_q(s, c);
                nearest_double(&(&q[axis] + rational(site[axis])))
            })
        };
        // A side's coordinate is exact.
        let p = match key {
            Point::Corner(a, b) => {
                let mut p = DVec2::ZERO;
                for (axis, at) in [self.side_line(a), self.side_line(b)] {
                    p[axis] = at;
                }
                p
            }
            Point::Crossing(i, ..) => {
                let (axis, at) = self.side_line(i);
                let mut p = DVec2::splat(at);
                p[1 - axis] = nearest(1 - axis);
                p
            }
            Point::Centre(_) => DVec2::new(nearest(0), nearest(1)),
        };
        self.placed.insert(key, p);
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_cocircular_sites_share_one_centre() {
        let t = 0.1111111111111111;
        let sites = [
            DVec2::new(0.4444444444444444, 0.0),
            DVec2::new(0.4444444444444444, t),
            DVec2::new(0.5555555555555556, 0.0),
            DVec2::new(0.5555555555555556, t),
        ];
        let rect = Rect {
            lo: DVec2::splat(-0.1),
            hi: DVec2::splat(1.1),
        };
        let mut builder = CellBuilder::new(&sites, rect);
        let all = [0, 1, 2, 3];
        let cells: Vec<Vec<DVec2>> = (0..4u32)
            .map(|s| {
                let others: Vec<u32> = all.iter().copied().filter(|&k| k != s).collect();
                builder.cell(s, &others)
            })
            .collect();
        // The centre of the four is a corner of each cell, the same double.
        let centre = cells[0]
            .iter()
            .find(|p| cells[1..].iter().all(|c| c.contains(p)))
            .copied();
        assert!(centre.is_some(), "{cells:?}");
        for c in &cells {
            assert_eq!(c.len(), 4, "{c:?}");
            let mut seen = c.clone();
            seen.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
            seen.dedup();
            assert_eq!(seen.len(), c.len());
        }
    }
}
