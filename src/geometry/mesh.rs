//! A triangulation of the sphere over point sites and the dummy vertex at
//! infinity, with triangle adjacency, for the steps from a digital
//! triangulation to the Delaunay one: flips, moving a site, removing it and
//! inserting one.
//!
//! Triangles are counter-clockwise; edge `e` of a triangle runs from its
//! vertex `e` to vertex `e + 1`, and `adjacent[t][e]` is the triangle on its
//! other side. A triangle with the dummy vertex (a *ghost*) stands for the
//! outside beyond its one finite edge: ghost (a, b, DUMMY) lies to the left of
//! a → b. Every predicate is exact (`robust`).

use glam::DVec2;
use rayon::prelude::*;

use super::buckets::group_by_bucket;
use super::exact::power::{power_test, Weighted};
use super::exact::predicates::{incircle, orient};
pub use super::triangulation::DUMMY;
use std::cmp::Ordering;

/// No triangle.
const NONE: u32 = u32::MAX;
/// A vertex slot of a removed triangle, kept for reuse.
const FREE: u32 = u32::MAX - 1;

fn next(e: usize) -> usize {
    (e + 1) % 3
}

fn prev(e: usize) -> usize {
    (e + 2) % 3
}

/// Two triangles (a, b, c) and u = (b, a, d) sharing an edge: a, b, c, d, and
/// the triangles beyond b → c, c → a, a → d and d → b.
struct Quad {
    u: u32,
    vertices: [u32; 4],
    beyond: [u32; 4],
}

/// Why a removal was refused: too few sites would remain.
#[derive(Debug)]
pub(crate) struct TooFewSites;

/// The triangulation.
pub(crate) struct Mesh {
    /// Where each vertex is now.
    pub points: Vec<DVec2>,
    triangles: Vec<[u32; 3]>,
    adjacent: Vec<[u32; 3]>,
    /// One triangle of each vertex (the dummy's last), or `NONE` while the
    /// vertex is not in the mesh.
    corner: Vec<u32>,
    free: Vec<u32>,
    /// Vertices in the mesh, the dummy not counted.
    present: usize,
    /// Xorshift state for the walk's random first edge.
    walk: u64,
    /// Each vertex's power weight, for a regular triangulation; empty for a
    /// Delaunay one.
    pub weights: Vec<f64>,
    /// Weighted vertices left out or taken out: their power cells are empty.
    pub hidden: Vec<u32>,
    /// The edges [`Mesh::legalize`] has yet to check, kept between calls.
    stack: Vec<(u32, usize)>,
    /// Each vertex's rank in the tie rule of [`Mesh::conflicts`] (the input
    /// index, so that every route builds the same triangulation); empty:
    /// the vertex's own number.
    pub rank: Vec<u32>,
}

impl Mesh {
    fn slot(&self, v: u32) -> usize {
        if v == DUMMY {
            self.points.len()
        } else {
            v as usize
        }
    }

    fn at(&self, v: u32) -> DVec2 {
        self.points[v as usize]
    }

    fn weighted(&self, v: u32) -> Weighted {
        Weighted {
            at: self.at(v),
            weight: self.weights[v as usize],
        }
    }

    /// Whether `q` conflicts with finite triangle `t`: lies inside its
    /// circumcircle, or for weights, would take part of its corners' power
    /// cells.
    fn conflicts(&self, t: [u32; 3], q: u32) -> bool {
        if self.weights.is_empty() {
            let [a, b, c] = t.map(|v| self.at(v));
            let inside = incircle(a, b, c, self.at(q));
            return inside > 0.0 || (inside == 0.0 && self.perturbed_inside(t, q));
        }
        let [a, b, c] = t.map(|v| self.weighted(v));
        power_test(a, b, c, self.weighted(q)) == Ordering::Greater
    }

