//! The Voronoi diagram against the per-pixel brute-force oracle, on random and
//! degenerate inputs, in every accuracy mode and with every speedup.

use glam::DVec2;
use pixgeo::{
    algorithms::voronoi::{voronoi, Accuracy, Method, Speedup, VoronoiDiagram, VoronoiOptions},
    geometry::{metric::Metric, Frame},
    machine::{MachineOptions, PixelRect},
    testing::bisector_deviation,
    Backend, Machine,
};
use pixgeo_reference::voronoi::{nearest_distances_metric, nearest_sites_brute_force};

use crate::common::{cases, machine, uniform};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// This file's diagrams are the cones' (the grid's are checked in
/// `certified.rs`), whatever the device.
fn cones(frame: Frame) -> VoronoiOptions {
    VoronoiOptions::exact(frame).method(Method::Cones)
}

const SPEEDUPS: [Speedup; 3] = [Speedup::None, Speedup::Quadtree, Speedup::Local];

fn run(
    m: &Machine,
    sites: &[DVec2],
    frame: Frame,
    accuracy: Accuracy,
    speedup: Speedup,
) -> VoronoiDiagram {
    voronoi(
        &Backend::Device(m),
        sites,
        &cones(frame).accuracy(accuracy).speedup(speedup),
    )
    .unwrap_or_else(|e| panic!("{accuracy:?} {speedup:?}: {e}"))
}

/// Exact mode: every pixel's site is at the minimum distance (ties either way), and
/// the distance map is that distance. Real coordinates go through float32 on the
/// device, hence the small tolerance.
fn assert_exact(d: &VoronoiDiagram, sites: &[DVec2], frame: &Frame, what: &str) {
    let (_, best) = nearest_sites_brute_force(sites, frame);
    let w = frame.width as usize;
    let mut wrong = 0;
    for (k, &label) in d.labels.iter().enumerate() {
        let q = DVec2::new((k % w) as f64, (k / w) as f64);
        assert_ne!(label, u32::MAX, "{what}: pixel {q} uncovered");
        let dl = (sites[label as usize] - q).length();
        let tol = 1e-3 * (1.0 + best[k]);
        if dl > best[k] + tol {
            wrong += 1;
            if wrong < 5 {
                eprintln!(
                    "{what}: pixel {q}: site {label} at {dl}, nearest at {}",
                    best[k]
                );
            }
        }
        let dd = d.distances[k] as f64;
        assert!(
            (dd - best[k]).abs() <= tol,
            "{what}: pixel {q}: distance {dd} vs {}",
            best[k]
        );
    }
    assert_eq!(
        wrong, 0,
        "{what}: {wrong} pixels labelled with a farther site"
    );
}

/// Fan mode: the distance map is an ε distance diagram, each label's site is within ε
/// of the nearest, and (for a fixed T) each pixel is on the wrong side of a bisector
/// by no more than the §3.4 deviation bound.
fn assert_fan(
    d: &VoronoiDiagram,
    sites: &[DVec2],
    frame: &Frame,
    epsilon: f64,
    triangles: Option<u32>,
    what: &str,
) {
    let (nearest, best) = nearest_sites_brute_force(sites, frame);
    let w = frame.width as usize;
    // Fan vertices are snapped to the rasterizer's subpixel grid (1/256 pixel on
    // lavapipe); with cone slope 1 that moves depths by about as much.
    let tol = 1e-2;
    let mut mislabelled = 0;
    for (k, &label) in d.labels.iter().enumerate() {
        let q = DVec2::new((k % w) as f64, (k / w) as f64);
        assert_ne!(label, u32::MAX, "{what}: pixel {q} uncovered");
        let dd = d.distances[k] as f64;
        assert!(
            dd >= best[k] - tol && dd <= best[k] + epsilon + tol,
            "{what}: pixel {q}: depth {dd}, true {}",
            best[k]
        );
        let site = sites[label as usize];
        let dl = (site - q).length();
        assert!(
            dl <= best[k] + epsilon + tol,
            "{what}: pixel {q}: label at {dl}, nearest {}",
            best[k]
        );
        if dl > best[k] + tol {
            mislabelled += 1;
            if let Some(t) = triangles {
                let a = (site - sites[nearest[k] as usize]).length();
                let offset = (dl * dl - best[k] * best[k]) / (2.0 * a);
                let bound = bisector_deviation(t, best[k], a);
                assert!(
                    offset <= bound + tol,
                    "{what}: pixel {q} {offset} beyond the bisector, bound {bound}"
                );
            }
        }
    }
    eprintln!(
        "{what}: {mislabelled} of {} pixels have a site within ε but not the nearest",
        d.labels.len()
    );
}

