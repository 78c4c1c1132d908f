//! The nearest shop for every pixel of a town: the shops of
//! `examples/data/shops.csv`, their Voronoi diagram on a 256 x 256 picture of
//! the town's bounding box, each shop's share of the town, and the place
//! farthest from every shop.
//!
//!     cargo run --example shops
#![allow(
    clippy::disallowed_macros,
    clippy::disallowed_methods,
    reason = "the rule on allocations (clippy.toml) binds the library, not its users"
)]

use glam::DVec2;
use pixgeo::{
    algorithms::voronoi::{voronoi, VoronoiOptions},
    geometry::Frame,
    with_default_machine, Backend,
};
use pixgeo_io::sites::read_sites;

fn main() -> Result<(), pixgeo::Error> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/shops.csv");
    let shops = read_sites(path.as_ref())?;
    let lo = shops.iter().fold(DVec2::INFINITY, |a, p| a.min(*p));
    let hi = shops.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
    let frame = Frame::fitting(256, lo, hi)?;
    let diagram = with_default_machine(|m| {
        voronoi(&Backend::Device(m), &shops, &VoronoiOptions::exact(frame))
    })?;

    // Each shop's share: the pixels nearest to it.
    let mut share = vec![0usize; shops.len()];
    for &label in &diagram.labels {
        share[label as usize] += 1;
    }
    let pixels = diagram.labels.len() as f64;
    for (i, (shop, n)) in shops.iter().zip(&share).enumerate() {
        println!(
            "shop {i} at ({:.1}, {:.1}): {:.1}% of the town",
            shop.x,
            shop.y,
            100.0 * *n as f64 / pixels
        );
    }
    // The pixel farthest from every shop, mapped back to the town's coordinates.
    let (far, _) = diagram
        .distances
        .iter()
        .enumerate()
        .fold(
            (0, f32::MIN),
            |best, (k, &d)| if d > best.1 { (k, d) } else { best },
        );
    let (i, j) = (
        (far as u32 % frame.width) as f64,
        (far as u32 / frame.width) as f64,
    );
    let at = diagram.frame.to_world(DVec2::new(i, j));
    println!("farthest from every shop: ({:.1}, {:.1})", at.x, at.y);

    assert_eq!(share.iter().sum::<usize>(), diagram.labels.len());
    Ok(())
}
