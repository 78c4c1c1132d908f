//! Regular triangulations and power diagrams against their definitions by
//! brute force, in exact arithmetic: every triangle has no site below its
//! lifted plane, the triangles tile the hull, hidden sites own no cell, and
//! every pixel's label has the least power exactly (ties to the lower index),
//! and every cell's corners are the doubles nearest the exact corners of the
//! clipped diagram, found by brute force in rationals.

use crate::{
    cells::check_ring,
    common::{ulps, uniform},
};
use glam::DVec2;
use num_rational::BigRational;
use pixgeo::{
    algorithms::cells::CellsOptions,
    algorithms::power::{power_cells, power_diagram, regular_triangulation, PowerOptions},
    geometry::{cell::Rect, power::Weighted, predicates::orient, Frame},
    machine::PixelRect,
};
use pixgeo_reference::exact::clipped_power_corners;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

fn rational(x: f64) -> BigRational {
    BigRational::from_float(x).unwrap()
}

fn exact_power(p: DVec2, s: Weighted) -> BigRational {
    let (x, y) = (
        rational(p.x) - rational(s.at.x),
        rational(p.y) - rational(s.at.y),
    );
    &x * &x + &y * &y - rational(s.weight)
}

/// Twice the triangle's area, exactly.
fn area(a: DVec2, b: DVec2, c: DVec2) -> BigRational {
    (rational(b.x) - rational(a.x)) * (rational(c.y) - rational(a.y))
        - (rational(b.y) - rational(a.y)) * (rational(c.x) - rational(a.x))
}

/// The power test in rationals: positive when `d`'s lifted point lies
/// below the plane through the counter-clockwise a, b, c's.
fn exact_power_test(t: [Weighted; 3], d: Weighted) -> BigRational {
    let rows = t.map(|s| {
        let (x, y) = (
            rational(s.at.x) - rational(d.at.x),
            rational(s.at.y) - rational(d.at.y),
        );
        let lift = &x * &x + &y * &y - rational(s.weight) + rational(d.weight);
        (x, y, lift)
    });
    let [(ax, ay, al), (bx, by, bl), (cx, cy, cl)] = rows;
    al * (&bx * &cy - &by * &cx) - bl * (&ax * &cy - &ay * &cx) + cl * (&ax * &by - &ay * &bx)
}

/// Checks the regular triangulation of `sites` against the definition.
fn check_regular(sites: &[Weighted]) -> Vec<u32> {
    let regular = regular_triangulation(sites).unwrap();
    let points: Vec<DVec2> = sites.iter().map(|s| s.at).collect();
    for t in &regular.triangles {
        let [a, b, c] = t.map(|v| sites[v as usize]);
        assert!(
            orient(a.at, b.at, c.at) > 0.0,
            "{t:?} is not counter-clockwise"
        );
        let zero = BigRational::from_integer(0.into());
        let below = sites
            .par_iter()
            .position_any(|s| exact_power_test([a, b, c], *s) > zero);
        assert_eq!(below, None, "a site below {t:?}");
        assert!(t.iter().all(|v| regular.hidden.binary_search(v).is_err()));
    }
    // The triangles tile the hull: their areas sum to the hull's.
    let hull = pixgeo::geometry::predicates::convex_hull(&points);
    let o = points[hull[0] as usize];
    let hull_area = (1..hull.len() - 1)
        .map(|k| area(o, points[hull[k] as usize], points[hull[k + 1] as usize]))
        .fold(BigRational::from_integer(0.into()), |s, a| s + a);
    let total = regular
        .triangles
        .iter()
        .map(|t| {
            area(
                points[t[0] as usize],
                points[t[1] as usize],
                points[t[2] as usize],
            )
        })
        .fold(BigRational::from_integer(0.into()), |s, a| s + a);
    assert_eq!(total, hull_area);
    // A hidden site is the least power nowhere: at its own point another
    // site has no more power (and less, unless it is a repeat).
    for &h in &regular.hidden {
        let s = sites[h as usize];
        let own = exact_power(s.at, s);
        assert!(
            sites
                .iter()
                .enumerate()
                .any(|(k, t)| k != h as usize && exact_power(s.at, *t) <= own),
            "hidden site {h}"
        );
    }
    regular.hidden
}

fn weighted(points: &[DVec2], weights: &[f64]) -> Vec<Weighted> {
    points
        .iter()
        .zip(weights)
        .map(|(&at, &weight)| Weighted { at, weight })
        .collect()
}

