//! Shapes of a point set, one call each: its Delaunay triangulation, diameter,
//! smallest enclosing circle, largest empty circle, convex hull and extremal
//! triangles, with a check of each against the definition.
//!
//!     cargo run --example shapes
#![allow(
    clippy::disallowed_macros,
    clippy::disallowed_methods,
    reason = "the rule on allocations (clippy.toml) binds the library, not its users"
)]

use glam::DVec2;
use pixgeo::algorithms::area::Extreme;

fn main() -> Result<(), pixgeo::Error> {
    // A fixed pseudo-random cloud, so that runs repeat.
    let mut state = 7u64;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let points: Vec<DVec2> = (0..200)
        .map(|_| DVec2::new(next(), next()) * 100.0)
        .collect();

    let mesh = pixgeo::delaunay(&points)?;
    println!("Delaunay: {} triangles", mesh.triangles.len());

    let d = pixgeo::diameter(&points)?;
    let brute = points
        .iter()
        .flat_map(|p| points.iter().map(move |q| p.distance(*q)))
        .fold(0.0, f64::max);
    println!(
        "diameter: {:.4} between points {} and {}",
        d.pair.distance, d.pair.from, d.pair.to
    );
    assert_eq!(d.pair.distance, brute);

    let circle = pixgeo::enclosing_circle(&points)?;
    let c = DVec2::from(circle.exact.centre);
    println!(
        "enclosing circle: centre ({:.3}, {:.3}), radius {:.4}",
        c.x, c.y, circle.exact.scale
    );
    assert!(points
        .iter()
        .all(|p| p.distance(c) <= circle.exact.scale * (1.0 + 1e-12)));

    let empty = pixgeo::largest_empty_circle(&points)?;
    let e = DVec2::from(empty.exact.centre);
    println!(
        "largest empty circle: centre ({:.3}, {:.3}), radius {:.4}",
        e.x, e.y, empty.exact.scale
    );
    assert!(points
        .iter()
        .all(|p| p.distance(e) >= empty.exact.scale * (1.0 - 1e-12)));

    let hull = pixgeo::alpha_hull(&points, 0.0)?;
    println!("convex hull: {} points", hull.boundary_sites.len());

    for extreme in [Extreme::Smallest, Extreme::Largest] {
        let t = pixgeo::extremal_triangle(&points, extreme)?;
        println!(
            "{extreme:?} triangle: points {:?}, area {:.6}",
            t.sites, t.area
        );
    }
    Ok(())
}
