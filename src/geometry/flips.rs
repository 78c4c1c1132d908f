//! From a valid triangulation of the sphere (sites plus the dummy vertex, as
//! [`super::triangulation::validate`] accepts) to the Delaunay triangulation of
//! its sites, by flips with exact predicates (the lecture notes' legal edges):
//!
//! 1. where the boundary turns inward at a site b between a and c, the two
//!    triangles (a, b, dummy) and (b, c, dummy) become (a, b, c) and
//!    (a, c, dummy), until the boundary is the convex hull;
//! 2. an inner edge whose opposite vertex lies strictly inside the other
//!    triangle's circumcircle is flipped, until none does (Lawson).
//!
//! Both steps only ever flip within convex quadrangles, so every triangle
//! stays counter-clockwise.

use std::collections::HashMap;

use glam::DVec2;

use super::triangulation::DUMMY;

fn coord(p: DVec2) -> robust::Coord<f64> {
    robust::Coord { x: p.x, y: p.y }
}

fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    robust::orient2d(coord(a), coord(b), coord(c))
}

/// Positive when `d` lies strictly inside the circle through the
/// counter-clockwise a, b, c.
fn incircle(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> f64 {
    robust::incircle(coord(a), coord(b), coord(c), coord(d))
}

/// Triangles with their directed edges indexed: `owner[(a, b)]` is the triangle
/// that has edge a → b.
struct Mesh {
    triangles: Vec<[u32; 3]>,
    owner: HashMap<(u32, u32), usize>,
}

impl Mesh {
    fn new(triangles: Vec<[u32; 3]>) -> Self {
        let mut owner = HashMap::with_capacity(3 * triangles.len());
        for (k, t) in triangles.iter().enumerate() {
            for e in 0..3 {
                owner.insert((t[e], t[(e + 1) % 3]), k);
            }
        }
        Self { triangles, owner }
    }

    /// The vertex of triangle `k` opposite its edge a → b.
    fn opposite(&self, k: usize, a: u32, b: u32) -> u32 {
        *self.triangles[k]
            .iter()
            .find(|&&v| v != a && v != b)
            .expect("a triangle has three vertices")
    }

    fn set(&mut self, k: usize, t: [u32; 3]) {
        for e in 0..3 {
            let edge = (self.triangles[k][e], self.triangles[k][(e + 1) % 3]);
            if self.owner.get(&edge) == Some(&k) {
                self.owner.remove(&edge);
            }
        }
        for e in 0..3 {
            self.owner.insert((t[e], t[(e + 1) % 3]), k);
        }
        self.triangles[k] = t;
    }

    /// Flips edge a → b (in triangle (a, b, c)) and b → a (in (b, a, d)) into
    /// c → d; returns the two triangles.
    fn flip(&mut self, a: u32, b: u32) -> (usize, usize) {
        let k = self.owner[&(a, b)];
        let l = self.owner[&(b, a)];
        let c = self.opposite(k, a, b);
        let d = self.opposite(l, b, a);
        self.set(k, [c, a, d]);
        self.set(l, [d, b, c]);
        (k, l)
    }
}

/// What the flips did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Flips {
    /// Flips that made the boundary convex, and Lawson flips.
    pub hull: usize,
    pub delaunay: usize,
}

/// The Delaunay triangulation (with the dummy vertex on the convex hull) of
/// `points` from a valid triangulation of them.
pub fn make_delaunay(points: &[DVec2], triangles: Vec<[u32; 3]>) -> (Vec<[u32; 3]>, Flips) {
    let p = |v: u32| points[v as usize];
    let mut mesh = Mesh::new(triangles);
    let mut flips = Flips::default();
    // 1. The boundary: around the dummy, triangle (a, b, D) follows (b, c, D)'s
    // predecessor; b turns inward when a, b, c are counter-clockwise.
    let mut stack: Vec<usize> = (0..mesh.triangles.len())
        .filter(|&k| mesh.triangles[k].contains(&DUMMY))
        .collect();
    let mut boundary: std::collections::HashSet<u32> = stack
        .iter()
        .flat_map(|&k| mesh.triangles[k])
        .filter(|&v| v != DUMMY)
        .collect();
    while let Some(k) = stack.pop() {
        let t = mesh.triangles[k];
        let Some(e) = (0..3).find(|&e| t[(e + 2) % 3] == DUMMY) else {
            continue;
        };
        // Triangle k is (a, b, D) with a → b its finite edge.
        let (a, b) = (t[e], t[(e + 1) % 3]);
        // The next boundary triangle (b, c, D) has the edge D → b.
        let Some(&next) = mesh.owner.get(&(DUMMY, b)) else {
            continue;
        };
        let c = mesh.opposite(next, b, DUMMY);
        // An ear of the pocket between the boundary and the hull: b turns
        // inward and no other boundary site lies in the triangle (a, b, c).
        let ear = c != a
            && orient(p(a), p(b), p(c)) > 0.0
            && !boundary.iter().any(|&v| {
                v != a
                    && v != b
                    && v != c
                    && orient(p(a), p(b), p(v)) >= 0.0
                    && orient(p(b), p(c), p(v)) >= 0.0
                    && orient(p(c), p(a), p(v)) >= 0.0
            });
        if ear {
            // (a, b, D) and (b, c, D) share the edge between b and D: flip it
            // to a → c, which leaves b inside.
            let (k1, k2) = mesh.flip(DUMMY, b);
            flips.hull += 1;
            boundary.remove(&b);
            stack.extend([k1, k2]);
            // The boundary triangle before a may now find a turning inward.
            if let Some(&before) = mesh.owner.get(&(a, DUMMY)) {
                stack.push(before);
            }
        }
    }
    // 2. Lawson flips of inner edges.
    let mut stack: Vec<(u32, u32)> = mesh
        .owner
        .keys()
        .copied()
        .filter(|&(a, b)| a != DUMMY && b != DUMMY && a < b)
        .collect();
    while let Some((a, b)) = stack.pop() {
        let (Some(&k), Some(&l)) = (mesh.owner.get(&(a, b)), mesh.owner.get(&(b, a))) else {
            continue;
        };
        let c = mesh.opposite(k, a, b);
        let d = mesh.opposite(l, b, a);
        if c == DUMMY || d == DUMMY {
            continue;
        }
        if incircle(p(a), p(b), p(c), p(d)) > 0.0 {
            mesh.flip(a, b);
            flips.delaunay += 1;
            stack.extend([(a, c), (c, b), (b, d), (d, a)]);
        }
    }
    (mesh.triangles, flips)
}
