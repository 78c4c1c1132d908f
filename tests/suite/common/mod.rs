//! Inputs and set-up shared by the integration tests.
#![allow(dead_code)]

use std::{ops::Deref, sync::Mutex};

use glam::DVec2;
use pixgeo::Machine;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A machine for one test. A device with its shaders costs more to make than
/// most tests take, so machines are handed from test to test: at most one per
/// test thread is ever made. A test that panics drops its machine rather than
/// passing on whatever state it left.
pub fn machine() -> Pooled {
    let spare = POOL.lock().unwrap_or_else(|e| e.into_inner()).pop();
    Pooled(Some(spare.unwrap_or_else(|| {
        Machine::from_env().expect("a Vulkan device (run tools/setup)")
    })))
}

static POOL: Mutex<Vec<Machine>> = Mutex::new(Vec::new());

/// A machine borrowed from the pool until dropped.
pub struct Pooled(Option<Machine>);

impl Deref for Pooled {
    type Target = Machine;
    fn deref(&self) -> &Machine {
        self.0
            .as_ref()
            .expect("a pooled machine is held until dropped")
    }
}

impl Drop for Pooled {
    fn drop(&mut self) {
        if let Some(machine) = self.0.take().filter(|_| !std::thread::panicking()) {
            POOL.lock().unwrap_or_else(|e| e.into_inner()).push(machine);
        }
    }
}

pub fn uniform(rng: &mut ChaCha8Rng, n: usize, w: f64, h: f64) -> Vec<DVec2> {
    (0..n)
        .map(|_| DVec2::new(rng.gen_range(-0.5..w - 0.5), rng.gen_range(-0.5..h - 0.5)))
        .collect()
}

pub fn clustered(rng: &mut ChaCha8Rng, n: usize, w: f64, h: f64) -> Vec<DVec2> {
    let centres = uniform(rng, 4, w, h);
    (0..n)
        .map(|i| {
            let c = centres[i % 4];
            c + DVec2::new(rng.gen_range(-6.0..6.0), rng.gen_range(-6.0..6.0))
        })
        .collect()
}

/// Named inputs: random, clustered, collinear, duplicate, co-circular lattice,
/// off-picture, one site, the thesis's worst case (a quarter empty), border.
pub fn cases(w: u32, h: u32) -> Vec<(&'static str, Vec<DVec2>)> {
    let (wf, hf) = (w as f64, h as f64);
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut out = vec![
        ("uniform", uniform(&mut rng, 300, wf, hf)),
        ("clustered", clustered(&mut rng, 200, wf, hf)),
        (
            "collinear",
            (0..25)
                .map(|i| DVec2::new(3.0 + 4.5 * i as f64, 2.0 + 3.1 * i as f64))
                .collect(),
        ),
        (
            "horizontal",
            (0..12)
                .map(|i| DVec2::new(i as f64 * 9.0, hf / 2.0))
                .collect(),
        ),
    ];
    let mut dup = uniform(&mut rng, 40, wf, hf);
    dup.extend(dup.clone());
    dup.push(dup[3]);
    out.push(("duplicates", dup));
    // Integer lattice: every pixel centre between four sites is co-circular.
    out.push((
        "lattice",
        (0..(w / 8) * (h / 8))
            .map(|k| DVec2::new((k % (w / 8) * 8 + 2) as f64, (k / (w / 8) * 8 + 3) as f64))
            .collect(),
    ));
    let mut off = uniform(&mut rng, 20, wf, hf);
    off.extend([
        DVec2::new(-40.0, 10.0),
        DVec2::new(wf + 15.0, hf + 3.0),
        DVec2::new(1e4, -1e4),
        DVec2::new(wf / 2.0, -25.0),
    ]);
    out.push(("off-picture", off));
    out.push((
        "only-outside",
        vec![DVec2::new(-30.0, -20.0), DVec2::new(wf + 50.0, hf * 0.3)],
    ));
    out.push(("single", vec![DVec2::new(wf * 0.3, hf * 0.8)]));
    let quarter: Vec<DVec2> = uniform(&mut rng, 300, wf, hf)
        .into_iter()
        .filter(|p| p.x < wf / 2.0 || p.y < hf / 2.0)
        .collect();
    out.push(("quarter-empty", quarter));
    out.push((
        "border",
        vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(wf - 1.0, 0.0),
            DVec2::new(0.0, hf - 1.0),
            DVec2::new(wf - 1.0, hf - 1.0),
            DVec2::new(wf / 2.0, 0.0),
        ],
    ));
    out
}

/// Triangles as sets up to rotation, sorted.
pub fn canonical(mut triangles: Vec<[u32; 3]>) -> Vec<[u32; 3]> {
    for t in &mut triangles {
        let k = (0..3).min_by_key(|&k| t[k]).unwrap();
        t.rotate_left(k);
    }
    triangles.sort_unstable();
    triangles
}

/// The double `steps` ulps from `x` (away from zero for positive steps); zero
/// stays.
pub fn ulps(x: f64, steps: i64) -> f64 {
    if x == 0.0 {
        return x;
    }
    // Doubles of one sign are ordered as their bits.
    let up = (steps > 0) == (x > 0.0);
    let bits = x.to_bits();
    f64::from_bits(if up {
        bits + steps.unsigned_abs()
    } else {
        bits - steps.unsigned_abs()
    })
}

pub use pixgeo_reference::hostile::{hostile, Hostile};

/// The CPU's labels and distances for weighted or extended `sites`.
pub fn cpu_sites(
    sites: &[pixgeo::Site],
    frame: &pixgeo::Frame,
    metric: pixgeo::Metric,
) -> pixgeo::Result<(Vec<u32>, Vec<f32>)> {
    use pixgeo::algorithms::voronoi::{voronoi, VoronoiOptions};
    let options = VoronoiOptions::exact(*frame).metric(metric);
    let d = voronoi(&pixgeo::Backend::Cpu, sites, &options)?;
    Ok((d.labels, d.distances))
}
