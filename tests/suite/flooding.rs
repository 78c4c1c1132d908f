//! Digital Voronoi diagrams by flooding and their dual triangulations (Cao,
//! Edelsbrunner and Tan 2015): the lemmas the paper proves, checked on every
//! colouring, and conditions I–III checked on every dual.

use glam::DVec2;
use pixgeo::geometry::triangulation::{validate, DUMMY};
use pixgeo_reference::flooding::{
    component, double_neck, dualize, euclidean, flood, has_hole, Seed, NONE,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn distinct(mut seeds: Vec<Seed>) -> Vec<Seed> {
    let mut seen = std::collections::HashSet::new();
    seeds.retain(|s| seen.insert(*s));
    seeds
}

/// `n` random seed pixels anywhere on 64 x 48, border included, without repeats.
fn anywhere(n: usize) -> (&'static str, Vec<Seed>) {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let seeds = (0..n)
        .map(|_| [rng.gen_range(0..64), rng.gen_range(0..48)])
        .collect();
    ("anywhere", distinct(seeds))
}

/// Random, clustered, lattice (many co-circular seeds) and nearly collinear
/// seed sets on a `w` x `h` texture, a few pixels clear of its border (see
/// `the_border_can_pinch_the_outside`).
fn inputs(w: u32, h: u32) -> Vec<(&'static str, Vec<Seed>)> {
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let (wi, hi) = (w as i32, h as i32);
    let uniform: Vec<Seed> = (0..60)
        .map(|_| [rng.gen_range(6..wi - 6), rng.gen_range(6..hi - 6)])
        .collect();
    let clustered: Vec<Seed> = (0..60)
        .map(|k| {
            let c = [[10, 12], [50, 40], [30, 8]][k % 3];
            [
                (c[0] + rng.gen_range(-4..=4)).clamp(0, wi - 1),
                (c[1] + rng.gen_range(-4..=4)).clamp(0, hi - 1),
            ]
        })
        .collect();
    let lattice: Vec<Seed> = (0..36)
        .map(|k| [3 + (k % 6) * 10, 2 + (k / 6) * 8])
        .collect();
    // Along a line of slope 1/7, rounded to pixels, and two more off it.
    let mut collinear: Vec<Seed> = (0..12).map(|k| [2 + 5 * k, 10 + (5 * k) / 7]).collect();
    collinear.extend([[30, 30], [5, 40]]);
    vec![
        ("uniform", distinct(uniform)),
        ("clustered", distinct(clustered)),
        ("lattice", lattice),
        ("nearly collinear", collinear),
    ]
}

#[test]
fn flooding_has_the_properties_the_paper_proves() {
    let (w, h) = (64, 48);
    for (name, seeds) in inputs(w, h) {
        let flooded = flood(w, h, &seeds).unwrap();
        let exact = euclidean(w, h, &seeds).unwrap();
        assert!(
            flooded.iter().all(|&c| c != NONE),
            "{name}: every pixel coloured"
        );
        assert_eq!(double_neck(&flooded, w, h), None, "{name}: One Neck Lemma");
        let mut in_bulk = vec![false; flooded.len()];
        for (i, &s) in seeds.iter().enumerate() {
            let i = i as u32;
            let region: Vec<bool> = flooded.iter().map(|&c| c == i).collect();
            // Connected (flooding grows from the seed) and simply connected.
            assert_eq!(
                component(&flooded, w, h, s, i),
                region,
                "{name}: F_{i} connected"
            );
            assert!(
                !has_hole(&flooded, w, h, i),
                "{name}: F_{i} simply connected"
            );
            // Bulk Lemma: F_i holds the bulk of E_i.
            let bulk = component(&exact, w, h, s, i);
            assert!(
                bulk.iter().zip(&region).all(|(b, r)| !b || *r),
                "{name}: F_{i} holds the bulk of E_{i}"
            );
            for (k, b) in bulk.iter().enumerate() {
                in_bulk[k] |= *b;
            }
        }
        // So flooding and the Euclidean colouring differ only on debris.
        for k in 0..flooded.len() {
            if flooded[k] != exact[k] {
                assert!(!in_bulk[k], "{name}: pixel {k} of a bulk recoloured");
            }
        }
    }
}

#[test]
fn a_sharp_corner_leaves_debris_that_flooding_joins_to_a_neighbour() {
    // Fig. 1's situation, found by search: E_0 has one pixel cut off from its
    // bulk inside a sharp corner of the Euclidean region.
    let (w, h) = (24, 24);
    let seeds: Vec<Seed> = vec![[2, 12], [11, 22], [0, 2]];
    let exact = euclidean(w, h, &seeds).unwrap();
    let flooded = flood(w, h, &seeds).unwrap();
    let mut debris = Vec::new();
    for (i, &s) in seeds.iter().enumerate() {
        let bulk = component(&exact, w, h, s, i as u32);
        debris.extend((0..exact.len()).filter(|&k| exact[k] == i as u32 && !bulk[k]));
        let region: Vec<bool> = flooded.iter().map(|&c| c == i as u32).collect();
        assert_eq!(component(&flooded, w, h, s, i as u32), region);
    }
    assert_eq!(debris.len(), 1);
    let differ: Vec<usize> = (0..exact.len())
        .filter(|&k| exact[k] != flooded[k])
        .collect();
    assert_eq!(differ, debris);
}

#[test]
fn the_dual_of_flooding_is_a_valid_triangulation() {
    let (w, h) = (64, 48);
    for (name, seeds) in inputs(w, h) {
        let flooded = flood(w, h, &seeds).unwrap();
        let triangles = dualize(&flooded, w, h);
        let points: Vec<DVec2> = seeds
            .iter()
            .map(|s| DVec2::new(s[0] as f64, s[1] as f64))
            .collect();
        let validity = validate(&points, &triangles);
        assert!(validity.is_valid(), "{name}: {:?}", validity.problems);
        assert_eq!(validity.euler_characteristic, 2);
        // A triangulation of n + 1 vertices of the sphere has 2 (n + 1) - 4 triangles.
        assert_eq!(validity.triangles, 2 * (seeds.len() + 1) - 4, "{name}");
        assert!(triangles.iter().any(|t| t.contains(&DUMMY)));
    }
}

#[test]
fn the_validator_finds_what_is_wrong() {
    let (w, h) = (40, 30);
    let seeds: Vec<Seed> = vec![[5, 5], [30, 6], [20, 25], [12, 14], [33, 20]];
    let points: Vec<DVec2> = seeds
        .iter()
        .map(|s| DVec2::new(s[0] as f64, s[1] as f64))
        .collect();
    let good = dualize(&flood(w, h, &seeds).unwrap(), w, h);
    assert!(validate(&points, &good).is_valid());
    // A triangle dropped: a hole (two edges in one triangle) and the wrong Euler count.
    let holed = &good[1..];
    let v = validate(&points, holed);
    assert!(
        v.problems.iter().any(|p| p.starts_with("II")),
        "{:?}",
        v.problems
    );
    // A finite triangle turned over.
    let k = good.iter().position(|t| !t.contains(&DUMMY)).unwrap();
    let mut flipped = good.clone();
    flipped[k] = [good[k][0], good[k][2], good[k][1]];
    assert!(!validate(&points, &flipped).is_valid());
    // A site left out.
    let fewer: Vec<[u32; 3]> = good.iter().copied().filter(|t| !t.contains(&4)).collect();
    assert!(validate(&points, &fewer)
        .problems
        .iter()
        .any(|p| p.starts_with("I:")));
}

/// The paper's outside region F_0 must meet every region in one stretch for
/// the dual to be a sphere. Seeds flush with the texture's border can break
/// that: a region runs along the border on both sides of a small one, and
/// the validator reports the edge to the dummy vertex twice. (Over 200 random
/// sets of 60 seeds on 64 x 48 pixels this happened 30 times with seeds
/// anywhere and never with seeds 3 or more pixels from the border.)
#[test]
fn the_border_can_pinch_the_outside() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let seeds = distinct(
        (0..60)
            .map(|_| [rng.gen_range(0..64), rng.gen_range(0..48)])
            .collect(),
    );
    let flooded = flood(64, 48, &seeds).unwrap();
    let points: Vec<DVec2> = seeds
        .iter()
        .map(|s| DVec2::new(s[0] as f64, s[1] as f64))
        .collect();
    let validity = validate(&points, &dualize(&flooded, 64, 48));
    assert!(
        validity
            .problems
            .iter()
            .any(|p| p.starts_with("II") && p.contains(&DUMMY.to_string())),
        "{:?}",
        validity.problems
    );
    // The regions themselves keep every lemma.
    assert_eq!(double_neck(&flooded, 64, 48), None);
    assert!((0..seeds.len() as u32).all(|i| !has_hole(&flooded, 64, 48, i)));
}

