//! Alpha hulls (thesis ch. 6) on a 512² picture, beside exact CPU methods that
//! make the same mask in the same run:
//!
//! - α < 0: the definition per pixel centre, through a bucket grid: a pixel is
//!   outside when an empty disc of radius r holds it, that is, when the nearest
//!   centre of an empty disc is closer than r. Those centres lie on the circles
//!   of radius r around the sites, at the point nearest the pixel or where two
//!   circles cross.
//! - α > 0: the hull walk's circles (the CPU part pixgeo also runs), every pixel
//!   tested against each.
//!
//! Both CPU methods use every core (rayon). `cargo bench --bench alpha` writes
//! `target/alpha/alpha.md`; `ALPHA_N` sets the site counts, `ALPHA_REPEATS` the
//! repeats (median).

use std::path::PathBuf;

use glam::DVec2;
use pixgeo::{
    algorithms::alpha_hull::{alpha_hull, hull_circles, AlphaHull, AlphaMethod, AlphaOptions},
    geometry::Frame,
    testing::PointGrid,
    Machine,
};
use rayon::prelude::*;

mod common {
    pub mod report;
    pub mod timing;
}
use common::timing::{env_list, time};

const SIZE: u32 = 512;

fn centres(frame: &Frame) -> Vec<DVec2> {
    (0..frame.len())
        .map(|k| {
            let w = frame.width as usize;
            frame.to_world(DVec2::new((k % w) as f64, (k / w) as f64))
        })
        .collect()
}

/// α < 0 by the definition: 1 where no empty disc of radius r holds the pixel.
fn negative_cpu(sites: &[DVec2], r: f64, frame: &Frame) -> Vec<u8> {
    let grid = PointGrid::new(sites);
    let clear = |c: DVec2| {
        grid.around(c, r)
            .all(|i| sites[i as usize].distance(c) >= r * (1.0 - 1e-12))
    };
    // Where two circles cross with no third disc holding the point.
    let vertices: Vec<DVec2> = (0..sites.len())
        .into_par_iter()
        .flat_map_iter(|i| {
            let a = sites[i];
            grid.around(a, 2.0 * r)
                .filter(move |&j| j as usize > i)
                .flat_map(move |j| {
                    let d = sites[j as usize] - a;
                    let l2 = d.length_squared();
                    let h2 = r * r - 0.25 * l2;
                    let (mid, normal) = (a + 0.5 * d, d.perp() / l2.sqrt());
                    (l2 > 0.0 && h2 >= 0.0)
                        .then(|| [mid + normal * h2.sqrt(), mid - normal * h2.sqrt()])
                        .into_iter()
                        .flatten()
                })
                .filter(|&c| clear(c))
                .collect::<Vec<_>>()
        })
        .collect();
    let vertex_grid = PointGrid::new(&vertices);
    centres(frame)
        .par_iter()
        .map(|&x| {
            let holding = grid
                .around(x, r)
                .filter(|&i| sites[i as usize].distance(x) < r);
            let mut nearest = f64::INFINITY;
            let mut any = false;
            for i in holding {
                any = true;
                let s = sites[i as usize];
                let c = s + r * (x - s).try_normalize().unwrap_or(DVec2::X);
                if clear(c) {
                    nearest = nearest.min(c.distance(x));
                }
            }
            if !any {
                return 0; // x itself centres an empty disc
            }
            if !vertices.is_empty() {
                for v in vertex_grid.around(x, r) {
                    nearest = nearest.min(vertices[v as usize].distance(x));
                }
            }
            u8::from(nearest >= r)
        })
        .collect()
}

/// α > 0: inside every circle of the hull walk.
fn positive_cpu(sites: &[DVec2], radius: f64, frame: &Frame) -> anyhow::Result<Vec<u8>> {
    let circles = hull_circles(sites, radius)?;
    Ok(centres(frame)
        .par_iter()
        .map(|&x| {
            u8::from(
                circles
                    .centres
                    .iter()
                    .all(|c| c.distance(x) <= circles.radius),
            )
        })
        .collect())
}

