//! Property tests: every algorithm family against its independent oracle in
//! `reference`, on generated degenerate site sets — integer lattices and their
//! subsets, duplicates, collinear and co-circular sets, sites outside the picture
//! — at every scale from 2^-40 to 2^40 (a power of two changes no answer).

use glam::DVec2;
use pixgeo::Backend;
use pixgeo::{
    algorithms::{
        area::{extremal_quadrangle, extremal_triangle, AreaOptions, Extreme},
        distances::{diameter, hausdorff, HausdorffOptions},
        higher_order::{k_nearest, k_nearest_peeled, KNearestOptions},
        voronoi::{voronoi, Accuracy, Speedup, VoronoiOptions},
    },
    geometry::{metric::Metric, Frame},
};
use pixgeo_reference::{
    area as area_oracle, higher_order::k_nearest_by_metric, voronoi::nearest_distances_metric,
};
use proptest::{
    prelude::*,
    test_runner::{Config, TestRunner},
};

const W: u32 = 36;
const H: u32 = 28;

/// Integer points on the circle of radius 5 around the origin.
const CIRCLE5: [(i32, i32); 12] = [
    (5, 0),
    (4, 3),
    (3, 4),
    (0, 5),
    (-3, 4),
    (-4, 3),
    (-5, 0),
    (-4, -3),
    (-3, -4),
    (0, -5),
    (3, -4),
    (4, -3),
];

/// One degenerate family, in pixel coordinates of a W×H picture.
fn family() -> impl Strategy<Value = Vec<DVec2>> {
    let p = |x: i32, y: i32| DVec2::new(x as f64, y as f64);
    prop_oneof![
        // A lattice subset: every pixel between four sites is co-circular.
        (
            1..6i32,
            0..4i32,
            0..4i32,
            prop::collection::vec(any::<bool>(), 60)
        )
            .prop_map(move |(s, ox, oy, keep)| {
                (0..60)
                    .filter(|&k| keep[k as usize])
                    .map(|k| p(ox + s * (k % 10), oy + s * (k / 10)))
                    .collect()
            }),
        // Duplicates: a few points, each up to three times.
        prop::collection::vec((0..W as i32, 0..H as i32, 1..4usize), 1..8).prop_map(move |v| v
            .into_iter()
            .flat_map(|(x, y, n)| std::iter::repeat_n(p(x, y), n))
            .collect()),
        // Collinear, at integer steps.
        (0..W as i32, 0..H as i32, -3..4i32, -3..4i32, 2..12i32)
            .prop_map(move |(x, y, dx, dy, n)| (0..n).map(|i| p(x + i * dx, y + i * dy)).collect()),
        // Co-circular: integer points of one circle.
        (5..30i32, 5..22i32, prop::collection::vec(any::<bool>(), 12)).prop_map(
            move |(cx, cy, keep)| CIRCLE5
                .iter()
                .zip(&keep)
                .filter(|(_, k)| **k)
                .map(|(&(x, y), _)| p(cx + x, cy + y))
                .collect()
        ),
        // Outside the picture, on every side.
        prop::collection::vec((-60..100i32, -60..90i32), 1..6)
            .prop_map(move |v| v.into_iter().map(|(x, y)| p(x, y)).collect()),
    ]
}

/// Up to three families together, at scale 2^e, with the frame that shows the
/// W×H picture at that scale.
fn site_sets() -> impl Strategy<Value = (Vec<DVec2>, Frame)> {
    (
        prop::collection::vec(family(), 1..4),
        prop_oneof![Just(0), Just(-40), Just(40), -8..8i32],
    )
        .prop_filter_map("at least one site", |(families, e)| {
            let sites: Vec<DVec2> = families.concat();
            if sites.is_empty() {
                return None;
            }
            let scale = 2f64.powi(e);
            let frame = Frame::with_bbox(
                W,
                Some(H),
                [
                    -0.5 * scale,
                    -0.5 * scale,
                    (W as f64 - 0.5) * scale,
                    (H as f64 - 0.5) * scale,
                ],
            )
            .ok()?;
            Some((sites.iter().map(|s| *s * scale).collect(), frame))
        })
}

