//! Exact Euclidean Voronoi cells as convex polygons: the plane region a site
//! wins, clipped to a rectangle, and its area. The settle point's refinement
//! (thesis §3.10) maximizes such an area beyond the pixels.

use glam::DVec2;

/// Clips the convex polygon `corners` to `v . normal <= limit`
/// (Sutherland–Hodgman), handing the result's corners to `push` in order: at
/// most one more than `corners` has.
pub(crate) fn clip_convex(
    corners: &[DVec2],
    normal: DVec2,
    limit: f64,
    mut push: impl FnMut(DVec2),
) {
    let Some(&last) = corners.last() else {
        return;
    };
    let (mut a, mut fa) = (last, last.dot(normal) - limit);
    for &b in corners {
        let fb = b.dot(normal) - limit;
        if (fa <= 0.0) != (fb <= 0.0) {
            push(a + (b - a) * (fa / (fa - fb)));
        }
        if fb <= 0.0 {
            push(b);
        }
        (a, fa) = (b, fb);
    }
}

/// An axis-aligned rectangle `[lo, hi]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    pub lo: DVec2,
    pub hi: DVec2,
}

impl Rect {
    /// Refuses a rectangle that is empty or not finite.
    pub fn check(&self) -> crate::Result<()> {
        let (lo, hi) = (self.lo, self.hi);
        if lo.is_finite() && hi.is_finite() && lo.x < hi.x && lo.y < hi.y {
            return Ok(());
        }
        Err(crate::Error::malformed(format!(
            "the rectangle {lo:?} to {hi:?} is empty or not finite"
        )))
    }
}

/// A convex polygon, counter-clockwise or clockwise, its corners relative to a
/// centre (the site whose cell it is), which keeps bisector clipping accurate far
/// from the origin.
#[derive(Clone, Debug, Default)]
struct Polygon {
    corners: Vec<DVec2>,
}

impl Polygon {
    fn rect(rect: &Rect, centre: DVec2) -> Self {
        let (lo, hi) = (rect.lo - centre, rect.hi - centre);
        Self {
            corners: Vec::from([lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)]),
        }
    }

    #[expect(clippy::disallowed_methods, reason = "a cell's corners")]
    fn shifted(&self, by: DVec2) -> Self {
        Self {
            corners: self.corners.iter().map(|&v| v + by).collect(),
        }
    }

    fn farthest2(&self) -> f64 {
        self.corners
            .iter()
            .map(|v| v.length_squared())
            .fold(0.0, f64::max)
    }

    /// Keeps the part with `v . normal <= limit`.
    #[expect(clippy::disallowed_methods, reason = "a cell's corners")]
    fn clip(&mut self, normal: DVec2, limit: f64) {
        if self.corners.iter().all(|v| v.dot(normal) <= limit) {
            return;
        }
        let mut out = Vec::with_capacity(self.corners.len() + 1);
        clip_convex(&self.corners, normal, limit, |v| out.push(v));
        self.corners = out;
    }

    /// Clips to the points nearer to the centre than to `other` (relative to the
    /// centre), i.e. `v . other <= |other|² / 2`.
    fn clip_by_bisector(&mut self, other: DVec2) {
        self.clip(other, 0.5 * other.length_squared());
    }

    fn area(&self) -> f64 {
        let n = self.corners.len();
        if n < 3 {
            return 0.0;
        }
        let twice: f64 = (0..n)
            .map(|i| self.corners[i].perp_dot(self.corners[(i + 1) % n]))
            .sum();
        0.5 * twice.abs()
    }

    /// Clips by the bisectors of `centre` with `sites` (absolute coordinates),
    /// nearest first, stopping once the rest lie beyond twice the farthest
    /// corner: their bisectors miss the polygon. Sites at the centre itself are
    /// skipped.
    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    fn clip_by_sites(&mut self, centre: DVec2, sites: &[DVec2]) {
        let mut offsets: Vec<(f64, DVec2)> = sites
            .iter()
            .map(|&s| s - centre)
            .map(|d| (d.length_squared(), d))
            .filter(|&(dd, _)| dd > 0.0)
            .collect();
        offsets.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        let mut reach2 = self.farthest2();
        for (dd, d) in offsets {
            if self.corners.is_empty() || dd >= 4.0 * reach2 {
                break;
            }
            self.clip_by_bisector(d);
            reach2 = self.farthest2();
        }
    }
}

/// The area of the Voronoi cell of `site` among `others` (which may contain
/// `site` itself), clipped to `rect`.
#[cfg(test)]
pub(crate) fn cell_area(site: DVec2, others: &[DVec2], rect: &Rect) -> f64 {
    let mut cell = Polygon::rect(rect, site);
    cell.clip_by_sites(site, others);
    cell.area()
}

