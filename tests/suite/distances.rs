//! Hausdorff distance, diameter and maximum distance against brute force on random,
//! clustered and degenerate sets: the answers must be exact.

use crate::common::{clustered, machine, uniform};
use glam::DVec2;
use pixgeo::algorithms::distances::{diameter, directed_hausdorff, hausdorff, max_distance};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn brute_directed(a: &[DVec2], b: &[DVec2]) -> f64 {
    a.iter()
        .map(|p| {
            b.iter()
                .map(|q| p.distance(*q))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

fn brute_max(a: &[DVec2], b: &[DVec2]) -> f64 {
    a.iter()
        .flat_map(|p| b.iter().map(|q| p.distance(*q)))
        .fold(0.0, f64::max)
}

/// Named pairs of sets.
fn pairs() -> Vec<(&'static str, Vec<DVec2>, Vec<DVec2>)> {
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let p = |x: f64, y: f64| DVec2::new(x, y);
    let mut out = vec![
        (
            "uniform",
            uniform(&mut rng, 400, 100.0, 60.0),
            uniform(&mut rng, 300, 100.0, 60.0),
        ),
        (
            "clustered",
            clustered(&mut rng, 300, 500.0, 500.0),
            clustered(&mut rng, 200, 500.0, 500.0),
        ),
        ("single points", vec![p(1.0, 2.0)], vec![p(-3.5, 7.25)]),
        (
            "same point",
            vec![p(4.0, 4.0)],
            vec![p(4.0, 4.0), p(4.0, 4.0)],
        ),
        (
            "collinear",
            (0..30).map(|i| p(i as f64 * 1.5, i as f64 * 0.5)).collect(),
            (0..7)
                .map(|i| p(i as f64 * 6.0 + 0.3, i as f64 * 2.0 + 0.1))
                .collect(),
        ),
        (
            "lattice",
            (0..100)
                .map(|i| p((i % 10) as f64, (i / 10) as f64))
                .collect(),
            (0..25)
                .map(|i| p((i % 5) as f64 * 2.0, (i / 5) as f64 * 2.0))
                .collect(),
        ),
        (
            "far apart, large coordinates",
            uniform(&mut rng, 50, 10.0, 10.0)
                .into_iter()
                .map(|q| q + DVec2::new(1e6, -2e6))
                .collect(),
            uniform(&mut rng, 40, 3.0, 3.0),
        ),
    ];
    let mut dup = uniform(&mut rng, 60, 20.0, 20.0);
    dup.extend(dup.clone());
    out.push(("duplicates", dup.clone(), dup[..30].to_vec()));
    out
}

#[test]
fn hausdorff_is_exact() {
    let m = machine();
    for (name, a, b) in pairs() {
        for side in [None, Some(64)] {
            let h = hausdorff(&m, &a, &b, side).unwrap_or_else(|e| panic!("{name}: {e}"));
            let (ab, ba) = (brute_directed(&a, &b), brute_directed(&b, &a));
            assert_eq!(h.a_to_b.pair.distance, ab, "{name} {side:?} a->b");
            assert_eq!(h.b_to_a.pair.distance, ba, "{name} {side:?} b->a");
            assert_eq!(h.distance, ab.max(ba), "{name}");
            let pair = h.a_to_b.pair;
            assert_eq!(a[pair.from as usize].distance(b[pair.to as usize]), ab);
        }
    }
}

#[test]
fn diameter_and_maximum_distance_are_exact() {
    let m = machine();
    for (name, a, b) in pairs() {
        for side in [None, Some(48)] {
            let d = diameter(&m, &a, side).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(
                d.pair.distance,
                brute_max(&a, &a),
                "{name} {side:?} diameter"
            );
            let x = max_distance(&m, &a, &b, side).unwrap();
            assert_eq!(
                x.pair.distance,
                brute_max(&a, &b),
                "{name} {side:?} maxdist"
            );
            assert_eq!(
                a[x.pair.from as usize].distance(b[x.pair.to as usize]),
                x.pair.distance
            );
        }
    }
}

#[test]
fn the_picture_leaves_few_points_to_check() {
    let m = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let a = uniform(&mut rng, 3000, 1000.0, 1000.0);
    let b = uniform(&mut rng, 3000, 1000.0, 1000.0);
    let h = directed_hausdorff(&m, &a, &b, None).unwrap();
    assert_eq!(h.pair.distance, brute_directed(&a, &b));
    assert!(h.checked < 30, "{} of 3000 points checked", h.checked);
}

#[test]
fn empty_or_invalid_sets_are_clear_errors() {
    let m = machine();
    let a = [DVec2::new(0.0, 0.0)];
    assert!(hausdorff(&m, &a, &[], None).is_err());
    assert!(diameter(&m, &[], None).is_err());
    assert!(max_distance(&m, &[DVec2::new(f64::NAN, 1.0)], &a, None).is_err());
}

#[test]
fn extreme_coordinates_keep_exact_distances() {
    // Squares of coordinates past 1e154 overflow and those of 1e-310 vanish:
    // the sets are scaled by a power of two, which changes no pair.
    let m = machine();
    let huge = [
        DVec2::new(1e300, 1e300),
        DVec2::new(-1e300, -1e300),
        DVec2::new(0.0, 5e299),
    ];
    let d = diameter(&m, &huge, None).unwrap();
    assert_eq!(d.pair.distance, 2f64.sqrt() * 2e300);
    let tiny = [
        DVec2::new(1e-310, 0.0),
        DVec2::new(3e-310, 0.0),
        DVec2::new(0.0, 2e-310),
    ];
    let d = diameter(&m, &tiny, None).unwrap();
    assert!(
        (d.pair.distance - 13f64.sqrt() * 1e-310).abs() < 1e-322,
        "{}",
        d.pair.distance
    );
}

#[test]
fn repeated_points_are_checked_once() {
    // 100000 copies of one point against a few others: the repeats change no
    // distance, the pair names first indices, and one point is checked.
    let m = machine();
    let mut a = vec![DVec2::new(3.5, 4.25); 100_000];
    a.push(DVec2::new(-7.0, 2.0));
    let b = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(9.0, 9.0),
        DVec2::new(0.0, 0.0),
    ];
    let h = hausdorff(&m, &a, &b, None).unwrap();
    assert_eq!(h.a_to_b.pair.distance, brute_directed(&a, &b));
    assert_eq!(h.b_to_a.pair.distance, brute_directed(&b, &a));
    assert_eq!((h.a_to_b.pair.from, h.a_to_b.pair.to), (100_000, 0));
    assert_eq!(h.b_to_a.pair.to, 0);
    assert!(h.a_to_b.checked <= 2 && h.b_to_a.checked <= 2, "{h:?}");
    let d = diameter(&m, &a, None).unwrap();
    assert_eq!(
        (d.pair.from, d.pair.to, d.pair.distance),
        (0, 100_000, a[0].distance(a[100_000]))
    );
}
