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

use glam::DVec2;

use super::mesh::Mesh;

/// What the flips did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Flips {
    /// Flips that made the boundary convex, and Lawson flips.
    pub hull: usize,
    pub delaunay: usize,
}

/// The Delaunay triangulation (with the dummy vertex on the convex hull) of
/// `points` from a valid triangulation of them; an error names an edge
/// without its twin.
pub fn make_delaunay(
    points: &[DVec2],
    triangles: Vec<[u32; 3]>,
) -> Result<(Vec<[u32; 3]>, Flips), String> {
    let mut mesh = Mesh::new(points.to_vec(), triangles)?;
    let hull = mesh.convexify();
    let delaunay = mesh.make_delaunay();
    Ok((mesh.triangles(), Flips { hull, delaunay }))
}