#[test]
fn regular_triangulations_are_their_definition() {
    let mut rng = ChaCha8Rng::seed_from_u64(52);
    // Random weights up to about a neighbour's distance squared: some sites
    // are hidden.
    let points = uniform(&mut rng, 120, 60.0, 60.0);
    let weights: Vec<f64> = (0..120).map(|_| rng.gen_range(0.0..60.0)).collect();
    let hidden = check_regular(&weighted(&points, &weights));
    assert!(!hidden.is_empty(), "no hidden site");
    // Equal weights: the Delaunay triangulation, on a lattice of
    // co-circular quadruples a tenth apart.
    let lattice: Vec<DVec2> = (0..64)
        .map(|k| DVec2::new(0.1 * (k % 8) as f64, 0.1 * (k / 8) as f64))
        .collect();
    assert!(check_regular(&weighted(&lattice, &[2.5; 64])).is_empty());
    // The lattice with weights an ulp apart, repeats, and a light site
    // inside a triangle of heavy ones (hidden at once, or later when they
    // come after it).
    let nudged: Vec<f64> = (0..64).map(|k| ulps(2.5, k % 3 - 1)).collect();
    check_regular(&weighted(&lattice, &nudged));
    let mut repeated = weighted(&points[..50], &weights[..50]);
    repeated.push(Weighted {
        at: points[3],
        weight: weights[3] + 1.0,
    });
    repeated.push(Weighted {
        at: points[4],
        weight: weights[4],
    });
    let hidden = check_regular(&repeated);
    assert!(hidden.contains(&3) && hidden.contains(&51), "{hidden:?}");
    let heavy = [(0.0, 0.0), (10.0, 0.0), (5.0, 9.0)].map(|(x, y)| Weighted {
        at: DVec2::new(x, y),
        weight: 40.0,
    });
    let light = Weighted {
        at: DVec2::new(5.0, 3.0),
        weight: 0.0,
    };
    for order in [
        vec![light, heavy[0], heavy[1], heavy[2]],
        vec![heavy[0], heavy[1], heavy[2], light],
    ] {
        let hidden = check_regular(&order);
        assert_eq!(hidden.len(), 1);
        assert_eq!(order[hidden[0] as usize], light);
    }
    // Far magnitudes.
    let far: Vec<DVec2> = points[..40].iter().map(|&p| p * 1e150).collect();
    let far_weights: Vec<f64> = weights[..40].iter().map(|w| w * 1e300).collect();
    check_regular(&weighted(&far, &far_weights));
    let line = weighted(&[DVec2::ZERO, DVec2::ONE, DVec2::splat(2.0)], &[0.0; 3]);
    assert!(regular_triangulation(&line).is_err());
}

#[test]
fn power_diagram_labels_have_the_least_power() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let frame = Frame::pixels(48, 40).unwrap();
    let points = uniform(&mut rng, 40, 48.0, 40.0);
    let weights: Vec<f64> = (0..40).map(|_| rng.gen_range(0.0..30.0)).collect();
    // And a lattice whose pixel centres have tied sites.
    let lattice: Vec<DVec2> = (0..20)
        .map(|k| DVec2::new(2.0 + 8.0 * (k % 5) as f64, 1.5 + 10.0 * (k / 5) as f64))
        .collect();
    // Repeated sites: a copy of equal weight ties everywhere, a lighter
    // one nowhere.
    let p = |x: f64, y: f64| DVec2::new(x, y);
    let repeats = weighted(
        &[
            p(5.0, 5.0),
            p(15.0, 5.0),
            p(5.0, 15.0),
            p(30.0, 20.0),
            p(30.0, 20.0),
            p(12.0, 30.0),
            p(12.0, 30.0),
        ],
        &[0.0, 0.0, 0.0, 10.0, 10.0, 3.0, 1.0],
    );
    let mut tied = 0;
    for sites in [
        weighted(&points, &weights),
        weighted(&lattice, &[4.0; 20]),
        repeats,
    ] {
        let d = power_diagram(&sites, &PowerOptions::new(frame)).unwrap();
        for (k, (&label, &power)) in d.labels.iter().zip(&d.powers).enumerate() {
            let p = DVec2::new((k % 48) as f64, (k / 48) as f64);
            let want = (0..sites.len())
                .min_by(|&a, &b| {
                    exact_power(p, sites[a])
                        .cmp(&exact_power(p, sites[b]))
                        .then(a.cmp(&b))
                })
                .unwrap();
            assert_eq!(label as usize, want, "pixel {k}");
            let exact = exact_power(p, sites[want]);
            let ties = sites
                .iter()
                .filter(|&&s| exact_power(p, s) == exact)
                .count();
            assert_eq!(d.ties[k] as usize, ties, "pixel {k}");
            assert_eq!(
                power,
                num_traits::ToPrimitive::to_f64(&exact).unwrap(),
                "pixel {k}"
            );
        }
        tied += d.ties.iter().filter(|&&t| t > 1).count();
        // Hidden sites own no pixel.
        assert!(d.regular.hidden.iter().all(|h| !d.labels.contains(h)));
    }
    assert!(tied > 0, "no tie on the lattice");
}

