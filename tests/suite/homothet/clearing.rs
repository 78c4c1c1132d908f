//! The largest empty circle among points and segments, `inside` a box: its
//! radius and centre the doubles nearest the exact ones, on near-degenerate
//! doubles, against the exact oracle over the quadratic fields that
//! axis-aligned pieces keep it in.

use super::*;
use num_rational::BigRational;
use pixgeo::{
    algorithms::homothet::{largest_empty, EmptyOptions},
    geometry::site::{Shape, Site},
};
use pixgeo_reference::{
    clearing::{is_clear, largest_empty_centre_in_box, largest_empty_in_box, Surd},
    exact::{is_nearest, is_nearest_root, is_nearest_surd},
};
use rand::Rng;

/// Whether `value` is the double nearest the exact `s`.
fn nearest(value: f64, s: &Surd) -> bool {
    if s.u == BigRational::from_integer(0.into()) || s.d == BigRational::from_integer(0.into()) {
        is_nearest(value, &s.w)
    } else {
        is_nearest_surd(value, &s.w, &s.u, &s.d)
    }
}

/// Lattice steps: not powers of two, and at far magnitudes.
const STEPS: [f64; 6] = [1.0, 0.1, 1.0 / 3.0, 7.3e-301, 1.7e300 / 64.0, 1e-151];

#[test]
fn largest_empty_among_points_is_the_nearest_double() {
    // Points on lattices, one in three moved by an ulp, some far from the
    // origin; the centre in a box: every candidate is rational (circumcentres,
    // the box's sides' points equidistant from two sites, corners).
    let machine = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(4848);
    let mut refused = 0;
    for round in 0..48 {
        let h = STEPS[round % STEPS.len()];
        let far = if round >= 36 {
            (1e15 * h).min(1e307)
        } else {
            0.0
        };
        let (w, t) = (rng.gen_range(4..12) as f64, rng.gen_range(4..12) as f64);
        let (lo, hi) = (DVec2::splat(far), DVec2::new(far + w * h, far + t * h));
        let points: Vec<DVec2> = (0..rng.gen_range(3..9))
            .map(|_| {
                let p = DVec2::new(
                    far + rng.gen_range(0..=w as i64) as f64 * h,
                    far + rng.gen_range(0..=t as i64) as f64 * h,
                );
                if rng.gen_range(0..3) == 0 {
                    DVec2::new(p.x, p.y.next_up())
                } else {
                    p
                }
            })
            .collect();
        let region = Region {
            rings: vec![vec![lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)]],
        };
        // An ulp above 0 is 5e-324: beside 1e299, no power of two scales both
        // exactly, and the refusal says so.
        let answer = match largest_empty(
            &machine,
            &points,
            &EmptyOptions::new(Unit::Circle)
                .region(region.clone())
                .side(128),
        ) {
            Err(e) if h > 1e150 && e.to_string().contains("round the smallest to 0") => {
                refused += 1;
                continue;
            }
            answer => answer.unwrap_or_else(|e| panic!("{round}: {points:?} in {hi:?}: {e}")),
        };
        let (squared, centres) = largest_empty_centre_in_box(&points, lo, hi);
        let label = format!("{round}: {points:?} in {lo:?}..{hi:?}: {answer:?}");
        assert_eq!(answer.tolerance, 0.0, "{label}");
        assert!(is_nearest_root(answer.exact.scale, &squared), "{label}");
        let [x, y] = answer.exact.centre;
        assert!(
            centres
                .iter()
                .any(|c| is_nearest(x, &c[0]) && is_nearest(y, &c[1])),
            "{label}"
        );
    }
    assert!(refused <= 4, "{refused} refused");
}

#[test]
fn largest_empty_among_points_and_segments_is_the_nearest_double() {
    // Lattices as above, with ulp moves and far offsets, and axis-aligned
    // segments.
    let machine = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(48);
    let mut cases = 0;
    // The last rounds far from the origin, where a set's digits are in its
    // offsets.
    let rounds = 48;
    for round in 0..rounds {
        let h = STEPS[round % STEPS.len()];
        let far = if round >= 36 {
            (1e15 * h).min(1e307)
        } else {
            0.0
        };
        let (w, t) = (rng.gen_range(8..20) as f64, rng.gen_range(8..20) as f64);
        let (lo, hi) = (DVec2::splat(far), DVec2::new(far + w * h, far + t * h));
        let lattice = |rng: &mut ChaCha8Rng| {
            let p = DVec2::new(
                far + rng.gen_range(1..w as i64) as f64 * h,
                far + rng.gen_range(1..t as i64) as f64 * h,
            );
            // One point in three moved by an ulp.
            if rng.gen_range(0..3) == 0 {
                DVec2::new(p.x.next_up(), p.y)
            } else {
                p
            }
        };
        let points: Vec<DVec2> = (0..rng.gen_range(2..6))
            .map(|_| lattice(&mut rng))
            .collect();
        let mut segments = Vec::new();
        for _ in 0..rng.gen_range(0..3) {
            let a = lattice(&mut rng);
            let b = if rng.gen_bool(0.5) {
                DVec2::new(a.x, far + rng.gen_range(1..t as i64) as f64 * h)
            } else {
                DVec2::new(far + rng.gen_range(1..w as i64) as f64 * h, a.y)
            };
            segments.push((a, b));
        }
        let sites: Vec<Site> = points
            .iter()
            .map(|p| Site::point(*p))
            .chain(
                segments
                    .iter()
                    .map(|&(a, b)| Site::new(Shape::Segment(a, b))),
            )
            .collect();
        let region = Region {
            rings: vec![vec![lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)]],
        };
        let answer = largest_empty(
            &machine,
            &sites,
            &EmptyOptions::new(Unit::Circle)
                .region(region.clone())
                .inside(true)
                .side(128),
        )
        .unwrap();
        let (radius, centres) = largest_empty_in_box(&points, &segments, lo, hi);
        let label = format!("{round}: {points:?} {segments:?} in {hi:?}: {answer:?}");
        assert_eq!(answer.tolerance, 0.0, "{label}");
        assert!(
            nearest(answer.exact.scale, &radius),
            "{label}: exact radius {}",
            radius.approximate()
        );
        // Centres: where the best circles form a corridor, any of its points
        // (the oracle lists its ends); the printed one clears the sites by
        // the radius less its rounding.
        let c = DVec2::from(answer.exact.centre);
        let ulp = |x: f64| x.abs().next_up() - x.abs();
        let rounding = 2.0 * ulp(c.abs().max_element().max(answer.exact.scale));
        let less = Surd {
            w: &radius.w - BigRational::from_float(rounding).unwrap(),
            ..radius.clone()
        };
        assert!(
            is_clear(&points, &segments, (lo, hi), c, &less),
            "{label}: exact centres {:?}",
            centres
                .iter()
                .map(|c| [c[0].approximate(), c[1].approximate()])
                .collect::<Vec<_>>()
        );
        cases += 1;
    }
    assert_eq!(cases, rounds);
}