    /// For `q` on the circle through `t`'s corners: whether it is inside once
    /// each vertex's lift onto the paraboloid is raised by ε^(1 + rank), ε
    /// infinitesimal (simulation of simplicity). The incircle determinant's
    /// derivative by each lift is an orientation of the other three points;
    /// the first that is not zero, in rank order, gives the sign. The lifted
    /// points are then in general position, so the Delaunay triangulation is
    /// unique: flips and insertion, in any order, end with the same
    /// triangles.
    fn perturbed_inside(&self, [a, b, c]: [u32; 3], d: u32) -> bool {
        let rank = |v: u32| self.rank.get(v as usize).copied().unwrap_or(v);
        let [pa, pb, pc, pd] = [a, b, c, d].map(|v| self.at(v));
        let mut terms = [
            (rank(a), orient(pb, pc, pd)),
            (rank(b), -orient(pa, pc, pd)),
            (rank(c), orient(pa, pb, pd)),
            (rank(d), -orient(pa, pb, pc)),
        ];
        terms.sort_unstable_by_key(|&(r, _)| r);
        // q's own term is -orient(a, b, c), not zero for a finite triangle.
        terms
            .iter()
            .find(|&&(_, s)| s != 0.0)
            .is_some_and(|&(_, s)| s > 0.0)
    }

    fn is_ghost(&self, t: u32) -> bool {
        self.triangles[t as usize].contains(&DUMMY)
    }

