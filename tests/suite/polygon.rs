//! Polygonal distances (thesis §3.6.5): the unit ball is any polygon star-shaped
//! around its kernel point, convex or not, symmetric or not. Every diagram kind
//! against its definition.

use pixgeo::Backend;
use std::f64::consts::TAU;

use glam::DVec2;
use pixgeo::{
    algorithms::{
        higher_order::{furthest, k_nearest, k_nearest_peeled, KNearestOptions},
        voronoi::{voronoi, Accuracy, Speedup, VoronoiOptions},
    },
    geometry::{
        metric::Metric,
        site::{Shape, Site},
        Frame,
    },
};
use pixgeo_reference::{
    higher_order::{furthest_brute_force, k_nearest_by_metric},
    voronoi::{nearest_distances_metric, nearest_weighted_distances},
};

use crate::common::{cases, machine};

/// A five-pointed star around a kernel off its centre (not convex, not
/// symmetric), and a triangle (convex, not symmetric).
fn polygons() -> Vec<(&'static str, Metric)> {
    let kernel = DVec2::new(0.3, -0.2);
    let star: Vec<DVec2> = (0..10)
        .map(|k| {
            let a = TAU * k as f64 / 10.0;
            let r = if k % 2 == 0 { 1.6 } else { 0.7 };
            DVec2::new(a.cos(), a.sin()) * r + kernel * 0.5
        })
        .collect();
    let triangle = [
        DVec2::new(2.0, 0.0),
        DVec2::new(-1.0, 1.5),
        DVec2::new(-0.5, -1.0),
    ];
    vec![
        (
            "star",
            Metric::polygon(&star, kernel * 0.5 + DVec2::new(0.05, 0.0)).unwrap(),
        ),
        ("triangle", Metric::polygon(&triangle, DVec2::ZERO).unwrap()),
    ]
}

/// Equal up to float32 and the rasterizer's snapping of fan vertices to its
/// subpixel grid (1/256 pixel on lavapipe), which moves a distance by up to the
/// gauge's steepest slope, b, per pixel of displacement.
fn close(metric: Metric, a: f64, b: f64) -> bool {
    (a - b).abs() <= 2e-3 * (1.0 + b) + metric.euclidean_bounds().1 / 128.0
}

