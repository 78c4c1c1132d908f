//! Triangulations of the sphere over point sites and a dummy vertex at
//! infinity, and the check of Cao, Edelsbrunner and Tan's conditions for a
//! valid one:
//!
//! - I. the vertices are the sites and the dummy vertex;
//! - II. the triangles triangulate the sphere: every edge lies in exactly two
//!   triangles, oppositely oriented, every vertex's triangles form one ring,
//!   and V − E + F = 2;
//! - III. without the dummy vertex's star the triangles lie in the plane
//!   without overlap: each is counter-clockwise, the triangles around an inner
//!   site turn once, and the boundary is a simple polygon. Triangles that are
//!   positive and turn once around every inner vertex form a local embedding
//!   of a disc; with a simple boundary it is an embedding.

use std::collections::HashMap;

use glam::DVec2;

use super::exact::predicates::{incircle, orient};

/// The vertex at infinity.
pub const DUMMY: u32 = u32::MAX;

/// What the check found.
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Validity {
    /// Vertices (sites in triangles, and the dummy), undirected edges,
    /// triangles.
    pub vertices: usize,
    pub edges: usize,
    pub triangles: usize,
    /// V − E + F: 2 for a sphere.
    pub euler_characteristic: i64,
    /// Each violated condition, with the first example.
    pub problems: Vec<String>,
}

impl Validity {
    pub fn is_valid(&self) -> bool {
        self.problems.is_empty()
    }
}

/// Whether segments ab and cd share a point other than a common endpoint.
fn segments_meet(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let shared = [a == c, a == d, b == c, b == d];
    let (o1, o2, o3, o4) = (
        orient(a, b, c),
        orient(a, b, d),
        orient(c, d, a),
        orient(c, d, b),
    );
    if shared.iter().any(|&s| s) {
        // Adjacent edges meet elsewhere only if they overlap along a line.
        return o1 == 0.0 && o2 == 0.0 && {
            let (p, q, r) = if a == c || a == d {
                (a, b, if a == c { d } else { c })
            } else {
                (b, a, if b == c { d } else { c })
            };
            (q - p).dot(r - p) > 0.0
        };
    }
    let on = |p: DVec2, q: DVec2, r: DVec2| {
        r.x >= p.x.min(q.x) && r.x <= p.x.max(q.x) && r.y >= p.y.min(q.y) && r.y <= p.y.max(q.y)
    };
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    (o1 == 0.0 && on(a, b, c))
        || (o2 == 0.0 && on(a, b, d))
        || (o3 == 0.0 && on(c, d, a))
        || (o4 == 0.0 && on(c, d, b))
}

/// Records the first violation of each condition.
fn note(problems: &mut Vec<String>, condition: &str, what: String) {
    if !problems.iter().any(|p| p.starts_with(condition)) {
        problems.push(format!("{condition}: {what}"));
    }
}

