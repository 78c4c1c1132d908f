//! Finding a pixel centre in the Delaunay triangulation, and the triangles
//! whose circumcircles hold it (Bowyer and Watson's cavity: the triangles a
//! new site there would destroy, whose corners are its natural neighbours).
//! Every test is an exact predicate.

use std::collections::HashMap;

use glam::DVec2;

use crate::{
    geometry::exact::predicates::{incircle, orient},
    Error, Result,
};

fn coord(p: DVec2) -> robust::Coord<f64> {
    robust::Coord { x: p.x, y: p.y }
}

/// No triangle across an edge: the edge is on the convex hull.
const NONE: u32 = u32::MAX;

/// Counter-clockwise triangles and, for each, the triangle across each edge
/// (edge `k` runs from corner `k` to corner `k + 1`).
pub(crate) struct Triangles<'a> {
    pub sites: &'a [DVec2],
    pub corners: &'a [[u32; 3]],
    across: Vec<[u32; 3]>,
    /// Whether the sites are scaled so that `robust`'s predicates are exact
    /// on them as they are (see [`crate::geometry::scale`]).
    direct: bool,
}

/// Where a point lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Place {
    /// Strictly inside the hull, in (or on the edge of) this triangle.
    Inside(u32),
    /// On a corner of this triangle, or on one of its edges that is on the
    /// hull: the interpolants reduce to the triangle's linear one.
    Boundary(u32),
    /// Outside the convex hull, seen across a hull edge of this triangle.
    Outside(u32),
}

impl<'a> Triangles<'a> {
    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    pub fn new(sites: &'a [DVec2], corners: &'a [[u32; 3]]) -> Self {
        let mut edges = HashMap::with_capacity(corners.len() * 3);
        for (t, c) in corners.iter().enumerate() {
            for k in 0..3 {
                edges.insert((c[k], c[(k + 1) % 3]), t as u32);
            }
        }
        let across = corners
            .iter()
            .map(|c| {
                std::array::from_fn(|k| edges.get(&(c[(k + 1) % 3], c[k])).copied().unwrap_or(NONE))
            })
            .collect();
        Self {
            sites,
            corners,
            across,
            direct: false,
        }
    }

    /// The same triangles over `sites` scaled by a power of two, on which
    /// (with points in their range) the predicates need no scaling of their
    /// own.
    pub fn scaled<'b>(&self, sites: &'b [DVec2]) -> Triangles<'b>
    where
        'a: 'b,
    {
        Triangles {
            sites,
            corners: self.corners,
            across: self.across.clone(),
            direct: true,
        }
    }

    fn orient(&self, a: DVec2, b: DVec2, c: DVec2) -> f64 {
        match self.direct {
            true => robust::orient2d(coord(a), coord(b), coord(c)),
            false => orient(a, b, c),
        }
    }

    fn incircle(&self, a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> f64 {
        match self.direct {
            true => robust::incircle(coord(a), coord(b), coord(c), coord(d)),
            false => incircle(a, b, c, d),
        }
    }

    /// The triangles across `t`'s edges (`u32::MAX` for none).
    pub fn across(&self, t: u32) -> [u32; 3] {
        self.across[t as usize]
    }

    pub fn corner_points(&self, t: u32) -> [DVec2; 3] {
        self.corners[t as usize].map(|i| self.sites[i as usize])
    }

    /// Where `q` lies, walking from triangle `start` toward it: each step
    /// crosses an edge that has `q` strictly on its far side. On a Delaunay
    /// triangulation this walk never cycles (Edelsbrunner 1990).
    pub fn locate(&self, q: DVec2, start: u32) -> Result<Place> {
        let mut t = start;
        for _ in 0..=self.corners.len() + 3 {
            let p = self.corner_points(t);
            let side: [f64; 3] = std::array::from_fn(|k| self.orient(p[k], p[(k + 1) % 3], q));
            match (0..3).find(|&k| side[k] < 0.0) {
                Some(k) => match self.across[t as usize][k] {
                    NONE => return Ok(Place::Outside(t)),
                    next => t = next,
                },
                None => {
                    let zeros = side.iter().filter(|s| **s == 0.0).count();
                    let on_hull =
                        (0..3).any(|k| side[k] == 0.0 && self.across[t as usize][k] == NONE);
                    return Ok(if zeros >= 2 || on_hull {
                        Place::Boundary(t)
                    } else {
                        Place::Inside(t)
                    });
                }
            }
        }
        Err(Error::Internal(
            "the walk through the triangulation did not end".into(),
        ))
    }

    /// The triangles whose circumcircles hold `q` strictly, found from the
    /// triangle `t` holding it: they form a connected region around `q`.
    /// (Triangles with `q` on their circumcircle add nothing to Sibson's
    /// areas, so leaving them out changes no weight.)
    pub fn cavity(&self, q: DVec2, t: u32, out: &mut Vec<u32>) {
        out.clear();
        out.push(t);
        let mut next = 0;
        while next < out.len() {
            let s = out[next];
            next += 1;
            for u in self.across[s as usize] {
                if u != NONE && !out.contains(&u) {
                    let [a, b, c] = self.corner_points(u);
                    if self.incircle(a, b, c, q) > 0.0 {
                        out.push(u);
                    }
                }
            }
        }
    }
}
