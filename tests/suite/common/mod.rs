//! Inputs and set-up shared by the integration tests.
#![allow(dead_code)]

use std::{ops::Deref, sync::Mutex};

use glam::DVec2;
use pixgeo::{geometry::Frame, Machine};
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

/// One input of the route-parity generator: sites and the picture over them,
/// both in world coordinates.
pub struct Hostile {
    pub name: String,
    pub frame: Frame,
    pub sites: Vec<DVec2>,
}

/// The inputs every route of a problem must answer alike: uniform and
/// clustered sites, an integer lattice whose pixels tie exactly, the lattice
/// nudged by ±1 ulp, repeats and a line, each on a `w` x `h` picture, then
/// moved by 1e9 and 1e15 and scaled by 1e-300, 1e300 and 0.1 with its
/// picture.
pub fn hostile(w: u32, h: u32) -> Vec<Hostile> {
    let (wf, hf) = (w as f64, h as f64);
    let mut rng = ChaCha8Rng::seed_from_u64(67);
    // Even steps: the bisectors of neighbours run through pixel centres.
    let lattice: Vec<DVec2> = (0..(w / 4) * (h / 4))
        .map(|k| DVec2::new((k % (w / 4) * 4 + 1) as f64, (k / (w / 4) * 4 + 2) as f64))
        .collect();
    let nudged = lattice
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let step = |s: i64| if k % 3 == 0 { s } else { 0 };
            DVec2::new(ulps(p.x, step(1)), ulps(p.y, step(-1)))
        })
        .collect();
    let mut repeats = uniform(&mut rng, 10, wf, hf);
    repeats.extend_from_within(2..6);
    repeats.push(repeats[0]);
    let kinds: Vec<(&str, Vec<DVec2>)> = vec![
        ("uniform", uniform(&mut rng, 30, wf, hf)),
        ("clustered", clustered(&mut rng, 24, wf, hf)),
        ("lattice", lattice),
        ("lattice ±1 ulp", nudged),
        ("repeats", repeats),
        (
            "line",
            (0..9)
                .map(|i| DVec2::new(1.5 + 2.5 * i as f64, 1.0 + 1.75 * i as f64))
                .collect(),
        ),
    ];
    let moves = [
        ("", 1.0, 0.0),
        (" + 1e9", 1.0, 1e9),
        (" + 1e15", 1.0, 1e15),
        (" × 1e-300", 1e-300, 0.0),
        (" × 1e300", 1e300, 0.0),
        (" × 0.1", 0.1, 0.0),
    ];
    let mut out = Vec::new();
    for (kind, sites) in &kinds {
        for (moved, scale, offset) in moves {
            let world = |p: DVec2| p * scale + offset;
            out.push(Hostile {
                name: format!("{kind}{moved}"),
                frame: Frame {
                    width: w,
                    height: h,
                    origin: world(DVec2::splat(-0.5)),
                    scale: 1.0 / scale,
                },
                sites: sites.iter().map(|&p| world(p)).collect(),
            });
        }
    }
    out
}
