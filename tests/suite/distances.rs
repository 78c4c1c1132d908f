//! Hausdorff distance, diameter and maximum distance against brute force on random,
//! clustered and degenerate sets: the answers must be exact.

use crate::common::{clustered, machine, uniform};
use glam::DVec2;
use pixgeo::algorithms::distances::{
    diameter, directed_hausdorff, hausdorff, max_distance, HausdorffOptions, Method,
};
use pixgeo::Backend;
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

/// Whether pixgeo's distance (the exact one, correctly rounded) matches a
/// float brute force's (rounded twice: the square and its root) to an ulp.
fn same(pixgeo: f64, brute: f64) -> bool {
    (pixgeo - brute).abs() <= f64::EPSILON * brute
}

#[test]
fn hausdorff_is_exact() {
    let m = machine();
    // Both ways of proposing partners, and the picture at two sizes.
    let ways = [
        (Method::Pixels, None),
        (Method::Pixels, Some(64)),
        (Method::Grid, None),
    ];
    for (name, a, b) in pairs() {
        for (method, side) in ways {
            let h = hausdorff(
                &Backend::Device(&m),
                &a,
                &b,
                &HausdorffOptions::default().method(Some(method)).side(side),
            )
            .unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(h.a_to_b.method, method);
            assert_eq!(
                hausdorff(
                    &Backend::Device(&m),
                    &a,
                    &b,
                    &HausdorffOptions::default().side(side)
                )
                .unwrap()
                .distance,
                h.distance
            );
            let (ab, ba) = (brute_directed(&a, &b), brute_directed(&b, &a));
            assert!(same(h.a_to_b.pair.distance, ab), "{name} {side:?} a->b");
            assert!(same(h.b_to_a.pair.distance, ba), "{name} {side:?} b->a");
            assert!(same(h.distance, ab.max(ba)), "{name}");
            let pair = h.a_to_b.pair;
            assert!(same(
                a[pair.from as usize].distance(b[pair.to as usize]),
                ab
            ));
        }
    }
}

#[test]
fn diameter_and_maximum_distance_are_exact() {
    let m = machine();
    for (name, a, b) in pairs() {
        for side in [None, Some(48)] {
            let d = diameter(&m, &a, side).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(
                same(d.pair.distance, brute_max(&a, &a)),
                "{name} {side:?} diameter"
            );
            let x = max_distance(&m, &a, &b, side).unwrap();
            assert!(
                same(x.pair.distance, brute_max(&a, &b)),
                "{name} {side:?} maxdist"
            );
            assert!(same(
                a[x.pair.from as usize].distance(b[x.pair.to as usize]),
                x.pair.distance
            ));
        }
    }
}

#[test]
fn the_picture_leaves_few_points_to_check() {
    let m = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let a = uniform(&mut rng, 3000, 1000.0, 1000.0);
    let b = uniform(&mut rng, 3000, 1000.0, 1000.0);
    for method in [Method::Pixels, Method::Grid] {
        let h = directed_hausdorff(
            &Backend::Device(&m),
            &a,
            &b,
            &HausdorffOptions::default().method(Some(method)),
        )
        .unwrap();
        assert_eq!(h.pair.distance, brute_directed(&a, &b));
        assert!(
            h.checked < 30,
            "{method:?}: {} of 3000 points checked",
            h.checked
        );
    }
}

#[test]
fn empty_or_invalid_sets_are_clear_errors() {
    let m = machine();
    let a = [DVec2::new(0.0, 0.0)];
    assert!(hausdorff(&Backend::Device(&m), &a, &[], &HausdorffOptions::default()).is_err());
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
    let h = hausdorff(&Backend::Device(&m), &a, &b, &HausdorffOptions::default()).unwrap();
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

/// Ties within an ulp: the vertices of regular polygons in tenths, each one
/// ulp off, and a lattice of a non-power-of-two step. The pair named is an
/// exact extreme and the distance printed its exact value rounded.
#[test]
fn extreme_pairs_are_exact_under_ulp_ties() {
    use num_rational::BigRational;
    use pixgeo::algorithms::distances::Pair;
    use pixgeo_reference::exact::{
        directed_hausdorff_squared, is_nearest_root, max_squared_distance, squared,
    };
    use rand::{Rng, SeedableRng};
    let m = crate::common::machine();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(17);
    let mut nudge = |v: f64| {
        let step = rng.gen_range(-1i64..=1);
        if v == 0.0 {
            v
        } else {
            f64::from_bits((v.to_bits() as i64 + step) as u64)
        }
    };
    let polygon = |n: usize, r: f64, centre: DVec2| -> Vec<DVec2> {
        (0..n)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / n as f64;
                centre + DVec2::new(t.cos(), t.sin()) * r
            })
            .collect()
    };
    let octagon: Vec<DVec2> = polygon(8, 0.3, DVec2::new(0.1, 0.7))
        .into_iter()
        .map(|p| DVec2::new(nudge(p.x), nudge(p.y)))
        .collect();
    let hexagon: Vec<DVec2> = polygon(6, 0.3, DVec2::new(0.1, 0.7))
        .into_iter()
        .map(|p| DVec2::new(nudge(p.x), nudge(p.y)))
        .collect();
    let lattice: Vec<DVec2> = (0..12)
        .map(|k| DVec2::new((k % 4) as f64 * 0.1 + 0.05, (k / 4) as f64 * 0.1 + 0.05))
        .collect();
    let cases = [
        ("octagon", octagon.clone(), hexagon.clone()),
        ("lattice", lattice.clone(), octagon),
        ("hexagon", hexagon, lattice),
    ];
    // The pair named is at the exact extreme, and its distance rounded.
    let check = |what: String, pair: Pair, from: &[DVec2], to: &[DVec2], want: BigRational| {
        let named = squared(from[pair.from as usize], to[pair.to as usize]);
        assert_eq!(named, want, "{what}");
        assert!(
            is_nearest_root(pair.distance, &want),
            "{what}: {}",
            pair.distance
        );
    };
    for (name, a, b) in cases {
        let d = diameter(&m, &a, None).unwrap().pair;
        check(
            format!("{name} diameter"),
            d,
            &a,
            &a,
            max_squared_distance(&a, &a),
        );
        let far = max_distance(&m, &a, &b, None).unwrap().pair;
        check(
            format!("{name} max"),
            far,
            &a,
            &b,
            max_squared_distance(&a, &b),
        );
        for method in [Method::Pixels, Method::Grid] {
            let h = directed_hausdorff(
                &Backend::Device(&m),
                &a,
                &b,
                &HausdorffOptions::default().method(Some(method)),
            )
            .unwrap()
            .pair;
            check(
                format!("{name} hausdorff by {method:?}"),
                h,
                &a,
                &b,
                directed_hausdorff_squared(&a, &b),
            );
        }
    }
}
