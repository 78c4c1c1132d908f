//! Higher-order diagrams against their definitions: the k nearest sites of every
//! pixel in order, the order-k sets and the furthest site, on random and degenerate
//! inputs and with every speedup.

use crate::common::{cases, machine};
use glam::DVec2;
use pixgeo::geometry::predicates::convex_hull;
use pixgeo::Backend;
use pixgeo::{
    algorithms::{
        higher_order::{furthest, k_nearest, k_nearest_peeled, KNearest, KNearestOptions},
        voronoi::{Accuracy, Speedup},
    },
    geometry::{metric::Metric, Frame},
};
use pixgeo_reference::higher_order::{
    furthest_brute_force, k_nearest_brute_force, k_nearest_by_metric,
};

const SPEEDUPS: [Speedup; 3] = [Speedup::None, Speedup::Quadtree, Speedup::Local];

/// Float32 on the device: squared distances of real coordinates carry a relative
/// error of about 1e-7.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-3 * (1.0 + b)
}

/// Level by level: the distance is the definition's l-th smallest (with
/// multiplicity), the label a site at that distance, and no site twice per pixel.
fn assert_levels(d: &KNearest, sites: &[DVec2], frame: &Frame, what: &str) {
    assert_levels_in(d, sites, frame, what, Metric::L2);
}

fn assert_levels_in(d: &KNearest, sites: &[DVec2], frame: &Frame, what: &str, metric: Metric) {
    let truth = k_nearest_by_metric(sites, frame, d.k as usize, metric);
    let w = frame.width as usize;
    for (p, expected) in truth.iter().enumerate() {
        let q = DVec2::new((p % w) as f64, (p / w) as f64);
        let k = d.k as usize;
        let labels = &d.labels[p * k..][..k];
        let distances = &d.distances[p * k..][..k];
        for l in 0..k {
            match expected.get(l) {
                None => {
                    assert_eq!(labels[l], u32::MAX, "{what}: pixel {q} level {l}");
                    assert!(distances[l].is_infinite());
                }
                Some(&(_, dist)) => {
                    let label = labels[l];
                    assert_ne!(label, u32::MAX, "{what}: pixel {q} level {l} empty");
                    let dl = metric.distance(sites[label as usize] - q);
                    assert!(
                        close(dl, dist) && close(distances[l] as f64, dist),
                        "{what}: pixel {q} level {l}: site {label} at {dl}, map {}, truth {dist}",
                        distances[l]
                    );
                    assert!(
                        !labels[..l].contains(&label),
                        "{what}: pixel {q}: site {label} twice"
                    );
                }
            }
        }
    }
}

#[test]
fn k_nearest_sites_match_the_definition() {
    let m = machine();
    let frame = Frame::pixels(97, 73).unwrap();
    for (name, sites) in cases(97, 73) {
        for speedup in SPEEDUPS {
            for k in [1, 4, 10] {
                let d = k_nearest(
                    &Backend::Device(&m),
                    &sites,
                    &KNearestOptions::exact(frame, k).speedup(speedup),
                )
                .unwrap_or_else(|e| panic!("{name} {speedup:?} k={k}: {e}"));
                assert_levels(&d, &sites, &frame, &format!("{name} {speedup:?} k={k}"));
            }
        }
    }
}

#[test]
fn many_cones_fill_several_rows_of_records() {
    // Picture-wide cones meet every screen tile: 70 tiles x 900 cones fill
    // sixteen rows of the fragment shader's records.
    let m = machine();
    let frame = Frame::pixels(160, 100).unwrap();
    let sites = frame.random_points(900, 7).unwrap();
    let d = k_nearest(
        &Backend::Device(&m),
        &sites,
        &KNearestOptions::exact(frame, 6).speedup(Speedup::None),
    )
    .unwrap();
    assert_levels(&d, &sites, &frame, "900 picture-wide cones");
}

#[test]
fn long_lists_insert_with_atomics() {
    // More levels than a tile fragment keeps: the one-pass atomic insertion.
    let m = machine();
    let frame = Frame::pixels(24, 20).unwrap();
    let (_, sites) = cases(24, 20).remove(0);
    let d = k_nearest(
        &Backend::Device(&m),
        &sites,
        &KNearestOptions::exact(frame, 40),
    )
    .unwrap();
    assert_levels(&d, &sites, &frame, "k=40");
}

