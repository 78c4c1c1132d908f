//! Smallest and largest triangles and quadrangles (thesis ch. 7) on pixgeo's
//! default picture for n sites (`AREA_SIZE` sets another), beside the exact CPU
//! methods in the same run: exhaustive search (a tight f64 loop, as a user would
//! write it) and pixgeo's exact O(n² log n) rotational sweep.
//!
//! `cargo bench --bench area` writes `target/area/area.md`. `AREA_N=100,500`
//! sets the site counts, `AREA_REPEATS` the repeats (median).

use pixgeo::geometry::predicates::convex_hull;
use std::path::PathBuf;

use glam::DVec2;
use pixgeo::{
    algorithms::area::{
        default_side, extremal_quadrangle, extremal_triangle, AreaOptions, Extreme,
    },
    geometry::Frame,
    Backend, Machine,
};

/// The picture side: `AREA_SIZE`, else pixgeo's default for n sites.
mod common {
    pub mod report;
    pub mod timing;
}
use common::timing::{env_list, time};

fn size(n: usize) -> u32 {
    env_list("AREA_SIZE", &[default_side(n) as usize])[0] as u32
}

fn cross(o: DVec2, a: DVec2, b: DVec2) -> f64 {
    (a - o).perp_dot(b - o)
}

/// Every triple, the extreme |cross| / 2.
fn exhaustive_triangle(p: &[DVec2], largest: bool) -> f64 {
    let mut best = if largest { 0.0 } else { f64::INFINITY };
    for i in 0..p.len() {
        for j in i + 1..p.len() {
            let (a, d) = (p[i], p[j] - p[i]);
            for s in &p[j + 1..] {
                let area = d.perp_dot(*s - a).abs();
                best = if largest {
                    best.max(area)
                } else {
                    best.min(area)
                };
            }
        }
    }
    0.5 * best
}

/// Every diagonal with its nearest (farthest) sites on both sides.
fn exhaustive_quadrangle(p: &[DVec2], largest: bool) -> f64 {
    let pick = |a: f64, b: f64| if largest { a.max(b) } else { a.min(b) };
    let none = if largest {
        f64::NEG_INFINITY
    } else {
        f64::INFINITY
    };
    let mut best = none;
    for i in 0..p.len() {
        for j in i + 1..p.len() {
            let (mut left, mut right) = (none, none);
            for s in p {
                let c = cross(p[i], p[j], *s);
                if c > 0.0 {
                    left = pick(left, c);
                } else if c < 0.0 {
                    right = pick(right, -c);
                }
            }
            if left.is_finite() && right.is_finite() {
                best = pick(best, left + right);
            }
        }
    }
    0.5 * best
}

fn same(a: f64, b: f64) -> &'static str {
    if (a - b).abs() <= 1e-9 * (1.0 + b.abs()) {
        "yes"
    } else {
        "no"
    }
}