fn run(cases: u32, test: impl Fn(Vec<DVec2>, Frame) -> Result<(), TestCaseError>) {
    let mut runner = TestRunner::new(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    runner
        .run(&site_sets(), |(sites, frame)| test(sites, frame))
        .unwrap();
}

/// Pixel centres and sites in pixel units: the scale is a power of two, so
/// these are the generated integers exactly.
fn in_pixels(sites: &[DVec2], frame: &Frame) -> Vec<DVec2> {
    sites.iter().map(|s| frame.to_pixel(*s)).collect()
}

/// The W×H picture in pixel units, where the oracles work.
fn pixel_frame() -> Frame {
    Frame::pixels(W, H).unwrap()
}

fn pixel(k: usize) -> DVec2 {
    DVec2::new((k % W as usize) as f64, (k / W as usize) as f64)
}

fn nearest(sites: &[DVec2], q: DVec2, metric: Metric) -> f64 {
    sites
        .iter()
        .map(|s| metric.distance(*s - q))
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn exact_diagrams_under_every_metric_and_speedup() {
    let metrics = [Metric::L2, Metric::L1, Metric::LInf, Metric::Lp(3.0)];
    exact_diagrams(
        &metrics,
        &[Speedup::None, Speedup::Quadtree, Speedup::Local],
    );
}

/// Found by the test above: under L∞ the quadtree's retry radii covered every
/// pixel with some cone, but not always with the nearest site's cone.
#[test]
fn linf_quadtree_labels_the_nearest_site() {
    let m = crate::common::machine();
    let sites = [
        DVec2::new(32.0, 22.0),
        DVec2::new(24.0, 22.0),
        DVec2::new(28.0, 14.0),
    ];
    let options = VoronoiOptions::exact(pixel_frame())
        .metric(Metric::LInf)
        .speedup(Speedup::Quadtree);
    let d = voronoi(&Backend::Device(&m), &sites, &options).unwrap();
    // Pixel (0, 0): site 1 at L∞ distance 24, site 2 at 28.
    assert_eq!(d.labels[0], 1);
}

fn exact_diagrams(metrics: &[Metric], speedups: &[Speedup]) {
    let m = crate::common::machine();
    run(96, |sites, frame| {
        let px = in_pixels(&sites, &frame);
        let world = frame.to_world(DVec2::ONE).x - frame.to_world(DVec2::ZERO).x;
        for &metric in metrics {
            let truth = nearest_distances_metric(&px, &pixel_frame(), metric);
            for &speedup in speedups {
                let options = VoronoiOptions::exact(frame).metric(metric).speedup(speedup);
                let d = voronoi(&Backend::Device(&m), &sites, &options)
                    .map_err(|e| TestCaseError::fail(format!("{metric} {speedup:?}: {e}")))?;
                for (k, &label) in d.labels.iter().enumerate() {
                    let (q, best) = (pixel(k), truth[k]);
                    prop_assert_ne!(label, u32::MAX, "{} {:?}: {} uncovered", metric, speedup, q);
                    let mine = metric.distance(px[label as usize] - q);
                    let tol = 1e-3 * (1.0 + best);
                    prop_assert!(
                        mine <= best + tol,
                        "{} {:?}: pixel {}: site {} at {}, nearest {}",
                        metric,
                        speedup,
                        q,
                        label,
                        mine,
                        best
                    );
                    let map = d.distances[k] as f64 / world;
                    prop_assert!(
                        (map - best).abs() <= tol,
                        "{} pixel {}: map {} vs {}",
                        metric,
                        q,
                        map,
                        best
                    );
                }
            }
        }
        Ok(())
    });
}

#[test]
fn fan_diagrams_keep_their_bound_on_every_pixel() {
    let m = crate::common::machine();
    run(96, |sites, frame| {
        let px = in_pixels(&sites, &frame);
        let truth = nearest_distances_metric(&px, &pixel_frame(), Metric::L2);
        for epsilon in [1.0, 0.25] {
            let options = VoronoiOptions::exact(frame).accuracy(Accuracy::Fan {
                epsilon,
                triangles: None,
            });
            let d = voronoi(&Backend::Device(&m), &sites, &options)
                .map_err(|e| TestCaseError::fail(format!("fan {epsilon}: {e}")))?;
            for (k, &label) in d.labels.iter().enumerate() {
                let (q, best) = (pixel(k), truth[k]);
                prop_assert_ne!(label, u32::MAX);
                // The fan's ε, plus the rasterizer's subpixel snapping.
                let mine = (px[label as usize] - q).length();
                prop_assert!(
                    mine <= best + epsilon + 1e-2,
                    "ε={}: pixel {}: site {} at {}, nearest {}",
                    epsilon,
                    q,
                    label,
                    mine,
                    best
                );
            }
        }
        Ok(())
    });
}

#[test]
fn k_nearest_levels_with_and_without_peeling() {
    let m = crate::common::machine();
    run(96, |sites, frame| {
        let px = in_pixels(&sites, &frame);
        for k in [1, 3] {
            let truth = k_nearest_by_metric(&px, &pixel_frame(), k, Metric::L2);
            let options = KNearestOptions::exact(frame, k as u32);
            for peeled in [false, true] {
                let d = if peeled {
                    k_nearest_peeled(&m, &sites, &options)
                } else {
                    k_nearest(&Backend::Device(&m), &sites, &options)
                }
                .map_err(|e| TestCaseError::fail(format!("k={k} peeled={peeled}: {e}")))?;
                for (p, expected) in truth.iter().enumerate() {
                    let labels = &d.labels[p * k..][..k];
                    for (l, &label) in labels.iter().enumerate() {
                        let Some(&(_, want)) = expected.get(l) else {
                            prop_assert_eq!(label, u32::MAX);
                            continue;
                        };
                        prop_assert_ne!(
                            label,
                            u32::MAX,
                            "k={} peeled={} pixel {} level {} empty",
                            k,
                            peeled,
                            p,
                            l
                        );
                        let got = (px[label as usize] - pixel(p)).length();
                        prop_assert!(
                            (got - want).abs() <= 1e-3 * (1.0 + want),
                            "k={} peeled={}: pixel {} level {}: site {} at {}, truth {}",
                            k,
                            peeled,
                            pixel(p),
                            l,
                            label,
                            got,
                            want
                        );
                        prop_assert!(
                            !labels[..l].contains(&label),
                            "site {} twice at pixel {}",
                            label,
                            p
                        );
                    }
                }
            }
        }
        Ok(())
    });
}

#[test]
fn extremal_triangles_and_quadrangles_match_exhaustive_search() {
    let m = crate::common::machine();
    run(96, |sites, _| {
        let sites: Vec<DVec2> = sites.into_iter().take(14).collect();
        for extreme in [Extreme::Smallest, Extreme::Largest] {
            let largest = extreme == Extreme::Largest;
            let cases = [
                (
                    "triangle",
                    extremal_triangle(
                        &Backend::Device(&m),
                        &sites,
                        &AreaOptions::new(extreme).side(Some(64)),
                    )
                    .map(|a| a.area),
                    area_oracle::extremal_triangle(&sites, largest).map(|(_, a)| a),
                ),
                (
                    "quadrangle",
                    extremal_quadrangle(
                        &Backend::Device(&m),
                        &sites,
                        &AreaOptions::new(extreme).side(Some(64)),
                    )
                    .map(|a| a.area),
                    area_oracle::extremal_quadrangle(&sites, largest).map(|(_, a)| a),
                ),
                (
                    "triangle by sweep",
                    extremal_triangle(&Backend::Cpu, &sites, &AreaOptions::new(extreme))
                        .map(|a| a.area),
                    area_oracle::extremal_triangle(&sites, largest).map(|(_, a)| a),
                ),
                (
                    "quadrangle by sweep",
                    extremal_quadrangle(&Backend::Cpu, &sites, &AreaOptions::new(extreme))
                        .map(|a| a.area),
                    area_oracle::extremal_quadrangle(&sites, largest).map(|(_, a)| a),
                ),
            ];
            for (what, answer, want) in cases {
                match (answer, want) {
                    (Ok(got), Some(want)) => prop_assert!(
                        (got - want).abs() <= 1e-9 * (1.0 + want.abs()),
                        "{} {:?}: {} against {}",
                        what,
                        extreme,
                        got,
                        want
                    ),
                    (Err(_), None) => {}
                    (got, want) => {
                        prop_assert!(
                            false,
                            "{} {:?}: {:?} against {:?}",
                            what,
                            extreme,
                            got,
                            want
                        )
                    }
                }
            }
        }
        Ok(())
    });
}

#[test]
fn hausdorff_and_diameter_are_exact() {
    let m = crate::common::machine();
    let brute_directed = |a: &[DVec2], b: &[DVec2]| {
        a.iter()
            .map(|p| nearest(b, *p, Metric::L2))
            .fold(0.0, f64::max)
    };
    run(96, |sites, _| {
        let (a, b) = sites.split_at(sites.len().div_ceil(2));
        let d = diameter(&m, &sites, None).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let want = sites
            .iter()
            .flat_map(|p| sites.iter().map(move |q| p.distance(*q)))
            .fold(0.0, f64::max);
        prop_assert_eq!(d.pair.distance, want);
        if !b.is_empty() {
            let h = hausdorff(&Backend::Device(&m), a, b, &HausdorffOptions::default())
                .map_err(|e| TestCaseError::fail(e.to_string()))?;
            prop_assert_eq!(h.distance, brute_directed(a, b).max(brute_directed(b, a)));
        }
        Ok(())
    });
}