#[test]
fn fan_levels_stay_inside_their_bound() {
    // Each site's fan height lies in [d, d + bound], so the l-th smallest height
    // lies within the bound above the l-th smallest distance.
    let m = machine();
    let frame = Frame::pixels(90, 70).unwrap();
    let (_, sites) = cases(90, 70).remove(0);
    let k = 3;
    let accuracies = [
        Accuracy::FAN,
        Accuracy::Fan {
            epsilon: 1.0,
            triangles: Some(12),
        },
    ];
    // Fans of other metrics too (thesis §3.6.1): chains or uniform samples.
    let metrics = [Metric::L2, Metric::L1, Metric::LInf, Metric::Lp(3.0)];
    for (metric, accuracy) in metrics.into_iter().flat_map(|m| accuracies.map(|a| (m, a))) {
        let truth = k_nearest_by_metric(&sites, &frame, k as usize, metric);
        for speedup in SPEEDUPS {
            let d = k_nearest(
                &Backend::Device(&m),
                &sites,
                &KNearestOptions::exact(frame, k)
                    .metric(metric)
                    .accuracy(accuracy)
                    .speedup(speedup),
            )
            .unwrap();
            let bound = d.stats.distance_error_bound;
            assert!(bound > 0.0 || metric != Metric::L2);
            for (p, expected) in truth.iter().enumerate() {
                for (l, &(_, dist)) in expected.iter().enumerate() {
                    let got = d.distances[p * k as usize + l] as f64;
                    // Vertices snap to the rasterizer's subpixel grid.
                    assert!(
                        got >= dist - 0.05 && got <= dist + bound + 0.05,
                        "{metric} {accuracy:?} {speedup:?}: pixel {p} level {l}: {got} vs {dist} (+{bound})"
                    );
                }
            }
        }
    }
}

#[test]
fn equal_distances_keep_their_multiplicity() {
    // An integer lattice of spacing 4: the pixel centres at the lattice's cell
    // centres have four sites at one distance, then eight at the next, so the
    // first twelve levels come in runs of equal distances.
    let m = machine();
    let frame = Frame::pixels(40, 40).unwrap();
    let sites: Vec<DVec2> = (0..100)
        .map(|i| DVec2::new((i % 10 * 4) as f64, (i / 10 * 4) as f64))
        .collect();
    for speedup in SPEEDUPS {
        let d = k_nearest(
            &Backend::Device(&m),
            &sites,
            &KNearestOptions::exact(frame, 12).speedup(speedup),
        )
        .unwrap();
        assert_levels(&d, &sites, &frame, &format!("lattice {speedup:?}"));
        // Pixel (18, 22) is the centre of a lattice cell: 4 sites at sqrt 8.
        let p = (22 * 40 + 18) * 12;
        let first: Vec<f32> = d.distances[p..p + 4].to_vec();
        assert!(first.iter().all(|x| *x == 8f32.sqrt()), "{first:?}");
        assert!(d.distances[p + 4] > 8f32.sqrt());
    }
}

#[test]
fn more_levels_than_sites_stay_empty() {
    let m = machine();
    let frame = Frame::pixels(30, 20).unwrap();
    let sites = [
        DVec2::new(3.0, 4.0),
        DVec2::new(20.5, 11.0),
        DVec2::new(3.0, 4.0),
    ];
    let d = k_nearest(
        &Backend::Device(&m),
        &sites,
        &KNearestOptions::exact(frame, 5),
    )
    .unwrap();
    assert_levels(&d, &sites, &frame, "three sites, five levels");
}

#[test]
fn order_sets_are_the_sets_of_nearest_sites() {
    let m = machine();
    let frame = Frame::pixels(64, 48).unwrap();
    let (_, sites) = cases(64, 48).remove(0);
    let k = 3;
    let d = k_nearest(
        &Backend::Device(&m),
        &sites,
        &KNearestOptions::exact(frame, k),
    )
    .unwrap();
    let sets = d.order_sets();
    let truth = k_nearest_brute_force(&sites, &frame, k as usize);
    for (p, expected) in truth.iter().enumerate() {
        let set = &sets[p * 3..][..3];
        assert!(set.windows(2).all(|w| w[0] < w[1]));
        // Real coordinates: no ties, so the sets agree exactly.
        let mut want: Vec<u32> = expected.iter().map(|e| e.0).collect();
        want.sort_unstable();
        assert_eq!(set, &want[..], "pixel {p}");
    }
}

