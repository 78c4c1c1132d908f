//! The definitions of α-hulls (thesis Defs. 6.1, 6.2) evaluated at a point, in
//! f64, from the circles of radius ρ around the sites: the boundary of the union
//! (α < 0) or of the intersection (α > 0) of their discs is made of arcs of
//! those circles, so the extreme distances from a point are reached at the arcs'
//! ends (two circles crossing) or at the point of a circle nearest to or
//! farthest from it.

use glam::DVec2;

/// The two points where the circles of radius `rho` around `a` and `b` cross.
fn crossings(a: DVec2, b: DVec2, rho: f64) -> Option<[DVec2; 2]> {
    let d = b - a;
    let l2 = d.length_squared();
    if l2 == 0.0 || l2 > 4.0 * rho * rho {
        return None;
    }
    let h = (rho * rho - 0.25 * l2).max(0.0).sqrt();
    let mid = a + 0.5 * d;
    let normal = d.perp() / l2.sqrt();
    Some([mid + normal * h, mid - normal * h])
}

fn all_crossings(sites: &[DVec2], rho: f64) -> Vec<DVec2> {
    let mut out = Vec::new();
    for (i, a) in sites.iter().enumerate() {
        for b in &sites[i + 1..] {
            out.extend(crossings(*a, *b, rho).into_iter().flatten());
        }
    }
    out
}

/// The point of the circle of radius `rho` around `s` in direction `towards`
/// (any point if that is zero).
fn on_circle(s: DVec2, towards: DVec2, rho: f64) -> DVec2 {
    s + rho * towards.try_normalize().unwrap_or(DVec2::X)
}

/// α < 0 with ρ = -1/α: the union of the open discs of radius ρ that hold no
/// site, as a margin per point.
pub struct EmptyDiscs<'a> {
    sites: &'a [DVec2],
    rho: f64,
    /// Crossings of two circles that no third disc holds.
    vertices: Vec<DVec2>,
}

impl<'a> EmptyDiscs<'a> {
    pub fn new(sites: &'a [DVec2], rho: f64) -> Self {
        let mut oracle = Self {
            sites,
            rho,
            vertices: Vec::new(),
        };
        oracle.vertices = all_crossings(sites, rho)
            .into_iter()
            .filter(|&c| oracle.clear(c))
            .collect();
        oracle
    }

    fn nearest(&self, c: DVec2) -> f64 {
        self.sites
            .iter()
            .map(|s| s.distance(c))
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether `c` can centre an empty disc: at least ρ from every site.
    fn clear(&self, c: DVec2) -> bool {
        self.nearest(c) >= self.rho * (1.0 - 1e-12)
    }

    /// ρ minus the distance from `x` to the nearest empty disc's centre: positive
    /// where an open empty disc holds `x`, that is, outside the α-hull.
    pub fn margin(&self, x: DVec2) -> f64 {
        if self.nearest(x) >= self.rho {
            return self.rho;
        }
        let to_circles = self
            .sites
            .iter()
            .map(|s| on_circle(*s, x - *s, self.rho))
            .filter(|&c| self.clear(c));
        let distance = to_circles
            .chain(self.vertices.iter().copied())
            .map(|c| c.distance(x))
            .fold(f64::INFINITY, f64::min);
        self.rho - distance
    }
}

/// α > 0 with ρ = 1/α: the intersection of the closed discs of radius ρ that
/// hold every site, as a margin per point.
pub struct HoldingDiscs<'a> {
    sites: &'a [DVec2],
    rho: f64,
    /// Crossings of two circles that every disc holds: corners of the set of
    /// centres.
    vertices: Vec<DVec2>,
}

impl<'a> HoldingDiscs<'a> {
    pub fn new(sites: &'a [DVec2], rho: f64) -> Self {
        let mut oracle = Self {
            sites,
            rho,
            vertices: Vec::new(),
        };
        oracle.vertices = all_crossings(sites, rho)
            .into_iter()
            .filter(|&c| oracle.holds(c))
            .collect();
        oracle
    }

    /// Whether the disc of radius ρ around `c` holds every site.
    fn holds(&self, c: DVec2) -> bool {
        self.sites
            .iter()
            .all(|s| s.distance(c) <= self.rho * (1.0 + 1e-12))
    }

    /// ρ minus the largest distance from `x` to a centre of a disc holding every
    /// site: non-negative exactly where every such disc holds `x`, the α-hull.
    /// Infinite when no disc of radius ρ holds the sites.
    pub fn margin(&self, x: DVec2) -> f64 {
        let from_circles = self
            .sites
            .iter()
            .map(|s| on_circle(*s, *s - x, self.rho))
            .filter(|&c| self.holds(c));
        let farthest = from_circles
            .chain(self.vertices.iter().copied())
            .map(|c| c.distance(x))
            .fold(f64::NEG_INFINITY, f64::max);
        self.rho - farthest
    }
}
