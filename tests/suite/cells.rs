//! Vector Voronoi cells exact for the doubles given: each cell's corners are
//! the doubles nearest the exact corners of the clipped diagram (every
//! rectangle corner, side crossing and vertex that the site is nearest to),
//! found by brute force in rationals; so cells that share a corner share its
//! double, and the cells form a coverage. On near-degenerate doubles: perturbed
//! lattices of decimal spacing (four sites to a vertex), co-circular sites,
//! bisectors through rectangle corners and along its sides, and magnitudes
//! from 1e-300 to 1e300.

use glam::DVec2;
use num_rational::BigRational;
use num_traits::Signed;
use pixgeo::Backend;
use pixgeo::{
    algorithms::cells::{voronoi_cells, CellsOptions},
    geometry::cell::Rect,
};
use pixgeo_reference::exact::{clipped_voronoi_corners, is_nearest, signed_double_area};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common::{machine, ulps};

/// One case: sites and the rectangle, far out or tiny by `scale` and `shift`.
fn case(rng: &mut ChaCha8Rng, family: usize) -> (Vec<DVec2>, Rect) {
    let spacing = [0.1, 1.0 / 9.0, 0.3, 1.0 / 7.0][rng.gen_range(0..4)];
    let at = |i: i32, j: i32| DVec2::new(i as f64 * spacing, j as f64 * spacing);
    let (sites, lo, hi): (Vec<DVec2>, DVec2, DVec2) = match family {
        // A lattice, some sites one ulp off, in a rectangle through sites
        // and midpoints: four sites to a vertex, bisectors through corners.
        0 => {
            let sites = (0..4)
                .flat_map(|j| (0..3).map(move |i| (i, j)))
                .map(|(i, j)| at(i, j))
                .map(|p| match rng.gen_range(0..3) {
                    0 => DVec2::new(ulps(p.x, rng.gen_range(-1..=1)), p.y),
                    _ => p,
                })
                .collect();
            (sites, at(0, 0) - spacing * 0.5, at(2, 3) + spacing * 0.5)
        }
        // Sites on a circle of integer points (3-4-5), scaled by a decimal.
        1 => {
            let ring = [(5, 0), (3, 4), (0, 5), (-4, 3), (-5, 0), (-3, -4), (4, -3)];
            let mut sites: Vec<DVec2> = ring.iter().map(|&(x, y)| at(x, y)).collect();
            sites.push(at(0, 0));
            sites.push(at(1, 7));
            (sites, at(-6, -6), at(6, 6))
        }
        // Random sites, some beyond the rectangle, and a rectangle side on
        // a bisector.
        _ => {
            let mut sites: Vec<DVec2> = (0..10)
                .map(|_| DVec2::new(rng.gen_range(-1.0..5.0), rng.gen_range(-1.0..4.0)))
                .collect();
            sites.push(DVec2::new(0.0, 1.0));
            sites.push(DVec2::new(2.0 * 0.7, 1.0));
            (sites, DVec2::new(0.7, 0.0), DVec2::new(4.0, 3.0))
        }
    };
    let (scale, shift) = match rng.gen_range(0..5) {
        0 => (1e-300, 0.0),
        1 => (1e300, 0.0),
        2 => (1.0, 1e15),
        3 => (3e-7, -2.5e-3),
        _ => (1.0, 0.0),
    };
    let place = |p: DVec2| p * scale + DVec2::splat(shift);
    let sites = sites.into_iter().map(place).collect();
    (
        sites,
        Rect {
            lo: place(lo),
            hi: place(hi),
        },
    )
}

#[test]
fn cell_corners_are_the_nearest_doubles_of_the_exact_corners() {
    let machine = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(48);
    let mut checked = 0;
    for round in 0..36 {
        let (sites, rect) = case(&mut rng, round % 3);
        let cells =
            voronoi_cells(&Backend::Device(&machine), &sites, &CellsOptions::new(rect)).unwrap();
        // Distinct sites (the first of equal ones) and the exact corners.
        let mut distinct: Vec<u32> = Vec::new();
        for (i, p) in sites.iter().enumerate() {
            if !distinct.iter().any(|&j| sites[j as usize] == *p) {
                distinct.push(i as u32);
            }
        }
        let points: Vec<DVec2> = distinct.iter().map(|&i| sites[i as usize]).collect();
        let corners = clipped_voronoi_corners(&points, rect.lo, rect.hi);
        for (k, &i) in distinct.iter().enumerate() {
            let ring = &cells.polygons[i as usize];
            let name = format!("round {round}, site {i} {ring:?} of {sites:?} in {rect:?}");
            if !ring.is_empty() {
                check_ring(ring, &corners, k as u32, &name);
                checked += 1;
            }
        }
    }
    assert!(checked > 200, "{checked}");
}

/// Checks that `ring`, the cell of site `k`, has the doubles nearest the
/// exact corners that `k` owns, each once, counter-clockwise.
pub(crate) fn check_ring(
    ring: &[DVec2],
    corners: &[([BigRational; 2], Vec<u32>)],
    k: u32,
    name: &str,
) {
    let matches = |d: DVec2, p: &[BigRational; 2]| is_nearest(d.x, &p[0]) && is_nearest(d.y, &p[1]);
    let mine: Vec<_> = corners
        .iter()
        .filter(|(_, owners)| owners.contains(&k))
        .collect();
    for (p, _) in &mine {
        assert!(ring.iter().any(|&d| matches(d, p)), "{name}: misses {p:?}");
    }
    for &d in ring {
        assert!(
            mine.iter().any(|(p, _)| matches(d, p)),
            "{name}: {d:?} is no exact corner"
        );
    }
    let mut seen = ring.to_vec();
    seen.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    seen.dedup();
    assert_eq!(seen.len(), ring.len(), "{name}: a repeated corner");
    let twice: BigRational = (1..ring.len() - 1)
        .map(|k| signed_double_area(ring[0], ring[k], ring[k + 1]))
        .sum();
    assert!(twice.is_positive(), "{name}: not counter-clockwise");
}
