//! Delaunay triangulations of n uniform random points, pixgeo's digital way
//! phase by phase, beside Shewchuk's Triangle (PyPI `triangle`, run by
//! `tools/peer_triangle.py`), `spade` and `delaunator` in the same run.
//!
//! `cargo bench --bench delaunay` writes `target/delaunay/delaunay.md`;
//! `DELAUNAY_N` sets the point counts, `DELAUNAY_REPEATS` the repeats
//! (median); `DELAUNAY_MEMORY=1` adds each tool's peak memory for one call,
//! measured in a fresh process of this benchmark. Triangle is skipped with a note if Python cannot import it
//! (`tools/setup --bench` installs it).

use pixgeo::Backend;
use std::{path::PathBuf, process::Command};

use glam::DVec2;
use pixgeo::{
    algorithms::delaunay::{delaunay, Delaunay, DelaunayOptions},
    Machine,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

mod common {
    pub mod points;
    pub mod report;
    pub mod timing;
}
use common::timing::{env_list, time};

fn points(n: usize) -> Vec<DVec2> {
    let mut rng = ChaCha8Rng::seed_from_u64(n as u64);
    (0..n).map(|_| DVec2::new(rng.gen(), rng.gen())).collect()
}

/// Triangle's median time and triangle count per file, if Python has it.
fn triangle_peer(repeats: usize, files: &[PathBuf]) -> Option<serde_json::Value> {
    let script =
        PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("tools/peer_triangle.py");
    let output = Command::new("python3")
        .arg(script)
        .arg(repeats.to_string())
        .args(files)
        .output()
        .ok()?;
    if !output.status.success() {
        eprintln!(
            "Triangle skipped: {}",
            String::from_utf8_lossy(&output.stderr)
                .lines()
                .last()
                .unwrap_or("")
        );
        return None;
    }
    serde_json::from_slice(&output.stdout).ok()
}

/// The tools whose peak memory is measured.
const TOOLS: [&str; 3] = ["pixgeo", "spade", "delaunator"];

/// Triangulates `pts` with `tool` once; returns the triangles.
fn run_tool(tool: &str, machine: &Machine, pts: &[DVec2]) -> anyhow::Result<usize> {
    Ok(match tool {
        "pixgeo" => delaunay(&Backend::Device(machine), pts, &DelaunayOptions::default())?
            .triangles
            .len(),
        "spade" => {
            use spade::{DelaunayTriangulation, Point2, Triangulation};
            let t: DelaunayTriangulation<Point2<f64>> = DelaunayTriangulation::bulk_load(
                pts.iter().map(|p| Point2::new(p.x, p.y)).collect(),
            )?;
            t.num_inner_faces()
        }
        _ => {
            let input: Vec<delaunator::Point> = pts
                .iter()
                .map(|p| delaunator::Point { x: p.x, y: p.y })
                .collect();
            delaunator::triangulate(&input).len()
        }
    })
}

/// A line of /proc/self/status, in MiB.
fn status_mib(key: &str) -> anyhow::Result<f64> {
    let status = std::fs::read_to_string("/proc/self/status")?;
    let line = status
        .lines()
        .find(|l| l.starts_with(key))
        .ok_or_else(|| anyhow::anyhow!("no {key} in /proc/self/status"))?;
    let kib: f64 = line.split_whitespace().nth(1).unwrap_or("").parse()?;
    Ok(kib / 1024.0)
}

/// In a child (`DELAUNAY_PEAK=tool,n`): one call's peak memory beyond what
/// the process held before it, once the points are made and the tool has run
/// on 1000 of them; printed in MiB.
fn peak_child(spec: &str) -> anyhow::Result<()> {
    let (tool, n) = spec
        .split_once(',')
        .ok_or_else(|| anyhow::anyhow!("DELAUNAY_PEAK={spec}: give TOOL,N"))?;
    let pts = points(n.parse()?);
    let machine = Machine::from_env()?;
    run_tool(tool, &machine, &pts[..1000])?;
    let before = status_mib("VmRSS")?;
    std::fs::write("/proc/self/clear_refs", "5")?;
    run_tool(tool, &machine, &pts)?;
    println!("{}", status_mib("VmHWM")? - before);
    Ok(())
}

/// Each tool's peak memory for `n` points, from a fresh process each.
fn peaks(n: usize) -> anyhow::Result<Vec<f64>> {
    TOOLS
        .iter()
        .map(|tool| {
            let out = Command::new(std::env::current_exe()?)
                .env("DELAUNAY_PEAK", format!("{tool},{n}"))
                .output()?;
            anyhow::ensure!(
                out.status.success(),
                "{tool}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            Ok(String::from_utf8_lossy(&out.stdout).trim().parse()?)
        })
        .collect()
}

fn main() -> anyhow::Result<()> {
    if let Ok(spec) = std::env::var("DELAUNAY_PEAK") {
        return peak_child(&spec);
    }
    let memory = std::env::var("DELAUNAY_MEMORY").is_ok_and(|v| v == "1");
    let ns = env_list("DELAUNAY_N", &[10_000, 100_000, 1_000_000]);
    let repeats = env_list("DELAUNAY_REPEATS", &[3])[0].max(1);
    let out_dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("target/delaunay");
    std::fs::create_dir_all(&out_dir)?;
    let machine = Machine::from_env()?;
    eprintln!("device: {}", machine.device_name());
    delaunay(
        &Backend::Device(&machine),
        &points(1000),
        &DelaunayOptions::default(),
    )?;

    let files: Vec<PathBuf> = ns
        .iter()
        .map(|&n| {
            let path = out_dir.join(format!("points_{n}.npy"));
            common::points::write_npy(&path, &points(n))?;
            Ok(path)
        })
        .collect::<anyhow::Result<_>>()?;
    let peer = triangle_peer(repeats, &files);

    let mut table = String::from(
        "| n | grid | pixgeo (ms) | colouring | repair | dualization | shifting | insertion | flips | Triangle (ms) | spade (ms) | delaunator (ms) | Triangle / pixgeo | spade / pixgeo | delaunator / pixgeo |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut memory_table = String::from(
        "| n | pixgeo peak (MiB) | spade peak (MiB) | delaunator peak (MiB) | pixgeo / smallest peer |\n|---|---|---|---|---|\n",
    );
    let mut fixes = String::from(
        "| n | seeds | debris recoloured | hull flips | seeds moved | seeds taken out | points inserted | insertion flips | Lawson flips | triangles |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (&n, file) in ns.iter().zip(&files) {
        let pts = points(n);
        let (ours, result): (f64, Delaunay) = time(repeats, || {
            Ok(delaunay(
                &Backend::Device(&machine),
                &pts,
                &DelaunayOptions::default(),
            )?)
        })?;
        let (spade_ms, spade_count) = time(repeats, || run_tool("spade", &machine, &pts))?;
        let (delaunator_ms, delaunator_count) =
            time(repeats, || run_tool("delaunator", &machine, &pts))?;
        let (triangle_ms, triangle_count) = peer
            .as_ref()
            .and_then(|v| v.get(file.to_str()?))
            .map_or((f64::NAN, 0), |v| {
                (
                    v[0].as_f64().unwrap_or(f64::NAN),
                    v[1].as_u64().unwrap_or(0) as usize,
                )
            });
        let s = &result.stats;
        let f = &s.flooding;
        eprintln!(
            "n = {n}: pixgeo {ours:.1} ms ({} triangles), Triangle {triangle_ms:.1} ({triangle_count}), spade {spade_ms:.1} ({spade_count}), delaunator {delaunator_ms:.1} ({delaunator_count}); {s:?}",
            result.triangles.len()
        );
        let fmt = |x: f64| {
            if x.is_nan() {
                "–".to_string()
            } else {
                format!("{x:.1}")
            }
        };
        table += &format!(
            "| {n} | {}×{} | {ours:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {} | {spade_ms:.1} | {delaunator_ms:.1} | {} | {:.2}× | {:.2}× |\n",
            s.width,
            s.height,
            f.colour_ms,
            f.debris_ms + f.repair_ms,
            s.dualize_ms,
            s.shift_ms,
            s.insert_ms,
            s.flip_ms,
            fmt(triangle_ms),
            if triangle_ms.is_nan() { "–".into() } else { format!("{:.2}×", triangle_ms / ours) },
            spade_ms / ours,
            delaunator_ms / ours,
        );
        if memory {
            let [mine, spade, delaunator]: [f64; 3] = peaks(n)?
                .try_into()
                .map_err(|_| anyhow::anyhow!("three peaks"))?;
            memory_table += &format!(
                "| {n} | {mine:.0} | {spade:.0} | {delaunator:.0} | {:.2}× |\n",
                mine / spade.min(delaunator)
            );
        }
        fixes += &format!(
            "| {n} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            s.seeds,
            f.recoloured,
            s.hull_flips,
            s.moved,
            s.taken_out,
            s.inserted,
            s.insertion_flips,
            s.delaunay_flips,
            result.triangles.len(),
        );
    }
    let mut text = format!(
        "Delaunay triangulations of n uniform random points in the unit square, device {}; median of {repeats}. Phases in ms; the grid is pixgeo's default (about one pixel per point). Ratios are the peer's time over pixgeo's: below 1 the peer is faster. pixgeo runs on the device and rayon's threads; the peers on one thread.\n\n{table}\nWhat each phase had to fix:\n\n{fixes}",
        machine.device_name()
    );
    if memory {
        text += &format!(
            "\nPeak memory of one call beyond the points, each in a fresh process:\n\n{memory_table}"
        );
    }
    common::report::write(&out_dir, "delaunay", &text, machine.device_name())?;
    println!("{text}");
    Ok(())
}
