//! Route parity as a property: every input of [`crate::common::hostile`]
//! through every route each problem has, on the device and the CPU, with the
//! same labels bit for bit, the exact answer for the doubles given (equal
//! distances to the smaller index) and the same distances to the bit.

use glam::DVec2;
use pixgeo::{
    algorithms::{
        delaunay::{delaunay, DelaunayOptions},
        distances::{directed_hausdorff, HausdorffOptions, Method as HausdorffMethod},
        higher_order::{furthest, k_nearest, k_nearest_peeled, KNearestOptions},
        voronoi::{voronoi, Method, Speedup, VoronoiOptions},
    },
    geometry::{metric::Metric, Frame},
    machine::PixelRect,
    Backend,
};
use pixgeo_reference::exact::{
    directed_hausdorff_squared, exact_distances, exact_k_nearest, exact_key, squared,
};

use crate::common::{hostile, machine, Hostile};

const W: u32 = 28;
const H: u32 = 20;

/// Differences as "what: n of m", for one report over every case.
#[derive(Default)]
struct Differences(Vec<String>);

impl Differences {
    fn check<T: PartialEq>(&mut self, what: String, got: &[T], want: &[T]) {
        let wrong = got.iter().zip(want).filter(|(g, w)| g != w).count();
        if wrong > 0 || got.len() != want.len() {
            self.0
                .push(format!("{what}: {wrong} of {} differ", want.len()));
        }
    }

    fn assert_none(self) {
        assert!(self.0.is_empty(), "{}", self.0.join("\n"));
    }
}

fn bits(d: &[f32]) -> Vec<u32> {
    d.iter().map(|v| v.to_bits()).collect()
}

/// The nearest site: cones with each speed-up, small tiles, the CPU grid,
/// the CPU's growth, and a window of each, against the exact labels.
#[test]
fn nearest_sites_are_the_same_on_every_route() {
    let m = machine();
    let mut differences = Differences::default();
    for Hostile { name, frame, sites } in hostile(W, H) {
        let (want, _) = exact_k_nearest(&sites, &frame, Metric::L2, 1);
        let base = VoronoiOptions::exact(frame);
        let cones = base.clone().method(Method::Cones);
        let grown = k_nearest(&Backend::Cpu, &sites, &KNearestOptions::exact(frame, 1)).unwrap();
        differences.check(format!("{name}: growth on the CPU"), &grown.labels, &want);
        // Every route's distances are the CPU's: the float32s nearest the exact ones.
        differences.check(
            format!("{name}: distances"),
            &bits(&grown.distances),
            &bits(&exact_distances(&sites, &frame, &want)),
        );
        let routes = [
            ("cones", voronoi(&Backend::Device(&m), &sites, &cones)),
            (
                "cones without a speed-up",
                voronoi(
                    &Backend::Device(&m),
                    &sites,
                    &cones.clone().speedup(Speedup::None),
                ),
            ),
            (
                "cones in tiles of 8",
                voronoi(&Backend::Device(&m), &sites, &cones.max_tile(Some(8))),
            ),
            (
                "grid",
                voronoi(&Backend::Cpu, &sites, &base.clone().method(Method::Grid)),
            ),
        ];
        for (route, diagram) in routes {
            let d = diagram.unwrap_or_else(|e| panic!("{name}, {route}: {e}"));
            differences.check(format!("{name}: {route}"), &d.labels, &want);
            differences.check(
                format!("{name}: {route} distances"),
                &bits(&d.distances),
                &bits(&grown.distances),
            );
        }
        let window = PixelRect {
            x: 5,
            y: 3,
            width: 17,
            height: 11,
        };
        let inside: Vec<u32> = (window.y..window.y + window.height)
            .flat_map(|j| (window.x..window.x + window.width).map(move |i| (j * W + i) as usize))
            .map(|p| want[p])
            .collect();
        for method in [Method::Cones, Method::Grid] {
            let options = base.clone().method(method).window(Some(window));
            let d = match method {
                Method::Grid => voronoi(&Backend::Cpu, &sites, &options),
                _ => voronoi(&Backend::Device(&m), &sites, &options),
            }
            .unwrap();
            differences.check(format!("{name}: window by {method:?}"), &d.labels, &inside);
        }
    }
    differences.assert_none();
}

