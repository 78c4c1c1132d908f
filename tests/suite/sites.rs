//! Generalized Voronoi diagrams (thesis §3.8–3.9) against the per-pixel
//! definition: weighted points, segments, circles and arcs, mixed, under every
//! metric that takes them, on random and degenerate inputs.

use std::f64::consts::PI;

use glam::DVec2;
use pixgeo::Backend;
use pixgeo::{
    algorithms::voronoi::{voronoi, Accuracy, Speedup, VoronoiOptions},
    geometry::{
        metric::Metric,
        site::{Shape, Site},
        Frame,
    },
    Machine,
};
use pixgeo_reference::voronoi::{curve_sampling_slack, nearest_weighted_distances};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

pub(crate) fn weighted(shape: Shape, m: f64, a: f64) -> Site {
    Site {
        shape,
        multiplicative: m,
        additive: a,
    }
}

/// Random sites of the given kinds with random weights (or none).
fn random_sites(
    rng: &mut ChaCha8Rng,
    n: usize,
    kinds: &[u32],
    weights: bool,
    w: f64,
    h: f64,
) -> Vec<Site> {
    let mut point = || DVec2::new(rng.gen_range(-5.0..w + 5.0), rng.gen_range(-5.0..h + 5.0));
    let shapes: Vec<Shape> = (0..n)
        .map(|i| match kinds[i % kinds.len()] {
            0 => Shape::Point(point()),
            1 => {
                let a = point();
                Shape::Segment(a, a + (point() - a) * 0.3)
            }
            2 => Shape::Circle {
                center: point(),
                radius: 2.0 + 10.0 * (i % 3) as f64,
            },
            _ => {
                let start = (i as f64) * 0.7;
                Shape::Arc {
                    center: point(),
                    radius: 3.0 + 7.0 * (i % 4) as f64,
                    start,
                    end: start + 0.5 + (i % 5) as f64,
                }
            }
        })
        .collect();
    shapes
        .into_iter()
        .enumerate()
        .map(|(i, s)| {
            if weights {
                weighted(s, 0.5 + (i % 4) as f64 * 0.5, (i % 3) as f64 * 3.0 - 3.0)
            } else {
                Site::new(s)
            }
        })
        .collect()
}

/// A zero-length segment, a zero-radius circle, arcs of zero and full angle.
fn degenerate_shapes() -> Vec<Site> {
    let p = DVec2::new;
    vec![
        Site::new(Shape::Segment(p(10.0, 10.0), p(10.0, 10.0))),
        Site::new(Shape::Circle {
            center: p(50.0, 30.0),
            radius: 0.0,
        }),
        Site::new(Shape::Arc {
            center: p(30.0, 30.0),
            radius: 8.0,
            start: 1.0,
            end: 1.0,
        }),
        Site::new(Shape::Arc {
            center: p(20.0, 40.0),
            radius: 6.0,
            start: -PI,
            end: 3.0 * PI,
        }),
    ]
}

/// Exact mode, with the culling grid and with picture-wide rectangles.
fn check(m: &Machine, sites: &[Site], frame: Frame, metric: Metric, what: &str) {
    for speedup in [Speedup::Local, Speedup::None] {
        check_with(
            m,
            sites,
            frame,
            metric,
            speedup,
            &format!("{what} {speedup:?}"),
        );
    }
}

fn check_with(
    m: &Machine,
    sites: &[Site],
    frame: Frame,
    metric: Metric,
    speedup: Speedup,
    what: &str,
) {
    let d = voronoi(
        &Backend::Device(m),
        sites,
        &VoronoiOptions::exact(frame).metric(metric).speedup(speedup),
    )
    .unwrap_or_else(|e| panic!("{what}: {e}"));
    let truth = nearest_weighted_distances(sites, &frame, metric);
    let slack = curve_sampling_slack(sites, metric);
    let w = frame.width as usize;
    for (k, &label) in d.labels.iter().enumerate() {
        let q = DVec2::new((k % w) as f64, (k / w) as f64);
        assert_ne!(label, u32::MAX, "{what}: pixel {q} uncovered");
        let mine = sites[label as usize].distance(metric, frame.to_world(q));
        // For p < 1 the distance is steep near the axes through a site's points,
        // so rounding the coordinates to float32 moves it more.
        let steep = if matches!(metric, Metric::Lp(p) if p < 1.0) {
            10.0
        } else {
            1.0
        };
        let tol = 1e-3 * steep * (1.0 + truth[k].abs()) + slack;
        assert!(
            mine <= truth[k] + tol && (d.distances[k] as f64 - truth[k]).abs() <= tol,
            "{what}: pixel {q}: site {label} at {mine}, map {}, nearest {}",
            d.distances[k],
            truth[k]
        );
    }
}