#[test]
fn furthest_site_matches_the_definition() {
    let m = machine();
    let frame = Frame::pixels(80, 60).unwrap();
    let metrics = [
        Metric::L2,
        Metric::L1,
        Metric::LInf,
        Metric::Lp(0.5),
        Metric::Lp(3.0),
    ];
    for metric in metrics {
        for (name, sites) in cases(80, 60) {
            let name = format!("{metric} {name}");
            let f = furthest(&Backend::Device(&m), &sites, &frame, metric)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            let (_, best) = furthest_brute_force(&sites, &frame, metric);
            let w = frame.width as usize;
            for (p, &label) in f.labels.iter().enumerate() {
                let q = DVec2::new((p % w) as f64, (p / w) as f64);
                let dl = metric.distance(sites[label as usize] - q);
                assert!(
                    close(dl, best[p]) && close(f.distances[p] as f64, best[p]),
                    "{name}: pixel {q}: site {label} at {dl}, furthest at {}",
                    best[p]
                );
            }
        }
    }
}

#[test]
fn convex_hull_of_degenerate_sets() {
    let p = |x: f64, y: f64| DVec2::new(x, y);
    assert_eq!(convex_hull(&[p(1.0, 1.0)]), vec![0]);
    assert_eq!(convex_hull(&[p(1.0, 1.0), p(1.0, 1.0)]).len(), 1);
    // Collinear: the two ends.
    let line: Vec<DVec2> = (0..6).map(|i| p(i as f64, 2.0 * i as f64)).collect();
    let mut h = convex_hull(&line);
    h.sort_unstable();
    assert_eq!(h, vec![0, 5]);
    // A square with points on its edges and inside.
    let square = [
        p(0.0, 0.0),
        p(2.0, 0.0),
        p(4.0, 0.0),
        p(4.0, 4.0),
        p(0.0, 4.0),
        p(1.0, 1.0),
        p(0.0, 2.0),
        p(4.0, 4.0),
    ];
    let mut h = convex_hull(&square);
    h.sort_unstable();
    assert_eq!(h, vec![0, 2, 3, 4]);
}

#[test]
fn convex_hull_equals_the_pairs_with_every_point_on_one_side() {
    use rand::SeedableRng;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(21);
    for points in [
        crate::common::uniform(&mut rng, 300, 100.0, 80.0),
        crate::common::clustered(&mut rng, 300, 100.0, 80.0),
    ] {
        let orient = |a: DVec2, b: DVec2, c: DVec2| (b - a).perp_dot(c - a);
        // Brute force: (a, b) is a hull edge when no point is to its right.
        let mut truth: Vec<u32> = Vec::new();
        for a in 0..points.len() {
            for b in 0..points.len() {
                if a != b
                    && points
                        .iter()
                        .all(|&c| orient(points[a], points[b], c) >= 0.0)
                {
                    truth.push(a as u32);
                }
            }
        }
        truth.sort_unstable();
        truth.dedup();
        let mut h = convex_hull(&points);
        h.sort_unstable();
        assert_eq!(h, truth);
    }
}

#[test]
fn bad_input_is_a_clear_error() {
    let m = machine();
    let frame = Frame::pixels(10, 10).unwrap();
    let sites = [DVec2::new(1.0, 1.0)];
    let opts = |k| KNearestOptions::exact(frame, k);
    assert!(k_nearest(&Backend::Device(&m), &sites, &opts(0)).is_err());
    assert!(k_nearest(&Backend::Device(&m), &sites, &opts(100_000)).is_err());
    assert!(k_nearest(&Backend::Device(&m), &[], &opts(2)).is_err());
    assert!(k_nearest(&Backend::Device(&m), &[DVec2::new(f64::NAN, 0.0)], &opts(2)).is_err());
    assert!(furthest(&Backend::Device(&m), &[], &frame, Metric::L2).is_err());
}