#[test]
fn exact_mode_matches_the_definition() {
    let m = machine();
    let frame = Frame::pixels(160, 120).unwrap();
    for (name, sites) in cases(160, 120) {
        for speedup in SPEEDUPS {
            let d = run(&m, &sites, frame, Accuracy::Exact, speedup);
            assert_exact(&d, &sites, &frame, &format!("{name} {speedup:?}"));
        }
    }
}

/// Exact cones with local radii are found per screen tile from the sites whose
/// boxes meet it (L∞ and L_p: from each tile's candidates); where those lists
/// would be too long (here hundreds of sites on a tiny circle, each owning a
/// wedge out to the picture's edge) the cones are drawn instead. Both give the
/// definition.
#[test]
fn screen_tiles_and_their_fallback_match_the_definition() {
    let m = machine();
    let frame = Frame::pixels(64, 48).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let spread = uniform(&mut rng, 40, 64.0, 48.0);
    let mut piled = uniform(&mut rng, 6, 64.0, 48.0);
    piled.extend((0..1000).map(|k| {
        let a = std::f64::consts::TAU * k as f64 / 1000.0;
        DVec2::new(20.25 + 1e-3 * a.cos(), 30.5 + 1e-3 * a.sin())
    }));
    for metric in [Metric::L2, Metric::LInf, Metric::Lp(3.0), Metric::Lp(0.7)] {
        for (sites, drawn) in [(&spread, "tiles"), (&piled, "polygon")] {
            let options = cones(frame).metric(metric);
            let d = voronoi(&Backend::Device(&m), sites, &options).unwrap();
            let kinds: Vec<&str> = d.stats.groups.iter().map(|g| g.kind).collect();
            assert_eq!(kinds, [drawn], "{metric}: how the cones were drawn");
            let truth = nearest_distances_metric(sites, &frame, metric);
            for (k, &label) in d.labels.iter().enumerate() {
                let q = DVec2::new((k % 64) as f64, (k / 64) as f64);
                assert_ne!(label, u32::MAX, "{metric} {drawn}: {q} uncovered");
                let mine = metric.distance(sites[label as usize] - q);
                assert!(
                    mine <= truth[k] * (1.0 + 1e-4) + 1e-4,
                    "{metric} {drawn}: pixel {q}: site {label} at {mine}, nearest {}",
                    truth[k]
                );
            }
        }
    }
}

#[test]
fn fan_mode_stays_inside_its_bounds() {
    let m = machine();
    let frame = Frame::pixels(128, 96).unwrap();
    for (name, sites) in cases(128, 96) {
        for speedup in [Speedup::Quadtree, Speedup::Local] {
            let d = run(&m, &sites, frame, Accuracy::FAN, speedup);
            assert_fan(
                &d,
                &sites,
                &frame,
                1.0,
                None,
                &format!("{name} {speedup:?} ε=1"),
            );
        }
        let d = run(
            &m,
            &sites,
            frame,
            Accuracy::Fan {
                epsilon: 0.25,
                triangles: None,
            },
            Speedup::Local,
        );
        assert_fan(&d, &sites, &frame, 0.25, None, &format!("{name} ε=0.25"));
    }
}

#[test]
fn fixed_triangle_count_obeys_the_bisector_bound() {
    let m = machine();
    let frame = Frame::pixels(128, 128).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let sites = uniform(&mut rng, 50, 128.0, 128.0);
    for t in [6, 12, 40] {
        let d = run(
            &m,
            &sites,
            frame,
            Accuracy::Fan {
                epsilon: 1.0,
                triangles: Some(t),
            },
            Speedup::None,
        );
        let eps = d.stats.distance_error_bound;
        assert!(eps > 0.0);
        assert_fan(&d, &sites, &frame, eps, Some(t), &format!("T={t}"));
    }
}