#[test]
fn flooding_on_the_machine_equals_the_reference() {
    let machine = crate::common::machine();
    let (w, h) = (64, 48);
    let mut cases = inputs(w, h);
    // Seeds on the border and a sharp corner with debris.
    cases.push(anywhere(80));
    cases.push(("sharp corner", vec![[2, 12], [11, 22], [0, 2]]));
    let mut recoloured = 0;
    for (name, seeds) in cases {
        let gpu = pixgeo::algorithms::flooding::flood(&machine, w, h, &seeds).unwrap();
        let cpu = flood(w, h, &seeds).unwrap();
        assert_eq!(gpu.labels, cpu, "{name}");
        let exact = euclidean(w, h, &seeds).unwrap();
        let colouring =
            pixgeo::algorithms::flooding::euclidean_colouring(&machine, w, h, &seeds).unwrap();
        assert_eq!(
            colouring, exact,
            "{name}: the Euclidean colouring and its ties"
        );
        recoloured += gpu.stats.recoloured;
    }
    assert!(recoloured > 0, "the debris repair ran");
}

#[test]
fn flooding_on_the_machine_equals_the_reference_where_corners_are_sharp() {
    // Few seeds on a small texture make sharp corners now and then: the first
    // 12 random sets whose Euclidean colouring has debris.
    let machine = crate::common::machine();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut found = 0;
    while found < 12 {
        let n = rng.gen_range(3..6);
        let seeds = distinct(
            (0..n)
                .map(|_| [rng.gen_range(0..24), rng.gen_range(0..24)])
                .collect(),
        );
        let exact = euclidean(24, 24, &seeds).unwrap();
        let has_debris = seeds.iter().enumerate().any(|(i, &s)| {
            let bulk = component(&exact, 24, 24, s, i as u32);
            exact.iter().zip(&bulk).any(|(c, b)| *c == i as u32 && !b)
        });
        if !has_debris {
            continue;
        }
        found += 1;
        let gpu = pixgeo::algorithms::flooding::flood(&machine, 24, 24, &seeds).unwrap();
        assert_eq!(gpu.labels, flood(24, 24, &seeds).unwrap(), "{seeds:?}");
        assert!(
            gpu.stats.debris > 0 && gpu.stats.components > 0,
            "{seeds:?}"
        );
    }
}