#[test]
fn power_diagram_windows_are_the_whole_diagrams_pixels() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let frame = Frame::pixels(40, 30).unwrap();
    let points = uniform(&mut rng, 25, 40.0, 30.0);
    let weights: Vec<f64> = (0..25).map(|_| rng.gen_range(0.0..20.0)).collect();
    let sites = weighted(&points, &weights);
    let whole = power_diagram(&sites, &PowerOptions::new(frame)).unwrap();
    let window = PixelRect {
        x: 9,
        y: 4,
        width: 17,
        height: 11,
    };
    let part = power_diagram(&sites, &PowerOptions::new(frame).window(Some(window))).unwrap();
    for (k, (&l, &p)) in part.labels.iter().zip(&part.powers).enumerate() {
        let at = (4 + k / 17) * 40 + 9 + k % 17;
        assert_eq!(
            (l, p.to_bits()),
            (whole.labels[at], whole.powers[at].to_bits())
        );
    }
    let outside = PixelRect {
        x: 30,
        y: 0,
        width: 20,
        height: 5,
    };
    assert!(power_diagram(&sites, &PowerOptions::new(frame).window(Some(outside))).is_err());
}

/// One case of weighted sites and a rectangle, far out or tiny by `scale`
/// and `shift` (weights scale by `scale²`).
fn cell_case(rng: &mut ChaCha8Rng, family: usize) -> (Vec<Weighted>, Rect) {
    let spacing = [0.1, 1.0 / 9.0, 0.3, 1.0 / 7.0][rng.gen_range(0..4)];
    let at = |i: i32, j: i32| DVec2::new(i as f64 * spacing, j as f64 * spacing);
    let square = spacing * spacing;
    let (points, weights, lo, hi): (Vec<DVec2>, Vec<f64>, DVec2, DVec2) = match family {
        // A lattice of equal weights, some an ulp off, in a rectangle
        // through sites and midpoints: four sites to a power centre.
        0 => {
            let points: Vec<DVec2> = (0..12).map(|k| at(k % 3, k / 3)).collect();
            let weights = (0..12)
                .map(|_| ulps(square, rng.gen_range(-1..=1)))
                .collect();
            (
                points,
                weights,
                at(0, 0) - spacing * 0.5,
                at(2, 3) + spacing * 0.5,
            )
        }
        // Co-circular sites of one weight around a heavier centre.
        1 => {
            let ring = [(5, 0), (3, 4), (0, 5), (-4, 3), (-5, 0), (-3, -4), (4, -3)];
            let mut points: Vec<DVec2> = ring.iter().map(|&(x, y)| at(x, y)).collect();
            let mut weights = vec![square; 7];
            points.push(at(0, 0));
            weights.push(9.0 * square);
            (points, weights, at(-6, -6), at(6, 6))
        }
        // Random sites and weights, some beyond the rectangle, some hidden.
        _ => {
            let points = (0..12)
                .map(|_| DVec2::new(rng.gen_range(-1.0..5.0), rng.gen_range(-1.0..4.0)))
                .collect();
            let weights = (0..12).map(|_| rng.gen_range(0.0..2.0)).collect();
            (points, weights, DVec2::new(0.7, 0.0), DVec2::new(4.0, 3.0))
        }
    };
    let (scale, shift) = match rng.gen_range(0..5) {
        0 => (1e-150, 0.0),
        1 => (1e150, 0.0),
        2 => (1.0, 1e15),
        3 => (3e-7, -2.5e-3),
        _ => (1.0, 0.0),
    };
    let place = |p: DVec2| p * scale + DVec2::splat(shift);
    let sites = points
        .iter()
        .zip(&weights)
        .map(|(&p, &w)| Weighted {
            at: place(p),
            weight: w * scale * scale,
        })
        .collect();
    let rect = Rect {
        lo: place(lo),
        hi: place(hi),
    };
    (sites, rect)
}

#[test]
fn power_cell_corners_are_the_nearest_doubles_of_the_exact_corners() {
    let mut rng = ChaCha8Rng::seed_from_u64(52);
    let mut checked = 0;
    for round in 0..30 {
        let (sites, rect) = cell_case(&mut rng, round % 3);
        let cells = power_cells(&sites, &CellsOptions::new(rect)).unwrap();
        let hidden = regular_triangulation(&sites).unwrap().hidden;
        let points: Vec<DVec2> = sites.iter().map(|s| s.at).collect();
        let weights: Vec<f64> = sites.iter().map(|s| s.weight).collect();
        let corners = clipped_power_corners(&points, &weights, rect.lo, rect.hi);
        for (i, ring) in cells.polygons.iter().enumerate() {
            let name = format!("round {round}, site {i} {ring:?} of {sites:?} in {rect:?}");
            if hidden.contains(&(i as u32)) {
                assert!(ring.is_empty(), "{name}: a hidden site's cell");
            } else if !ring.is_empty() {
                check_ring(ring, &corners, i as u32, &name);
                checked += 1;
            }
        }
        // The cells cover the rectangle.
        let total: f64 = (0..sites.len()).map(|i| cells.area(i)).sum();
        let whole = (rect.hi - rect.lo).element_product();
        assert!(
            (total - whole).abs() <= 1e-9 * whole,
            "round {round}: {total} of {whole}"
        );
    }
    assert!(checked > 150, "{checked}");
}