fn main() -> anyhow::Result<()> {
    let ns = env_list("AREA_N", &[100, 200, 500, 1000]);
    let repeats = env_list("AREA_REPEATS", &[3])[0].max(1);
    let out_dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("target/area");
    std::fs::create_dir_all(&out_dir)?;
    let machine = Machine::from_env()?;
    eprintln!("device: {}", machine.device_name());
    let frame = Frame::pixels(1000, 1000)?;
    let warm = frame.random_points(50, 1).unwrap();
    for extreme in [Extreme::Smallest, Extreme::Largest] {
        extremal_triangle(
            &Backend::Device(&machine),
            &warm,
            &AreaOptions::new(extreme).side(Some(size(50))),
        )?;
        extremal_quadrangle(
            &Backend::Device(&machine),
            &warm,
            &AreaOptions::new(extreme).side(Some(size(50))),
        )?;
    }

    let mut smallest = String::from(
        "| n | picture | pixgeo (ms) | prepare / draw / reduce / exact (ms) | roofs | exhaustive (ms) | sweep O(n² log n) (ms) | exhaustive / pixgeo | pixgeo / sweep | same area |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut largest = String::from(
        "| n | hull | pixgeo (ms) | exhaustive (ms) | hull + exhaustive (ms) | exhaustive / pixgeo | pixgeo / hull + exhaustive | same area |\n|---|---|---|---|---|---|---|---|\n",
    );
    let mut quadrangles = String::from(
        "| n | roofs smallest (ms) | draw (ms) | sweep (ms) | exhaustive O(n³) (ms) | exhaustive / roofs | roofs / sweep | same area | roofs largest (ms) | exhaustive O(n³) (ms) | exhaustive / roofs | same area |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for &n in &ns {
        let sites = frame.random_points(n, n as u64).unwrap();
        let (ours, a) = time(repeats, || {
            Ok(extremal_triangle(
                &Backend::Device(&machine),
                &sites,
                &AreaOptions::new(Extreme::Smallest).side(Some(size(n))),
            )?)
        })?;
        let (brute, b) = time(repeats, || Ok(exhaustive_triangle(&sites, false)))?;
        let (sweep, s) = time(repeats, || {
            Ok(
                extremal_triangle(&Backend::Cpu, &sites, &AreaOptions::new(Extreme::Smallest))?
                    .area,
            )
        })?;
        eprintln!(
            "n = {n}: smallest triangle {ours:.1} ms ({:.1}/{:.1}/{:.1}/{:.1}), exhaustive {brute:.1} ms, sweep {sweep:.1} ms; areas {} {b} {s}",
            a.prepare_ms, a.draw_ms, a.reduce_ms, a.exact_ms, a.area
        );
        smallest += &format!(
            "| {n} | {}² | {ours:.1} | {:.1} / {:.1} / {:.1} / {:.1} | {} | {brute:.1} | {sweep:.1} | {:.2}× | {:.2}× | {} |\n",
            size(n),
            a.prepare_ms,
            a.draw_ms,
            a.reduce_ms,
            a.exact_ms,
            a.roofs,
            brute / ours,
            ours / sweep,
            if same(a.area, b) == "yes" && same(s, b) == "yes" { "yes" } else { "no" },
        );

        let (ours, a) = time(repeats, || {
            Ok(extremal_triangle(
                &Backend::Device(&machine),
                &sites,
                &AreaOptions::new(Extreme::Largest).side(Some(size(n))),
            )?)
        })?;
        let (brute, b) = time(repeats, || Ok(exhaustive_triangle(&sites, true)))?;
        let hull = convex_hull(&sites);
        let (on_hull, c) = time(repeats, || {
            let h = convex_hull(&sites);
            let points: Vec<DVec2> = h.iter().map(|&i| sites[i as usize]).collect();
            Ok(exhaustive_triangle(&points, true))
        })?;
        eprintln!("n = {n}: largest triangle {ours:.1} ms, exhaustive {brute:.1} ms, hull + exhaustive {on_hull:.2} ms; areas {} {b} {c}", a.area);
        largest += &format!(
            "| {n} | {} | {ours:.1} | {brute:.1} | {on_hull:.2} | {:.2}× | {:.1}× | {} |\n",
            hull.len(),
            brute / ours,
            ours / on_hull,
            if same(a.area, b) == "yes" && same(c, b) == "yes" {
                "yes"
            } else {
                "no"
            },
        );

        if n <= 500 {
            let (ours, a) = time(repeats, || {
                Ok(extremal_quadrangle(
                    &Backend::Device(&machine),
                    &sites,
                    &AreaOptions::new(Extreme::Smallest).side(Some(size(n))),
                )?)
            })?;
            let (brute, b) = time(repeats, || Ok(exhaustive_quadrangle(&sites, false)))?;
            let (sweep, s) = time(repeats, || {
                Ok(extremal_quadrangle(
                    &Backend::Cpu,
                    &sites,
                    &AreaOptions::new(Extreme::Smallest),
                )?
                .area)
            })?;
            let (ours_max, c) = time(repeats, || {
                Ok(extremal_quadrangle(
                    &Backend::Device(&machine),
                    &sites,
                    &AreaOptions::new(Extreme::Largest).side(Some(size(n))),
                )?)
            })?;
            let (brute_max, d) = time(repeats, || Ok(exhaustive_quadrangle(&sites, true)))?;
            eprintln!(
                "n = {n}: smallest quadrangle {ours:.1} ms, exhaustive {brute:.1} ms; areas {} {b}; largest {ours_max:.1} ms, exhaustive {brute_max:.1} ms; areas {} {d}",
                a.area, c.area
            );
            quadrangles += &format!(
                "| {n} | {ours:.1} | {:.1} | {sweep:.1} | {brute:.1} | {:.2}× | {:.0}× | {} | {ours_max:.1} | {brute_max:.1} | {:.2}× | {} |\n",
                a.draw_ms,
                brute / ours,
                ours / sweep,
                if same(a.area, b) == "yes" && same(s, b) == "yes" { "yes" } else { "no" },
                brute_max / ours_max,
                same(c.area, d),
            );
        }
    }
    let text = format!(
        "Extremal triangles and quadrangles of n uniform random points, device {}; median of {repeats}.\n\n\
         Smallest triangle:\n\n{smallest}\nLargest triangle:\n\n{largest}\nQuadrangles:\n\n{quadrangles}",
        machine.device_name()
    );
    common::report::write(&out_dir, "area", &text, machine.device_name())?;
    println!("{text}");
    Ok(())
}
