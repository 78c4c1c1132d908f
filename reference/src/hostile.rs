//! The inputs on which every route and front end of a problem must give the
//! same answer: one generator for the core's, the C library's, and the
//! command line's parity tests.

use crate::metric::to_world;
use glam::DVec2;
use pixgeo::geometry::Frame;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// One input of the route-parity generator: sites and the picture over them,
/// both in world coordinates.
pub struct Hostile {
    pub name: String,
    pub frame: Frame,
    pub sites: Vec<DVec2>,
}

impl Hostile {
    /// The world box the picture shows, as a front end's `bbox` gives it.
    pub fn bbox(&self) -> [f64; 4] {
        let f = &self.frame;
        let far = to_world(f, DVec2::new(f.width as f64, f.height as f64) - 0.5);
        [f.origin.x, f.origin.y, far.x, far.y]
    }
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
        .map(|(k, p)| match k % 3 {
            0 => DVec2::new(ulp(p.x, true), ulp(p.y, false)),
            _ => *p,
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

fn uniform(rng: &mut ChaCha8Rng, n: usize, w: f64, h: f64) -> Vec<DVec2> {
    (0..n)
        .map(|_| DVec2::new(rng.gen_range(-0.5..w - 0.5), rng.gen_range(-0.5..h - 0.5)))
        .collect()
}

fn clustered(rng: &mut ChaCha8Rng, n: usize, w: f64, h: f64) -> Vec<DVec2> {
    let centres = uniform(rng, 4, w, h);
    (0..n)
        .map(|i| centres[i % 4] + DVec2::new(rng.gen_range(-4.0..4.0), rng.gen_range(-4.0..4.0)))
        .collect()
}

/// The double one ulp from `x` > 0, up or down.
fn ulp(x: f64, up: bool) -> f64 {
    f64::from_bits(if up { x.to_bits() + 1 } else { x.to_bits() - 1 })
}