#[test]
fn mixed_weighted_sites_match_the_definition() {
    let m = crate::common::machine();
    let frame = Frame::pixels(71, 53).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    // Fig. 3.45: points, segments, circles and arcs in one diagram (Euclidean).
    for weights in [false, true] {
        let sites = random_sites(&mut rng, 40, &[0, 1, 2, 3], weights, 71.0, 53.0);
        check(
            &m,
            &sites,
            frame,
            Metric::L2,
            &format!("mixed weights={weights}"),
        );
    }
    // Points and segments under the other metrics; under L_p segments have
    // no exact distance, and weighted points are drawn alone.
    for metric in [Metric::L1, Metric::LInf, Metric::Lp(0.5), Metric::Lp(3.0)] {
        let kinds: &[u32] = if matches!(metric, Metric::Lp(_)) {
            let segments = random_sites(&mut rng, 4, &[1], false, 71.0, 53.0);
            let exact = VoronoiOptions::exact(frame).metric(metric);
            let refused = voronoi(&Backend::Device(&m), &segments, &exact).unwrap_err();
            assert!(
                refused.to_string().contains("no exact distance"),
                "{refused}"
            );
            &[0]
        } else {
            &[0, 1]
        };
        for weights in [false, true] {
            let sites = random_sites(&mut rng, 30, kinds, weights, 71.0, 53.0);
            check(
                &m,
                &sites,
                frame,
                metric,
                &format!("{metric} weights={weights}"),
            );
        }
    }
    // Many sites: the culling grid gets coarser.
    let sites = random_sites(&mut rng, 3000, &[0, 1, 2, 3], true, 71.0, 53.0);
    check(&m, &sites, frame, Metric::L2, "3000 sites");
}

#[test]
fn degenerate_sites_match_the_definition() {
    let m = crate::common::machine();
    let frame = Frame::pixels(64, 48).unwrap();
    let p = DVec2::new;
    let mut sites = degenerate_shapes();
    sites.extend([
        // Far outside the picture, and a segment crossing it.
        Site::new(Shape::Point(p(-300.0, 500.0))),
        Site::new(Shape::Segment(p(-20.0, 47.0), p(90.0, 0.0))),
    ]);
    check(&m, &sites, frame, Metric::L2, "degenerate");
    // A heavy weight swallows the others' regions; a negative additive weight
    // makes one site win everywhere.
    let mut swallow = sites.clone();
    swallow[2].multiplicative = 50.0;
    check(&m, &swallow, frame, Metric::L2, "swallow");
    let mut lead = sites.clone();
    lead[4].additive = -1000.0;
    check(&m, &lead, frame, Metric::L2, "lead");
    // A world rectangle mapped onto the picture.
    let frame = Frame::with_bbox(64, None, [-1.0, -1.0, 1.0, 0.5]).unwrap();
    let small = vec![
        Site::new(Shape::Segment(p(-0.5, -0.5), p(0.5, 0.2))),
        weighted(
            Shape::Circle {
                center: p(0.3, -0.6),
                radius: 0.2,
            },
            2.0,
            0.1,
        ),
        Site::new(Shape::Point(p(-0.8, 0.4))),
    ];
    check(&m, &small, frame, Metric::L2, "bbox");
}

#[test]
fn bad_sites_are_clear_errors() {
    let m = crate::common::machine();
    let frame = Frame::pixels(16, 16).unwrap();
    let options = VoronoiOptions::exact(frame);
    let circle = Site::new(Shape::Circle {
        center: DVec2::ZERO,
        radius: 3.0,
    });
    let fan = options.clone().accuracy(Accuracy::Fan {
        epsilon: 0.0,
        triangles: None,
    });
    assert!(voronoi(&Backend::Device(&m), &[circle], &fan).is_err());
    let mut zero = circle;
    zero.multiplicative = 0.0;
    assert!(voronoi(&Backend::Device(&m), &[zero], &options).is_err());
    assert!(voronoi(&Backend::Device(&m), &[] as &[Site], &options).is_err());
}

/// Fan mode: the distance map within the reported bound of the definition (either
/// way: chords of circles and arcs may cut inside), and each label's site within
/// twice the bound of the nearest.
fn check_fan(
    m: &Machine,
    sites: &[Site],
    frame: Frame,
    metric: Metric,
    accuracy: Accuracy,
    what: &str,
) {
    let options = VoronoiOptions::exact(frame)
        .metric(metric)
        .accuracy(accuracy);
    check_fan_with(m, sites, &options, what);
}

