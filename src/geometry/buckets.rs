//! A bucket grid over a point set for exact nearest-point queries: the check that
//! turns a pixel answer into an exact one; the counting sort that every
//! bucketed structure of pixgeo is built with, and the ring walk they search by.

use std::borrow::Cow;

use glam::DVec2;

/// Visits the cells `(x, y)` of an `nx` x `ny` grid at Chebyshev distance exactly
/// `ring` from the block of cells `[x0, y0, x1, y1]` (ring 0: the block), row by
/// row; cells outside the grid are skipped.
pub(crate) fn for_ring_cells(
    (nx, ny): (usize, usize),
    [x0, y0, x1, y1]: [isize; 4],
    ring: usize,
    mut visit: impl FnMut(usize, usize),
) {
    let r = ring as isize;
    let (nx, ny) = (nx as isize, ny as isize);
    let columns = (x0 - r).max(0)..=(x1 + r).min(nx - 1);
    for y in (y0 - r).max(0)..=(y1 + r).min(ny - 1) {
        if r == 0 || y == y0 - r || y == y1 + r {
            columns.clone().for_each(|x| visit(x as usize, y as usize));
        } else {
            for x in [x0 - r, x1 + r] {
                if (0..nx).contains(&x) {
                    visit(x as usize, y as usize);
                }
            }
        }
    }
}

/// Items grouped by bucket (a counting sort, stable): those of bucket `b` are
/// `grouped[start[b]..start[b + 1]]`, in the order `items` gives them. Returns
/// `(start, grouped)`; `items` is walked twice.
#[expect(
    clippy::disallowed_macros,
    reason = "as many as the items, within the budget the caller reserved"
)]
pub(crate) fn group_by_bucket<T: Copy + Default>(
    buckets: usize,
    items: impl Iterator<Item = (usize, T)> + Clone,
) -> (Vec<u32>, Vec<T>) {
    let mut start = vec![0u32; buckets + 1];
    for (b, _) in items.clone() {
        start[b + 1] += 1;
    }
    for b in 0..buckets {
        start[b + 1] += start[b];
    }
    let mut fill = start.clone();
    let mut grouped = vec![T::default(); start[buckets] as usize];
    for (b, item) in items {
        grouped[fill[b] as usize] = item;
        fill[b] += 1;
    }
    (start, grouped)
}

/// Points binned into square buckets over their bounding box.
pub struct PointGrid<'a> {
    points: Cow<'a, [DVec2]>,
    origin: DVec2,
    cell: f64,
    nx: usize,
    ny: usize,
    /// Points of bucket (x, y) are `order[start[y * nx + x]..start[y * nx + x + 1]]`.
    start: Vec<u32>,
    order: Vec<u32>,
}

impl<'a> PointGrid<'a> {
    /// About one point per bucket.
    pub fn new(points: &'a [DVec2]) -> Self {
        Self::over(Cow::Borrowed(points))
    }