/// The area that a new site at `t` takes from the `rivals`, within `rect`: its
/// Voronoi cell among all sites, less the parts that the `own` sites held
/// before it came. Zero when `t` coincides with a site.
#[cfg(test)]
pub(crate) fn stolen_area(t: DVec2, rivals: &[DVec2], own: &[DVec2], rect: &Rect) -> f64 {
    StolenArea::new(t, rivals, own, rect).at(t)
}

/// `stolen_area` for many positions near one origin: the sites are sorted by
/// distance from the origin once, and the own stores' former cells computed
/// once.
pub(crate) struct StolenArea {
    rect: Rect,
    origin: DVec2,
    /// Every site with its distance from the origin, nearest first.
    sites: Vec<(f64, DVec2)>,
    /// The cells the own stores held, as corners relative to the rectangle's
    /// low corner, counter-clockwise.
    own_cells: Vec<Polygon>,
}

impl StolenArea {
    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    pub fn new(origin: DVec2, rivals: &[DVec2], own: &[DVec2], rect: &Rect) -> Self {
        let mut sites: Vec<(f64, DVec2)> = rivals
            .iter()
            .chain(own)
            .map(|&s| (s.distance(origin), s))
            .collect();
        sites.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        let all: Vec<DVec2> = rivals.iter().chain(own).copied().collect();
        let own_cells = own
            .iter()
            .map(|&o| {
                let mut cell = Polygon::rect(rect, o);
                cell.clip_by_sites(o, &all);
                cell.shifted(o - rect.lo)
            })
            .collect();
        Self {
            rect: *rect,
            origin,
            sites,
            own_cells,
        }
    }

    /// The area a new site at `t` takes from the rivals.
    pub fn at(&self, t: DVec2) -> f64 {
        // A site s is at least |s - origin| - shift from t; once that is twice
        // the cell's farthest corner, its bisector and all later ones miss.
        let shift = t.distance(self.origin);
        let mut cell = Polygon::rect(&self.rect, t);
        let mut reach = cell.farthest2().sqrt();
        for &(d, s) in &self.sites {
            if d - shift >= 2.0 * reach || cell.corners.is_empty() {
                break;
            }
            if s == t {
                return 0.0;
            }
            cell.clip_by_bisector(s - t);
            reach = cell.farthest2().sqrt();
        }
        let mut area = cell.area();
        for own_cell in &self.own_cells {
            let mut part = cell.clone();
            let corners = &own_cell.corners;
            for (k, &a) in corners.iter().enumerate() {
                // Keep the left of edge a -> b (relative to t).
                let edge = corners[(k + 1) % corners.len()] - a;
                let a = a + self.rect.lo - t;
                part.clip(-edge.perp(), -a.dot(edge.perp()));
            }
            area -= part.area();
        }
        area.max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit() -> Rect {
        Rect {
            lo: DVec2::ZERO,
            hi: DVec2::ONE,
        }
    }

    #[test]
    fn two_sites_split_the_square() {
        let a = DVec2::new(0.25, 0.5);
        let b = DVec2::new(0.75, 0.5);
        assert!((cell_area(a, &[a, b], &unit()) - 0.5).abs() < 1e-12);
        assert!((stolen_area(b, &[a], &[], &unit()) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn own_regions_do_not_count() {
        // Rival on the left, own store on the right; a new site in the middle
        // takes the strip between x = 0.375 and 0.625, half of it from each.
        let rival = DVec2::new(0.25, 0.5);
        let own = DVec2::new(0.75, 0.5);
        let t = DVec2::new(0.5, 0.5);
        let all = stolen_area(t, &[rival, own], &[], &unit());
        assert!((all - 0.25).abs() < 1e-12);
        let stolen = stolen_area(t, &[rival], &[own], &unit());
        assert!((stolen - 0.125).abs() < 1e-12);
    }

    #[test]
    fn a_site_on_another_wins_nothing() {
        let a = DVec2::new(0.3, 0.3);
        assert_eq!(stolen_area(a, &[a], &[], &unit()), 0.0);
    }

    #[test]
    fn cells_tile_the_rectangle() {
        let sites: Vec<DVec2> = (0..40)
            .map(|i| {
                let f = i as f64;
                DVec2::new((f * 0.618).fract(), (f * 0.377 + 0.1).fract())
            })
            .collect();
        let total: f64 = sites.iter().map(|&s| cell_area(s, &sites, &unit())).sum();
        assert!((total - 1.0).abs() < 1e-9, "{total}");
    }
}