fn check_fan_with(m: &Machine, sites: &[Site], options: &VoronoiOptions, what: &str) {
    let (frame, metric) = (options.frame, options.metric);
    let d = voronoi(&Backend::Device(m), sites, options).unwrap_or_else(|e| panic!("{what}: {e}"));
    let bound = d.stats.distance_error_bound;
    assert!(bound > 0.0, "{what}");
    let truth = nearest_weighted_distances(sites, &frame, metric);
    let w = frame.width as usize;
    let tol = 0.02 / frame.scale + curve_sampling_slack(sites, metric);
    for (k, &label) in d.labels.iter().enumerate() {
        let q = DVec2::new((k % w) as f64, (k / w) as f64);
        assert_ne!(label, u32::MAX, "{what}: pixel {q} uncovered");
        let depth = d.distances[k] as f64;
        let mine = sites[label as usize].distance(metric, frame.to_world(q));
        assert!(
            (depth - truth[k]).abs() <= bound + tol && mine <= truth[k] + 2.0 * bound + tol,
            "{what}: pixel {q}: depth {depth}, label at {mine}, nearest {}, bound {bound}",
            truth[k]
        );
    }
}

#[test]
fn fans_of_every_site_stay_inside_their_bounds() {
    // Cones with weighted apexes, roofs swept along segments, the straw hut and
    // the sliced hut as swept chords (thesis §3.8–3.9, Fig. 3.41).
    let m = crate::common::machine();
    let frame = Frame::pixels(71, 53).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let fixed = Accuracy::Fan {
        epsilon: 1.0,
        triangles: Some(16),
    };
    for accuracy in [Accuracy::FAN, fixed] {
        let sites = random_sites(&mut rng, 30, &[0, 1, 2, 3], true, 71.0, 53.0);
        check_fan(
            &m,
            &sites,
            frame,
            Metric::L2,
            accuracy,
            &format!("mixed {accuracy:?}"),
        );
        for metric in [Metric::L1, Metric::LInf, Metric::Lp(3.0)] {
            // Points, segments and circles.
            let sites = random_sites(&mut rng, 30, &[0, 1, 2], true, 71.0, 53.0);
            check_fan(
                &m,
                &sites,
                frame,
                metric,
                accuracy,
                &format!("{metric} {accuracy:?}"),
            );
        }
    }
    // Degenerate shapes and a far, heavy site.
    let mut degenerate = degenerate_shapes();
    degenerate.push(weighted(
        Shape::Point(DVec2::new(-300.0, 500.0)),
        20.0,
        -5.0,
    ));
    check_fan(
        &m,
        &degenerate,
        frame,
        Metric::L2,
        Accuracy::FAN,
        "degenerate fans",
    );
}

#[test]
fn fans_under_concave_metrics_are_refused() {
    // Under L_p with p < 1 the ball is not convex: a fan's flat sides cut
    // through it, so no ε bounds a fan of any site (a point at (96, 80) erred
    // by 0.6 pixels at ε = 0.25; past an axis-aligned segment's end, along its
    // line, distances came out near 0 where they are up to 26).
    let m = crate::common::machine();
    let frame = Frame::pixels(128, 112).unwrap();
    let shapes = [
        Shape::Point(DVec2::new(96.0, 80.0)),
        Shape::Segment(DVec2::new(40.0, 10.0), DVec2::new(40.0, 60.0)),
        Shape::Circle {
            center: DVec2::new(60.0, 60.0),
            radius: 25.0,
        },
    ];
    for p in [0.5, 0.7] {
        for shape in shapes {
            let fan = VoronoiOptions::exact(frame)
                .metric(Metric::Lp(p))
                .accuracy(Accuracy::Fan {
                    epsilon: 0.25,
                    triangles: None,
                });
            let refused =
                voronoi(&Backend::Device(&m), &[weighted(shape, 1.0, 0.0)], &fan).unwrap_err();
            assert!(
                refused.to_string().contains("not convex"),
                "{shape:?}: {refused}"
            );
        }
    }
}

#[test]
fn arc_fans_reach_past_their_ends() {
    // An arc's end cones are halves beyond its ends' radial lines: arcs alone,
    // large and of every span (nearly none, a half turn, nearly a full one), so
    // that most pixels take their distance from an end.
    let m = crate::common::machine();
    let frame = Frame::pixels(96, 80).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let spans = [1e-3, 0.4, std::f64::consts::PI, 4.0, 6.2];
    let sites: Vec<Site> = (0..10)
        .map(|i| {
            let start = rng.gen_range(0.0..std::f64::consts::TAU);
            Site::new(Shape::Arc {
                center: DVec2::new(rng.gen_range(0.0..96.0), rng.gen_range(0.0..80.0)),
                radius: rng.gen_range(4.0..30.0),
                start,
                end: start + spans[i % spans.len()],
            })
        })
        .collect();
    for accuracy in [
        Accuracy::FAN,
        Accuracy::Fan {
            epsilon: 1.0,
            triangles: Some(6),
        },
    ] {
        check_fan(&m, &sites, frame, Metric::L2, accuracy, "arcs");
    }
}