#[test]
fn quadtree_retries_until_covered_and_local_radii_are_smaller() {
    let m = machine();
    let frame = Frame::pixels(256, 256).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    // The thesis's worst case: one quarter of the picture holds no site.
    let sites: Vec<DVec2> = uniform(&mut rng, 2000, 256.0, 256.0)
        .into_iter()
        .filter(|p| p.x < 128.0 || p.y < 128.0)
        .collect();
    let q = run(&m, &sites, frame, Accuracy::Exact, Speedup::Quadtree);
    assert_exact(&q, &sites, &frame, "quarter quadtree");
    let l = run(&m, &sites, frame, Accuracy::Exact, Speedup::Local);
    assert_exact(&l, &sites, &frame, "quarter local");
    assert!(
        l.stats.radius_mean < q.stats.radius_mean / 2.0,
        "{:?} vs {:?}",
        l.stats,
        q.stats
    );
    // Uniform sites: the first quadtree radius is usually enough.
    let sites = uniform(&mut rng, 2000, 256.0, 256.0);
    let q = run(&m, &sites, frame, Accuracy::Exact, Speedup::Quadtree);
    assert!(q.stats.passes <= 2, "{:?}", q.stats);
    assert_exact(&q, &sites, &frame, "uniform quadtree");
}

#[test]
fn bounding_box_maps_world_to_pixels() {
    let m = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let world: Vec<DVec2> = (0..80)
        .map(|_| DVec2::new(rng.gen_range(10.0..12.0), rng.gen_range(-3.0..-1.5)))
        .collect();
    let frame = Frame::with_bbox(100, None, [10.0, -3.0, 12.0, -1.5]).unwrap();
    assert_eq!((frame.width, frame.height), (100, 75));
    let d = run(&m, &world, frame, Accuracy::Exact, Speedup::Local);
    let pixels: Vec<DVec2> = world.iter().map(|p| frame.to_pixel(*p)).collect();
    let pixel_frame = Frame::pixels(100, 75).unwrap();
    let mut in_pixels = d.clone();
    in_pixels
        .distances
        .iter_mut()
        .for_each(|v| *v *= frame.scale as f32);
    assert_exact(&in_pixels, &pixels, &pixel_frame, "bbox");
    assert!(Frame::with_bbox(100, Some(10), [0.0, 0.0, 1.0, 1.0]).is_err());
}

#[test]
fn bad_input_is_a_clear_error() {
    let m = machine();
    let frame = Frame::pixels(16, 16).unwrap();
    let opts = cones(frame);
    let err = |sites: &[DVec2]| {
        voronoi(&Backend::Device(&m), sites, &opts)
            .unwrap_err()
            .to_string()
    };
    assert!(err(&[]).contains("empty"));
    assert!(err(&[DVec2::new(f64::NAN, 1.0)]).contains("non-finite"));
    assert!(err(&[DVec2::new(1.0, f64::INFINITY)]).contains("non-finite"));
    assert!(Frame::pixels(0, 5).is_err());
    let big = Frame {
        width: Frame::MAX_SIDE + 1,
        ..frame
    };
    let e = voronoi(
        &Backend::Device(&m),
        &[DVec2::ZERO],
        &opts.clone().frame(big),
    )
    .unwrap_err();
    assert!(matches!(e, pixgeo::Error::PictureTooLarge { .. }), "{e}");
    let bad_fan = opts.accuracy(Accuracy::Fan {
        epsilon: 0.0,
        triangles: None,
    });
    assert!(voronoi(&Backend::Device(&m), &[DVec2::ZERO], &bad_fan).is_err());
}