/// Checks conditions I–III for `triangles` over `points` (indices, or
/// [`DUMMY`]).
#[expect(clippy::disallowed_macros, reason = "a flag a point")]
#[expect(
    clippy::disallowed_methods,
    reason = "per-site values, within the room the sites reserved where they entered (memory::MEMORY_PER_SITE)"
)]
pub fn validate(points: &[DVec2], triangles: &[[u32; 3]]) -> Validity {
    let mut problems: Vec<String> = Vec::new();
    let n = points.len();
    // I. The vertices.
    let mut used = vec![false; n];
    let mut dummy_used = false;
    for t in triangles {
        for &v in t {
            if v == DUMMY {
                dummy_used = true;
            } else if (v as usize) < n {
                used[v as usize] = true;
            } else {
                note(
                    &mut problems,
                    "I",
                    format!("triangle {t:?} names vertex {v} of {n}"),
                );
            }
        }
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            note(
                &mut problems,
                "II",
                format!("triangle {t:?} repeats a vertex"),
            );
        }
    }
    if let Some(v) = used.iter().position(|u| !u) {
        note(&mut problems, "I", format!("site {v} is in no triangle"));
    }
    if !dummy_used {
        note(
            &mut problems,
            "I",
            "the dummy vertex is in no triangle".into(),
        );
    }
    if !problems.is_empty() {
        return Validity {
            triangles: triangles.len(),
            problems,
            ..Validity::default()
        };
    }

    // II. Each directed edge once, its reverse once; one ring per vertex.
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for (k, t) in triangles.iter().enumerate() {
        for e in 0..3 {
            let edge = (t[e], t[(e + 1) % 3]);
            if directed.insert(edge, k).is_some() {
                note(
                    &mut problems,
                    "II",
                    format!("edge {edge:?} has two triangles on the same side"),
                );
            }
        }
    }
    for &(a, b) in directed.keys() {
        if !directed.contains_key(&(b, a)) {
            note(
                &mut problems,
                "II",
                format!("edge ({a}, {b}) lies in one triangle only"),
            );
        }
    }
    let edges = directed.len() / 2;
    let vertices = n + 1;
    let euler = vertices as i64 - edges as i64 + triangles.len() as i64;
    if euler != 2 {
        note(&mut problems, "II", format!("V - E + F = {euler}, not 2"));
    }
    // Around vertex a, triangle (a, b, c) leads from b to c.
    let mut next: HashMap<u32, HashMap<u32, u32>> = HashMap::new();
    for t in triangles {
        for e in 0..3 {
            let (a, b, c) = (t[e], t[(e + 1) % 3], t[(e + 2) % 3]);
            next.entry(a).or_default().insert(b, c);
        }
    }
    for (&a, ring) in &next {
        let &start = ring.keys().next().expect("a vertex has a triangle");
        let (mut at, mut steps) = (start, 0);
        while let Some(&to) = ring.get(&at) {
            at = to;
            steps += 1;
            if at == start || steps > ring.len() {
                break;
            }
        }
        if at != start || steps != ring.len() {
            let name = if a == DUMMY {
                "the dummy".to_string()
            } else {
                format!("site {a}")
            };
            note(
                &mut problems,
                "II",
                format!("the triangles around {name} do not form one ring"),
            );
        }
    }

    // III. The finite part in the plane (its rings are only known on a sphere).
    let p = |v: u32| points[v as usize];
    if !problems.is_empty() {
        return Validity {
            vertices,
            edges,
            triangles: triangles.len(),
            euler_characteristic: euler,
            problems,
        };
    }
    for t in triangles.iter().filter(|t| !t.contains(&DUMMY)) {
        if orient(p(t[0]), p(t[1]), p(t[2])) <= 0.0 {
            note(
                &mut problems,
                "III",
                format!("triangle {t:?} is not counter-clockwise"),
            );
        }
    }
    let boundary: Vec<u32> = match next.get(&DUMMY) {
        Some(ring) => {
            let &start = ring.keys().next().expect("the dummy has triangles");
            let mut cycle = Vec::from([start]);
            while let Some(&to) = ring.get(cycle.last().expect("non-empty")) {
                if to == start || cycle.len() > ring.len() {
                    break;
                }
                cycle.push(to);
            }
            cycle
        }
        None => Vec::new(),
    };
    let on_boundary: std::collections::HashSet<u32> = boundary.iter().copied().collect();
    for (&a, ring) in &next {
        if a == DUMMY || on_boundary.contains(&a) {
            continue;
        }
        let turn: f64 = ring
            .iter()
            .map(|(&b, &c)| {
                let (u, v) = (p(b) - p(a), p(c) - p(a));
                u.perp_dot(v).atan2(u.dot(v))
            })
            .sum();
        if (turn - std::f64::consts::TAU).abs() > 1e-6 {
            note(
                &mut problems,
                "III",
                format!("the triangles around site {a} turn {turn:.6} radians, not once"),
            );
        }
    }
    let h = boundary.len();
    'outer: for i in 0..h {
        for j in i + 1..h {
            let (a, b) = (p(boundary[i]), p(boundary[(i + 1) % h]));
            let (c, d) = (p(boundary[j]), p(boundary[(j + 1) % h]));
            if segments_meet(a, b, c, d) {
                note(
                    &mut problems,
                    "III",
                    format!(
                        "boundary edges ({}, {}) and ({}, {}) cross",
                        boundary[i],
                        boundary[(i + 1) % h],
                        boundary[j],
                        boundary[(j + 1) % h]
                    ),
                );
                break 'outer;
            }
        }
    }
    Validity {
        vertices,
        edges,
        triangles: triangles.len(),
        euler_characteristic: euler,
        problems,
    }
}