#[test]
fn cpu_pixel_algorithm_matches_the_definition_and_the_gpu() {
    let m = machine();
    let frame = Frame::pixels(97, 73).unwrap();
    // Thesis §3.12.1–3.12.2 with every metric: the CPU's levels equal the
    // definition and the GPU's.
    let metrics = [
        Metric::L2,
        Metric::L1,
        Metric::LInf,
        Metric::Lp(0.5),
        Metric::Lp(3.0),
    ];
    for metric in metrics {
        for (name, sites) in cases(97, 73) {
            let name = format!("{metric} {name}");
            for k in [1, 4] {
                let c = k_nearest(
                    &Backend::Cpu,
                    &sites,
                    &KNearestOptions::exact(frame, k).metric(metric),
                )
                .unwrap_or_else(|e| panic!("{name}: {e}"));
                if metric == Metric::L2 {
                    assert_levels(&c, &sites, &frame, &format!("cpu {name} k={k}"));
                } else {
                    let truth = k_nearest_by_metric(&sites, &frame, k as usize, metric);
                    for (p, expected) in truth.iter().enumerate() {
                        for (l, &(_, dist)) in expected.iter().enumerate() {
                            let got = c.distances[p * k as usize + l] as f64;
                            assert!(
                                close(got, dist),
                                "cpu {name}: pixel {p} level {l}: {got} vs {dist}"
                            );
                        }
                    }
                }
                let g = k_nearest(
                    &Backend::Device(&m),
                    &sites,
                    &KNearestOptions::exact(frame, k).metric(metric),
                )
                .unwrap();
                for (a, b) in c.distances.iter().zip(&g.distances) {
                    assert!(
                        a == b || close(*a as f64, *b as f64),
                        "{name}: cpu {a} gpu {b}"
                    );
                }
            }
            let f = furthest(&Backend::Cpu, &sites, &frame, metric).unwrap();
            let g = furthest(&Backend::Device(&m), &sites, &frame, metric).unwrap();
            for (a, b) in f.distances.iter().zip(&g.distances) {
                assert!(
                    close(*a as f64, *b as f64),
                    "{name}: furthest cpu {a} gpu {b}"
                );
            }
        }
    }
}

#[test]
fn the_thesis_peeling_gives_the_same_levels() {
    // Two depth buffers (thesis §3.7), ties peeled by site id: the same
    // distances, and equally far sites each on a level of their own.
    let m = machine();
    let frame = Frame::pixels(60, 50).unwrap();
    let lattice: Vec<DVec2> = (0..100)
        .map(|i| DVec2::new((i % 10 * 6) as f64, (i / 10 * 5) as f64))
        .collect();
    let mut inputs = cases(60, 50);
    inputs.push(("lattice 6x5", lattice));
    for (name, sites) in inputs {
        for speedup in [Speedup::Quadtree, Speedup::Local] {
            let options = KNearestOptions::exact(frame, 5).speedup(speedup);
            let d = k_nearest_peeled(&m, &sites, &options)
                .unwrap_or_else(|e| panic!("{name} {speedup:?}: {e}"));
            assert_levels(&d, &sites, &frame, &format!("peeled {name} {speedup:?}"));
            // The same labels and distances, bit for bit, as the default's and
            // the CPU's.
            let drawn = k_nearest(&Backend::Device(&m), &sites, &options).unwrap();
            let on_cpu =
                k_nearest(&Backend::Cpu, &sites, &KNearestOptions::exact(frame, 5)).unwrap();
            let bits = |d: &KNearest| d.distances.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            for (route, other) in [("default", &drawn), ("cpu", &on_cpu)] {
                assert!(
                    d.labels == other.labels && bits(&d) == bits(other),
                    "{name} {speedup:?}: peeled and {route} differ"
                );
            }
        }
    }
}

#[test]
fn other_metrics_give_their_k_nearest() {
    // L1, L-infinity and L_p, by the tiles, the atomic lists and the peeling.
    let m = machine();
    let frame = Frame::pixels(50, 40).unwrap();
    for metric in [Metric::L1, Metric::LInf, Metric::Lp(0.5), Metric::Lp(3.0)] {
        for (name, sites) in cases(50, 40).into_iter().take(3) {
            for speedup in [Speedup::Quadtree, Speedup::Local] {
                for k in [3, 33] {
                    let options = KNearestOptions::exact(frame, k)
                        .metric(metric)
                        .speedup(speedup);
                    let what = format!("{metric} {name} {speedup:?} k={k}");
                    let d = k_nearest(&Backend::Device(&m), &sites, &options)
                        .unwrap_or_else(|e| panic!("{what}: {e}"));
                    assert_levels_in(&d, &sites, &frame, &what, metric);
                }
                let options = KNearestOptions::exact(frame, 3)
                    .metric(metric)
                    .speedup(speedup);
                let d = k_nearest_peeled(&m, &sites, &options).unwrap();
                assert_levels_in(
                    &d,
                    &sites,
                    &frame,
                    &format!("peeled {metric} {name}"),
                    metric,
                );
            }
        }
    }
}