#[test]
fn tiles_give_the_same_diagram_pixel_for_pixel() {
    let m = machine();
    let (w, h) = (173u32, 131u32);
    let frame = Frame::pixels(w, h).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let mut sites = uniform(&mut rng, 150, w as f64, h as f64);
    // Sites on and beside tile borders (tiles of 40), on the integer lattice so that
    // exact ties abound, and outside the picture.
    for k in 0..12 {
        sites.push(DVec2::new(
            40.0 * (k % 4) as f64,
            40.0 * (k / 4) as f64 + 0.5,
        ));
        sites.push(DVec2::new(
            39.0 + 40.0 * (k % 4) as f64,
            20.0 + 40.0 * (k / 4) as f64,
        ));
    }
    sites.extend([
        DVec2::new(-12.0, 60.0),
        DVec2::new(w as f64 + 30.0, -8.0),
        DVec2::new(90.0, h as f64 + 5.0),
    ]);
    // L3 lists each screen tile's candidates in its own order (picture tiles
    // where the tiling keeps them, the regions' boxes where it does not).
    let runs = [
        (Speedup::Local, Metric::L2),
        (Speedup::Quadtree, Metric::L2),
        (Speedup::Local, Metric::Lp(3.0)),
    ];
    for (speedup, metric) in runs {
        let options = |max_tile| {
            cones(frame)
                .metric(metric)
                .speedup(speedup)
                .max_tile(max_tile)
        };
        let whole = voronoi(&Backend::Device(&m), &sites, &options(None)).unwrap();
        assert_eq!(whole.stats.tiles, 1);
        if metric == Metric::L2 {
            assert_exact(&whole, &sites, &frame, "whole");
        }
        for tile in [40, 64, 100] {
            let tiled = voronoi(&Backend::Device(&m), &sites, &options(Some(tile))).unwrap();
            assert_eq!(
                tiled.stats.tiles,
                (w.div_ceil(tile) * h.div_ceil(tile)) as usize
            );
            assert!(
                whole.labels == tiled.labels,
                "{speedup:?} {metric} tile {tile}: {} labels differ",
                whole
                    .labels
                    .iter()
                    .zip(&tiled.labels)
                    .filter(|(a, b)| a != b)
                    .count()
            );
            assert_eq!(
                whole.distances, tiled.distances,
                "{speedup:?} {metric} tile {tile}"
            );
        }
    }
    // Fan cones are bounded the same way in every tile.
    let fan = cones(frame).accuracy(Accuracy::FAN).max_tile(Some(50));
    let d = voronoi(&Backend::Device(&m), &sites, &fan).unwrap();
    assert_fan(&d, &sites, &frame, 1.0, None, "fan tiles");
}

#[test]
fn random_windows_tile_into_the_whole_diagram_bit_for_bit() {
    let m = machine();
    let (w, h) = (150u32, 110u32);
    let frame = Frame::with_bbox(w, Some(h), [-3.0, -2.0, 12.0, 9.0]).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    // Random sites, an integer lattice (exact ties everywhere), repeats and
    // sites outside the frame.
    let mut sites = uniform(&mut rng, 60, 15.0, 11.0)
        .into_iter()
        .map(|p| p - DVec2::new(3.0, 2.0))
        .collect::<Vec<_>>();
    sites.extend((0..20).map(|k| DVec2::new((k % 5) as f64 * 2.0, (k / 5) as f64 * 2.0)));
    sites.extend([sites[3], DVec2::new(-9.0, 4.0), DVec2::new(20.0, 20.0)]);
    let runs = [
        (Speedup::Local, Metric::L2, Accuracy::Exact, false),
        (Speedup::Quadtree, Metric::L2, Accuracy::Exact, false),
        (Speedup::Local, Metric::L1, Accuracy::Exact, true),
        (Speedup::Local, Metric::Lp(3.0), Accuracy::Exact, false),
    ];
    for (speedup, metric, accuracy, ties) in runs {
        let options = |window| {
            cones(frame)
                .metric(metric)
                .accuracy(accuracy)
                .speedup(speedup)
                .ties(ties)
                .max_tile(Some(48))
                .window(window)
        };
        let whole = voronoi(&Backend::Device(&m), &sites, &options(None)).unwrap();
        // Cut the picture at random columns and rows into windows.
        let cuts = |side: u32, rng: &mut ChaCha8Rng| {
            let mut c: Vec<u32> = (0..3).map(|_| rng.gen_range(1..side)).collect();
            c.extend([0, side]);
            c.sort_unstable();
            c.dedup();
            c
        };
        let (xs, ys) = (cuts(w, &mut rng), cuts(h, &mut rng));
        let mut covered = 0;
        for y in ys.windows(2) {
            for x in xs.windows(2) {
                let window = PixelRect {
                    x: x[0],
                    y: y[0],
                    width: x[1] - x[0],
                    height: y[1] - y[0],
                };
                let part = voronoi(&Backend::Device(&m), &sites, &options(Some(window))).unwrap();
                assert_eq!((part.width, part.height), (window.width, window.height));
                for j in 0..window.height {
                    let row = |v: &[u32], width: u32, x0: u32, y0: u32| {
                        let at = ((y0 + j) * width + x0) as usize;
                        v[at..at + window.width as usize].to_vec()
                    };
                    let what =
                        format!("{metric} {accuracy:?} {speedup:?} window {window:?} row {j}");
                    assert_eq!(
                        row(&part.labels, window.width, 0, 0),
                        row(&whole.labels, w, x[0], y[0]),
                        "{what}"
                    );
                    let at = ((y[0] + j) * w + x[0]) as usize;
                    let want = &whole.distances[at..at + window.width as usize];
                    let got =
                        &part.distances[(j * window.width) as usize..][..window.width as usize];
                    assert!(
                        want.iter()
                            .zip(got)
                            .all(|(a, b)| a.to_bits() == b.to_bits()),
                        "{what}: distances"
                    );
                    if ties {
                        assert_eq!(
                            row(&part.ties, window.width, 0, 0),
                            row(&whole.ties, w, x[0], y[0]),
                            "{what}"
                        );
                    }
                }
                covered += window.width * window.height;
            }
        }
        assert_eq!(covered, w * h);
    }
    // A window must lie inside the picture.
    for bad in [
        (0, 0, 0, 5),
        (140, 0, 20, 5),
        (0, 100, 5, 11),
        (u32::MAX, 0, 2, 2),
    ] {
        let window = PixelRect {
            x: bad.0,
            y: bad.1,
            width: bad.2,
            height: bad.3,
        };
        let options = cones(frame).window(Some(window));
        let err = voronoi(&Backend::Device(&m), &sites, &options).unwrap_err();
        assert!(
            err.to_string().contains("inside the 150x110 picture"),
            "{err}"
        );
    }
}

