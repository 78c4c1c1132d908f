//! Thesis Fig. 3.36 on this machine: the order-10 distance diagram (the 10 nearest
//! sites of every pixel) of n uniform random sites on a 1024² picture, with and
//! without the quadtree of Theorem 3.3 and with per-site radii, beside one ordinary
//! diagram of the same sites; and `hausdorff` beside SciPy's
//! `directed_hausdorff` on the same sets.
//!
//! `cargo bench --bench higher_order` (after `tools/setup --bench`) writes
//! `target/higher_order/higher_order.md` and `fig336.png`. `HO_N=100,1000` limits
//! the site counts, `HO_REPEATS` sets the repeats (median reported),
//! `HO_HAUSDORFF=10000,100000` the Hausdorff set sizes.

use pixgeo::Backend;
use std::{path::PathBuf, process::Command, time::Instant};

use common::plot::{Series, PALETTE};
use pixgeo::{
    algorithms::{
        distances::{hausdorff, HausdorffOptions},
        higher_order::{k_nearest, k_nearest_peeled, KNearestOptions},
        voronoi::{voronoi, Speedup, VoronoiOptions},
    },
    geometry::Frame,
    Machine,
};
use plotters::style::RGBColor;

mod common {
    pub mod plot;
    pub mod points;
    pub mod report;
}

const SIZE: u32 = 1024;
const LEVELS: u32 = 10;
/// Picture-wide cones for ten levels cost n full pictures of atomic insertions.
const NO_SPEEDUP_MAX_N: usize = 500;

