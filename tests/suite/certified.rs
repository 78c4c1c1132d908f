//! Exact labels for the doubles the user gave: every route to a nearest-site
//! diagram (the screen tiles, the cones of each speedup, tiles and windows,
//! tie counts, the k nearest drawn and peeled, the CPU's pixel algorithm)
//! against ranks in exact rational arithmetic, on near-degenerate doubles:
//! lattices of a non-power-of-two spacing seen through a frame whose pixel
//! centres are not doubles, one-ulp perturbations, sites mirrored about pixel
//! centres to within an ulp, and magnitudes from 1e-150 to 1e15.

use glam::DVec2;
use pixgeo::{
    algorithms::{
        higher_order::{k_nearest, k_nearest_peeled, KNearestOptions},
        voronoi::{voronoi, Method, Speedup, VoronoiOptions},
    },
    geometry::{metric::Metric, Frame},
    machine::PixelRect,
    Backend, Machine,
};
use pixgeo_reference::exact::exact_k_nearest;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common::{machine, ulps};

const METRICS: [Metric; 4] = [Metric::L2, Metric::L1, Metric::LInf, Metric::Lp(3.0)];

/// A lattice of `spacing` from `corner`, every site moved by up to one ulp,
/// in reverse order so that float ties would favour the wrong index.
fn perturbed_lattice(rng: &mut ChaCha8Rng, corner: DVec2, spacing: f64, n: [u32; 2]) -> Vec<DVec2> {
    let mut sites: Vec<DVec2> = (0..n[1])
        .flat_map(|j| (0..n[0]).map(move |i| corner + DVec2::new(i as f64, j as f64) * spacing))
        .map(|p| {
            DVec2::new(
                ulps(p.x, rng.gen_range(-1..=1)),
                ulps(p.y, rng.gen_range(-1..=1)),
            )
        })
        .collect();
    sites.reverse();
    sites
}

/// Pairs of sites mirrored about pixel centres, the second one ulp nearer:
/// the first's index is the smaller, which a float tie would choose.
fn mirrored_pairs(rng: &mut ChaCha8Rng, frame: &Frame, pairs: usize) -> Vec<DVec2> {
    let mut sites = Vec::new();
    for _ in 0..pairs {
        let pixel = DVec2::new(
            rng.gen_range(0..frame.width) as f64,
            rng.gen_range(0..frame.height) as f64,
        );
        let centre = frame.to_world(pixel);
        let offset = DVec2::new(rng.gen_range(-3.0..3.0), rng.gen_range(-3.0..3.0)) / frame.scale;
        let far = centre + offset;
        let mirror = centre - offset;
        let nearer = DVec2::new(
            ulps(mirror.x, if offset.x > 0.0 { 1 } else { -1 }),
            mirror.y,
        );
        sites.extend([far, nearer]);
    }
    sites
}

/// Named inputs, each with its frame.
fn inputs() -> Vec<(&'static str, Frame, Vec<DVec2>)> {
    let mut rng = ChaCha8Rng::seed_from_u64(48);
    let tenths = Frame::with_bbox(48, Some(40), [0.0, 0.0, 4.8, 4.0]).unwrap();
    let far = Frame::with_bbox(48, Some(40), [1e15, 1e15, 1e15 + 18.0, 1e15 + 15.0]).unwrap();
    let tiny = Frame::with_bbox(48, Some(40), [0.0, 0.0, 4.8e-150, 4.0e-150]).unwrap();
    let uniform: Vec<DVec2> = (0..300)
        .map(|_| DVec2::new(rng.gen_range(0.0..4.8), rng.gen_range(0.0..4.0)))
        .collect();
    vec![
        (
            "lattice of 0.3",
            tenths,
            perturbed_lattice(&mut rng, DVec2::new(0.15, 0.05), 0.3, [16, 13]),
        ),
        (
            "mirrored pairs",
            tenths,
            mirrored_pairs(&mut rng, &tenths, 40),
        ),
        ("uniform", tenths, uniform),
        (
            "lattice at 1e15",
            far,
            perturbed_lattice(&mut rng, DVec2::splat(1e15 + 0.25), 1.125, [16, 13]),
        ),
        (
            "lattice at 1e-150",
            tiny,
            perturbed_lattice(&mut rng, DVec2::new(1.5e-151, 0.5e-151), 3e-151, [16, 13]),
        ),
    ]
}