/// Pixels whose seed is farther than their nearest: jump flooding's errors.
fn wrong_pixels(labels: &[u32], exact: &[u32], seeds: &[Seed], w: u32) -> usize {
    (0..labels.len())
        .filter(|&k| {
            let p = [(k as u32 % w) as i64, (k as u32 / w) as i64];
            let d2 = |i: u32| {
                let s = seeds[i as usize];
                (s[0] as i64 - p[0]).pow(2) + (s[1] as i64 - p[1]).pow(2)
            };
            labels[k] == NONE || d2(labels[k]) > d2(exact[k])
        })
        .count()
}

#[test]
fn jump_flooding_is_nearly_the_euclidean_colouring() {
    let machine = crate::common::machine();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let (mut wrong, mut pixels) = (0, 0);
    for (w, h, n) in [(64, 48, 60), (200, 150, 400), (97, 61, 5)] {
        let seeds = distinct(
            (0..n)
                .map(|_| [rng.gen_range(0..w as i32), rng.gen_range(0..h as i32)])
                .collect(),
        );
        let jfa = pixgeo::algorithms::flooding::jump_flood(&machine, w, h, &seeds).unwrap();
        let exact = euclidean(w, h, &seeds).unwrap();
        for (i, s) in seeds.iter().enumerate() {
            assert_eq!(jfa[(s[1] as u32 * w + s[0] as u32) as usize], i as u32);
        }
        wrong += wrong_pixels(&jfa, &exact, &seeds, w);
        pixels += jfa.len();
    }
    // Rong and Tan report well under one percent of pixels wrong.
    let rate = wrong as f64 / pixels as f64;
    assert!(
        rate < 0.005,
        "{wrong} of {pixels} pixels have a farther seed"
    );
}

#[test]
fn dualization_on_the_machine_equals_the_reference() {
    let machine = crate::common::machine();
    let (w, h) = (64, 48);
    let mut cases = inputs(w, h);
    cases.push(anywhere(60));
    for (name, seeds) in cases {
        let labels = flood(w, h, &seeds).unwrap();
        let gpu = pixgeo::algorithms::flooding::dualize(&machine, &labels, w, h).unwrap();
        assert_eq!(
            crate::common::canonical(gpu),
            crate::common::canonical(dualize(&labels, w, h)),
            "{name}"
        );
    }
}