    /// The mesh of a triangulation of the sphere over `points` (sites and
    /// [`DUMMY`]). An error says what keeps it from being one: an edge without
    /// a twin or in more than two triangles, a vertex whose triangles form
    /// more than one ring, an Euler characteristic other than 2, or a finite
    /// triangle that is not counter-clockwise. (That the boundary is simple is
    /// not checked; [`super::triangulation::validate`] checks everything.)
    #[expect(
        clippy::disallowed_macros,
        reason = "as many as the points and triangles, within the budget the caller reserved"
    )]
    pub fn new(points: Vec<DVec2>, triangles: Vec<[u32; 3]>) -> Result<Self, String> {
        let n = points.len();
        let slot = |v: u32| if v == DUMMY { n } else { v as usize };
        if let Some((t, v)) = triangles
            .iter()
            .flat_map(|t| t.iter().map(move |&v| (t, v)))
            .find(|&(_, v)| v != DUMMY && v as usize >= n)
        {
            return Err(format!("triangle {t:?} names vertex {v} of {n}"));
        }
        // The edges leaving each vertex, as (triangle, edge) in CSR order.
        let corners = triangles.iter().enumerate().flat_map(|(k, t)| {
            t.iter()
                .enumerate()
                .map(move |(e, &v)| (slot(v), (k as u32, e as u8)))
        });
        let (start, leaving) = group_by_bucket(n + 1, corners);
        let edges_of = |v: u32| &leaving[start[slot(v)] as usize..start[slot(v) + 1] as usize];
        // Each edge's twin: the triangle and the twin's edge index there.
        let twins: Vec<([u32; 3], [u8; 3])> = triangles
            .par_iter()
            .enumerate()
            .map(|(k, t)| {
                let mut row = [NONE; 3];
                let mut index = [0u8; 3];
                for e in 0..3 {
                    let (a, b) = (t[e], t[next(e)]);
                    // The twin b → a, looked up at its finite end.
                    let twin = if b != DUMMY {
                        edges_of(b)
                            .iter()
                            .find(|&&(u, f)| triangles[u as usize][next(f as usize)] == a)
                            .map(|&(u, f)| (u, f))
                    } else {
                        edges_of(a)
                            .iter()
                            .find(|&&(u, f)| triangles[u as usize][prev(f as usize)] == b)
                            .map(|&(u, f)| (u, prev(f as usize) as u8))
                    };
                    match twin {
                        Some((u, f)) if u as usize != k => (row[e], index[e]) = (u, f),
                        _ => return Err(format!("edge {a} -> {b} of triangle {k} has no twin")),
                    }
                }
                Ok((row, index))
            })
            .collect::<Result<_, String>>()?;
        let (adjacent, twin_edges): (Vec<[u32; 3]>, Vec<[u8; 3]>) = twins.into_iter().unzip();
        let mut corner = vec![NONE; n + 1];
        for (k, t) in triangles.iter().enumerate() {
            for &v in t {
                corner[slot(v)] = k as u32;
            }
        }
        let present = corner[..n].iter().filter(|&&c| c != NONE).count();
        let mesh = Self {
            points,
            triangles,
            adjacent,
            corner,
            free: Vec::new(),
            present,
            walk: 0x9e37_79b9_7f4a_7c15,
            weights: Vec::new(),
            hidden: Vec::new(),
            stack: Vec::new(),
            rank: Vec::new(),
        };
        mesh.check(&twin_edges, |v| {
            (start[slot(v) + 1] - start[slot(v)]) as usize
        })?;
        Ok(mesh)
    }

    /// What [`Mesh::new`] needs beyond twins: twins pair up (no directed edge
    /// twice), each vertex's triangles form one ring (`degree` of them), the
    /// Euler characteristic is a sphere's, and every finite triangle is
    /// counter-clockwise.
    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    fn check(
        &self,
        twin_edges: &[[u8; 3]],
        degree: impl Fn(u32) -> usize + Sync,
    ) -> Result<(), String> {
        let triangles = &self.triangles;
        (0..triangles.len()).into_par_iter().try_for_each(|t| {
            let tv = triangles[t];
            for e in 0..3 {
                let (u, f) = (self.adjacent[t][e] as usize, twin_edges[t][e] as usize);
                if self.adjacent[u][f] as usize != t || twin_edges[u][f] as usize != e {
                    return Err(format!(
                        "edge {} -> {} lies in more than two triangles",
                        tv[e],
                        tv[next(e)]
                    ));
                }
            }
            if !tv.contains(&DUMMY) && orient(self.at(tv[0]), self.at(tv[1]), self.at(tv[2])) <= 0.0
            {
                return Err(format!("triangle {tv:?} is not counter-clockwise"));
            }
            Ok(())
        })?;
        let vertices: Vec<u32> = (0..self.points.len() as u32)
            .filter(|&v| self.contains(v))
            .chain([DUMMY])
            .collect();
        vertices.par_iter().try_for_each(|&v| {
            // Around v: from corner (t, i) across edge i - 1 to the twin's
            // start, which is v.
            let first = self.corner[self.slot(v)];
            let (mut t, mut i) = (first, self.index_in(first, v));
            let mut ring = 0;
            loop {
                ring += 1;
                let e = prev(i);
                (t, i) = (
                    self.adjacent[t as usize][e],
                    twin_edges[t as usize][e] as usize,
                );
                if t == first || ring > degree(v) {
                    break;
                }
            }
            if ring != degree(v) {
                return Err(format!(
                    "the triangles around vertex {v} form more than one ring"
                ));
            }
            Ok(())
        })?;
        let edges = 3 * triangles.len() / 2;
        if vertices.len() + triangles.len() != edges + 2 {
            return Err("the triangles are not a sphere".into());
        }
        Ok(())
    }

    /// The triangle a, b, c (counter-clockwise, distinct points) and its three
    /// ghosts: the start of an incremental triangulation.
    pub fn triangle(points: Vec<DVec2>, [a, b, c]: [u32; 3]) -> Self {
        let triangles = Vec::from([[a, b, c], [b, a, DUMMY], [c, b, DUMMY], [a, c, DUMMY]]);
        Self::new(points, triangles).expect("a triangle and its ghosts are a sphere")
    }

    /// Whether vertex `v` is in the mesh.
    pub fn contains(&self, v: u32) -> bool {
        self.corner[v as usize] != NONE
    }

    /// The triangles (ghosts included), in no particular order.
    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        self.triangles
            .iter()
            .filter(|t| t[0] != FREE)
            .copied()
            .collect()
    }

    fn index_in(&self, t: u32, v: u32) -> usize {
        self.triangles[t as usize]
            .iter()
            .position(|&w| w == v)
            .expect("the vertex is in the triangle")
    }

    /// Makes `new` the neighbour that `t` had in `old`.
    fn repoint(&mut self, t: u32, old: u32, new: u32) {
        let row = &mut self.adjacent[t as usize];
        let e = row.iter().position(|&u| u == old).expect("neighbours");
        row[e] = new;
    }

    fn set(&mut self, t: u32, vertices: [u32; 3], adjacent: [u32; 3]) {
        self.triangles[t as usize] = vertices;
        self.adjacent[t as usize] = adjacent;
        for v in vertices {
            let s = self.slot(v);
            self.corner[s] = t;
        }
    }

    fn allocate(&mut self) -> u32 {
        match self.free.pop() {
            Some(t) => t,
            None => {
                self.triangles.push([FREE; 3]);
                self.adjacent.push([NONE; 3]);
                (self.triangles.len() - 1) as u32
            }
        }
    }

    /// The triangles around `v`, counter-clockwise, each with `v`'s index.
    #[expect(clippy::disallowed_methods, reason = "one vertex's ring")]
    fn ring(&self, v: u32) -> Vec<(u32, usize)> {
        let first = self.corner[self.slot(v)];
        let mut ring = Vec::with_capacity(8);
        let mut t = first;
        loop {
            let i = self.index_in(t, v);
            ring.push((t, i));
            // The next triangle around v shares the edge t[i - 1] → v.
            t = self.adjacent[t as usize][prev(i)];
            if t == first {
                return ring;
            }
        }
    }

    /// The edge index in `u` of its edge shared with `t`.
    fn twin_index(&self, u: u32, t: u32) -> usize {
        self.adjacent[u as usize]
            .iter()
            .position(|&w| w == t)
            .expect("twins")
    }

    /// The two triangles at edge `e` of `t`, (a, b, c) and u = (b, a, d), and
    /// the four beyond their other edges.
    fn quad(&self, t: u32, e: usize) -> Quad {
        let u = self.adjacent[t as usize][e];
        let f = self.twin_index(u, t);
        let [tv, ta] = [self.triangles[t as usize], self.adjacent[t as usize]];
        let [uv, ua] = [self.triangles[u as usize], self.adjacent[u as usize]];
        Quad {
            u,
            vertices: [tv[e], tv[next(e)], tv[prev(e)], uv[prev(f)]],
            beyond: [ta[next(e)], ta[prev(e)], ua[next(f)], ua[prev(f)]],
        }
    }

    /// Flips edge `e` of triangle `t`: (a, b, c) and (b, a, d) become
    /// (c, a, d) and (d, b, c).
    fn flip(&mut self, t: u32, e: usize) {
        let Quad {
            u,
            vertices: [a, b, c, d],
            beyond: [n_bc, n_ca, n_ad, n_db],
        } = self.quad(t, e);
        self.set(t, [c, a, d], [n_ca, n_ad, u]);
        self.set(u, [d, b, c], [n_db, n_bc, t]);
        self.repoint(n_bc, t, u);
        self.repoint(n_ad, u, t);
    }

    /// Whether edge `e` of `t` is finite, between finite triangles, and not
    /// locally Delaunay.
    fn is_illegal(&self, t: u32, e: usize) -> bool {
        let tv = self.triangles[t as usize];
        if tv[0] == FREE || tv.contains(&DUMMY) {
            return false;
        }
        // The far corner of the triangle beyond: its vertices less the
        // edge's two (no search for the twin edge).
        let uv = self.triangles[self.adjacent[t as usize][e] as usize];
        let d = uv
            .iter()
            .fold(0u32, |sum, &v| sum.wrapping_add(v))
            .wrapping_sub(tv[e])
            .wrapping_sub(tv[next(e)]);
        d != DUMMY && self.conflicts(tv, d)
    }

    /// For weights, where the illegal edge `e` of `t` cannot be flipped (its
    /// quadrilateral is not convex): the reflex corner, taken out if three
    /// triangles surround it (a 3-1 flip; its cell is empty), else left for
    /// later insertions to settle (Edelsbrunner and Shah 1996). Returns
    /// whether the edge was handled so.
    fn unflippable(&mut self, t: u32, e: usize, stack: &mut Vec<(u32, usize)>) -> bool {
        if self.weights.is_empty() {
            return false;
        }
        let [a, b, c, d] = self.quad(t, e).vertices;
        let reflex = if orient(self.at(c), self.at(a), self.at(d)) <= 0.0 {
            a
        } else if orient(self.at(d), self.at(b), self.at(c)) <= 0.0 {
            b
        } else {
            return false;
        };
        let ring = self.ring(reflex);
        if ring.len() == 3 && ring.iter().all(|&(r, _)| !self.is_ghost(r)) {
            let [x, y, z] = [0, 1, 2].map(|k| self.triangles[ring[k].0 as usize][next(ring[k].1)]);
            self.take_out(reflex);
            self.hidden.push(reflex);
            let filled = self.corner[x as usize];
            debug_assert!(self.triangles[filled as usize].contains(&y) && y != z);
            stack.extend([(filled, 0), (filled, 1), (filled, 2)]);
        }
        true
    }

    /// Lawson's flips from the edges on `stack` until every edge they reach is
    /// locally Delaunay; returns the number of flips.
    fn legalize(&mut self, edges: &[(u32, usize)]) -> usize {
        // One stack for every insertion's flips, not an allocation each.
        let mut stack = std::mem::take(&mut self.stack);
        stack.clear();
        stack.extend_from_slice(edges);
        let mut flips = 0;
        while let Some((t, e)) = stack.pop() {
            if self.is_illegal(t, e) && !self.unflippable(t, e, &mut stack) {
                let u = self.adjacent[t as usize][e];
                self.flip(t, e);
                flips += 1;
                stack.extend([(t, 0), (t, 1), (u, 0), (u, 1)]);
            }
        }
        self.stack = stack;
        flips
    }

    /// Lawson's flips over every edge: the Delaunay triangulation, once the
    /// boundary is the convex hull. Returns the number of flips.
    pub fn make_delaunay(&mut self) -> usize {
        // The edges to flip first, found in parallel; flipping is sequential.
        let stack: Vec<(u32, usize)> = (0..self.triangles.len() as u32)
            .into_par_iter()
            .flat_map_iter(|t| (0..3).map(move |e| (t, e)))
            .filter(|&(t, e)| t < self.adjacent[t as usize][e] && self.is_illegal(t, e))
            .collect();
        self.legalize(&stack)
    }

    /// The ghost after ghost `g` along the boundary: with `g` = (a, b, D), the
    /// ghost (b, c, D).
    fn next_ghost(&self, g: u32) -> u32 {
        let i = self.index_in(g, DUMMY);
        // The edge DUMMY → a leads to the ghost before; b → DUMMY to the next.
        self.adjacent[g as usize][prev(i)]
    }

    fn previous_ghost(&self, g: u32) -> u32 {
        let i = self.index_in(g, DUMMY);
        self.adjacent[g as usize][i]
    }

    /// The finite edge (a, b) of ghost `g`.
    fn ghost_edge(&self, g: u32) -> (u32, u32) {
        let i = self.index_in(g, DUMMY);
        let t = self.triangles[g as usize];
        (t[next(i)], t[prev(i)])
    }

    /// Makes the boundary the convex hull: where it turns inward at b between
    /// a and c and no other boundary site lies in triangle (a, b, c), the
    /// ghosts (a, b, D) and (b, c, D) become (a, b, c) and (a, c, D). Returns
    /// the number of flips.
    #[expect(
        clippy::disallowed_macros,
        reason = "a flag a point, within the budget the caller reserved"
    )]
    #[expect(
        clippy::disallowed_methods,
        reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
    )]
    pub(crate) fn convexify(&mut self) -> usize {
        let first = self.corner[self.points.len()];
        let mut ghosts = Vec::from([first]);
        let mut g = self.next_ghost(first);
        while g != first {
            ghosts.push(g);
            g = self.next_ghost(g);
        }
        let mut on_boundary = vec![false; self.points.len()];
        for &g in &ghosts {
            on_boundary[self.ghost_edge(g).0 as usize] = true;
        }
        let boundary: Vec<u32> = (0..self.points.len() as u32)
            .filter(|&v| on_boundary[v as usize])
            .collect();
        let mut flips = 0;
        let mut stack = ghosts;
        while let Some(g) = stack.pop() {
            if !self.is_ghost(g) || self.triangles[g as usize][0] == FREE {
                continue;
            }
            let (a, b) = self.ghost_edge(g);
            let h = self.next_ghost(g);
            let (_, c) = self.ghost_edge(h);
            if c == a || orient(self.at(a), self.at(b), self.at(c)) <= 0.0 {
                continue;
            }
            let (pa, pb, pc) = (self.at(a), self.at(b), self.at(c));
            let (lo, hi) = (pa.min(pb).min(pc), pa.max(pb).max(pc));
            let blocked = boundary.iter().any(|&v| {
                let p = self.at(v);
                on_boundary[v as usize]
                    && v != a
                    && v != b
                    && v != c
                    && p.cmpge(lo).all()
                    && p.cmple(hi).all()
                    && orient(pa, pb, p) >= 0.0
                    && orient(pb, pc, p) >= 0.0
                    && orient(pc, pa, p) >= 0.0
            });
            if blocked {
                continue;
            }
            // Edge b → DUMMY of g, shared with h.
            self.flip(g, self.index_in(g, b));
            flips += 1;
            on_boundary[b as usize] = false;
            // g is now (a, b, c) or the ghost (a, c, D); find the ghost.
            let ghost = if self.is_ghost(g) { g } else { h };
            stack.push(ghost);
            stack.push(self.previous_ghost(ghost));
        }
        flips
    }

    /// Moves vertex `v` to `to` if the mesh stays valid there: every triangle
    /// around it stays counter-clockwise and, on the hull, the hull stays
    /// convex. Returns whether it moved.
    pub(crate) fn try_move(&mut self, v: u32, to: DVec2) -> bool {
        let first = self.corner[v as usize];
        let mut t = first;
        // On the hull: the ghosts with hull edges u → v and v → w.
        let (mut ending, mut starting) = (None, None);
        loop {
            let tv = self.triangles[t as usize];
            let i = self.index_in(t, v);
            let (a, b) = (tv[next(i)], tv[prev(i)]);
            if a == DUMMY {
                ending = Some(t);
            } else if b == DUMMY {
                starting = Some(t);
            } else if orient(self.at(a), self.at(b), to) <= 0.0 {
                return false;
            }
            t = self.adjacent[t as usize][prev(i)];
            if t == first {
                break;
            }
        }
        if let (Some(ending), Some(starting)) = (ending, starting) {
            // The boundary z → u → v → w → y must keep turning clockwise.
            let (z, u) = self.ghost_edge(self.previous_ghost(ending));
            let (w, y) = self.ghost_edge(self.next_ghost(starting));
            let p = |x: u32| self.at(x);
            if orient(p(z), p(u), to) > 0.0
                || orient(p(u), to, p(w)) > 0.0
                || orient(to, p(w), p(y)) > 0.0
            {
                return false;
            }
        }
        self.points[v as usize] = to;
        true
    }

    /// Takes vertex `v` out of the mesh and fills its hole: an inner vertex's
    /// star-shaped link by ears, a hull vertex's pocket up to the new convex
    /// hull. Refused when fewer than four sites would remain.
    pub fn remove(&mut self, v: u32) -> Result<(), TooFewSites> {
        if self.present <= 4 {
            return Err(TooFewSites);
        }
        self.take_out(v);
        Ok(())
    }

    /// [`Mesh::remove`] without its guard.
    #[expect(clippy::disallowed_methods, reason = "one vertex's ring")]
    fn take_out(&mut self, v: u32) {
        let ring = self.ring(v);
        // The link cycle, each edge with the triangle beyond it.
        let mut polygon = Vec::with_capacity(ring.len());
        let mut outside = Vec::with_capacity(ring.len());
        for &(t, i) in &ring {
            polygon.push(self.triangles[t as usize][next(i)]);
            outside.push(self.adjacent[t as usize][next(i)]);
        }
        let new = match polygon.iter().position(|&x| x == DUMMY) {
            None => self.ears(&polygon),
            Some(d) => {
                // Start the chain after the dummy: l0, ..., lk, D.
                polygon.rotate_left(d + 1);
                outside.rotate_left(d + 1);
                self.pocket(&polygon[..polygon.len() - 1])
            }
        };
        for &(t, _) in &ring {
            self.triangles[t as usize] = [FREE; 3];
            self.free.push(t);
        }
        self.corner[v as usize] = NONE;
        self.present -= 1;
        self.stitch(&polygon, &outside, &new);
    }

    /// Ear clipping of a simple counter-clockwise polygon of sites.
    #[expect(clippy::disallowed_methods, reason = "one vertex's ring")]
    fn ears(&self, polygon: &[u32]) -> Vec<[u32; 3]> {
        let mut left = polygon.to_vec();
        let mut out = Vec::with_capacity(polygon.len() - 2);
        while left.len() > 3 {
            let k = left.len();
            let ear = (0..k)
                .find(|&i| {
                    let (a, b, c) = (left[(i + k - 1) % k], left[i], left[(i + 1) % k]);
                    let (pa, pb, pc) = (self.at(a), self.at(b), self.at(c));
                    orient(pa, pb, pc) > 0.0
                        && left.iter().all(|&x| {
                            let p = self.at(x);
                            x == a
                                || x == b
                                || x == c
                                || orient(pa, pb, p) < 0.0
                                || orient(pb, pc, p) < 0.0
                                || orient(pc, pa, p) < 0.0
                        })
                })
                .expect("a simple polygon has an ear");
            out.push([left[(ear + k - 1) % k], left[ear], left[(ear + 1) % k]]);
            left.remove(ear);
        }
        out.push([left[0], left[1], left[2]]);
        out
    }

    /// The triangles between a removed hull vertex's link chain and the
    /// chain's convex side toward it (a Graham scan; the chain is sorted by
    /// angle around the removed vertex), and the ghosts of the new hull edges.
    #[expect(clippy::disallowed_methods, reason = "one vertex's ring")]
    fn pocket(&self, chain: &[u32]) -> Vec<[u32; 3]> {
        let mut out = Vec::new();
        let mut hull: Vec<u32> = Vec::with_capacity(chain.len());
        for &c in chain {
            while hull.len() >= 2 {
                let (a, b) = (hull[hull.len() - 2], hull[hull.len() - 1]);
                if orient(self.at(a), self.at(b), self.at(c)) > 0.0 {
                    out.push([a, b, c]);
                    hull.pop();
                } else {
                    break;
                }
            }
            hull.push(c);
        }
        out.extend(hull.windows(2).map(|w| [w[0], w[1], DUMMY]));
        out
    }

    /// Puts triangles `new`, which fill `polygon` (edge k from vertex k to
    /// k + 1, with `outside[k]` beyond it), into the mesh.
    #[expect(clippy::disallowed_methods, reason = "one vertex's ring")]
    fn stitch(&mut self, polygon: &[u32], outside: &[u32], new: &[[u32; 3]]) {
        let slots: Vec<u32> = new.iter().map(|_| self.allocate()).collect();
        let k = polygon.len();
        for (j, tv) in new.iter().enumerate() {
            let mut row = [NONE; 3];
            for e in 0..3 {
                let (a, b) = (tv[e], tv[next(e)]);
                row[e] = match (0..k).find(|&m| polygon[m] == a && polygon[(m + 1) % k] == b) {
                    Some(m) => {
                        let out = outside[m];
                        // The outer triangle's edge b → a pointed into the hole.
                        let o = self.triangles[out as usize];
                        let f = (0..3)
                            .find(|&f| o[f] == b && o[next(f)] == a)
                            .expect("the outer triangle borders the hole");
                        self.adjacent[out as usize][f] = slots[j];
                        out
                    }
                    None => {
                        let twin = new
                            .iter()
                            .position(|u| (0..3).any(|f| u[f] == b && u[next(f)] == a))
                            .expect("an inner edge of the fill has a twin");
                        slots[twin]
                    }
                };
            }
            self.set(slots[j], *tv, row);
        }
    }

    /// Inserts vertex `v` (not in the mesh, at `points[v]`, distinct from every
    /// site in it) by a walk from a triangle of `near` (a vertex in the mesh),
    /// then legalizes the new edges. Returns the flips.
    pub fn insert(&mut self, v: u32, near: u32) -> usize {
        let q = self.at(v);
        let mut t = self.corner[self.slot(near)];
        loop {
            if self.is_ghost(t) {
                let (a, b) = self.ghost_edge(t);
                if orient(self.at(a), self.at(b), q) > 0.0 {
                    return self.insert_outside(v, t);
                }
                // Step inside across the hull edge.
                t = self.adjacent[t as usize][self.index_in(t, a)];
                continue;
            }
            // A stochastic walk (a random first edge), which ends in any
            // triangulation; the edge it came through is never crossed back,
            // as q lies strictly on this side of it.
            let tv = self.triangles[t as usize];
            self.walk ^= self.walk << 13;
            self.walk ^= self.walk >> 7;
            self.walk ^= self.walk << 17;
            let first = (self.walk % 3) as usize;
            let mut crossed = None;
            let mut zero = None;
            let mut zeros = 0;
            for j in 0..3 {
                let e = (first + j) % 3;
                let side = orient(self.at(tv[e]), self.at(tv[next(e)]), q);
                if side < 0.0 {
                    crossed = Some(self.adjacent[t as usize][e]);
                    break;
                }
                if side == 0.0 {
                    zero = Some(e);
                    zeros += 1;
                }
            }
            if let Some(u) = crossed {
                t = u;
                continue;
            }
            if !self.weights.is_empty() && !self.conflicts(tv, v) {
                // Its lifted point lies on or above the lower hull: its power
                // cell is empty.
                self.hidden.push(v);
                return 0;
            }
            self.present += 1;
            return match (zeros, zero) {
                (0, _) => self.split_triangle(t, v),
                (1, Some(e)) => self.split_edge(t, e, v),
                _ => panic!("inserted point {v} coincides with a site"),
            };
        }
    }

    fn split_triangle(&mut self, t: u32, q: u32) -> usize {
        let [a, b, c] = self.triangles[t as usize];
        let [n_ab, n_bc, n_ca] = self.adjacent[t as usize];
        let (t1, t2) = (self.allocate(), self.allocate());
        self.set(t1, [b, c, q], [n_bc, t2, t]);
        self.set(t2, [c, a, q], [n_ca, t, t1]);
        self.set(t, [a, b, q], [n_ab, t1, t2]);
        self.repoint(n_bc, t, t1);
        self.repoint(n_ca, t, t2);
        self.legalize(&[(t, 0), (t1, 0), (t2, 0)])
    }

    fn split_edge(&mut self, t: u32, e: usize, q: u32) -> usize {
        let Quad {
            u,
            vertices: [a, b, c, d],
            beyond: [n_bc, n_ca, n_ad, n_db],
        } = self.quad(t, e);
        let (t1, u1) = (self.allocate(), self.allocate());
        self.set(t, [q, b, c], [u1, n_bc, t1]);
        self.set(t1, [a, q, c], [u, t, n_ca]);
        self.set(u, [q, a, d], [t1, n_ad, u1]);
        self.set(u1, [b, q, d], [t, u, n_db]);
        self.repoint(n_ca, t, t1);
        self.repoint(n_db, u, u1);
        self.legalize(&[(t, 1), (t1, 2), (u, 1), (u1, 2)])
    }

    /// Inserts `q` beyond the hull edge of ghost `g`, then flips ghosts until
    /// the hull is convex again.
    fn insert_outside(&mut self, q: u32, g: u32) -> usize {
        let (a, b) = self.ghost_edge(g);
        let i = self.index_in(g, DUMMY);
        let row = self.adjacent[g as usize];
        // Neighbours of (a, b, D): across a → b, b → D, D → a.
        let (n_ab, n_bd, n_da) = (row[next(i)], row[prev(i)], row[i]);
        let (g1, g2) = (self.allocate(), self.allocate());
        self.set(g, [a, b, q], [n_ab, g2, g1]);
        self.set(g1, [a, q, DUMMY], [g, g2, n_da]);
        self.set(g2, [q, b, DUMMY], [g, n_bd, g1]);
        self.repoint(n_da, g, g1);
        self.repoint(n_bd, g, g2);
        self.present += 1;
        let mut flips = 0;
        let mut inner = Vec::from([(g, 0)]);
        // Walk back over a while z → a → q turns left, then on over b.
        let mut ghost = g1;
        loop {
            let before = self.previous_ghost(ghost);
            let (z, a) = self.ghost_edge(before);
            if orient(self.at(z), self.at(a), self.at(q)) <= 0.0 {
                break;
            }
            // Edge a → DUMMY of `before`, shared with `ghost`.
            self.flip(before, self.index_in(before, a));
            flips += 1;
            // `before` is now (z, a, q): its edge z → a is inner.
            inner.push((before, 0));
            ghost = if self.is_ghost(before) { before } else { ghost };
        }
        let mut ghost = g2;
        loop {
            let after = self.next_ghost(ghost);
            let (b, y) = self.ghost_edge(after);
            if orient(self.at(q), self.at(b), self.at(y)) <= 0.0 {
                break;
            }
            let finite = ghost;
            self.flip(ghost, self.index_in(ghost, b));
            flips += 1;
            // `finite` is now (q, b, y): its edge b → y is inner.
            inner.push((finite, 1));
            ghost = if self.is_ghost(ghost) { ghost } else { after };
        }
        flips + self.legalize(&inner)
    }
}