/// Pixels where two masks differ.
fn differ(a: &[u8], b: &[u8]) -> usize {
    a.iter().zip(b).filter(|(x, y)| x != y).count()
}

fn main() -> anyhow::Result<()> {
    let ns = env_list("ALPHA_N", &[100, 1000, 10_000]);
    let repeats = env_list("ALPHA_REPEATS", &[3])[0].max(1);
    let out_dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("target/alpha");
    std::fs::create_dir_all(&out_dir)?;
    let machine = Machine::from_env()?;
    eprintln!("device: {}", machine.device_name());
    let world = Frame::pixels(1000, 1000)?;
    let warm = world.random_points(100, 1).unwrap();
    alpha_hull(&machine, &warm, &AlphaOptions::new(-0.02).side(SIZE))?;
    alpha_hull(
        &machine,
        &warm,
        &AlphaOptions::new(1.0 / 2000.0)
            .method(AlphaMethod::Pixels)
            .side(SIZE),
    )?;

    let mut table = String::from(
        "| n | r = -1/α | pixgeo α < 0 (ms) | CPU definition (ms) | pixgeo / CPU | pixels differing | R = 1/α | pixgeo hull walk (ms) | pixgeo pixels only (ms) | CPU circles (ms) | hull walk / CPU | pixels differing (walk, pixels only) |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for &n in &ns {
        let sites = world.random_points(n, n as u64).unwrap();
        // Empty discs twice the mean spacing across; holding discs half again
        // the smallest enclosing circle.
        let r = (1e6 / n as f64).sqrt();
        let (ours, neg): (f64, AlphaHull) = time(repeats, || {
            Ok(alpha_hull(
                &machine,
                &sites,
                &AlphaOptions::new(-1.0 / r).side(SIZE),
            )?)
        })?;
        let (cpu, neg_cpu) = time(repeats, || Ok(negative_cpu(&sites, r, &neg.frame)))?;
        let neg_diff = differ(&neg.mask(), &neg_cpu);
        let big = 1.5 * hull_circles(&sites, f64::INFINITY)?.mec_radius;
        let (walk, pos) = time(repeats, || {
            Ok(alpha_hull(
                &machine,
                &sites,
                &AlphaOptions::new(1.0 / big).side(SIZE),
            )?)
        })?;
        let (pixels, pix) = time(repeats, || {
            Ok(alpha_hull(
                &machine,
                &sites,
                &AlphaOptions::new(1.0 / big)
                    .method(AlphaMethod::Pixels)
                    .side(SIZE),
            )?)
        })?;
        let (cpu_pos, pos_cpu) = time(repeats, || positive_cpu(&sites, big, &pos.frame))?;
        let pix_cpu = positive_cpu(&sites, big, &pix.frame)?;
        let (walk_diff, pix_diff) = (differ(&pos.mask(), &pos_cpu), differ(&pix.mask(), &pix_cpu));
        eprintln!(
            "n = {n}: alpha < 0 {ours:.1} ms vs CPU {cpu:.1} ms ({neg_diff} differ, {} discs); alpha > 0 walk {walk:.1} ms, pixels {pixels:.1} ms, CPU {cpu_pos:.1} ms ({walk_diff}, {pix_diff} differ)",
            neg.discs
        );
        table += &format!(
            "| {n} | {r:.1} | {ours:.1} | {cpu:.1} | {:.2}× | {neg_diff} | {big:.0} | {walk:.1} | {pixels:.1} | {cpu_pos:.1} | {:.2}× | {walk_diff}, {pix_diff} |\n",
            ours / cpu,
            walk / cpu_pos,
        );
    }
    let text = format!(
        "Alpha hulls of n uniform random points in a 1000² box, {SIZE}² picture, device {}; median of {repeats}.\n\n{table}",
        machine.device_name()
    );
    common::report::write(&out_dir, "alpha", &text, machine.device_name())?;
    println!("{text}");
    Ok(())
}
