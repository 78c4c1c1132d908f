//! Great circles on the device against the CPU's answer (itself checked
//! against brute force in the module's tests) and brute force, on random
//! sites and on grids across the antimeridian, at the poles, with exact ties
//! and with sites an ulp from equidistant.

use crate::common::machine;
use glam::DVec2;
use pixgeo::algorithms::great_circle::{
    distance, great_circle_grid, great_circle_nearest, DISTANCE_ERROR,
};
use pixgeo::Backend;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Evenly spaced degrees from `a` to `b`, `n` of them.
fn steps(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| a + (b - a) * k as f64 / (n - 1).max(1) as f64)
        .collect()
}

/// A named case: sites, then the grid's longitudes and latitudes.
type Case = (&'static str, Vec<DVec2>, Vec<f64>, Vec<f64>);

fn cases() -> Vec<Case> {
    let mut rng = ChaCha8Rng::seed_from_u64(50);
    let random: Vec<DVec2> = (0..300)
        .map(|_| DVec2::new(rng.gen_range(-180.0..180.0), rng.gen_range(-90.0..90.0)))
        .collect();
    let local: Vec<DVec2> = (0..500)
        .map(|_| DVec2::new(rng.gen_range(4.0..6.0), rng.gen_range(50.0..51.0)))
        .collect();
    // Sites a whole degree apart: the grid's lines through their midpoints
    // are equidistant to two sites, and its lattice points to four.
    let lattice: Vec<DVec2> = (0..6)
        .flat_map(|i| (0..4).map(move |j| DVec2::new(i as f64 - 2.5, j as f64 - 1.5)))
        .collect();
    // One ulp of 0.90439 degrees farther on the meridian than on the equator.
    let a: f64 = 0.90439;
    let ulp = vec![
        DVec2::new(0.0, f64::from_bits(a.to_bits() + 1)),
        DVec2::new(a, 0.0),
    ];
    vec![
        (
            "world",
            random.clone(),
            steps(-180.0, 179.0, 181),
            steps(-90.0, 90.0, 97),
        ),
        ("local", local, steps(3.5, 6.5, 150), steps(50.9, 49.9, 70)),
        (
            "antimeridian",
            random.clone(),
            steps(150.0, 210.0, 120),
            steps(-30.0, 30.0, 40),
        ),
        (
            "poles",
            random.clone(),
            steps(-180.0, 180.0, 90),
            steps(80.0, 90.0, 33),
        ),
        (
            "lattice",
            lattice,
            steps(-4.0, 4.0, 41),
            steps(-3.0, 3.0, 31),
        ),
        ("ulp", ulp, steps(0.0, 0.5, 17), steps(0.0, 0.5, 17)),
        (
            "coarse",
            random[..40].to_vec(),
            steps(-180.0, 170.0, 3),
            steps(-80.0, 80.0, 2),
        ),
        (
            "one site",
            random[..1].to_vec(),
            steps(-10.0, 10.0, 20),
            steps(0.0, 5.0, 9),
        ),
    ]
}

#[test]
fn great_circles_on_the_device_are_the_cpus_answer() {
    let machine = machine();
    for (name, sites, lons, lats) in cases() {
        let places: Vec<DVec2> = lats
            .iter()
            .flat_map(|&y| lons.iter().map(move |&x| DVec2::new(x, y)))
            .collect();
        let cpu = great_circle_nearest(&sites, &places, &Default::default()).unwrap();
        let grid = great_circle_grid(&Backend::Cpu, &sites, &lons, &lats, &Default::default());
        let grid = grid.unwrap();
        assert!(
            grid.labels == cpu.labels && grid.distances == cpu.distances,
            "{name}"
        );
        let device = great_circle_grid(
            &Backend::Device(&machine),
            &sites,
            &lons,
            &lats,
            &Default::default(),
        )
        .unwrap();
        let first_difference = |a: &[u32], b: &[u32]| a.iter().zip(b).position(|(a, b)| a != b);
        assert_eq!(
            first_difference(&device.labels, &cpu.labels),
            None,
            "{name}"
        );
        assert_eq!(device.labels.len(), places.len(), "{name}");
        assert!(
            device.distances == cpu.distances,
            "{name}: distances differ"
        );
        assert_eq!(device.equidistant, cpu.equidistant, "{name}");
        for (k, &place) in places.iter().enumerate() {
            let brute = sites
                .iter()
                .map(|&s| distance(place, s))
                .fold(f64::INFINITY, f64::min);
            assert!(
                (device.distances[k] - brute).abs() <= 2.0 * DISTANCE_ERROR,
                "{name}: place {k}"
            );
        }
        match name {
            // Exact ties and the ulp are beyond float32: the host decides them.
            "lattice" => assert!(device.equidistant > 0 && device.decided_on_host > 0),
            "ulp" => {
                assert_eq!(device.labels[0], 1, "the nearer by an ulp");
                assert!(device.decided_on_host > 0);
            }
            _ => {}
        }
    }
}

#[test]
fn great_circles_on_the_device_refuse_places_off_the_earth() {
    let machine = machine();
    let sites = [DVec2::new(0.0, 0.0)];
    let err = great_circle_grid(
        &Backend::Device(&machine),
        &sites,
        &[0.0],
        &[91.0],
        &Default::default(),
    )
    .unwrap_err();
    assert!(err.to_string().contains("latitude"), "{err}");
    let err = great_circle_grid(
        &Backend::Device(&machine),
        &[],
        &[0.0],
        &[0.0],
        &Default::default(),
    )
    .unwrap_err();
    assert!(err.to_string().contains("no sites"), "{err}");
}
