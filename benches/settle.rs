//! Thesis Fig. 3.53 on this machine: the settle point's running time against the
//! number of sites n, which *falls* as n grows (discs shrink with the regions).
//! Span counting on the device and the thesis's CPU variant at 1024²; the
//! thesis's own disc drawing (stencil wrap-around + blending) on smaller pictures,
//! beside the span counting of the same picture, for the ratio between them.
//!
//! `cargo bench --bench settle` (after `tools/setup --bench`) writes
//! `target/settle/settle.md` and `fig353.png`. `SETTLE_N=2,20` limits the site
//! counts, `SETTLE_FAITHFUL_SIZES=128,256` the faithful method's picture sides.

use std::{path::PathBuf, time::Instant};

use common::plot::{Series, PALETTE};
use glam::DVec2;
use pixgeo::{
    algorithms::settle::{potential_areas, PotentialAreas, SettleMethod, SettleOptions},
    geometry::Frame,
    Backend, Machine,
};

mod common {
    pub mod plot;
    pub mod report;
}

const SIZE: u32 = 1024;

fn env_list(name: &str, default: &[usize]) -> Vec<usize> {
    std::env::var(name)
        .ok()
        .map(|s| s.split(',').filter_map(|t| t.trim().parse().ok()).collect())
        .unwrap_or_else(|| default.to_vec())
}

fn timed(
    f: impl FnOnce() -> anyhow::Result<PotentialAreas>,
) -> anyhow::Result<(f64, PotentialAreas)> {
    let t = Instant::now();
    let map = f()?;
    Ok((t.elapsed().as_secs_f64(), map))
}

fn gpu(
    machine: &Machine,
    sites: &[DVec2],
    frame: Frame,
    method: SettleMethod,
) -> anyhow::Result<(f64, PotentialAreas)> {
    let options = SettleOptions::new(frame).method(method);
    timed(|| {
        Ok(potential_areas(
            &Backend::Device(machine),
            sites,
            &[],
            &options,
        )?)
    })
}

fn main() -> anyhow::Result<()> {
    let ns = env_list("SETTLE_N", &[2, 3, 5, 10, 20, 50, 100, 200]);
    let faithful_sizes = env_list("SETTLE_FAITHFUL_SIZES", &[128, 256]);
    let out_dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("target/settle");
    std::fs::create_dir_all(&out_dir)?;
    let machine = Machine::from_env()?;
    eprintln!("device: {}", machine.device_name());
    let frame = Frame::pixels(SIZE, SIZE)?;
    gpu(
        &machine,
        &frame.random_points(50, 0).unwrap(),
        Frame::pixels(64, 64)?,
        SettleMethod::Spans,
    )?;

    let mut md = format!(
        "# Settle point, time against n (thesis Fig. 3.53)\n\n\
         Device: {}. Uniform random sites (seed 1), Euclidean metric; seconds, one run each.\n\n\
         ## {SIZE}² pixels\n\n\
         | n | spans (device) | thesis CPU variant (§3.12.3) | best area (pixels) |\n\
         | ---: | ---: | ---: | ---: |\n",
        machine.device_name()
    );
    let mut spans_points = Vec::new();
    let mut cpu_points = Vec::new();
    for &n in &ns {
        let sites = frame.random_points(n, 1).unwrap();
        let (t_spans, spans) = gpu(&machine, &sites, frame, SettleMethod::Spans)?;
        let (t_cpu, cpu) = timed(|| {
            Ok(potential_areas(
                &Backend::Cpu,
                &sites,
                &[],
                &SettleOptions::new(frame),
            )?)
        })?;
        anyhow::ensure!(spans.area == cpu.area, "n = {n}: the CPU variant disagrees");
        eprintln!("{SIZE}² n={n}: spans {t_spans:.2} s, cpu {t_cpu:.2} s");
        md += &format!(
            "| {n} | {t_spans:.2} | {t_cpu:.2} | {} |\n",
            spans.best_area
        );
        spans_points.push((n as f64, t_spans));
        cpu_points.push((n as f64, t_cpu));
    }

    let mut series = vec![
        Series {
            name: format!("spans on the device, {SIZE}²"),
            points: spans_points,
            color: PALETTE[0],
            peer: false,
        },
        Series {
            name: format!("thesis CPU variant, {SIZE}², 2 threads"),
            points: cpu_points,
            color: PALETTE[1],
            peer: true,
        },
    ];
    for (k, &side) in faithful_sizes.iter().enumerate() {
        let frame = Frame::pixels(side as u32, side as u32)?;
        md += &format!(
            "\n## {side}² pixels: the thesis's disc drawing beside span counting\n\n\
             | n | faithful (stencil wrap + blending) | spans | faithful / spans | readbacks |\n\
             | ---: | ---: | ---: | ---: | ---: |\n"
        );
        let mut points = Vec::new();
        for &n in &ns {
            let sites = frame.random_points(n, 1).unwrap();
            let (t_faithful, faithful) = gpu(&machine, &sites, frame, SettleMethod::Faithful)?;
            let (t_spans, spans) = gpu(&machine, &sites, frame, SettleMethod::Spans)?;
            anyhow::ensure!(
                faithful.area == spans.area,
                "{side}² n = {n}: the methods disagree"
            );
            eprintln!("{side}² n={n}: faithful {t_faithful:.2} s, spans {t_spans:.3} s");
            md += &format!(
                "| {n} | {t_faithful:.2} | {t_spans:.3} | {:.0}× | {} |\n",
                t_faithful / t_spans,
                faithful.stats.readbacks
            );
            points.push((n as f64, t_faithful));
        }
        series.push(Series {
            name: format!("thesis's discs (faithful), {side}²"),
            points,
            color: PALETTE[2 + k % 4],
            peer: false,
        });
    }
    md += "\nThesis (2003 GPU, 1024²): about 10 s for 100 sites, 4 minutes for 2 sites.\n";
    common::report::write(&out_dir, "settle", &md, machine.device_name())?;
    println!("{md}");
    common::plot::plot(
        &out_dir.join("fig353.png"),
        "Settle point: seconds against n (cf. thesis Fig. 3.53)",
        "number of sites n (log scale)",
        &series,
    )?;
    Ok(())
}
