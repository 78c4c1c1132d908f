//! Thesis Fig. 3.13 on this machine: time to compute the Voronoi diagram of n
//! uniform random sites on a 1024² picture, with and without the speedups, in both
//! accuracy modes; beside it, on the same sites in the same run, SciPy's exact
//! Euclidean distance transform with indices (the peer a user would pick) and an
//! exact CPU nearest-site search over a bucket grid.
//!
//! `cargo bench --bench fig313` (after `tools/setup --bench`) writes
//! `target/fig313/fig313.md` and `target/fig313/fig313.png`.
//! `FIG313_N=100,1000` limits the site counts, `FIG313_REPEATS` sets the repeats
//! (median reported).

use std::{path::PathBuf, process::Command, time::Instant};

use common::plot::{Series, PALETTE};
use glam::DVec2;
use pixgeo::{
    algorithms::voronoi::{voronoi, Accuracy, Speedup, VoronoiOptions},
    geometry::Frame,
    Backend, Machine,
};
use pixgeo_reference::voronoi::nearest_sites_grid;
use plotters::style::RGBColor;

mod common {
    pub mod plot;
    pub mod points;
    pub mod report;
}

const SIZE: u32 = 1024;
/// Picture-wide cones cost n full pictures of fragments; beyond this they take
/// tens of seconds per run and add nothing the slope does not already show.
const NO_SPEEDUP_MAX_N: usize = 2000;

struct Config {
    name: &'static str,
    accuracy: Accuracy,
    speedup: Speedup,
}