/// The two nearest sites: drawn levels, depth peeling and the CPU's growth.
#[test]
fn second_nearest_sites_are_the_same_on_every_route() {
    let m = machine();
    let mut differences = Differences::default();
    for Hostile { name, frame, sites } in hostile(W, H) {
        let (want, _) = exact_k_nearest(&sites, &frame, Metric::L2, 2);
        let options = KNearestOptions::exact(frame, 2);
        let grown = k_nearest(&Backend::Cpu, &sites, &KNearestOptions::exact(frame, 2)).unwrap();
        let routes = [
            (
                "levels",
                k_nearest(&Backend::Device(&m), &sites, &options).unwrap(),
            ),
            ("peeled", k_nearest_peeled(&m, &sites, &options).unwrap()),
            ("growth on the CPU", grown.clone()),
        ];
        for (route, near) in routes {
            differences.check(format!("{name}: {route}"), &near.labels, &want);
            differences.check(
                format!("{name}: {route} distances"),
                &bits(&near.distances),
                &bits(&grown.distances),
            );
        }
    }
    differences.assert_none();
}

/// The furthest site, filtered on the device and searched on the CPU.
#[test]
fn furthest_sites_are_the_same_on_every_route() {
    let m = machine();
    let mut differences = Differences::default();
    for Hostile { name, frame, sites } in hostile(W, H) {
        let want = exact_furthest(&sites, &frame);
        let device = furthest(&Backend::Device(&m), &sites, &frame, Metric::L2).unwrap();
        let on_cpu = furthest(&Backend::Cpu, &sites, &frame, Metric::L2).unwrap();
        differences.check(format!("{name}: device"), &device.labels, &want);
        differences.check(format!("{name}: CPU"), &on_cpu.labels, &want);
        differences.check(
            format!("{name}: distances"),
            &bits(&device.distances),
            &bits(&on_cpu.distances),
        );
    }
    differences.assert_none();
}

/// Every pixel's furthest site by rational arithmetic, ties to the smaller
/// index, among the sites whose float distance is within a millionth of the
/// largest (far beyond the doubles' rounding).
fn exact_furthest(sites: &[DVec2], frame: &Frame) -> Vec<u32> {
    use rayon::prelude::*;
    (0..frame.len() as u32)
        .into_par_iter()
        .map(|q| {
            let (i, j) = (q % frame.width, q / frame.width);
            let centre = frame.to_world(DVec2::new(i as f64, j as f64));
            let far = |s: &DVec2| ((*s - centre) * frame.scale).length_squared();
            let most = sites.iter().map(far).fold(0.0, f64::max);
            let (mut best, mut key) = (u32::MAX, None);
            for (n, s) in sites.iter().enumerate() {
                if far(s) >= most * (1.0 - 1e-6) {
                    let k = exact_key(frame, Metric::L2, *s, i, j);
                    if key.as_ref().is_none_or(|b| k > *b) {
                        (best, key) = (n as u32, Some(k));
                    }
                }
            }
            best
        })
        .collect()
}

/// Delaunay triangles by flooding on the device and by insertion on the
/// CPU, the same list; a refusal the same refusal.
#[test]
fn delaunay_is_the_same_on_every_route() {
    let m = machine();
    let options = DelaunayOptions::default();
    for Hostile { name, sites, .. } in hostile(W, H) {
        let device = delaunay(&Backend::Device(&m), &sites, &options);
        let on_cpu = delaunay(&Backend::Cpu, &sites, &options);
        match (device, on_cpu) {
            (Ok(d), Ok(c)) => {
                assert_eq!(d.triangles, c.triangles, "{name}");
                assert_eq!(d.duplicates, c.duplicates, "{name}");
            }
            (Err(d), Err(c)) => assert_eq!(d.to_string(), c.to_string(), "{name}"),
            (d, c) => panic!(
                "{name}: the device gave {:?}, the CPU {:?}",
                d.err(),
                c.err()
            ),
        }
    }
}

/// The directed Hausdorff distance from the first half of the sites to the
/// second, proposed by the picture and by the grid: the exact distance, the
/// same pair.
#[test]
fn hausdorff_is_the_same_on_every_route() {
    let m = machine();
    for Hostile { name, sites, .. } in hostile(W, H) {
        let (a, b) = sites.split_at(sites.len() / 2);
        let want = directed_hausdorff_squared(a, b);
        let pixels = directed_hausdorff(
            &Backend::Device(&m),
            a,
            b,
            &HausdorffOptions::default()
                .method(Some(HausdorffMethod::Pixels))
                .side(Some(64)),
        )
        .unwrap();
        let grid = directed_hausdorff(
            &Backend::Cpu,
            a,
            b,
            &HausdorffOptions::default().method(Some(HausdorffMethod::Grid)),
        )
        .unwrap();
        assert_eq!(
            (pixels.pair.from, pixels.pair.to),
            (grid.pair.from, grid.pair.to),
            "{name}"
        );
        let (from, to) = (a[grid.pair.from as usize], b[grid.pair.to as usize]);
        assert_eq!(squared(from, to), want, "{name}");
    }
}