#[test]
fn pictures_wider_than_the_device_are_tiled() {
    let m = machine();
    let w = m.max_picture_side() + 300;
    let frame = Frame::pixels(w, 3).unwrap();
    let sites: Vec<DVec2> = (0..40)
        .map(|k| DVec2::new(k as f64 * w as f64 / 40.0 + 7.3, (k % 3) as f64))
        .collect();
    let d = voronoi(&Backend::Device(&m), &sites, &cones(frame)).unwrap();
    assert_eq!(d.stats.tiles, 2);
    assert_exact(&d, &sites, &frame, "wide");
}

#[test]
fn other_metrics_match_their_definition() {
    // Thesis §3.6: L1, L-infinity and L_p (p < 1 too) in exact mode: every pixel
    // gets a site at the smallest distance of the metric, with every speedup.
    let m = machine();
    let frame = Frame::pixels(61, 47).unwrap();
    // p close to 0 and very large too.
    // Power sums as keys for 2p whole (0.5, 1.5, 3, 4), distances otherwise.
    let metrics = [
        Metric::L1,
        Metric::LInf,
        Metric::Lp(0.5),
        Metric::Lp(1.5),
        Metric::Lp(3.0),
        Metric::Lp(4.0),
        Metric::Lp(0.1),
        Metric::Lp(60.0),
    ];
    for metric in metrics {
        for (name, sites) in cases(61, 47) {
            let truth = nearest_distances_metric(&sites, &frame, metric);
            for speedup in SPEEDUPS {
                let d = voronoi(
                    &Backend::Device(&m),
                    &sites,
                    &cones(frame).metric(metric).speedup(speedup),
                )
                .unwrap_or_else(|e| panic!("{metric} {name} {speedup:?}: {e}"));
                for (k, &label) in d.labels.iter().enumerate() {
                    let q = DVec2::new((k % 61) as f64, (k / 61) as f64);
                    assert_ne!(
                        label,
                        u32::MAX,
                        "{metric} {name} {speedup:?}: {q} uncovered"
                    );
                    let mine = metric.distance(sites[label as usize] - q);
                    // The distance is the 1/p-th power of a sum of float32
                    // powers, which multiplies their rounding by 1/p.
                    let amplified = match metric {
                        Metric::Lp(p) => p.recip().max(1.0),
                        _ => 1.0,
                    };
                    let tol = 1e-3 * amplified * (1.0 + truth[k]);
                    assert!(
                        mine <= truth[k] + tol && (d.distances[k] as f64 - truth[k]).abs() <= tol,
                        "{metric} {name} {speedup:?}: pixel {q}: site {label} at {mine}, map {}, nearest {}",
                        d.distances[k],
                        truth[k]
                    );
                }
            }
        }
    }
}

