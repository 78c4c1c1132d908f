//! Smallest enclosing and largest empty circles (thesis ch. 4–5) on a 1024²
//! picture, beside the exact CPU methods a user would otherwise pick, in the same
//! run: Welzl's algorithm for the enclosing circle, and the largest empty circle
//! from a Delaunay triangulation (`spade`): circumcentres inside the box, Voronoi
//! edges crossing its sides, and its corners. `empty` runs twice: its default
//! pixel stage (the distance transform) and the thesis's envelope of cones.
//!
//! `cargo bench --bench homothet` writes `target/homothet/homothet.md`.
//! `HM_N=100,1000` sets the site counts, `HM_REPEATS` the repeats (median).

use pixgeo::Backend;
use std::path::PathBuf;

use glam::DVec2;
use pixgeo::{
    algorithms::homothet::{
        enclose, largest_empty, EmptyOptions, EncloseOptions, PixelStage, Unit,
    },
    geometry::Frame,
    Machine,
};
use pixgeo_reference::homothet::welzl;
use spade::{DelaunayTriangulation, HierarchyHintGenerator, Point2, Triangulation};

mod common {
    pub mod report;
    pub mod timing;
}
use common::timing::{env_list, time};

const SIZE: u32 = 1024;

/// The largest empty circle centred in the box [lo, hi] of the points, from
/// their Delaunay triangulation.
fn delaunay_empty_circle(points: &[DVec2]) -> anyhow::Result<f64> {
    let lo = points.iter().fold(DVec2::INFINITY, |a, p| a.min(*p));
    let hi = points.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
    let inside = |c: DVec2| c.cmpge(lo).all() && c.cmple(hi).all();
    let vertices: Vec<Point2<f64>> = points.iter().map(|p| Point2::new(p.x, p.y)).collect();
    // The hierarchy makes nearest-neighbour queries logarithmic.
    type Hierarchical = DelaunayTriangulation<Point2<f64>, (), (), (), HierarchyHintGenerator<f64>>;
    let t = Hierarchical::bulk_load(vertices)?;
    let point = |p: Point2<f64>| DVec2::new(p.x, p.y);
    let nearest = |c: DVec2| {
        let v = t
            .nearest_neighbor(Point2::new(c.x, c.y))
            .expect("points exist");
        point(v.position()).distance(c)
    };
    let mut best = [lo, hi, DVec2::new(lo.x, hi.y), DVec2::new(hi.x, lo.y)]
        .into_iter()
        .map(nearest)
        .fold(0.0, f64::max);
    for face in t.inner_faces() {
        let (c, r2) = face.circumcircle();
        if inside(point(c)) {
            best = best.max(r2.sqrt());
        }
    }
    // Voronoi edges crossing the box's sides: each Delaunay edge's Voronoi edge
    // runs between the circumcentres of its two triangles (a ray beyond a hull
    // edge), and where it crosses a side the circle through the edge's ends is
    // empty.
    let sides = [
        (lo, DVec2::new(hi.x, lo.y)),
        (DVec2::new(hi.x, lo.y), hi),
        (hi, DVec2::new(lo.x, hi.y)),
        (DVec2::new(lo.x, hi.y), lo),
    ];
    for edge in t.undirected_edges() {
        let e = edge.as_directed();
        let (u, v) = (point(e.from().position()), point(e.to().position()));
        let m = (u + v) / 2.0;
        let dir = (v - u).perp();
        // The Voronoi edge as m + t dir for t in [t0, t1].
        let param = |c: DVec2| (c - m).dot(dir) / dir.length_squared();
        let (left, right) = (e.face().as_inner(), e.rev().face().as_inner());
        let (t0, t1) = match (left, right) {
            (Some(f), Some(g)) => {
                let (a, b) = (
                    param(point(f.circumcircle().0)),
                    param(point(g.circumcircle().0)),
                );
                (a.min(b), a.max(b))
            }
            // A hull edge: the ray from the inner triangle's circumcentre away
            // from that triangle (dir points to the edge's left).
            (Some(f), None) => (f64::NEG_INFINITY, param(point(f.circumcircle().0))),
            (None, Some(g)) => (param(point(g.circumcircle().0)), f64::INFINITY),
            (None, None) => (f64::NEG_INFINITY, f64::INFINITY),
        };
        for (p, q) in sides {
            let d = q - p;
            let denom = d.perp_dot(dir);
            if denom == 0.0 {
                continue;
            }
            // p + s d = m + t dir.
            let w = m - p;
            let s_at = w.perp_dot(dir) / denom;
            let t_at = w.perp_dot(d) / denom;
            if (0.0..=1.0).contains(&s_at) && t_at >= t0 && t_at <= t1 {
                best = best.max((p + d * s_at).distance(u));
            }
        }
    }
    Ok(best)
}