/// The first `k` labels of each pixel of `near` (row-major, `levels` to a
/// pixel) restricted to `window`.
fn levels_in(
    labels: &[u32],
    levels: usize,
    k: usize,
    frame: &Frame,
    window: PixelRect,
) -> Vec<u32> {
    let mut out = Vec::new();
    for j in window.y..window.y + window.height {
        for i in window.x..window.x + window.width {
            let at = (j * frame.width + i) as usize * levels;
            out.extend_from_slice(&labels[at..at + k]);
        }
    }
    out
}

/// Adds to `failures` a line for `got` where it differs from `want`.
fn check(failures: &mut Vec<String>, what: &str, got: &[u32], want: &[u32]) {
    let wrong = got.iter().zip(want).filter(|(g, w)| g != w).count();
    if wrong > 0 || got.len() != want.len() {
        failures.push(format!(
            "{what}: {wrong} of {} differ from the exact answer",
            want.len()
        ));
    }
}

fn diagrams_are_exact(
    failures: &mut Vec<String>,
    m: &Machine,
    name: &str,
    frame: Frame,
    sites: &[DVec2],
    metric: Metric,
) {
    let (ranks, ties) = exact_k_nearest(sites, &frame, metric, 3);
    let nearest = levels_in(
        &ranks,
        3,
        1,
        &frame,
        PixelRect::sized(frame.width, frame.height),
    );
    let what = |route: &str| format!("{name}, {metric}, {route}");
    let base = VoronoiOptions::exact(frame).metric(metric);
    let cones = base.clone().method(Method::Cones);
    let grown = k_nearest(
        &Backend::Cpu,
        sites,
        &KNearestOptions::exact(frame, 1).metric(metric),
    )
    .unwrap();
    let bits = |d: &[f32]| d.iter().map(|v| v.to_bits()).collect::<Vec<u32>>();
    let mut routes = vec![
        ("screen tiles", cones.clone()),
        ("cones", cones.clone().speedup(Speedup::None)),
        ("quadtree", cones.clone().speedup(Speedup::Quadtree)),
        ("tiles of 16", cones.max_tile(Some(16))),
    ];
    let mut methods = vec![Method::Cones];
    if metric == Metric::L2 {
        routes.push(("grid", base.clone().method(Method::Grid)));
        methods.push(Method::Grid);
    }
    for (route, options) in routes {
        let d = voronoi(&Backend::Device(m), sites, &options)
            .unwrap_or_else(|e| panic!("{}: {e}", what(route)));
        check(failures, &what(route), &d.labels, &nearest);
        // Distances from the labels: the CPU's, to the bit.
        let distances = what(&format!("{route} distances"));
        check(
            failures,
            &distances,
            &bits(&d.distances),
            &bits(&grown.distances),
        );
    }
    let window = PixelRect {
        x: 8,
        y: 16,
        width: 24,
        height: 16,
    };
    let inside = |v: &[f32]| -> Vec<u32> {
        (window.y..window.y + window.height)
            .flat_map(|j| (window.x..window.x + window.width).map(move |i| (i, j)))
            .map(|(i, j)| v[(j * frame.width + i) as usize].to_bits())
            .collect()
    };
    let capped: Vec<u32> = ties.iter().map(|t| (*t).min(255)).collect();
    for method in methods {
        let what = |route: &str| what(&format!("{route} by {method:?}"));
        let base = base.clone().method(method);
        let counted = voronoi(&Backend::Device(m), sites, &base.clone().ties(true)).unwrap();
        check(
            failures,
            &what("tie-counting labels"),
            &counted.labels,
            &nearest,
        );
        check(failures, &what("tie counts"), &counted.ties, &capped);
        let part = voronoi(
            &Backend::Device(m),
            sites,
            &base.window(Some(window)).max_tile(Some(8)),
        )
        .unwrap();
        check(
            failures,
            &what("window"),
            &part.labels,
            &levels_in(&ranks, 3, 1, &frame, window),
        );
        check(
            failures,
            &what("window distances"),
            &bits(&part.distances),
            &inside(&grown.distances),
        );
    }
    if metric == Metric::L2 {
        let alone = voronoi(&Backend::Cpu, sites, &base.ties(true)).unwrap();
        check(failures, &what("grid on the cpu"), &alone.labels, &nearest);
        check(
            failures,
            &what("grid's ties on the cpu"),
            &alone.ties,
            &capped,
        );
    }
    check(failures, &what("cpu"), &grown.labels, &nearest);
    let options = KNearestOptions::exact(frame, 3).metric(metric);
    check(
        failures,
        &what("3 nearest"),
        &k_nearest(&Backend::Device(m), sites, &options)
            .unwrap()
            .labels,
        &ranks,
    );
    check(
        failures,
        &what("3 nearest peeled"),
        &k_nearest_peeled(m, sites, &options).unwrap().labels,
        &ranks,
    );
    check(
        failures,
        &what("3 nearest on the cpu"),
        &k_nearest(
            &Backend::Cpu,
            sites,
            &KNearestOptions::exact(frame, 3).metric(metric),
        )
        .unwrap()
        .labels,
        &ranks,
    );
}