#[test]
fn ordinary_diagrams_match_the_definition_with_every_speedup() {
    let m = machine();
    let frame = Frame::pixels(61, 47).unwrap();
    for (name, metric) in polygons() {
        for (case, sites) in cases(61, 47) {
            let truth = nearest_distances_metric(&sites, &frame, metric);
            for speedup in [Speedup::None, Speedup::Quadtree, Speedup::Local] {
                for accuracy in [Accuracy::Exact, Accuracy::FAN] {
                    let what = format!("{name} {case} {speedup:?} {accuracy:?}");
                    let d = voronoi(
                        &Backend::Device(&m),
                        &sites,
                        &VoronoiOptions::exact(frame)
                            .metric(metric)
                            .speedup(speedup)
                            .accuracy(accuracy),
                    )
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                    // The fan over the polygon is its distance: no error bound.
                    assert_eq!(d.stats.distance_error_bound, 0.0, "{what}");
                    for (k, &label) in d.labels.iter().enumerate() {
                        let q = DVec2::new((k % 61) as f64, (k / 61) as f64);
                        assert_ne!(label, u32::MAX, "{what}: {q} uncovered");
                        let mine = metric.distance(q - sites[label as usize]);
                        assert!(
                            close(metric, mine, truth[k])
                                && close(metric, d.distances[k] as f64, truth[k]),
                            "{what}: pixel {q}: site {label} at {mine}, map {}, nearest {}",
                            d.distances[k],
                            truth[k]
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn curves_are_refused_in_exact_mode_and_bounded_in_fan_mode() {
    // The distance to a circle under a gauge is curved, with no closed form:
    // exact mode refuses it on every device, and
    // fan mode's chords cost the gauge's steepest slope per pixel of deviation,
    // which for a non-convex star exceeds its largest radius ratio.
    let m = machine();
    let frame = Frame::pixels(96, 80).unwrap();
    let (_, star) = polygons().remove(0);
    let mut sites: Vec<Site> = cases(96, 80)
        .remove(0)
        .1
        .into_iter()
        .map(Site::point)
        .collect();
    for (k, r) in [3.0, 9.5, 17.0, 30.0].into_iter().enumerate() {
        let mut circle = Site::point(DVec2::ZERO);
        circle.shape = Shape::Circle {
            center: DVec2::new(15.0 + 22.0 * k as f64, 20.0 + 13.0 * k as f64),
            radius: r,
        };
        sites.push(circle);
    }
    let exact = VoronoiOptions::exact(frame).metric(star);
    let refused = voronoi(&Backend::Device(&m), &sites, &exact)
        .unwrap_err()
        .to_string();
    assert!(refused.contains("no exact distance"), "{refused}");
    assert!(crate::common::cpu_sites(&sites, &frame, star).is_err());
    let truth = nearest_weighted_distances(&sites, &frame, star);
    let fan = exact.accuracy(Accuracy::FAN);
    let d = voronoi(&Backend::Device(&m), &sites, &fan).unwrap();
    let bound = d.stats.distance_error_bound;
    for (k, &label) in d.labels.iter().enumerate() {
        let q = DVec2::new((k % 96) as f64, (k / 96) as f64);
        let mine = sites[label as usize].distance(star, q);
        let depth = d.distances[k] as f64;
        assert!(
            (depth - truth[k]).abs() <= bound + 1e-2 && mine <= truth[k] + 2.0 * bound + 1e-2,
            "pixel {q}: site {label} at {mine}, map {depth}, nearest {}, bound {bound}",
            truth[k]
        );
    }
}

#[test]
fn levels_furthest_and_cpu_match_the_definition() {
    let m = machine();
    let frame = Frame::pixels(53, 41).unwrap();
    for (name, metric) in polygons() {
        for (case, sites) in cases(53, 41).into_iter().take(6) {
            let what = format!("{name} {case}");
            let k = 3;
            let truth = k_nearest_by_metric(&sites, &frame, k, metric);
            let options = KNearestOptions::exact(frame, k as u32).metric(metric);
            let g = k_nearest(&Backend::Device(&m), &sites, &options)
                .unwrap_or_else(|e| panic!("{what}: {e}"));
            let c = k_nearest(
                &Backend::Cpu,
                &sites,
                &KNearestOptions::exact(frame, k as u32).metric(metric),
            )
            .unwrap();
            for (p, expected) in truth.iter().enumerate() {
                for (l, &(_, dist)) in expected.iter().enumerate() {
                    let (gd, cd) = (g.distances[p * k + l] as f64, c.distances[p * k + l] as f64);
                    assert!(
                        close(metric, gd, dist) && close(metric, cd, dist),
                        "{what}: pixel {p} level {l}: gpu {gd} cpu {cd} vs {dist}"
                    );
                }
            }
            let (_, far) = furthest_brute_force(&sites, &frame, metric);
            let f = furthest(&Backend::Device(&m), &sites, &frame, metric).unwrap();
            let fc = furthest(&Backend::Cpu, &sites, &frame, metric).unwrap();
            for (p, &want) in far.iter().enumerate() {
                let (gpu, cpu) = (f.distances[p] as f64, fc.distances[p] as f64);
                assert!(
                    close(metric, gpu, want) && close(metric, cpu, want),
                    "{what}: furthest at pixel {p}: gpu {gpu} cpu {cpu} vs {want}"
                );
            }
            // The thesis's peeling evaluates exact distances per fragment: not
            // for polygons.
            assert!(k_nearest_peeled(&m, &sites, &options).is_err());
        }
    }
}

#[test]
fn weighted_points_and_segments_match_the_definition() {
    let m = machine();
    let frame = Frame::pixels(64, 48).unwrap();
    let p = DVec2::new;
    let sites = vec![
        Site::new(Shape::Segment(p(5.0, 5.0), p(40.0, 12.0))),
        Site {
            multiplicative: 2.0,
            ..Site::point(p(50.0, 40.0))
        },
        Site {
            additive: 3.0,
            ..Site::point(p(15.0, 35.0))
        },
        Site::new(Shape::Segment(p(60.0, 2.0), p(60.0, 2.0))),
    ];
    for (name, metric) in polygons() {
        let truth = nearest_weighted_distances(&sites, &frame, metric);
        for accuracy in [Accuracy::Exact, Accuracy::FAN] {
            let d = voronoi(
                &Backend::Device(&m),
                &sites,
                &VoronoiOptions::exact(frame)
                    .metric(metric)
                    .accuracy(accuracy),
            )
            .unwrap_or_else(|e| panic!("{name}: {e}"));
            for (k, &label) in d.labels.iter().enumerate() {
                let q = DVec2::new((k % 64) as f64, (k / 64) as f64);
                let mine = sites[label as usize].distance(metric, q);
                assert!(
                    close(metric, mine, truth[k]) && close(metric, d.distances[k] as f64, truth[k]),
                    "{name} {accuracy:?}: pixel {q}: site {label} at {mine}, map {}, nearest {}",
                    d.distances[k],
                    truth[k]
                );
            }
        }
    }
}

#[test]
fn unsupported_combinations_are_clear_errors() {
    let m = machine();
    let frame = Frame::pixels(16, 16).unwrap();
    let (_, metric) = polygons().remove(0);
    let ties = VoronoiOptions::exact(frame).metric(metric).ties(true);
    assert!(voronoi(&Backend::Device(&m), &[DVec2::ZERO], &ties).is_err());
    use pixgeo::algorithms::settle::{potential_areas, SettleOptions};
    let settle = potential_areas(
        &Backend::Cpu,
        &[DVec2::ZERO],
        &[],
        &SettleOptions::new(frame).metric(metric),
    );
    assert!(settle.is_err());
}

#[test]
fn polygons_of_every_size_float32_holds_and_no_other() {
    // Distances go through float32: a polygon 1e39 across gave distances below
    // its smallest normal number, and 4024 of 4096 pixels the wrong site.
    let m = crate::common::machine();
    let frame = Frame::pixels(64, 64).unwrap();
    let sites = [
        DVec2::new(1.0, 2.0),
        DVec2::new(5.0, 7.0),
        DVec2::new(9.0, 1.0),
    ];
    let square = |e: f64| {
        let v = [(e, 0.0), (0.0, e), (-e, 0.0), (0.0, -e)];
        Metric::polygon(&v.map(|(x, y)| DVec2::new(x, y)), DVec2::ZERO)
    };
    for e in [1e-19, 1e19] {
        let metric = square(e).unwrap();
        let truth = nearest_distances_metric(&sites, &frame, metric);
        let options = VoronoiOptions::exact(frame).metric(metric);
        let d = voronoi(&Backend::Device(&m), &sites, &options).unwrap();
        for (k, &label) in d.labels.iter().enumerate() {
            let q = DVec2::new((k % 64) as f64, (k / 64) as f64);
            let mine = metric.distance(sites[label as usize] - q);
            assert!(mine <= truth[k] * (1.0 + 1e-6), "{e}: pixel {q}");
        }
    }
    for e in [1e-21, 1e21, 1e39] {
        let err = square(e).unwrap_err();
        assert!(err.contains("scale the polygon"), "{err}");
    }
}
