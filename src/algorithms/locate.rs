//! Point location in a triangulation: the triangle holding each query point,
//! decided by exact orientation tests (SciPy's `Delaunay.find_simplex`, with
//! no tolerance).

use crate::memory::Gather;
use glam::DVec2;

use crate::{
    algorithms::interpolate::walk::{Place, Triangles},
    geometry::{exact::predicates::orient, frame::check_sites},
    Error, Result,
};

/// No triangle holds the point: it lies outside the triangulation's hull.
pub const OUTSIDE: u32 = u32::MAX;

/// The triangle of `triangles` (counter-clockwise corners into `points`, as
/// [`crate::algorithms::delaunay::delaunay`] gives them, covering their
/// convex hull) that holds each of `queries`, closed: the smallest index
/// among those holding a point on an edge or a corner; [`OUTSIDE`] beyond
/// the hull. Each walk starts where the last ended, so queries near one
/// another are found in a few steps; on a triangulation that is not
/// Delaunay, where a walk may circle, the triangles are searched one by one.
///
/// ```
/// use glam::DVec2;
/// use pixgeo::{algorithms::{delaunay::{delaunay, DelaunayOptions}, locate::{locate, OUTSIDE}}, Backend};
///
/// let p = [DVec2::new(0.0, 0.0), DVec2::new(2.0, 0.0), DVec2::new(2.0, 2.0), DVec2::new(0.0, 2.0)];
/// let t = delaunay(&Backend::Cpu, &p, &DelaunayOptions::default())?.triangles;
/// let q = [DVec2::new(1.5, 0.5), DVec2::new(1.0, 1.0), DVec2::new(3.0, 1.0)];
/// let found = locate(&p, &t, &q)?;
/// assert_eq!(found[1], 0); // on the diagonal both hold it: the smaller index
/// assert_eq!(found[2], OUTSIDE);
/// # Ok::<(), pixgeo::Error>(())
/// ```
pub fn locate(points: &[DVec2], triangles: &[[u32; 3]], queries: &[DVec2]) -> Result<Vec<u32>> {
    check_sites(points)?;
    if let Some((i, q)) = queries.iter().enumerate().find(|(_, q)| !q.is_finite()) {
        return Err(Error::not_finite(
            Some(i),
            format!(
                "query point {i} has a non-finite coordinate ({:?}, {:?})",
                q.x, q.y
            ),
        ));
    }
    if let Some(t) = triangles
        .iter()
        .position(|t| t.iter().any(|&c| c as usize >= points.len()))
    {
        return Err(Error::malformed(format!(
            "triangle {t} names a point beyond the {} given",
            points.len()
        )));
    }
    if let Some(t) = triangles.iter().position(|t| {
        let [a, b, c] = t.map(|c| points[c as usize]);
        orient(a, b, c) <= 0.0
    }) {
        return Err(Error::malformed(format!(
            "triangle {t} is not counter-clockwise: give the triangulation's own triangles"
        )));
    }
    crate::memory::reserve(4 * queries.len() as u64, || {
        format!("the triangles of {} query points", queries.len())
    })?;
    if triangles.is_empty() {
        return crate::memory::filled(queries.len(), OUTSIDE, "the queries' triangles");
    }
    let mesh = Triangles::new(points, triangles);
    let mut start = 0;
    let search = |q: DVec2| {
        let holds = |t: &[u32; 3]| {
            let p = t.map(|c| points[c as usize]);
            (0..3).all(|k| orient(p[k], p[(k + 1) % 3], q) >= 0.0)
        };
        match triangles.iter().position(holds) {
            Some(t) => Place::Boundary(t as u32),
            None => Place::Outside(0),
        }
    };
    queries
        .iter()
        .map(
            |&q| match mesh.locate(q, start).unwrap_or_else(|_| search(q)) {
                Place::Outside(t) => {
                    start = t;
                    OUTSIDE
                }
                Place::Inside(t) | Place::Boundary(t) => {
                    start = t;
                    least_holding(&mesh, q, t)
                }
            },
        )
        .gather("values")
}

/// The smallest index among the triangles that hold `q`, from `t`, one of
/// them: those reached across edges that `q` lies on.
fn least_holding(mesh: &Triangles<'_>, q: DVec2, t: u32) -> u32 {
    let (mut seen, mut todo, mut least) = (Vec::from([t]), Vec::from([t]), t);
    while let Some(t) = todo.pop() {
        least = least.min(t);
        let p = mesh.corner_points(t);
        for (k, next) in mesh.across(t).into_iter().enumerate() {
            let on_edge = orient(p[k], p[(k + 1) % 3], q) == 0.0;
            if on_edge && next != u32::MAX && !seen.contains(&next) {
                seen.push(next);
                todo.push(next);
            }
        }
    }
    least
}
