//! Computes a small Voronoi diagram through pixgeo's library API and checks two
//! pixels against their nearest sites.

use glam::DVec2;

fn main() -> Result<(), pixgeo::Error> {
    let sites = [DVec2::new(10.0, 20.0), DVec2::new(40.5, 7.0)];
    let diagram = pixgeo::voronoi(&sites, 64, 48)?;
    assert_eq!(diagram.labels[20 * 64 + 10], 0);
    assert_eq!(diagram.labels[7 * 64 + 40], 1);
    println!("pixgeo from a dependent crate: 64x48 diagram of 2 sites, labels checked");
    Ok(())
}
