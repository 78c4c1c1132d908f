//! Inputs at the edges of the doubles that once spun for minutes: sites one
//! ulp apart, sites scaled to 1e-300, sites 1e15 away from the picture. Each
//! now answers, exactly where the answer is exact, in about a second at most.

use glam::DVec2;
use pixgeo::{
    algorithms::{
        distances::{directed_hausdorff, HausdorffOptions, Method},
        interpolate::discrete_sibson,
        lloyd::{lloyd, LloydOptions},
        voronoi::{voronoi, VoronoiOptions},
    },
    geometry::{metric::Metric, Frame},
    Backend,
};
use pixgeo_reference::exact::exact_k_nearest;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn tiny_sites(n: usize) -> Vec<DVec2> {
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    (0..n)
        .map(|_| DVec2::new(rng.gen_range(0.0..100.0), rng.gen_range(0.0..100.0)) * 1e-300)
        .collect()
}

/// Sites scaled to 1e-300 all lie within rounding of one pixel's corner:
/// every pixel is a near tie, decided exactly, on the device and the CPU.
#[test]
fn sites_at_1e_minus_300_get_exact_labels() {
    let machine = crate::common::machine();
    let sites = tiny_sites(8);
    let frame = Frame::pixels(24, 20).unwrap();
    let options = VoronoiOptions::exact(frame);
    let (want, _) = exact_k_nearest(&sites, &frame, Metric::L2, 1);
    assert_eq!(
        voronoi(&Backend::Cpu, &sites, &options).unwrap().labels,
        want
    );
    assert_eq!(
        voronoi(&Backend::Device(&machine), &sites, &options)
            .unwrap()
            .labels,
        want
    );
    let lloyd_options = LloydOptions::new(Frame::pixels(64, 64).unwrap()).iterations(2);
    let moved = lloyd(&Backend::Cpu, &tiny_sites(40), None, &lloyd_options).unwrap();
    assert_eq!(moved.labels.len(), 64 * 64);
}

/// Two points one ulp apart: the picture names one or the other at every
/// pixel, by the exact bisector, and the pixels and the grid agree.
#[test]
fn points_one_ulp_apart_are_told_apart_quickly() {
    let machine = crate::common::machine();
    let red = [DVec2::new(3.0, 4.0), DVec2::new(5.0, 1.0)];
    let blue = [DVec2::new(1.0, 1.0), DVec2::new(1.0000000000000002, 1.0)];
    let device = Backend::Device(&machine);
    let pixels = directed_hausdorff(
        &device,
        &red,
        &blue,
        &HausdorffOptions::default()
            .method(Some(Method::Pixels))
            .side(Some(256)),
    )
    .unwrap();
    let grid = directed_hausdorff(
        &Backend::Cpu,
        &red,
        &blue,
        &HausdorffOptions::default().method(Some(Method::Grid)),
    )
    .unwrap();
    assert_eq!(pixels.pair, grid.pair);
}

/// Samples 1e15 pixels away from the picture: their discs are cut to the
/// picture's rows, not walked row by row.
#[test]
fn discrete_sibson_of_far_samples() {
    let at = |x: f64, y: f64| DVec2::new(1e15 + x, y);
    let sites = [at(0.0, 0.0), at(0.125, 0.0), at(0.25, 0.125), at(0.0, 0.25)];
    let raster = discrete_sibson(
        None,
        &sites,
        &[1.0, 2.0, 3.0, 4.0],
        &Frame::pixels(64, 64).unwrap(),
    )
    .unwrap();
    // The picture lies outside the samples' hull.
    assert!(raster.iter().all(|v| v.is_nan()));
}