#[test]
fn the_cpu_growth_skips_to_far_sites() {
    // Sites 1e8 pixels out grow through no ring that misses the picture: as
    // fast as near ones, and exact (in f64, which the GPU's f32 is not there).
    let frame = Frame::pixels(64, 64).unwrap();
    let sites = [
        DVec2::new(-1e8, 5.0),
        DVec2::new(1e8, 30.0),
        DVec2::new(2e8, -3e8),
    ];
    let started = std::time::Instant::now();
    let d = k_nearest(&Backend::Cpu, &sites, &KNearestOptions::exact(frame, 2)).unwrap();
    assert!(started.elapsed().as_secs() < 5);
    assert_levels(&d, &sites, &frame, "far sites on the CPU");
    // Past 1e9 pixels the nearest site comes from the search by blocks; more
    // levels are refused.
    let farther = [DVec2::new(1e12, 0.0), DVec2::new(-1e12, 3.0)];
    let d = k_nearest(&Backend::Cpu, &farther, &KNearestOptions::exact(frame, 1)).unwrap();
    assert_levels(&d, &farther, &frame, "sites 1e12 out on the CPU");
    assert!(
        k_nearest(&Backend::Cpu, &farther, &KNearestOptions::exact(frame, 2))
            .unwrap_err()
            .to_string()
            .contains("pixels from the picture")
    );
}

#[test]
fn repeated_sites_cost_one_position_and_keep_their_ids() {
    // A hundred thousand copies of one point beside three others, on a small
    // lattice whose pixels tie: every route gives the brute force's levels
    // (equal distances by index, copies included), at the cost of four sites.
    let m = machine();
    let frame = Frame::pixels(24, 20).unwrap();
    let mut sites = vec![DVec2::new(6.0, 5.0); 100_000];
    sites.splice(1..1, [DVec2::new(12.0, 5.0), DVec2::new(6.0, 15.0)]);
    sites.push(DVec2::new(12.0, 15.0));
    sites.push(DVec2::new(12.0, 5.0));
    // Brute force over the positions, spread as the definition orders them.
    let positions = [0u32, 1, 2, 100_002];
    let ids = |p: u32| -> Vec<u32> {
        (0..sites.len() as u32)
            .filter(|&i| sites[i as usize] == sites[p as usize])
            .collect()
    };
    let k = 3;
    for metric in [Metric::L2, Metric::L1] {
        let options = KNearestOptions::exact(frame, k).metric(metric);
        let routes = [
            (
                "levels",
                k_nearest(&Backend::Device(&m), &sites, &options).unwrap(),
            ),
            ("peeled", k_nearest_peeled(&m, &sites, &options).unwrap()),
            (
                "cpu",
                k_nearest(
                    &Backend::Cpu,
                    &sites,
                    &KNearestOptions::exact(frame, k).metric(metric),
                )
                .unwrap(),
            ),
        ];
        let distinct: Vec<DVec2> = positions.iter().map(|&p| sites[p as usize]).collect();
        let truth = k_nearest_by_metric(&distinct, &frame, distinct.len(), metric);
        for (p, levels) in truth.iter().enumerate() {
            // Positions by distance, each tie's sites in index order.
            let mut expected: Vec<u32> = Vec::new();
            let mut l = 0;
            while l < levels.len() {
                let mut run: Vec<u32> = Vec::new();
                let d = levels[l].1;
                while l < levels.len() && levels[l].1 == d {
                    run.extend(ids(positions[levels[l].0 as usize]));
                    l += 1;
                }
                run.sort_unstable();
                expected.extend(run);
            }
            expected.truncate(k as usize);
            for (name, near) in &routes {
                let got = &near.labels[p * k as usize..][..k as usize];
                assert_eq!(got, &expected[..], "{name} {metric}: pixel {p}");
            }
        }
    }
}