/// Checks a planar Delaunay triangulation the way delaunator's tests do, plus
/// exact local Delaunay-ness; returns each problem found (none for a good
/// one). `triangles` are finite and index `points`; `expected` points (the
/// distinct input) must all be used.
///
/// - every triangle counter-clockwise;
/// - half-edges: each directed edge once, and twins pair up;
/// - the boundary (edges without a twin) is one closed convex polygon, with
///   every point on or inside it;
/// - the triangles' areas add up to the hull's;
/// - every inner edge is locally Delaunay (exact incircle), which for a
///   triangulation of the convex hull means Delaunay.
#[expect(clippy::disallowed_macros, reason = "a flag a point")]
pub fn check_delaunay(points: &[DVec2], triangles: &[[u32; 3]], expected: &[u32]) -> Vec<String> {
    let mut problems = Vec::new();
    // The predicates' signs are those of the points scaled into their range.
    let points = &match super::scale::incircle_exponent(points) {
        Ok(k) => super::scale::scaled(points, k),
        Err(e) => return Vec::from([e.to_string()]),
    };
    let p = |v: u32| points[v as usize];
    let mut owner: HashMap<(u32, u32), usize> = HashMap::with_capacity(3 * triangles.len());
    let mut area = 0.0;
    let mut compensation = 0.0;
    for (k, t) in triangles.iter().enumerate() {
        let o = orient(p(t[0]), p(t[1]), p(t[2]));
        if o <= 0.0 {
            note(
                &mut problems,
                "orientation",
                format!("triangle {t:?} is not counter-clockwise"),
            );
        }
        // Kahan summation of twice the areas.
        let twice = (p(t[1]) - p(t[0])).perp_dot(p(t[2]) - p(t[0])) - compensation;
        let sum = area + twice;
        compensation = (sum - area) - twice;
        area = sum;
        for e in 0..3 {
            if owner.insert((t[e], t[(e + 1) % 3]), k).is_some() {
                note(
                    &mut problems,
                    "half-edges",
                    format!("edge ({}, {}) twice", t[e], t[(e + 1) % 3]),
                );
            }
        }
    }
    // The boundary, as next[a] = b for each edge a → b without a twin.
    let mut next: HashMap<u32, u32> = HashMap::new();
    for &(a, b) in owner.keys() {
        if !owner.contains_key(&(b, a)) && next.insert(a, b).is_some() {
            note(
                &mut problems,
                "boundary",
                format!("site {a} starts two boundary edges"),
            );
        }
    }
    let Some(&start) = next.keys().min() else {
        note(&mut problems, "boundary", "there is no boundary".into());
        return problems;
    };
    let mut hull = Vec::from([start]);
    while let Some(&b) = next.get(hull.last().expect("non-empty")) {
        if b == start || hull.len() > next.len() {
            break;
        }
        hull.push(b);
    }
    if hull.len() != next.len() {
        note(
            &mut problems,
            "boundary",
            format!(
                "{} boundary edges, but a cycle of {}",
                next.len(),
                hull.len()
            ),
        );
    }
    let h = hull.len();
    for i in 0..h {
        let (a, b, c) = (p(hull[i]), p(hull[(i + 1) % h]), p(hull[(i + 2) % h]));
        if orient(a, b, c) < 0.0 {
            note(
                &mut problems,
                "convexity",
                format!("the hull turns right at site {}", hull[(i + 1) % h]),
            );
        }
    }
    let mut hull_area = 0.0;
    for i in 0..h {
        let (a, b) = (p(hull[i]) - p(hull[0]), p(hull[(i + 1) % h]) - p(hull[0]));
        hull_area += a.perp_dot(b);
    }
    let scale = triangles
        .iter()
        .map(|t| (p(t[1]) - p(t[0])).perp_dot(p(t[2]) - p(t[0])).abs())
        .sum::<f64>();
    if (area - hull_area).abs() > 1e-9 * scale.max(f64::MIN_POSITIVE) {
        note(
            &mut problems,
            "area",
            format!("triangles cover {area}, the hull {hull_area} (twice)"),
        );
    }
    let mut used = vec![false; points.len()];
    for t in triangles {
        for &v in t {
            used[v as usize] = true;
        }
    }
    if let Some(v) = expected.iter().find(|&&v| !used[v as usize]) {
        note(
            &mut problems,
            "points",
            format!("point {v} is in no triangle"),
        );
    }
    // Points outside the hull (O(n h), only where few enough).
    if (points.len() as u64) * (h as u64) <= 50_000_000 {
        if let Some(v) = expected
            .iter()
            .find(|&&v| (0..h).any(|i| orient(p(hull[i]), p(hull[(i + 1) % h]), p(v)) < 0.0))
        {
            note(
                &mut problems,
                "convexity",
                format!("point {v} lies outside the hull"),
            );
        }
    }
    for (&(a, b), &k) in &owner {
        if let Some(&l) = owner.get(&(b, a)) {
            let t = triangles[k];
            let d = triangles[l]
                .iter()
                .copied()
                .find(|&v| v != a && v != b)
                .expect("three vertices");
            if incircle(p(t[0]), p(t[1]), p(t[2]), p(d)) > 0.0 {
                note(
                    &mut problems,
                    "delaunay",
                    format!("edge ({a}, {b}) is not locally Delaunay"),
                );
            }
        }
    }
    problems
}