#[test]
fn fans_of_other_metrics_stay_inside_their_bounds() {
    // Thesis §3.6.1–3.6.2: fans over the polygonal chain of each metric's circle
    // give an ε distance diagram, with every speedup; a fixed T samples the circle
    // at equal angles and reports its own bound.
    let m = machine();
    let frame = Frame::pixels(61, 47).unwrap();
    let metrics = [
        Metric::L1,
        Metric::LInf,
        Metric::Lp(1.5),
        Metric::Lp(4.0),
        Metric::Lp(60.0),
    ];
    // No ε bounds a fan of a ball that is not convex: refused.
    for p in [0.5, 0.1] {
        let fan = cones(frame).metric(Metric::Lp(p)).accuracy(Accuracy::FAN);
        let refused = voronoi(&Backend::Device(&m), &[DVec2::new(30.0, 20.0)], &fan).unwrap_err();
        assert!(refused.to_string().contains("not convex"), "{refused}");
    }
    for metric in metrics {
        for (name, sites) in cases(61, 47) {
            // The rasterizer snaps a fan's vertices to its subpixel grid (1/256
            // pixel on lavapipe), so the apex may sit that far from the site; for
            // p < 1 the distance is steep near the axes, so compare with the
            // distances of the site moved by that much towards or away from the
            // pixel.
            let snap = 1.0 / 256.0;
            let moved = |toward: f64| -> Vec<f64> {
                let w = frame.width as usize;
                (0..frame.len())
                    .map(|k| {
                        let q = DVec2::new((k % w) as f64, (k / w) as f64);
                        sites
                            .iter()
                            .map(|s| metric.distance(((*s - q).abs() - toward).max(DVec2::ZERO)))
                            .fold(f64::INFINITY, f64::min)
                    })
                    .collect()
            };
            let (near, far) = (moved(snap), moved(-snap));
            for (accuracy, speedup) in [
                (Accuracy::FAN, Speedup::None),
                (Accuracy::FAN, Speedup::Quadtree),
                (Accuracy::FAN, Speedup::Local),
                (
                    Accuracy::Fan {
                        epsilon: 1.0,
                        triangles: Some(24),
                    },
                    Speedup::Local,
                ),
            ] {
                let what = format!("{metric} {name} {accuracy:?} {speedup:?}");
                let d = voronoi(
                    &Backend::Device(&m),
                    &sites,
                    &cones(frame)
                        .metric(metric)
                        .accuracy(accuracy)
                        .speedup(speedup),
                )
                .unwrap_or_else(|e| panic!("{what}: {e}"));
                let bound = d.stats.distance_error_bound;
                assert!(
                    bound > 0.0 || matches!(metric, Metric::L1 | Metric::LInf),
                    "{what}"
                );
                let tol = 1e-3;
                // The bound holds either way: the rasterizer's snapping of
                // vertices may also lower a fan (for p < 1, along the spikes).
                for (k, &label) in d.labels.iter().enumerate() {
                    let q = DVec2::new((k % 61) as f64, (k / 61) as f64);
                    assert_ne!(label, u32::MAX, "{what}: {q} uncovered");
                    let depth = d.distances[k] as f64;
                    let mine = metric.distance(sites[label as usize] - q);
                    assert!(
                        depth >= near[k] - bound - tol && depth <= far[k] + bound + tol,
                        "{what}: pixel {q}: depth {depth}, nearest {} to {}, bound {bound}",
                        near[k],
                        far[k]
                    );
                    assert!(
                        mine <= far[k] + bound + tol,
                        "{what}: pixel {q}: label at {mine}, nearest {}",
                        far[k]
                    );
                }
            }
        }
    }
}

