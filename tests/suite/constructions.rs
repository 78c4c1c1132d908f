//! Property tests of the exact constructions on generated near-degenerate
//! doubles: decimal lattices with one-ulp moves, decimal points along a line
//! (nearly collinear once rounded), integer points of a circle scaled by a
//! decimal (nearly co-circular), each at magnitudes from 1e-300 to 1e300 or
//! 1e15 from the origin. Every answer is checked against brute force in
//! exact rationals: the smallest enclosing circle's centre and radius are the
//! doubles nearest the exact ones; the extremal triangles and quadrangles
//! named have the extreme exact area, printed rounded to nearest; the pairs
//! of the diameter, maximum distance and Hausdorff distance are exact
//! extremes, their distances rounded to nearest.

use glam::DVec2;
use num_rational::BigRational;
use pixgeo::algorithms::{
    area::{extremal_quadrangle, extremal_triangle, AreaAnswer, AreaOptions, Extreme},
    distances::{diameter, directed_hausdorff, max_distance, HausdorffOptions, Method, Pair},
    homothet::{enclose, EncloseOptions, Unit},
};
use pixgeo::Backend;
use pixgeo_reference::exact::{
    directed_hausdorff_squared, double_area, extremal_quadrangle_double_area, extremal_triangles,
    is_nearest, is_nearest_root, max_squared_distance, smallest_enclosing_circle, squared,
};
use proptest::prelude::*;

use crate::common::{machine, ulps};

/// Near-degenerate points: `family` picks a lattice, a line or a circle,
/// `tenths` their decimal spacing, `moves` the ulps each coordinate moves,
/// `magnitude` where they end up.
fn points(family: usize, tenths: u32, moves: &[i64], magnitude: usize, n: usize) -> Vec<DVec2> {
    let step = tenths as f64 / 10.0;
    let ring = [
        (5, 0),
        (3, 4),
        (0, 5),
        (-4, 3),
        (-5, 0),
        (-3, -4),
        (4, -3),
        (-3, 4),
    ];
    let base: Vec<DVec2> = (0..n)
        .map(|k| match family {
            0 => DVec2::new((k % 3) as f64, (k / 3) as f64) * step + DVec2::splat(0.05),
            1 => {
                let t = (k as f64 * 0.7 + 0.1) * step;
                DVec2::new(t, t * 3.3 + 0.2)
            }
            _ => DVec2::new(ring[k % 8].0 as f64, ring[k % 8].1 as f64) * step,
        })
        .collect();
    let mut moves = moves.iter().copied().cycle();
    let (scale, shift) = [
        (1.0, 0.0),
        (1e-300, 0.0),
        (1e300, 0.0),
        (3.7e-150, 0.0),
        (1.0, 1e15),
    ][magnitude];
    base.into_iter()
        .map(|p| {
            let p = DVec2::new(
                ulps(p.x, moves.next().unwrap_or(0)),
                ulps(p.y, moves.next().unwrap_or(0)),
            );
            p * scale + DVec2::splat(shift)
        })
        .collect()
}

fn half(twice: &BigRational) -> BigRational {
    twice / BigRational::from_integer(2.into())
}

/// The answer, or `None` where it was refused because the exact area (twice
/// `twice`) rounds beyond the largest double; any other refusal fails.
fn representable(answer: pixgeo::Result<AreaAnswer>, twice: &BigRational) -> Option<AreaAnswer> {
    match answer {
        Ok(answer) => Some(answer),
        Err(e) => {
            assert!(e.to_string().contains("beyond the largest float"), "{e}");
            assert!(half(twice) > max(), "{e}");
            None
        }
    }
}

fn max() -> BigRational {
    BigRational::from_float(f64::MAX).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 40, ..ProptestConfig::default() })]

    #[test]
    fn exact_constructions_on_near_degenerate_doubles(
        family in 0usize..3,
        tenths in 1u32..10,
        moves in prop::collection::vec(-1i64..=1, 18),
        magnitude in 0usize..5,
        n in 4usize..8,
    ) {
        let m = machine();
        let sites = points(family, tenths, &moves, magnitude, n);
        let what = format!("{sites:?}");

        // The smallest enclosing circle.
        let circle = enclose(&Backend::Device(&m), &sites, &EncloseOptions::new(Unit::Circle).side(256)).unwrap();
        let (centre, r2) = smallest_enclosing_circle(&sites);
        let [x, y] = circle.exact.centre;
        prop_assert!(is_nearest(x, &centre[0]) && is_nearest(y, &centre[1]), "{what}: centre");
        prop_assert!(is_nearest_root(circle.exact.scale, &r2), "{what}: radius");

        for extreme in [Extreme::Smallest, Extreme::Largest] {
            let largest = extreme == Extreme::Largest;
            // Triangles, by the roofs and the sweep.
            let (best, twice) = extremal_triangles(&sites, largest);
            let answers = [
                extremal_triangle(&Backend::Device(&m), &sites, &AreaOptions::new(extreme).side(Some(64))),
                extremal_triangle(&Backend::Cpu, &sites, &AreaOptions::new(extreme)),
            ];
            for answer in answers {
                let Some(answer) = representable(answer, &twice) else { continue };
                let mut set = [answer.sites[0], answer.sites[1], answer.sites[2]];
                set.sort_unstable();
                prop_assert!(best.contains(&set), "{what} {extreme:?}: {:?}", answer.sites);
                prop_assert!(is_nearest(answer.area, &half(&twice)), "{what}: area");
            }
            // Quadrangles.
            if let Some(twice) = extremal_quadrangle_double_area(&sites, largest) {
                let answers = [
                    extremal_quadrangle(&Backend::Device(&m), &sites, &AreaOptions::new(extreme).side(Some(64))),
                    extremal_quadrangle(&Backend::Cpu, &sites, &AreaOptions::new(extreme)),
                ];
                for answer in answers {
                    let Some(answer) = representable(answer, &twice) else { continue };
                    let v: Vec<DVec2> = answer.sites.iter().map(|&k| sites[k as usize]).collect();
                    let named = double_area(v[0], v[1], v[2]) + double_area(v[2], v[3], v[0]);
                    prop_assert_eq!(&named, &twice, "{} {:?}: {:?}", what, extreme, answer.sites);
                    prop_assert!(is_nearest(answer.area, &half(&twice)), "{what}: area");
                }
            }
        }

        // Extreme pairs: within the set, and from its first half to the rest.
        let (a, b) = sites.split_at(n / 2);
        let check = |pair: Pair, from: &[DVec2], to: &[DVec2], want: BigRational| {
            let named = squared(from[pair.from as usize], to[pair.to as usize]);
            named == want && is_nearest_root(pair.distance, &want)
        };
        let d = diameter(&m, &sites, None).unwrap().pair;
        prop_assert!(check(d, &sites, &sites, max_squared_distance(&sites, &sites)), "{what}");
        let far = max_distance(&m, a, b, None).unwrap().pair;
        prop_assert!(check(far, a, b, max_squared_distance(a, b)), "{what}");
        for method in [Method::Pixels, Method::Grid] {
            let h = directed_hausdorff(&Backend::Device(&m), a, b, &HausdorffOptions::default().method(Some(method))).unwrap().pair;
            prop_assert!(check(h, a, b, directed_hausdorff_squared(a, b)), "{what} {method:?}");
        }
    }
}
