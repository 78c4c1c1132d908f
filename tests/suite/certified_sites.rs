//! Exact labels of general sites (weighted points, segments, circles, arcs)
//! for the doubles given: the device, the CPU's pixel algorithm and tiles
//! against intervals of rationals to 2^-128 (`pixgeo_reference::sites`), on
//! random sites and on exact ties seen through a frame of scale 10, whose
//! sites (1.05, 0.15, ...) are not the decimals they are written as, so that
//! their rounding decides each tie; and on the same ties moved by an ulp.

use glam::DVec2;
use pixgeo::Backend;
use pixgeo::{
    algorithms::voronoi::{voronoi, VoronoiOptions},
    geometry::{
        metric::Metric,
        site::{Shape, Site},
        Frame,
    },
    Machine,
};
use pixgeo_reference::sites::nearest_general_sites;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::{
    common::{machine, ulps},
    sites::weighted,
};

/// π as people type it: the arc's end lies 2.9e-8 off the centre's row.
#[allow(clippy::approx_constant)]
const TYPED_PI: f64 = 3.14159265;

/// Ties by construction, in world units of a frame of scale 10: concentric
/// circles, mirrored points and arcs, parallel segments, a point on a circle's
/// centre, weights that balance.
fn ties() -> Vec<Site> {
    let p = DVec2::new;
    vec![
        weighted(
            Shape::Circle {
                center: p(1.05, 1.05),
                radius: 0.3,
            },
            1.0,
            0.0,
        ),
        weighted(
            Shape::Circle {
                center: p(1.05, 1.05),
                radius: 0.7,
            },
            1.0,
            0.0,
        ),
        weighted(Shape::Point(p(0.25, 2.55)), 1.0, 0.1),
        weighted(Shape::Point(p(0.85, 2.55)), 1.0, 0.1),
        weighted(Shape::Segment(p(2.1, 0.15), p(3.9, 0.15)), 2.0, 0.0),
        weighted(Shape::Segment(p(2.1, 0.95), p(3.9, 0.95)), 2.0, 0.0),
        weighted(Shape::Point(p(3.05, 2.05)), 0.5, 0.2),
        weighted(
            Shape::Circle {
                center: p(3.05, 2.05),
                radius: 0.4,
            },
            1.0,
            0.0,
        ),
        weighted(
            Shape::Arc {
                center: p(1.55, 3.55),
                radius: 0.5,
                start: 0.5,
                end: 2.0,
            },
            1.0,
            0.0,
        ),
        weighted(Shape::Segment(p(0.05, 3.05), p(0.05, 3.95)), 1.0, 0.05),
    ]
}

/// Random sites of every kind and weight.
fn random(rng: &mut ChaCha8Rng, n: usize) -> Vec<Site> {
    let mut at = || DVec2::new(rng.gen_range(-0.3..4.3), rng.gen_range(-0.3..4.3));
    let shapes: Vec<Shape> = (0..n)
        .map(|i| match i % 4 {
            0 => Shape::Point(at()),
            1 => {
                let a = at();
                Shape::Segment(a, a + (at() - a) * 0.3)
            }
            2 => Shape::Circle {
                center: at(),
                radius: 0.1 + 0.05 * (i % 7) as f64,
            },
            _ => {
                let start = i as f64 * 0.9;
                Shape::Arc {
                    center: at(),
                    radius: 0.2 + 0.1 * (i % 5) as f64,
                    start,
                    end: start + 0.4 + (i % 6) as f64,
                }
            }
        })
        .collect();
    shapes
        .into_iter()
        .map(|s| weighted(s, rng.gen_range(0.5..2.0), rng.gen_range(-0.1..0.1)))
        .collect()
}

/// The frame of scale 10 the sites are drawn in: pixel (i, j) is centred on
/// world point ((i - 0.5) / 10, (j - 0.5) / 10).
const DECIMAL: Frame = Frame {
    width: 44,
    height: 42,
    origin: DVec2::new(-0.1, -0.1),
    scale: 10.0,
};

/// Every route's labels equal the exact nearest (the smallest index of equally
/// near ones), and their distances agree to the bit. Returns the pixels with
/// exact ties, and those whose two nearest are within 1e-12 in doubles.
fn check(m: &Machine, sites: &[Site], frame: Frame, metric: Metric, what: &str) -> [usize; 2] {
    let exact = VoronoiOptions::exact(frame).metric(metric);
    let device =
        voronoi(&Backend::Device(m), sites, &exact).unwrap_or_else(|e| panic!("{what}: {e}"));
    let tiled = voronoi(&Backend::Device(m), sites, &exact.max_tile(Some(16))).unwrap();
    let (labels, distances) = crate::common::cpu_sites(sites, &frame, metric).unwrap();
    let truth = nearest_general_sites(sites, &frame, metric);
    let w = frame.width as usize;
    let mut counts = [0, 0];
    for (k, near) in truth.iter().enumerate() {
        let q = frame.to_world(DVec2::new((k % w) as f64, (k / w) as f64));
        let mut floats: Vec<f64> = sites.iter().map(|s| s.distance(metric, q)).collect();
        floats.sort_by(f64::total_cmp);
        counts[0] += usize::from(near.len() > 1);
        counts[1] += usize::from(floats[1] - floats[0] <= 1e-12 * (1.0 + floats[0].abs()));
        assert_eq!(
            device.labels[k],
            near[0],
            "{what} {metric}: pixel ({}, {}): exact nearest {near:?}",
            k % w,
            k / w
        );
    }
    assert_eq!(labels, device.labels, "{what} {metric}: the CPU's labels");
    assert_eq!(tiled.labels, device.labels, "{what} {metric}: tiles");
    let bits = |d: &[f32]| d.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&distances), bits(&device.distances), "{what} {metric}");
    assert_eq!(
        bits(&tiled.distances),
        bits(&device.distances),
        "{what} {metric}"
    );
    counts
}

