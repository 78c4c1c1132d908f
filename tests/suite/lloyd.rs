//! Lloyd's iterations against a brute-force Lloyd (nearest site by scanning
//! every site, ties to the lower index; centroids from whole-number sums, one
//! division), on the device and on the CPU; a lattice that is its own
//! fixed point; energies that never increase; densities refused by name.

use crate::common::{machine, uniform};
use glam::DVec2;
use pixgeo::Backend;
use pixgeo::{
    algorithms::lloyd::{lloyd, LloydOptions},
    geometry::Frame,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// One brute-force iteration on `Frame::pixels(w, h)`, whose pixel centres
/// are the whole numbers: each site's region's weighted mean of `i` and `j`,
/// `Σ q i / Σ q` (both sums exact in doubles here) rounded once.
fn brute_step(sites: &[DVec2], w: usize, h: usize, q: &[u64]) -> Vec<DVec2> {
    let mut sums = vec![(0u64, 0u64, 0u64); sites.len()];
    for j in 0..h {
        for i in 0..w {
            let p = DVec2::new(i as f64, j as f64);
            let nearest = (0..sites.len())
                .min_by(|&a, &b| {
                    p.distance_squared(sites[a])
                        .total_cmp(&p.distance_squared(sites[b]))
                        .then(a.cmp(&b))
                })
                .unwrap();
            let k = q[j * w + i];
            let s = &mut sums[nearest];
            s.0 += k;
            s.1 += k * i as u64;
            s.2 += k * j as u64;
        }
    }
    sites
        .iter()
        .zip(sums)
        .map(|(&site, (weight, x, y))| {
            if weight == 0 {
                site
            } else {
                DVec2::new(x as f64 / weight as f64, y as f64 / weight as f64)
            }
        })
        .collect()
}

/// A smooth density in whole levels 0..=255, darker to one side.
fn density(w: usize, h: usize) -> Vec<u64> {
    (0..w * h)
        .map(|k| {
            let (i, j) = ((k % w) as f64, (k / w) as f64);
            (255.0 * (0.5 + 0.5 * (i / 9.0).sin() * (j / 13.0).cos())).round() as u64
        })
        .collect()
}

#[test]
fn lloyd_matches_brute_force_on_the_device_and_the_cpu() {
    let machine = machine();
    let (w, h) = (64usize, 48usize);
    let frame = Frame::pixels(w as u32, h as u32).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(52);
    let start = uniform(&mut rng, 40, w as f64, h as f64);
    for q in [vec![1u64; w * h], density(w, h)] {
        let levels: Vec<f64> = q.iter().map(|&v| v as f64).collect();
        let options = LloydOptions::new(frame).iterations(6).tolerance(0.0);
        let on_device = lloyd(&Backend::Device(&machine), &start, Some(&levels), &options).unwrap();
        let on_cpu = lloyd(&Backend::Cpu, &start, Some(&levels), &options).unwrap();
        assert_eq!(on_device, on_cpu);
        let mut sites = start.clone();
        for _ in 0..6 {
            sites = brute_step(&sites, w, h, &q);
        }
        assert_eq!(on_device.sites, sites, "bit for bit");
        assert_eq!(on_device.steps.len(), 6);
        // The assignment and the move each lower the energy.
        let energies: Vec<f64> = on_device.steps.iter().map(|s| s.energy).collect();
        for pair in energies.windows(2) {
            assert!(pair[1] <= pair[0] * (1.0 + 1e-12), "{energies:?}");
        }
        assert!(on_device.energy <= energies[5] * (1.0 + 1e-12));
    }
}

#[test]
fn a_lattice_of_cell_centres_is_its_own_fixed_point() {
    let machine = machine();
    // 6 x 4 cells of 10 pixels: a site at each cell's centroid, 10a + 4.5.
    let frame = Frame::pixels(60, 40).unwrap();
    let sites: Vec<DVec2> = (0..6)
        .flat_map(|a| (0..4).map(move |b| DVec2::new(10.0 * a as f64 + 4.5, 10.0 * b as f64 + 4.5)))
        .collect();
    let options = LloydOptions::new(frame);
    let answer = lloyd(&Backend::Device(&machine), &sites, None, &options).unwrap();
    assert_eq!(answer.sites, sites);
    assert!(answer.converged && answer.steps.len() == 1);
    assert_eq!(answer.steps[0].largest_move, 0.0);
    assert_eq!(answer.idle, 0);
}

#[test]
fn lloyd_refuses_densities_it_cannot_sum_exactly() {
    let frame = Frame::pixels(8, 8).unwrap();
    let sites = [DVec2::new(2.0, 2.0), DVec2::new(5.0, 5.0)];
    let options = LloydOptions::new(frame);
    let run = |d: &[f64]| lloyd(&Backend::Cpu, &sites, Some(d), &options);
    let mut d = vec![1.0; 64];
    d[3] = -1.0;
    assert!(run(&d).unwrap_err().to_string().contains("not negative"));
    assert!(run(&[0.0; 64])
        .unwrap_err()
        .to_string()
        .contains("zero everywhere"));
    let mut d = vec![1.0; 64];
    d[5] = 1e-300;
    assert!(run(&d).unwrap_err().to_string().contains("bits"));
    assert!(run(&[1.0; 10])
        .unwrap_err()
        .to_string()
        .contains("10 values"));
    // A site whose region has no weight stays put, counted.
    let mut d = vec![0.0; 64];
    d[0] = 1.0;
    let answer = run(&d).unwrap();
    assert_eq!(answer.sites[1], sites[1]);
    assert_eq!(answer.idle, 1);
}