#[test]
fn ties_count_the_sites_at_the_smallest_distance() {
    // Thesis §3.6.4: the second pass with the depth test EQUAL counts every site at
    // a pixel's smallest distance. Integer sites, so ties are exact: the L1 and
    // L-infinity areas of equidistant points, lattice corners, duplicates; and
    // for L3, whose keys are sums of cubes, exact for integers, the lattice's
    // mirror images (the oracle compares the cube sums, exact in f64 as well).
    let m = machine();
    let frame = Frame::pixels(48, 40).unwrap();
    let p = |x: f64, y: f64| DVec2::new(x, y);
    let inputs = [
        ("diagonal pair", vec![p(15.0, 12.0), p(30.0, 27.0)]),
        (
            "lattice",
            (0..42)
                .map(|k| p((k % 7 * 6) as f64, (k / 7 * 6) as f64))
                .collect(),
        ),
        (
            "duplicates",
            vec![p(10.0, 10.0), p(10.0, 10.0), p(33.0, 25.0)],
        ),
    ];
    for metric in [Metric::L2, Metric::L1, Metric::LInf, Metric::Lp(3.0)] {
        let order = |d: DVec2| match metric {
            Metric::Lp(_) => d.x.abs().powi(3) + d.y.abs().powi(3),
            _ => metric.distance(d),
        };
        for (name, sites) in &inputs {
            let d = voronoi(
                &Backend::Device(&m),
                sites,
                &cones(frame).metric(metric).ties(true).max_tile(Some(20)),
            )
            .unwrap_or_else(|e| panic!("{metric} {name}: {e}"));
            let mut tied = 0;
            for (k, &count) in d.ties.iter().enumerate() {
                let q = p((k % 48) as f64, (k / 48) as f64);
                let dists: Vec<f64> = sites.iter().map(|s| order(*s - q)).collect();
                let best = dists.iter().copied().fold(f64::INFINITY, f64::min);
                let want = dists.iter().filter(|x| **x == best).count() as u32;
                assert_eq!(count, want, "{metric} {name}: pixel {q}");
                tied += (want > 1) as usize;
            }
            assert!(tied > 0, "{metric} {name}: no ties to count");
            // Without the count, the smallest index of the tied sites wins,
            // whatever order a screen tile lists them in.
            let d = voronoi(&Backend::Device(&m), sites, &cones(frame).metric(metric))
                .unwrap_or_else(|e| panic!("{metric} {name}: {e}"));
            for (k, &label) in d.labels.iter().enumerate() {
                let q = p((k % 48) as f64, (k / 48) as f64);
                let dists: Vec<f64> = sites.iter().map(|s| order(*s - q)).collect();
                let best = dists.iter().copied().fold(f64::INFINITY, f64::min);
                let first = dists.iter().position(|x| *x == best).unwrap() as u32;
                assert_eq!(label, first, "{metric} {name}: pixel {q}");
            }
        }
    }
    // Fans have no exact ties to count.
    let fan = cones(frame).ties(true).accuracy(Accuracy::FAN);
    assert!(voronoi(&Backend::Device(&m), &[DVec2::ZERO], &fan).is_err());
}

#[test]
fn repeated_sites_cost_nothing_and_the_first_wins() {
    // Equal sites are merged up front; every pixel names the first of the
    // equal nearest sites, as it names the smallest id among equidistant ones.
    let m = machine();
    let frame = Frame::pixels(64, 48).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let distinct = uniform(&mut rng, 25, 64.0, 48.0);
    let sites: Vec<DVec2> = (0..4000).map(|k| distinct[(k * 7 + k / 13) % 25]).collect();
    let d = voronoi(&Backend::Device(&m), &sites, &cones(frame)).unwrap();
    assert_eq!(d.stats.sites, 4000);
    let truth = nearest_distances_metric(&sites, &frame, Metric::L2);
    for (k, &label) in d.labels.iter().enumerate() {
        let q = DVec2::new((k % 64) as f64, (k / 64) as f64);
        let at = sites[label as usize];
        assert!((at.distance(q) - truth[k]).abs() < 1e-9, "pixel {q}");
        let first = sites.iter().position(|s| *s == at).unwrap();
        assert_eq!(label as usize, first, "pixel {q}");
    }
    // Tie counts count every copy: on an integer lattice of positions, under
    // L1 (areas of equal distance), against the exact count of all sites.
    let lattice: Vec<DVec2> = (0..12)
        .map(|k| DVec2::new((8 + 16 * (k % 4)) as f64, (8 + 16 * (k / 4)) as f64))
        .collect();
    let sites: Vec<DVec2> = (0..6000).map(|k| lattice[(k * 5 + k / 7) % 12]).collect();
    for metric in [Metric::L1, Metric::L2] {
        let options = cones(frame).metric(metric).ties(true);
        let d = voronoi(&Backend::Device(&m), &sites, &options).unwrap();
        for (k, &count) in d.ties.iter().enumerate() {
            let q = DVec2::new((k % 64) as f64, (k / 64) as f64);
            let key = |s: &DVec2| metric.key(q - *s);
            let least = sites.iter().map(key).fold(f64::INFINITY, f64::min);
            let tied = sites.iter().filter(|s| key(s) == least).count().min(255);
            assert_eq!(count as usize, tied, "{metric} pixel {q}");
        }
    }
}