fn env_list(name: &str, default: &[usize]) -> Vec<usize> {
    std::env::var(name)
        .ok()
        .map(|s| s.split(',').filter_map(|t| t.trim().parse().ok()).collect())
        .unwrap_or_else(|| default.to_vec())
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn time(repeats: usize, mut f: impl FnMut() -> anyhow::Result<()>) -> anyhow::Result<f64> {
    let mut v = Vec::new();
    for _ in 0..repeats {
        let t = Instant::now();
        f()?;
        v.push(t.elapsed().as_secs_f64() * 1e3);
    }
    Ok(median(v))
}

fn main() -> anyhow::Result<()> {
    let ns = env_list("HO_N", &[100, 500, 1000, 2000, 4000, 8000, 16000]);
    let sets = env_list("HO_HAUSDORFF", &[10_000, 100_000]);
    let repeats = env_list("HO_REPEATS", &[3])[0].max(1);
    let out_dir =
        PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("target/higher_order");
    std::fs::create_dir_all(&out_dir)?;
    let machine = Machine::from_env()?;
    let frame = Frame::pixels(SIZE, SIZE)?;
    eprintln!("device: {}", machine.device_name());

    let speedups = [
        ("local radii", Speedup::Local),
        ("quadtree (Thm. 3.3)", Speedup::Quadtree),
        ("no speedup", Speedup::None),
    ];
    let warm = frame.random_points(100, 0).unwrap();
    voronoi(
        &Backend::Device(&machine),
        &warm,
        &VoronoiOptions::exact(frame),
    )?;
    let order = |speedup| KNearestOptions::exact(frame, LEVELS).speedup(speedup);
    k_nearest(&Backend::Device(&machine), &warm, &order(Speedup::Local))?;

    // rows[n] = (times per speedup, one diagram)
    let mut rows: Vec<(Vec<Option<f64>>, f64)> = Vec::new();
    for &n in &ns {
        let sites = frame.random_points(n, n as u64).unwrap();
        let mut times = Vec::new();
        for (name, speedup) in speedups {
            if speedup == Speedup::None && n > NO_SPEEDUP_MAX_N {
                times.push(None);
                continue;
            }
            let t = time(repeats, || {
                k_nearest(&Backend::Device(&machine), &sites, &order(speedup))?;
                Ok(())
            })?;
            eprintln!("n = {n:>5}  order {LEVELS}, {name:<22} {t:>9.1} ms");
            times.push(Some(t));
        }
        let peeled = time(repeats, || {
            k_nearest_peeled(&machine, &sites, &order(Speedup::Local))?;
            Ok(())
        })?;
        eprintln!("n = {n:>5}  order {LEVELS}, thesis peeling         {peeled:>9.1} ms");
        times.push(Some(peeled));
        let on_cpu = time(repeats, || {
            k_nearest(
                &Backend::Cpu,
                &sites,
                &KNearestOptions::exact(frame, LEVELS),
            )?;
            Ok(())
        })?;
        eprintln!("n = {n:>5}  order {LEVELS}, CPU pixel algorithm    {on_cpu:>9.1} ms");
        times.push(Some(on_cpu));
        let opts = VoronoiOptions::exact(frame).distances(false);
        let one = time(repeats, || {
            voronoi(&Backend::Device(&machine), &sites, &opts)?;
            Ok(())
        })?;
        eprintln!("n = {n:>5}  one diagram                    {one:>9.1} ms");
        rows.push((times, one));
    }

    // Hausdorff: pixgeo and SciPy on the same sets.
    let mut files = Vec::new();
    let mut ours = Vec::new();
    for &m in &sets {
        let box_frame = Frame::pixels(1000, 1000)?;
        let a = box_frame.random_points(m, 2 * m as u64).unwrap();
        let b = box_frame.random_points(m, 2 * m as u64 + 1).unwrap();
        for (name, set) in [("a", &a), ("b", &b)] {
            let file = out_dir.join(format!("hausdorff_{m}_{name}.npy"));
            common::points::write_npy(&file, set)?;
            files.push(file);
        }
        let mut distance = 0.0;
        let t = time(repeats, || {
            distance = hausdorff(
                &Backend::Device(&machine),
                &a,
                &b,
                &HausdorffOptions::default(),
            )?
            .distance;
            Ok(())
        })?;
        eprintln!("hausdorff {m:>7} points: {t:.1} ms, distance {distance}");
        ours.push((t, distance));
    }
    let script =
        PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("tools/peer_hausdorff.py");
    let peer = Command::new("python3")
        .arg(&script)
        .arg(repeats.to_string())
        .args(&files)
        .output();
    let scipy: Vec<Option<(f64, f64)>> = match peer {
        Ok(out) if out.status.success() => {
            let v: serde_json::Value = serde_json::from_slice(&out.stdout)?;
            files
                .iter()
                .step_by(2)
                .map(|f| {
                    let e = &v[f.to_string_lossy().as_ref()];
                    Some((e[0].as_f64()?, e[1].as_f64()?))
                })
                .collect()
        }
        other => {
            eprintln!("scipy peer failed (run tools/setup --bench): {other:?}");
            vec![None; sets.len()]
        }
    };

    let mut md = format!(
        "Order-{LEVELS} distance diagram (the {LEVELS} nearest sites of every pixel) of n uniform \
         random sites, {SIZE}×{SIZE} pixels, on {} (median of {repeats}; milliseconds, whole \
         call), beside one ordinary Voronoi diagram of the same sites.\n\n| n |",
        machine.device_name()
    );
    let columns: Vec<String> = speedups
        .iter()
        .map(|(name, _)| name.to_string())
        .chain([
            "thesis peeling (local radii)".into(),
            "CPU pixel algorithm (§3.12.2)".into(),
        ])
        .collect();
    for name in &columns {
        md.push_str(&format!(" order {LEVELS}, {name} |"));
    }
    md.push_str(" one diagram | order 10 (local) / one diagram |\n|");
    md.push_str(&"---|".repeat(columns.len() + 3));
    md.push('\n');
    for (n, (times, one)) in ns.iter().zip(&rows) {
        md.push_str(&format!("| {n} |"));
        for t in times {
            md.push_str(&t.map_or(" — |".into(), |t| format!(" {t:.1} |")));
        }
        let ratio = times[0].map_or("—".into(), |t| format!("{:.1}×", t / one));
        md.push_str(&format!(" {one:.1} | {ratio} |\n"));
    }
    md.push_str(&format!(
        "\nThe thesis: {LEVELS} levels cost 2·{LEVELS} ordinary diagrams (two passes per level).\n\n\
         Hausdorff distance (both directions) between two sets of m uniform random points:\n\n\
         | m | pixgeo hausdorff (ms) | scipy directed_hausdorff ×2 (ms) | scipy / pixgeo | same distance |\n\
         |---|---|---|---|---|\n"
    ));
    for ((m, (t, d)), peer) in sets.iter().zip(&ours).zip(&scipy) {
        match peer {
            Some((ts, ds)) => md.push_str(&format!(
                "| {m} | {t:.1} | {ts:.1} | {:.1}× | {} |\n",
                ts / t,
                if (ds - d).abs() <= 1e-9 * d.max(1.0) {
                    "yes"
                } else {
                    "NO"
                }
            )),
            None => md.push_str(&format!("| {m} | {t:.1} | — | — | — |\n")),
        }
    }
    common::report::write(&out_dir, "higher_order", &md, machine.device_name())?;
    println!("{md}");

    let mut series: Vec<Series> = columns
        .iter()
        .enumerate()
        .map(|(c, name)| Series {
            name: format!("order {LEVELS}, {name}"),
            points: ns
                .iter()
                .zip(&rows)
                .filter_map(|(n, r)| r.0[c].map(|t| (*n as f64, t)))
                .collect(),
            color: PALETTE[c],
            peer: false,
        })
        .collect();
    series.push(Series {
        name: "one ordinary diagram".into(),
        points: ns
            .iter()
            .zip(&rows)
            .map(|(n, r)| (*n as f64, r.1))
            .collect(),
        color: RGBColor(120, 120, 120),
        peer: true,
    });
    common::plot::plot(
        &out_dir.join("fig336.png"),
        &format!("Order-{LEVELS} distance diagram, {SIZE}² pixels (cf. thesis Fig. 3.36)"),
        "number of sites n (log scale)",
        &series,
    )?;
    Ok(())
}