/// The CPU's growth reports its radius, up to its last, and answers as
/// without a report.
#[test]
fn cpu_growth_reports_its_progress() {
    let frame = Frame::pixels(64, 48).unwrap();
    let sites = [
        DVec2::new(3.0, 4.0),
        DVec2::new(40.5, 20.0),
        DVec2::new(60.0, 45.0),
    ];
    let told = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
    let tell = told.clone();
    let control = pixgeo::Control::new().progress(move |d, t| tell.lock().unwrap().push((d, t)));
    let options = KNearestOptions::exact(frame, 2).control(control);
    let reported = k_nearest(&Backend::Cpu, &sites, &options).unwrap();
    let told = told.lock().unwrap().clone();
    let plain = k_nearest(&Backend::Cpu, &sites, &KNearestOptions::exact(frame, 2)).unwrap();
    assert_eq!(reported.labels, plain.labels);
    let total = told.last().unwrap().1;
    assert!(
        told.iter().all(|&(d, t)| t == total && d <= total),
        "{told:?}"
    );
    assert!(told.windows(2).all(|w| w[0].0 < w[1].0), "{told:?}");
}

/// The furthest site of every pixel against rational arithmetic from the
/// doubles given, equal distances to the smaller index, and the same labels
/// and distances bit for bit on the device and on the CPU: on sites one ulp
/// off a lattice, on exact ties, and on the sites where a float key names the
/// wrong site.
#[test]
fn furthest_is_exact_and_the_same_on_every_route() {
    use pixgeo_reference::exact::exact_key;
    let m = machine();
    let p = |x: f64, y: f64| DVec2::new(x, y);
    let nudge = |v: f64, k: i64| f64::from_bits((v.to_bits() as i64 + k) as u64);
    let mut cases: Vec<(&str, Frame, Vec<DVec2>)> = vec![
        (
            "a float key names site 1",
            Frame::pixels(40, 32).unwrap(),
            vec![p(40.00000000000001, 32.0), p(0.0, 32.0), p(0.0, 8.0)],
        ),
        (
            "two sites, a tied column",
            Frame::pixels(8, 4).unwrap(),
            vec![p(0.0, 0.0), p(4.0, 0.0)],
        ),
        (
            "repeats on the hull",
            Frame::pixels(12, 10).unwrap(),
            vec![
                p(9.0, 1.0),
                p(1.0, 1.0),
                p(9.0, 1.0),
                p(5.0, 9.0),
                p(1.0, 1.0),
            ],
        ),
    ];
    for (k, name) in [
        (1, "lattice + 1 ulp"),
        (-1, "lattice - 1 ulp"),
        (0, "lattice"),
    ] {
        let sites = (0..16)
            .map(|i| {
                let (x, y) = ((i % 4 * 7) as f64 + 3.0, (i / 4 * 5) as f64 + 2.0);
                p(nudge(x, k * (i % 3 - 1)), nudge(y, k * (i % 2)))
            })
            .collect();
        cases.push((name, Frame::pixels(30, 24).unwrap(), sites));
    }
    for metric in [Metric::L2, Metric::LInf, Metric::L1] {
        for (name, frame, sites) in &cases {
            let name = format!("{metric} {name}");
            let device = furthest(&Backend::Device(&m), sites, frame, metric).unwrap();
            let on_cpu = furthest(&Backend::Cpu, sites, frame, metric).unwrap();
            assert!(
                device.labels == on_cpu.labels,
                "{name}: labels differ by route"
            );
            let bits = |d: &[f32]| d.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert!(
                bits(&device.distances) == bits(&on_cpu.distances),
                "{name}: distances differ by route"
            );
            let w = frame.width;
            for (q, &label) in device.labels.iter().enumerate() {
                let (i, j) = (q as u32 % w, q as u32 / w);
                let keys: Vec<_> = sites
                    .iter()
                    .map(|&s| exact_key(frame, metric, s, i, j))
                    .collect();
                let far = keys.iter().max().unwrap();
                let first = keys.iter().position(|k| k == far).unwrap() as u32;
                assert_eq!(label, first, "{name}: pixel ({i}, {j})");
            }
        }
    }
}