#[test]
fn sites_beyond_float32_are_refused_on_the_device() {
    // Sites 1e8 pixels out own pixels whose distances float32 cannot tell
    // apart: refused, pointing at the CPU algorithm, which is exact in f64.
    let m = machine();
    let frame = Frame::pixels(64, 64).unwrap();
    let far = [DVec2::new(-1e8, 5.0), DVec2::new(1e8, 30.0)];
    let e = voronoi(&Backend::Device(&m), &far, &cones(frame)).unwrap_err();
    assert!(e.to_string().contains("--device cpu"), "{e}");
    use pixgeo::algorithms::higher_order::{k_nearest, KNearestOptions};
    let d = k_nearest(&Backend::Cpu, &far, &KNearestOptions::exact(frame, 1)).unwrap();
    // The grid works in doubles and answers the same.
    let grid = VoronoiOptions::exact(frame).method(Method::Grid);
    let searched = voronoi(&Backend::Device(&m), &far, &grid).unwrap();
    assert_eq!(searched.labels, d.labels);
    // At x = 0 the first site is nearer exactly where y < 17.5.
    for j in 0..64 {
        assert_eq!(d.labels[j * 64], u32::from(j >= 18), "row {j}");
    }
}

#[test]
fn far_sites_under_quadtree_fans_answer_or_are_refused() {
    // A quadtree cone reaches the farthest pixel its square might own: past
    // MAX_FAN_TRIANGLES that fan is refused before any memory is taken.
    let m = machine();
    let frame = Frame::pixels(24, 24).unwrap();
    let sites = [
        DVec2::new(3.0, 4.0),
        DVec2::new(20.0, 21.0),
        DVec2::new(1e15, -1e15),
        DVec2::new(-1e300, 1e300),
    ];
    let options = cones(frame)
        .accuracy(Accuracy::FAN)
        .speedup(Speedup::Quadtree);
    match voronoi(&Backend::Device(&m), &sites, &options) {
        Ok(d) => assert!(d.labels.iter().all(|&l| l < 2)),
        Err(e) => assert!(e.to_string().contains("triangles"), "{e}"),
    }
}

#[test]
fn pipelines_are_kept_between_machines_and_a_broken_cache_file_is_ignored() {
    let folder = std::env::temp_dir().join(format!("pixgeo-cache-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    let options = MachineOptions::from_env().pipeline_cache(Some(folder.clone()));
    let sites = [
        DVec2::new(3.0, 4.0),
        DVec2::new(20.0, 9.0),
        DVec2::new(11.0, 25.0),
    ];
    let diagram = |machine: &Machine| {
        voronoi(
            &Backend::Device(machine),
            &sites,
            &cones(Frame::pixels(32, 32).unwrap()),
        )
        .unwrap()
    };
    let cache_file = || {
        let files: Vec<_> = std::fs::read_dir(&folder).unwrap().flatten().collect();
        assert_eq!(
            files.len(),
            1,
            "one file per device and driver, no temporaries"
        );
        files[0].path()
    };

    let first = diagram(&Machine::new(&options).unwrap());
    let written = std::fs::read(cache_file()).unwrap();
    assert!(
        written.len() >= 32,
        "at least the header vkGetPipelineCacheData writes"
    );
    assert_eq!(&written[..4], &32u32.to_le_bytes());

    assert_eq!(
        diagram(&Machine::new(&options).unwrap()).labels,
        first.labels
    );

    std::fs::write(cache_file(), b"not a pipeline cache").unwrap();
    assert_eq!(
        diagram(&Machine::new(&options).unwrap()).labels,
        first.labels
    );
    assert_eq!(
        &std::fs::read(cache_file()).unwrap()[..4],
        &32u32.to_le_bytes()
    );
    std::fs::remove_dir_all(&folder).unwrap();
}

/// Distances are the float32s nearest the exact ones, on every route: a site
/// 2⁻⁵³ below a pixel centre is 2⁻⁵³ from it, not 0 (the site's pixel
/// position rounds onto the centre), and a distance 2⁻⁸¹ past the midpoint
/// of 1 and the next float32 rounds up, though its double rounds to the
/// midpoint itself.
#[test]
fn distances_are_the_nearest_float32s_of_the_exact_ones() {
    let m = machine();
    let frame = Frame::pixels(4, 2).unwrap();
    let cases = [
        (
            DVec2::new(1.0, 1.0 - 2f64.powi(-53)),
            (1, 1),
            2f32.powi(-53),
        ),
        (
            DVec2::new(-(2f64.powi(-24)), 2f64.powi(-40)),
            (1, 0),
            1.0 + 2f32.powi(-23),
        ),
    ];
    for (site, (i, j), want) in cases {
        for backend in [Backend::Device(&m), Backend::Cpu] {
            let d = voronoi(&backend, &[site], &VoronoiOptions::exact(frame)).unwrap();
            let got = d.distances[j * 4 + i];
            assert_eq!(
                got.to_bits(),
                want.to_bits(),
                "{site}: {got:e}, not {want:e}"
            );
        }
    }
}