/// The sites scaled by 10 in place, for a frame of scale 1: the decimals
/// become integers and halves, and the ties exact.
fn scaled(sites: &[Site]) -> Vec<Site> {
    sites
        .iter()
        .map(|s| Site {
            additive: 10.0 * s.additive,
            ..s.to_pixels(|p| 10.0 * p, 10.0)
        })
        .collect()
}

#[test]
fn general_sites_are_exact_for_the_doubles_given() {
    let m = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(48);
    let integers = Frame {
        scale: 1.0,
        origin: DVec2::splat(-1.0),
        ..DECIMAL
    };
    for metric in [Metric::L2, Metric::L1, Metric::LInf] {
        // Arcs' ends are transcendental: ties with them are refused (below).
        let tied: Vec<Site> = ties()
            .into_iter()
            .filter(|s| !matches!(s.shape, Shape::Arc { .. }))
            .collect();
        let [exact_ties, _] = check(&m, &scaled(&tied), integers, metric, "exact ties");
        assert!(exact_ties > 0, "{metric}: no exact tie tried");
        let [_, near_ties] = check(&m, &tied, DECIMAL, metric, "ties of decimals");
        assert!(near_ties > 0, "{metric}: no near tie tried");
        let moved: Vec<Site> = scaled(&tied)
            .iter()
            .map(|s| {
                let mut s = *s;
                if let Shape::Point(p) | Shape::Circle { center: p, .. } = &mut s.shape {
                    p.x = ulps(p.x, rng.gen_range(-1..=1));
                }
                s.additive = ulps(s.additive, rng.gen_range(-1..=1));
                s
            })
            .collect();
        check(&m, &moved, integers, metric, "ties moved by an ulp");
        check(&m, &ties(), DECIMAL, metric, "arcs among the ties");
        // An arc's end at angle 0 is the rational point c + (r, 0): pixel
        // (50, 21) is 16 from it and from the segment.
        let p = DVec2::new;
        let end_at_zero = [
            weighted(Shape::Point(p(10.0, 10.0)), 2.0, 0.0),
            weighted(Shape::Segment(p(40.0, 5.0), p(60.0, 5.0)), 1.0, 0.0),
            weighted(
                Shape::Arc {
                    center: p(50.0, 36.0),
                    radius: 8.0,
                    start: 0.0,
                    end: TYPED_PI,
                },
                1.0,
                -1.0,
            ),
        ];
        let pixels = Frame::pixels(64, 48).unwrap();
        check(&m, &end_at_zero, pixels, metric, "an arc's end at angle 0");
        // The end at the double nearest π/2 lies 4.9e-16 right of the centre's
        // column and 1.5e-32 below (10, 18): pixel (10, 22) is 4 + 4.5e-32
        // from it and faces no point of the arc, while the point is 4 away.
        let past_the_end = [
            weighted(
                Shape::Arc {
                    center: p(10.0, 10.0),
                    radius: 8.0,
                    start: 0.1,
                    end: std::f64::consts::FRAC_PI_2,
                },
                1.0,
                0.0,
            ),
            weighted(Shape::Point(p(10.0, 26.0)), 1.0, 0.0),
        ];
        let frame = Frame::pixels(24, 32).unwrap();
        check(&m, &past_the_end, frame, metric, "a transcendental end");
        for n in [12, 40] {
            check(&m, &random(&mut rng, n), DECIMAL, metric, "random");
        }
    }
}

#[test]
fn general_sites_refuse_what_exact_arithmetic_cannot_hold() {
    let m = machine();
    let frame = Frame::pixels(32, 32).unwrap();
    let p = DVec2::new;
    // Two arcs mirrored about pixel row 16 (Frame::pixels centres pixels on
    // integers): their ends are transcendental points, equally far from the
    // pixels on that row.
    let arcs = [
        Site::new(Shape::Arc {
            center: p(10.0, 10.0),
            radius: 4.0,
            start: 0.25,
            end: 1.0,
        }),
        Site::new(Shape::Arc {
            center: p(10.0, 22.0),
            radius: 4.0,
            start: -1.0,
            end: -0.25,
        }),
    ];
    let refused = voronoi(&Backend::Device(&m), &arcs, &VoronoiOptions::exact(frame)).unwrap_err();
    assert!(
        refused.to_string().contains("transcendental point"),
        "{refused}"
    );
    assert!(crate::common::cpu_sites(&arcs, &frame, Metric::L2).is_err());
    // Segments under L_p have no closed-form distance.
    let segment = [Site::new(Shape::Segment(p(1.0, 1.0), p(20.0, 9.0)))];
    let lp = VoronoiOptions::exact(frame).metric(Metric::Lp(3.0));
    let refused = voronoi(&Backend::Device(&m), &segment, &lp).unwrap_err();
    assert!(
        refused.to_string().contains("no exact distance"),
        "{refused}"
    );
}