#[test]
fn flips_make_the_digital_triangulation_delaunay() {
    let (w, h) = (64, 48);
    for (name, seeds) in inputs(w, h) {
        let points: Vec<DVec2> = seeds
            .iter()
            .map(|s| DVec2::new(s[0] as f64, s[1] as f64))
            .collect();
        let digital = dualize(&flood(w, h, &seeds).unwrap(), w, h);
        let (triangles, flips) = pixgeo::testing::make_delaunay(&points, digital).unwrap();
        let validity = validate(&points, &triangles);
        assert!(validity.is_valid(), "{name}: {:?}", validity.problems);
        // Empty circles, exactly.
        let c = |p: DVec2| robust::Coord { x: p.x, y: p.y };
        for t in triangles.iter().filter(|t| !t.contains(&DUMMY)) {
            let [a, b, d] = t.map(|v| c(points[v as usize]));
            for (v, q) in points.iter().enumerate() {
                if !t.contains(&(v as u32)) {
                    assert!(
                        robust::incircle(a, b, d, c(*q)) <= 0.0,
                        "{name}: site {v} inside {t:?}"
                    );
                }
            }
        }
        // The boundary is the convex hull: every site on or left of each
        // boundary edge, counter-clockwise (the dummy triangle (a, b, D) has
        // the hull edge b -> a).
        for t in triangles.iter().filter(|t| t.contains(&DUMMY)) {
            let k = (0..3).find(|&k| t[(k + 2) % 3] == DUMMY).unwrap();
            let (a, b) = (c(points[t[k] as usize]), c(points[t[(k + 1) % 3] as usize]));
            assert!(
                points.iter().all(|q| robust::orient2d(b, a, c(*q)) >= 0.0),
                "{name}: boundary edge {t:?} is no hull edge"
            );
        }
        if name == "uniform" {
            assert!(flips.hull > 0 && flips.delaunay > 0, "{name}: {flips:?}");
        }
        // The Delaunay triangulation is unique but for co-circular sites: ours
        // and spade's differ only in triangles with a fourth site on their circle.
        {
            use spade::{DelaunayTriangulation, Point2, Triangulation};
            let t: DelaunayTriangulation<Point2<f64>> = DelaunayTriangulation::bulk_load(
                points.iter().map(|p| Point2::new(p.x, p.y)).collect(),
            )
            .unwrap();
            let index: std::collections::HashMap<(i64, i64), u32> = seeds
                .iter()
                .enumerate()
                .map(|(i, s)| ((s[0] as i64, s[1] as i64), i as u32))
                .collect();
            let theirs: Vec<[u32; 3]> = t
                .inner_faces()
                .map(|f| {
                    f.vertices()
                        .map(|v| index[&(v.position().x as i64, v.position().y as i64)])
                })
                .collect();
            let ours: Vec<[u32; 3]> = triangles
                .iter()
                .copied()
                .filter(|t| !t.contains(&DUMMY))
                .collect();
            let (ours, theirs) = (
                crate::common::canonical(ours),
                crate::common::canonical(theirs),
            );
            assert_eq!(ours.len(), theirs.len(), "{name}");
            for t in ours.iter().filter(|t| theirs.binary_search(t).is_err()) {
                let [a, b, d] = t.map(|v| c(points[v as usize]));
                let tie = points.iter().enumerate().any(|(v, q)| {
                    !t.contains(&(v as u32)) && robust::incircle(a, b, d, c(*q)) == 0.0
                });
                assert!(
                    tie,
                    "{name}: {t:?} differs from spade without a co-circular site"
                );
            }
        }
    }
}

#[test]
fn bad_seeds_are_clear_errors() {
    assert!(flood(10, 10, &[[10, 0]]).is_err());
    assert!(flood(10, 10, &[[1, 1], [1, 1]]).is_err());
    assert!(flood(0, 10, &[]).is_err());
}

#[test]
fn the_euclidean_colouring_takes_the_longest_sides() {
    // 16000 pixels along a row or a column: each invocation of the colouring
    // loops about four times that, just under lavapipe's limit of 65535.
    let machine = crate::common::machine();
    let side = pixgeo::algorithms::flooding::MAX_SIDE;
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    for (w, h) in [(side, 3), (3, side)] {
        let mut seeds: Vec<Seed> = (0..40)
            .map(|_| [rng.gen_range(0..w as i32), rng.gen_range(0..h as i32)])
            .collect();
        seeds.sort_unstable();
        seeds.dedup();
        let colouring =
            pixgeo::algorithms::flooding::euclidean_colouring(&machine, w, h, &seeds).unwrap();
        assert_eq!(colouring, euclidean(w, h, &seeds).unwrap(), "{w}x{h}");
    }
    assert!(
        pixgeo::algorithms::flooding::euclidean_colouring(&machine, side + 1, 2, &[[0, 0]])
            .is_err()
    );
}