fn main() -> anyhow::Result<()> {
    let ns = env_list("HM_N", &[100, 1000, 10_000, 100_000]);
    let repeats = env_list("HM_REPEATS", &[3])[0].max(1);
    let out_dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("target/homothet");
    std::fs::create_dir_all(&out_dir)?;
    let machine = Machine::from_env()?;
    eprintln!("device: {}", machine.device_name());
    let frame = Frame::pixels(1000, 1000)?;
    let warm = frame.random_points(100, 1).unwrap();
    enclose(
        &Backend::Device(&machine),
        &warm,
        &EncloseOptions::new(Unit::Circle).side(SIZE),
    )?;
    largest_empty(&machine, &warm, &EmptyOptions::new(Unit::Circle).side(SIZE))?;

    let mut table = String::from(
        "| n | pixgeo enclose (ms) | Welzl (ms) | enclose / Welzl | same radius | pixgeo empty (ms) | empty with cones (ms) | Delaunay (spade) (ms) | empty / Delaunay | cones / Delaunay | same radius |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for &n in &ns {
        let sites = frame.random_points(n, n as u64).unwrap();
        let (ours, a) = time(repeats, || {
            Ok(enclose(
                &Backend::Device(&machine),
                &sites,
                &EncloseOptions::new(Unit::Circle).side(SIZE),
            )?)
        })?;
        let (theirs, w) = time(repeats, || Ok(welzl(&sites)))?;
        let same_enclose = (a.exact.scale - w.radius).abs() <= 1e-9 * w.radius;
        let (ours_e, e) = time(repeats, || {
            Ok(largest_empty(
                &machine,
                &sites,
                &EmptyOptions::new(Unit::Circle).side(SIZE),
            )?)
        })?;
        // The thesis's pixel stage, for comparison: the envelope of cones.
        let (cones_e, c) = time(repeats, || {
            Ok(largest_empty(
                &machine,
                &sites,
                &EmptyOptions::new(Unit::Circle)
                    .side(SIZE)
                    .stage(Some(PixelStage::Cones)),
            )?)
        })?;
        let (theirs_e, d) = time(repeats, || delaunay_empty_circle(&sites))?;
        let same_empty = [e.exact.scale, c.exact.scale]
            .iter()
            .all(|r| (r - d).abs() <= 1e-9 * d);
        eprintln!(
            "n = {n:>6}: enclose {ours:.1} ms, Welzl {theirs:.2} ms ({}); empty {ours_e:.1} ms ({:?}), with cones {cones_e:.1} ms, Delaunay {theirs_e:.1} ms ({}); radii {} / {} and {} / {}",
            same_enclose, e.pixel_stage, same_empty, a.exact.scale, w.radius, e.exact.scale, d
        );
        table += &format!(
            "| {n} | {ours:.1} | {theirs:.2} | {:.1}× | {} | {ours_e:.1} | {cones_e:.1} | {theirs_e:.1} | {:.2}× | {:.2}× | {} |\n",
            ours / theirs,
            if same_enclose { "yes" } else { "no" },
            ours_e / theirs_e,
            cones_e / theirs_e,
            if same_empty { "yes" } else { "no" },
        );
    }
    let text = format!(
        "Smallest enclosing and largest empty circle of n uniform random points, {SIZE}² picture, device {}; median of {repeats}.\n\n{table}",
        machine.device_name()
    );
    common::report::write(&out_dir, "homothet", &text, machine.device_name())?;
    println!("{text}");
    Ok(())
}