#[test]
fn the_cpu_pixel_algorithm_matches_the_definition_and_the_gpu() {
    // Thesis §3.12.1 for every site kind, weight and metric.
    let m = crate::common::machine();
    let frame = Frame::pixels(57, 43).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let mut inputs = vec![(
        Metric::L2,
        random_sites(&mut rng, 25, &[0, 1, 2, 3], true, 57.0, 43.0),
    )];
    for metric in [Metric::L1, Metric::LInf, Metric::Lp(0.5), Metric::Lp(3.0)] {
        let kinds: &[u32] = if matches!(metric, Metric::Lp(_)) {
            &[0]
        } else {
            &[0, 1]
        };
        inputs.push((metric, random_sites(&mut rng, 25, kinds, true, 57.0, 43.0)));
    }
    for (metric, sites) in inputs {
        let (labels, distances) = crate::common::cpu_sites(&sites, &frame, metric).unwrap();
        let truth = nearest_weighted_distances(&sites, &frame, metric);
        for (k, (&label, &d)) in labels.iter().zip(&distances).enumerate() {
            let q = frame.to_world(DVec2::new((k % 57) as f64, (k / 57) as f64));
            let mine = sites[label as usize].distance(metric, q);
            assert!(
                (mine - truth[k]).abs() <= 1e-9 * (1.0 + truth[k].abs())
                    && (d as f64 - truth[k]).abs() <= 1e-5 * (1.0 + truth[k].abs()),
                "{metric}: pixel {q}: site {label} at {mine}, map {d}, nearest {}",
                truth[k]
            );
        }
        let g = voronoi(
            &Backend::Device(&m),
            &sites,
            &VoronoiOptions::exact(frame).metric(metric),
        )
        .unwrap();
        let steep = if matches!(metric, Metric::Lp(p) if p < 1.0) {
            10.0
        } else {
            1.0
        };
        for (a, b) in distances.iter().zip(&g.distances) {
            assert!(
                (a - b).abs() as f64 <= 1e-3 * steep * (1.0 + a.abs() as f64),
                "{metric}: cpu {a} gpu {b}"
            );
        }
    }
}

#[test]
fn circles_and_arcs_under_every_metric() {
    // Euclidean circles and arcs measured with other distances: exact under L1
    // and L∞, refused under L_p and polygons; fans as swept chords; the
    // oracle samples the curve densely.
    let m = crate::common::machine();
    let frame = Frame::pixels(48, 36).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let triangle = [
        DVec2::new(2.0, 0.0),
        DVec2::new(-1.0, 1.5),
        DVec2::new(-0.5, -1.0),
    ];
    let metrics = [
        Metric::L1,
        Metric::LInf,
        Metric::Lp(0.5),
        Metric::Lp(3.0),
        Metric::polygon(&triangle, DVec2::ZERO).unwrap(),
    ];
    for metric in metrics {
        let sites = random_sites(&mut rng, 10, &[2, 3, 0, 2, 3], true, 48.0, 36.0);
        if matches!(metric, Metric::Polygon(_) | Metric::Lp(_)) {
            // Curved under a gauge or L_p: no exact distance, refused on
            // every device.
            let exact = VoronoiOptions::exact(frame).metric(metric);
            let refused = voronoi(&Backend::Device(&m), &sites, &exact).unwrap_err();
            assert!(
                refused.to_string().contains("no exact distance"),
                "{refused}"
            );
            let cpu = crate::common::cpu_sites(&sites, &frame, metric);
            assert!(cpu.is_err());
        } else {
            check(&m, &sites, frame, metric, &format!("curves {metric}"));
            let (_, cpu) = crate::common::cpu_sites(&sites, &frame, metric).unwrap();
            let truth = nearest_weighted_distances(&sites, &frame, metric);
            let slack = curve_sampling_slack(&sites, metric);
            for (k, (&c, &t)) in cpu.iter().zip(&truth).enumerate() {
                assert!(
                    (c as f64) <= t + 1e-4 * (1.0 + t.abs())
                        && (c as f64) >= t - slack - 1e-4 * (1.0 + t.abs()),
                    "curves {metric}: cpu pixel {k}: {c} vs {t}"
                );
            }
        }
        if metric != Metric::Lp(0.5) {
            check_fan(
                &m,
                &sites,
                frame,
                metric,
                Accuracy::FAN,
                &format!("curve fans {metric}"),
            );
        }
    }
}