#[test]
fn labels_are_exact_for_the_doubles_given() {
    let m = machine();
    let mut failures = Vec::new();
    for (name, frame, sites) in inputs() {
        for metric in METRICS {
            diagrams_are_exact(&mut failures, &m, name, frame, &sites, metric);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The example: random doubles over a large picture, where float32
/// sites named a farther site on about a pixel in a million.
#[test]
fn random_doubles_over_a_large_picture() {
    let m = machine();
    let frame = Frame::pixels(256, 256).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let sites: Vec<DVec2> = (0..2000)
        .map(|_| DVec2::new(rng.gen_range(-0.5..255.5), rng.gen_range(-0.5..255.5)))
        .collect();
    let (ranks, _) = exact_k_nearest(&sites, &frame, Metric::L2, 1);
    let mut failures = Vec::new();
    for method in [Method::Cones, Method::Grid] {
        let d = voronoi(
            &Backend::Device(&m),
            &sites,
            &VoronoiOptions::exact(frame).method(method),
        )
        .unwrap();
        check(
            &mut failures,
            &format!("random doubles by {method:?}"),
            &d.labels,
            &ranks,
        );
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A lattice of a decimal spacing (a non-power-of-two step) seen through a
/// frame of tenths, every coordinate moved by up to an ulp.
fn near_degenerate_lattice() -> impl proptest::strategy::Strategy<Value = Vec<DVec2>> {
    use proptest::prelude::*;
    (
        2u32..9,
        3u32..7,
        3u32..6,
        prop::collection::vec(-1i64..=1, 84),
    )
        .prop_map(|(tenths, nx, ny, moves)| {
            let spacing = tenths as f64 / 10.0;
            let mut moves = moves.into_iter().cycle();
            (0..nx * ny)
                .map(|k| {
                    let p = DVec2::new(0.05, 0.15)
                        + DVec2::new((k % nx) as f64, (k / nx) as f64) * spacing;
                    DVec2::new(
                        ulps(p.x, moves.next().unwrap_or(0)),
                        ulps(p.y, moves.next().unwrap_or(0)),
                    )
                })
                .collect()
        })
}

proptest::proptest! {
    #![proptest_config(proptest::test_runner::Config { cases: 24, ..Default::default() })]

    /// Random near-degenerate lattices under a random metric: the device's
    /// screen tiles and the CPU's pixel algorithm name the exact nearest.
    #[test]
    fn near_degenerate_lattices_get_exact_labels(
        sites in near_degenerate_lattice(),
        metric in 0usize..4,
    ) {
        let m = machine();
        let metric = METRICS[metric];
        let frame = Frame::with_bbox(32, Some(24), [0.0, 0.0, 3.2, 2.4]).unwrap();
        let (ranks, _) = exact_k_nearest(&sites, &frame, metric, 1);
        let options = VoronoiOptions::exact(frame).metric(metric);
        let device = voronoi(&Backend::Device(&m), &sites, &options.clone().method(Method::Cones)).unwrap();
        let grown = k_nearest(&Backend::Cpu, &sites, &KNearestOptions::exact(frame, 1).metric(metric)).unwrap();
        proptest::prop_assert_eq!(&device.labels, &ranks);
        proptest::prop_assert_eq!(&grown.labels, &ranks);
        if metric == Metric::L2 {
            let grid = voronoi(&Backend::Cpu, &sites, &options).unwrap();
            proptest::prop_assert_eq!(&grid.labels, &ranks);
        }
    }
}

/// Under polygon metrics (star-shaped and convex, drawn as fans) the labels
/// are certified too: the device's, tiled, in a window, the 3 nearest and the
/// CPU's equal exact ranks by the gauge in rationals, on a lattice full of
/// ties and on random doubles; the distances come from the labels, bit for
/// bit the CPU's.
#[test]
fn polygon_labels_are_exact_in_every_tile() {
    let m = machine();
    let star: Vec<DVec2> = [
        (1.0, 0.0),
        (0.5, 0.8),
        (-0.6, 0.7),
        (-1.0, -0.1),
        (-0.3, -0.9),
        (0.7, -0.6),
    ]
    .map(|(x, y)| DVec2::new(x, y))
    .to_vec();
    let frame = Frame::pixels(48, 40).unwrap();
    let lattice: Vec<DVec2> = (0..30)
        .map(|k| DVec2::new((k % 6) as f64 * 8.0 + 3.0, (k / 6) as f64 * 8.0 + 2.0))
        .rev()
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(52);
    let random: Vec<DVec2> = (0..40)
        .map(|_| DVec2::new(rng.gen_range(0.0..48.0), rng.gen_range(0.0..40.0)))
        .collect();
    let bits = |d: &[f32]| d.iter().map(|v| v.to_bits()).collect::<Vec<u32>>();
    let mut failures = Vec::new();
    for (shape, kernel) in [(&star, DVec2::ZERO), (&star, DVec2::new(0.1, -0.05))] {
        let metric = Metric::polygon(shape, kernel).unwrap();
        // Near ties that float32 cannot see: pairs of sites along two
        // vertices' directions from a pixel centre, the first (smaller index)
        // farther by a relative 1e-12 to 1e-9.
        let Metric::Polygon(gauge) = metric else {
            unreachable!()
        };
        let mut pairs = Vec::new();
        for _ in 0..12 {
            let centre = DVec2::new(rng.gen_range(2..46) as f64, rng.gen_range(2..38) as f64) + 0.5;
            let n = gauge.vertices.len();
            let (a, b) = (rng.gen_range(0..n), rng.gen_range(0..n));
            let t = rng.gen_range(2.0..6.0);
            let gap = 10f64.powf(rng.gen_range(-12.0..-9.0));
            pairs.push(centre - gauge.vertices[a] * (t * (1.0 + gap)));
            pairs.push(centre - gauge.vertices[b] * t);
        }
        for (name, sites) in [
            ("lattice", &lattice),
            ("random", &random),
            ("near ties", &pairs),
        ] {
            let what = |route: &str| format!("{name}, polygon, {route}");
            let (ranks, _) = exact_k_nearest(sites, &frame, metric, 3);
            let all = PixelRect::sized(frame.width, frame.height);
            let nearest = levels_in(&ranks, 3, 1, &frame, all);
            let base = VoronoiOptions::exact(frame).metric(metric);
            let grown = k_nearest(
                &Backend::Cpu,
                sites,
                &KNearestOptions::exact(frame, 1).metric(metric),
            )
            .unwrap();
            check(&mut failures, &what("cpu"), &grown.labels, &nearest);
            for (route, options) in [
                ("screen tiles", base.clone()),
                ("tiles of 16", base.clone().max_tile(Some(16))),
            ] {
                let d = voronoi(&Backend::Device(&m), sites, &options).unwrap();
                check(&mut failures, &what(route), &d.labels, &nearest);
                let distances = what(&format!("{route} distances"));
                check(
                    &mut failures,
                    &distances,
                    &bits(&d.distances),
                    &bits(&grown.distances),
                );
            }
            let window = PixelRect {
                x: 5,
                y: 7,
                width: 20,
                height: 13,
            };
            let part = voronoi(
                &Backend::Device(&m),
                sites,
                &base.window(Some(window)).max_tile(Some(8)),
            )
            .unwrap();
            check(
                &mut failures,
                &what("window"),
                &part.labels,
                &levels_in(&ranks, 3, 1, &frame, window),
            );
            let options = KNearestOptions::exact(frame, 3).metric(metric);
            let three = k_nearest(&Backend::Device(&m), sites, &options).unwrap();
            check(&mut failures, &what("3 nearest"), &three.labels, &ranks);
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The grid refuses what it cannot compute, in words, before any work.
#[test]
fn the_grid_refuses_bad_input() {
    let frame = Frame::pixels(16, 16).unwrap();
    let options = VoronoiOptions::exact(frame);
    let err = |sites: &[DVec2], options: &VoronoiOptions| {
        voronoi(&Backend::Cpu, sites, options)
            .unwrap_err()
            .to_string()
    };
    assert!(err(&[], &options).contains("empty"));
    assert!(err(&[DVec2::new(f64::NAN, 1.0)], &options).contains("non-finite"));
    let big = Frame {
        width: Frame::MAX_SIDE + 1,
        ..frame
    };
    let e = voronoi(&Backend::Cpu, &[DVec2::ZERO], &options.clone().frame(big)).unwrap_err();
    assert!(matches!(e, pixgeo::Error::PictureTooLarge { .. }), "{e}");
    let l1 = options.clone().metric(Metric::L1);
    assert!(err(&[DVec2::ZERO], &l1).contains("Euclidean"));
    let drawn = options.clone().method(Method::Cones);
    assert!(err(&[DVec2::ZERO], &drawn).contains("Vulkan device"));
    // Sites whose squared distances overflow doubles are still decided.
    let far = [DVec2::new(-1.7e308, 2.4e10), DVec2::new(1e308, 5.0)];
    let d = voronoi(&Backend::Cpu, &far, &options).unwrap();
    assert!(d.labels.iter().all(|&l| l < 2));
}

/// A site one ulp nearer than another at the corner pixel of a block, the
/// only pixel where they nearly tie, both far off so that their keys' float
/// difference is mostly rounding: a block is not given to one site unless
/// its margin holds at every pixel.
#[test]
fn a_near_tie_at_a_blocks_corner_is_decided_exactly() {
    let frame = Frame::pixels(4, 4).unwrap();
    let mut wrong_in_floats = 0;
    for far in [123456.789, 2345678.91, 34567891.23, 98765432.1, 3.456789e9] {
        // Mirrored about pixel (0, 0), whose bisector crosses no other pixel.
        let owner = DVec2::new(far, far);
        let nearer = DVec2::new(ulps(-far, 1), -far);
        let sites = [owner, nearer];
        let (ranks, _) = exact_k_nearest(&sites, &frame, Metric::L2, 1);
        assert_eq!(ranks[0], 1, "{far}");
        let d = voronoi(&Backend::Cpu, &sites, &VoronoiOptions::exact(frame)).unwrap();
        assert_eq!(d.labels, ranks, "{far}");
        let key = |s: DVec2| s.length_squared();
        wrong_in_floats += usize::from(key(nearer) >= key(owner));
    }
    // Doubles alone name the wrong site here.
    assert!(wrong_in_floats > 0);
}