const CONFIGS: [Config; 6] = [
    Config {
        name: "exact, local radii (default)",
        accuracy: Accuracy::Exact,
        speedup: Speedup::Local,
    },
    Config {
        name: "exact, quadtree",
        accuracy: Accuracy::Exact,
        speedup: Speedup::Quadtree,
    },
    Config {
        name: "exact, no speedup",
        accuracy: Accuracy::Exact,
        speedup: Speedup::None,
    },
    Config {
        name: "fan ε=1, local radii",
        accuracy: Accuracy::FAN,
        speedup: Speedup::Local,
    },
    Config {
        name: "fan ε=1, quadtree",
        accuracy: Accuracy::FAN,
        speedup: Speedup::Quadtree,
    },
    Config {
        name: "fan ε=1, no speedup",
        accuracy: Accuracy::FAN,
        speedup: Speedup::None,
    },
];

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> anyhow::Result<()> {
    let ns: Vec<usize> = std::env::var("FIG313_N")
        .ok()
        .map(|s| s.split(',').filter_map(|t| t.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![100, 500, 1000, 2000, 4000, 8000, 16000]);
    let repeats: usize = std::env::var("FIG313_REPEATS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(5);
    let out_dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("target/fig313");
    std::fs::create_dir_all(&out_dir)?;
    let machine = Machine::from_env()?;
    let frame = Frame::pixels(SIZE, SIZE)?;
    eprintln!("device: {}", machine.device_name());

    // Warm up every pipeline: lavapipe compiles shaders on first draw.
    let warm = frame.random_points(100, 0).unwrap();
    for c in &CONFIGS {
        voronoi(
            &Backend::Device(&machine),
            &warm,
            &VoronoiOptions::exact(frame)
                .accuracy(c.accuracy)
                .speedup(c.speedup)
                .distances(false),
        )?;
    }

    // rows[n][config] = (total ms, render ms)
    let mut rows: Vec<Vec<Option<(f64, f64)>>> = Vec::new();
    let mut cpu_ms = Vec::new();
    let mut site_files = Vec::new();
    for &n in &ns {
        let sites = frame.random_points(n, n as u64).unwrap();
        let file = out_dir.join(format!("sites_{n}.npy"));
        common::points::write_npy(&file, &sites)?;
        site_files.push(file);
        let mut row = Vec::new();
        for c in &CONFIGS {
            if c.speedup == Speedup::None && n > NO_SPEEDUP_MAX_N {
                row.push(None);
                continue;
            }
            // Labels only, like the peers: the label map is what they compute.
            let opts = VoronoiOptions::exact(frame)
                .accuracy(c.accuracy)
                .speedup(c.speedup)
                .distances(false);
            let mut total = Vec::new();
            let mut render = Vec::new();
            let reps = if c.speedup == Speedup::None {
                repeats.min(3)
            } else {
                repeats
            };
            for _ in 0..reps {
                let t = Instant::now();
                let d = voronoi(&Backend::Device(&machine), &sites, &opts)?;
                total.push(t.elapsed().as_secs_f64() * 1e3);
                render.push(d.stats.render_ms);
            }
            let cell = (median(total), median(render));
            eprintln!(
                "n = {n:>5}  {:<30} total {:>8.1} ms  render {:>8.1} ms",
                c.name, cell.0, cell.1
            );
            row.push(Some(cell));
        }
        rows.push(row);
        let pixels: Vec<DVec2> = sites.iter().map(|p| frame.to_pixel(*p)).collect();
        let cpu = median(
            (0..repeats)
                .map(|_| {
                    let t = Instant::now();
                    std::hint::black_box(nearest_sites_grid(&pixels, &frame));
                    t.elapsed().as_secs_f64() * 1e3
                })
                .collect(),
        );
        eprintln!("n = {n:>5}  exact CPU bucket search        {cpu:>8.1} ms");
        cpu_ms.push(cpu);
    }

    let script =
        PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("tools/peer_edt.py");
    let peer = Command::new("python3")
        .arg(&script)
        .arg(SIZE.to_string())
        .arg(repeats.to_string())
        .args(&site_files)
        .output();
    let scipy_ms: Vec<Option<f64>> = match peer {
        Ok(out) if out.status.success() => {
            let v: serde_json::Value = serde_json::from_slice(&out.stdout)?;
            site_files
                .iter()
                .map(|f| v[f.to_string_lossy().as_ref()].as_f64())
                .collect()
        }
        Ok(out) => {
            eprintln!(
                "scipy peer failed (run tools/setup --bench): {}",
                String::from_utf8_lossy(&out.stderr)
            );
            vec![None; ns.len()]
        }
        Err(e) => {
            eprintln!("python3 not runnable: {e}");
            vec![None; ns.len()]
        }
    };

    let table = markdown(&machine, &ns, &rows, &cpu_ms, &scipy_ms, repeats);
    common::report::write(&out_dir, "fig313", &table, machine.device_name())?;
    println!("{table}");
    plot(&out_dir.join("fig313.png"), &ns, &rows, &cpu_ms, &scipy_ms)?;
    Ok(())
}

fn fmt(v: Option<f64>) -> String {
    v.map_or("—".into(), |x| format!("{x:.1}"))
}

fn markdown(
    machine: &Machine,
    ns: &[usize],
    rows: &[Vec<Option<(f64, f64)>>],
    cpu: &[f64],
    scipy: &[Option<f64>],
    repeats: usize,
) -> String {
    let mut s = format!(
        "Voronoi diagram of n uniform random sites, {SIZE}×{SIZE} pixels, on {} \
         (median of {repeats}; milliseconds, whole call: cone sizing, rendering, coverage \
         check, readback of the label map; in brackets the rendering alone).\n\n",
        machine.device_name()
    );
    s.push_str("| n |");
    for c in &CONFIGS {
        s.push_str(&format!(" {} |", c.name));
    }
    s.push_str(&format!(
        " scipy EDT + indices | exact CPU bucket search ({} threads) | scipy / default |\n|",
        rayon::current_num_threads()
    ));
    s.push_str(&"---|".repeat(CONFIGS.len() + 4));
    s.push('\n');
    for (k, n) in ns.iter().enumerate() {
        s.push_str(&format!("| {n} |"));
        for cell in &rows[k] {
            match cell {
                Some((t, r)) => s.push_str(&format!(" {t:.1} ({r:.1}) |")),
                None => s.push_str(" — |"),
            }
        }
        let default = rows[k][0].map(|c| c.0);
        let ratio = match (scipy[k], default) {
            (Some(a), Some(b)) => format!("{:.1}×", a / b),
            _ => "—".into(),
        };
        s.push_str(&format!(
            " {} | {:.1} | {} |\n",
            fmt(scipy[k]),
            cpu[k],
            ratio
        ));
    }
    let at = |n: usize| {
        ns.iter()
            .position(|&m| m == n)
            .and_then(|k| rows[k][0])
            .map(|c| c.0)
    };
    if let (Some(a), Some(b)) = (at(1000), at(16000)) {
        s.push_str(&format!(
            "\nDefault mode, 16000 vs 1000 sites: {:.2}×.\n",
            b / a
        ));
    }
    s.push_str(
        "\nThesis (GeForce 2, 2003, 1000² picture): about 50 ms for 2000 sites, 170 ms for \
         16000 sites with the quadtree; without it, time grows linearly in n.\n",
    );
    s
}

fn plot(
    path: &std::path::Path,
    ns: &[usize],
    rows: &[Vec<Option<(f64, f64)>>],
    cpu: &[f64],
    scipy: &[Option<f64>],
) -> anyhow::Result<()> {
    let mut series: Vec<Series> = CONFIGS
        .iter()
        .enumerate()
        .map(|(c, config)| Series {
            name: config.name.to_string(),
            points: ns
                .iter()
                .zip(rows)
                .filter_map(|(n, r)| r[c].map(|v| (*n as f64, v.0)))
                .collect(),
            color: PALETTE[c % PALETTE.len()],
            peer: false,
        })
        .collect();
    series.push(Series {
        name: "scipy distance_transform_edt + indices".into(),
        points: ns
            .iter()
            .zip(scipy)
            .filter_map(|(n, v)| v.map(|v| (*n as f64, v)))
            .collect(),
        color: RGBColor(255, 140, 0),
        peer: true,
    });
    series.push(Series {
        name: "exact CPU bucket search".into(),
        points: ns.iter().zip(cpu).map(|(n, v)| (*n as f64, *v)).collect(),
        color: RGBColor(120, 120, 120),
        peer: true,
    });
    common::plot::plot(
        path,
        &format!("Voronoi diagram, {SIZE}² pixels (cf. thesis Fig. 3.13)"),
        "number of sites n (log scale)",
        &series,
    )
}