#[test]
fn tiles_give_the_same_diagram_pixel_for_pixel() {
    // Small tiles, sites on tile borders and outside the picture, both modes.
    let m = crate::common::machine();
    let frame = Frame::pixels(70, 50).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let mut sites = random_sites(&mut rng, 24, &[0, 1, 2, 3], true, 70.0, 50.0);
    let p = DVec2::new;
    sites.extend([
        Site::new(Shape::Segment(p(16.0, -10.0), p(16.0, 60.0))),
        Site::point(p(32.0, 17.0)),
        Site::point(p(-25.0, 20.0)),
    ]);
    let run = |max_tile| {
        voronoi(
            &Backend::Device(&m),
            &sites,
            &VoronoiOptions::exact(frame).max_tile(max_tile),
        )
        .unwrap()
    };
    let (whole, tiled) = (run(None), run(Some(16)));
    assert_eq!(whole.stats.tiles, 1);
    assert_eq!(tiled.stats.tiles, 5 * 4);
    assert_eq!(whole.labels, tiled.labels);
    assert_eq!(whole.distances, tiled.distances);
    // Fans are interpolated per tile: bounded the same way in every tile.
    let fan = VoronoiOptions::exact(frame)
        .accuracy(Accuracy::FAN)
        .max_tile(Some(16));
    check_fan_with(&m, &sites, &fan, "fan tiles");
}

#[test]
fn additive_weights_far_apart_keep_float32_in_range() {
    // A weight of -1e18 wins everywhere; a weight shared by all changes no
    // label. Neither may stretch the depths past float32's resolution.
    let m = crate::common::machine();
    let frame = Frame::pixels(64, 48).unwrap();
    let heavy = [
        weighted(Shape::Point(DVec2::new(10.0, 10.0)), 1.0, -1e18),
        weighted(Shape::Point(DVec2::new(40.0, 40.0)), 1.0, 0.0),
    ];
    let d = voronoi(&Backend::Device(&m), &heavy, &VoronoiOptions::exact(frame)).unwrap();
    assert!(d.labels.iter().all(|&l| l == 0));
    assert!(d.distances.iter().all(|&x| x == -1e18));
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let sites = random_sites(&mut rng, 20, &[0, 1], true, 64.0, 48.0);
    let shifted: Vec<Site> = sites
        .iter()
        .map(|s| Site {
            additive: s.additive + 1e9,
            ..*s
        })
        .collect();
    let a = voronoi(&Backend::Device(&m), &sites, &VoronoiOptions::exact(frame)).unwrap();
    let b = voronoi(
        &Backend::Device(&m),
        &shifted,
        &VoronoiOptions::exact(frame),
    )
    .unwrap();
    assert_eq!(a.labels, b.labels);
}

/// Circles and arcs under L1 and L∞ on the device: the distances are the
/// CPU's to float32 precision (float32 angles, asin near ±1 above all, once
/// moved them by up to 0.006 pixels and mislabelled pixels beside a point).
#[test]
fn curves_under_l1_and_linf_match_the_cpu_on_the_device() {
    let m = crate::common::machine();
    let frame = Frame::pixels(128, 112).unwrap();
    let sites = [
        Shape::Circle {
            center: DVec2::new(64.0, 56.0),
            radius: 20.0,
        },
        Shape::Point(DVec2::new(80.70628082921817, 45.0)),
        Shape::Arc {
            center: DVec2::new(30.0, 30.0),
            radius: 15.0,
            start: 0.3,
            end: 2.5,
        },
        Shape::Point(DVec2::new(100.0, 90.0)),
    ]
    .map(|s| weighted(s, 1.0, 0.0));
    for metric in [Metric::L1, Metric::LInf] {
        let options = VoronoiOptions::exact(frame).metric(metric);
        let device = voronoi(&Backend::Device(&m), &sites, &options).unwrap();
        let (_, cpu) = crate::common::cpu_sites(&sites, &frame, metric).unwrap();
        for (k, (&d, &c)) in device.distances.iter().zip(&cpu).enumerate() {
            assert!(
                (d - c).abs() <= 1e-4,
                "{metric}: pixel {k}: {d} against the CPU's {c}"
            );
        }
        if metric == Metric::L1 {
            // Nearer the circle (5.703293) than the point (5.706281).
            assert_eq!(device.labels[45 * 128 + 75], 0);
        }
    }
}