    /// About one point per bucket, holding the points.
    pub fn owning(points: Vec<DVec2>) -> PointGrid<'static> {
        PointGrid::over(Cow::Owned(points))
    }

    fn over(points: Cow<'a, [DVec2]>) -> Self {
        let lo = points.iter().fold(DVec2::INFINITY, |a, p| a.min(*p));
        let hi = points.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
        let extent = (hi - lo).max(DVec2::splat(f64::MIN_POSITIVE));
        let n = points.len().max(1) as f64;
        let cell = ((extent.x * extent.y / n).sqrt())
            .max(extent.max_element() / n)
            .max(f64::MIN_POSITIVE);
        let nx = ((extent.x / cell) as usize + 1).min(1 << 12);
        let ny = ((extent.y / cell) as usize + 1).min(1 << 12);
        let origin = if points.is_empty() { DVec2::ZERO } else { lo };
        let mut grid = Self {
            points,
            origin,
            cell,
            nx,
            ny,
            start: Vec::new(),
            order: Vec::new(),
        };
        let (start, order) = group_by_bucket(
            nx * ny,
            grid.points
                .iter()
                .enumerate()
                .map(|(i, p)| (grid.bucket(*p), i as u32)),
        );
        (grid.start, grid.order) = (start, order);
        grid
    }

    fn cell_of(&self, p: DVec2) -> (usize, usize) {
        let c = ((p - self.origin) / self.cell).floor();
        (
            c.x.clamp(0.0, (self.nx - 1) as f64) as usize,
            c.y.clamp(0.0, (self.ny - 1) as f64) as usize,
        )
    }

    fn bucket(&self, p: DVec2) -> usize {
        let (x, y) = self.cell_of(p);
        y * self.nx + x
    }

    /// Indices of the points within distance `radius` of `q` (and a few more
    /// from the buckets around it).
    pub fn around(&self, q: DVec2, radius: f64) -> impl Iterator<Item = u32> + '_ {
        let (x0, y0) = self.cell_of(q - radius);
        let (x1, y1) = self.cell_of(q + radius);
        (y0..=y1).flat_map(move |y| {
            let row = y * self.nx;
            self.order[self.start[row + x0] as usize..self.start[row + x1 + 1] as usize]
                .iter()
                .copied()
        })
    }

    /// The point nearest to `q` (lowest index among equals) and its distance.
    pub fn nearest(&self, q: DVec2) -> Option<(u32, f64)> {
        if self.points.is_empty() {
            return None;
        }
        // A point r rings of buckets away is at least (r - 1) cells from q's
        // bucket, and so from q: a q outside the grid lies beyond its projection
        // onto the grid, which is in that bucket.
        let (cx, cy) = self.cell_of(q);
        let (cx, cy) = (cx as isize, cy as isize);
        // From outside the grid, every point is as far as the grid's box,
        // and farther by its distance from q's nearest point of the box.
        let extent = DVec2::new(self.nx as f64, self.ny as f64) * self.cell;
        let outside = q.distance_squared(q.clamp(self.origin, self.origin + extent));
        let mut best = (u32::MAX, f64::INFINITY);
        let visit = |best: &mut (u32, f64), x: isize, y: isize| {
            if x < 0 || y < 0 || x >= self.nx as isize || y >= self.ny as isize {
                return;
            }
            let b = y as usize * self.nx + x as usize;
            for &i in &self.order[self.start[b] as usize..self.start[b + 1] as usize] {
                let d = self.points[i as usize].distance_squared(q);
                if d < best.1 || (d == best.1 && i < best.0) {
                    *best = (i, d);
                }
            }
        };
        for r in 0..=self.nx.max(self.ny) as isize {
            let gap = (r - 1).max(0) as f64 * self.cell;
            if r > 1 && outside + gap * gap > best.1 {
                break;
            }
            for x in cx - r..=cx + r {
                visit(&mut best, x, cy - r);
                if r > 0 {
                    visit(&mut best, x, cy + r);
                }
            }
            for y in cy - r + 1..cy + r {
                visit(&mut best, cx - r, y);
                visit(&mut best, cx + r, y);
            }
        }
        Some((best.0, best.1.sqrt()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn nearest_matches_brute_force() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let mut points: Vec<DVec2> = (0..500)
            .map(|_| DVec2::new(rng.gen_range(0.0..100.0), rng.gen_range(0.0..30.0)))
            .collect();
        points.extend([DVec2::new(5.0, 5.0), DVec2::new(5.0, 5.0)]);
        let line: Vec<DVec2> = (0..50).map(|i| DVec2::new(i as f64, 0.0)).collect();
        for set in [&points[..], &line[..], &points[..1]] {
            let grid = PointGrid::new(set);
            for _ in 0..300 {
                let q = DVec2::new(rng.gen_range(-50.0..150.0), rng.gen_range(-50.0..80.0));
                let (i, d) = grid.nearest(q).unwrap();
                let truth = set
                    .iter()
                    .map(|p| p.distance(q))
                    .fold(f64::INFINITY, f64::min);
                assert_eq!(d, truth);
                assert_eq!(set[i as usize].distance(q), truth);
            }
        }
    }
}
