//! The Delaunay triangulation from the digital Voronoi diagram, checked
//! against spade and against the empty-circle property itself.

use std::collections::HashMap;

use glam::DVec2;
use pixgeo::{
    algorithms::delaunay::{delaunay, Delaunay, DelaunayOptions},
    geometry::triangulation::check_delaunay,
    Backend,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Triangulates and runs the delaunator-style checks; with `brute`, also the
/// empty-circle property against every point.
fn triangulate(name: &str, points: &[DVec2], options: &DelaunayOptions, brute: bool) -> Delaunay {
    let machine = crate::common::machine();
    let result =
        on_both_routes(name, &machine, points, options).unwrap_or_else(|e| panic!("{name}: {e}"));
    let expected = result.distinct();
    let problems = check_delaunay(points, &result.triangles, &expected);
    assert!(problems.is_empty(), "{name}: {problems:?}");
    if brute {
        let c = |p: DVec2| robust::Coord { x: p.x, y: p.y };
        for t in &result.triangles {
            let [a, b, d] = t.map(|v| c(points[v as usize]));
            for &v in &expected {
                assert!(
                    t.contains(&v) || robust::incircle(a, b, d, c(points[v as usize])) <= 0.0,
                    "{name}: point {v} inside the circle of {t:?}"
                );
            }
        }
    }
    // The validator and the mesh's own checks agree on the digital
    // triangulation.
    if let Some(validity) = &result.digital_validity {
        match &result.stats.incremental {
            None => assert!(validity.is_valid(), "{name}: {:?}", validity.problems),
            Some(why) if why.contains("not valid") => assert!(!validity.is_valid(), "{name}"),
            Some(_) => {}
        }
    }
    result
}

/// The triangulation on the device and on the CPU, which must be the same
/// bit for bit (co-circular points included) or the same error.
fn on_both_routes(
    name: &str,
    machine: &pixgeo::Machine,
    points: &[DVec2],
    options: &DelaunayOptions,
) -> pixgeo::Result<Delaunay> {
    let device = delaunay(&Backend::Device(machine), points, options);
    let cpu = delaunay(&Backend::Cpu, points, options);
    match (&device, &cpu) {
        (Ok(d), Ok(c)) => {
            assert!(
                d.triangles == c.triangles && d.duplicates == c.duplicates,
                "{name}: {} triangles on the device, {} on the CPU, differing at {:?}",
                d.triangles.len(),
                c.triangles.len(),
                d.triangles
                    .iter()
                    .zip(&c.triangles)
                    .position(|(a, b)| a != b)
            );
            assert!(c.digital.is_none() && d.digital.is_some(), "{name}");
        }
        (Err(d), Err(c)) => assert_eq!(d.to_string(), c.to_string(), "{name}"),
        _ => panic!(
            "{name}: the device gave {:?}, the CPU {:?}",
            device.as_ref().err(),
            cpu.as_ref().err()
        ),
    }
    device
}

fn spade_triangles(points: &[DVec2]) -> Vec<[u32; 3]> {
    use spade::{DelaunayTriangulation, Point2, Triangulation};
    let t: DelaunayTriangulation<Point2<f64>> =
        DelaunayTriangulation::bulk_load(points.iter().map(|p| Point2::new(p.x, p.y)).collect())
            .unwrap();
    let index: HashMap<(u64, u64), u32> = points
        .iter()
        .enumerate()
        .map(|(i, p)| ((p.x.to_bits(), p.y.to_bits()), i as u32))
        .collect();
    t.inner_faces()
        .map(|f| {
            f.vertices()
                .map(|v| index[&(v.position().x.to_bits(), v.position().y.to_bits())])
        })
        .collect()
}

fn checked() -> DelaunayOptions {
    DelaunayOptions::default().check(true)
}

#[test]
fn random_points_give_spades_triangulation() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for (n, scale) in [(50, 1.0), (2000, 1.0), (5000, 1e-3), (3000, 1e6)] {
        let points: Vec<DVec2> = (0..n)
            .map(|_| DVec2::new(rng.gen::<f64>(), rng.gen::<f64>() * 0.7) * scale + 17.0 * scale)
            .collect();
        let result = triangulate("uniform", &points, &checked(), n <= 2000);
        assert_eq!(
            crate::common::canonical(result.triangles.clone()),
            crate::common::canonical(spade_triangles(&points)),
            "n = {n}, scale {scale}"
        );
        assert!(result.stats.incremental.is_none(), "{:?}", result.stats);
        assert!(result.stats.moved > 0);
    }
}

#[test]
fn crowded_grids_insert_what_shares_a_pixel() {
    // 4000 points on a 64-pixel grid: most pixels hold several.
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let points: Vec<DVec2> = (0..4000)
        .map(|_| DVec2::new(rng.gen::<f64>() * 10.0, rng.gen::<f64>() * 10.0))
        .collect();
    let options = DelaunayOptions::default().grid(Some(64)).check(true);
    let result = triangulate("crowded", &points, &options, false);
    assert!(result.stats.inserted > 2000, "{:?}", result.stats);
    assert_eq!(
        crate::common::canonical(result.triangles.clone()),
        crate::common::canonical(spade_triangles(&points))
    );
}

#[test]
fn degenerate_inputs_are_delaunay() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let mut cases: Vec<(&str, Vec<DVec2>)> = Vec::new();
    cases.push((
        "clustered",
        crate::common::clustered(&mut rng, 1500, 300.0, 200.0),
    ));
    // A lattice: every square's four corners are co-circular.
    cases.push((
        "lattice",
        (0..900)
            .map(|k| DVec2::new((k % 30) as f64 * 0.5, (k / 30) as f64 * 0.5))
            .collect(),
    ));
    // A lattice on a grid whose pixels do not match it.
    cases.push((
        "fine lattice",
        (0..2500)
            .map(|k| DVec2::new((k % 50) as f64, (k / 50) as f64))
            .collect(),
    ));
    // Nearly collinear: a line with tiny offsets, and two points off it.
    let mut line: Vec<DVec2> = (0..400)
        .map(|i| {
            let t = i as f64 / 400.0;
            DVec2::new(t, 0.5 * t + 1e-9 * rng.gen::<f64>())
        })
        .collect();
    line.push(DVec2::new(0.3, 0.9));
    line.push(DVec2::new(0.6, -0.2));
    cases.push(("nearly collinear", line));
    // Points on a circle: all co-circular.
    cases.push((
        "circle",
        (0..64)
            .map(|i| {
                let a = i as f64 * std::f64::consts::TAU / 64.0;
                DVec2::new(a.cos(), a.sin())
            })
            .chain([DVec2::ZERO])
            .collect(),
    ));
    // Duplicates, and -0.0 beside 0.0.
    let mut dup = crate::common::uniform(&mut rng, 300, 50.0, 50.0);
    dup.extend(dup.clone());
    dup.push(DVec2::new(0.0, 0.0));
    dup.push(DVec2::new(-0.0, 0.0));
    cases.push(("duplicates", dup));
    for (name, points) in cases {
        let result = triangulate(name, &points, &checked(), points.len() <= 2500);
        // The digital triangulation was valid (and so passed conditions I–III).
        assert_eq!(result.stats.incremental, None, "{name}");
        if name == "duplicates" {
            assert_eq!(result.duplicates.len(), 301, "{name}");
            assert!(result
                .duplicates
                .iter()
                .all(|&[d, k]| d > k && points[d as usize] == points[k as usize]));
        }
        if name == "lattice" || name == "fine lattice" {
            // Two triangles per lattice square.
            let side = if name == "lattice" { 30 } else { 50 };
            assert_eq!(
                result.triangles.len(),
                2 * (side - 1) * (side - 1),
                "{name}"
            );
        }
    }
}

#[test]
fn tiny_inputs_and_every_grid_size() {
    let mut rng = ChaCha8Rng::seed_from_u64(14);
    // Few points leave big regions, and one that reaches the texture's border
    // twice makes the outside meet it twice: the digital triangulation is then
    // not valid, and the points are inserted one by one instead.
    let mut invalid = 0;
    for n in (3..40).chain(3..40) {
        let points = crate::common::uniform(&mut rng, n, 10.0, 10.0);
        let result = triangulate("tiny", &points, &DelaunayOptions::default(), true);
        assert_eq!(
            crate::common::canonical(result.triangles),
            crate::common::canonical(spade_triangles(&points))
        );
        let reason = result.stats.incremental.unwrap_or_default();
        invalid += usize::from(reason.contains("not valid"));
    }
    eprintln!("{invalid} of 74 small sets had an invalid digital triangulation");
    assert!(invalid > 0);
    let points = crate::common::uniform(&mut rng, 700, 10.0, 3.0);
    for grid in [10, 16, 40, 100, 1000] {
        let options = DelaunayOptions::default().grid(Some(grid)).check(true);
        let result = triangulate("grid", &points, &options, true);
        assert_eq!(
            crate::common::canonical(result.triangles),
            crate::common::canonical(spade_triangles(&points)),
            "grid {grid}"
        );
    }
}

#[test]
fn bad_input_is_a_clear_error() {
    let machine = crate::common::machine();
    let options = DelaunayOptions::default();
    let p = |x: f64, y: f64| DVec2::new(x, y);
    for (points, says) in [
        (vec![], "empty"),
        (vec![p(0.0, 0.0), p(1.0, 1.0)], "three distinct"),
        (
            vec![p(0.0, 0.0), p(1.0, 1.0), p(1.0, 1.0)],
            "three distinct",
        ),
        (vec![p(0.0, 0.0), p(1.0, 1.0), p(2.0, 2.0)], "one line"),
        (
            vec![p(0.0, 0.0), p(f64::NAN, 1.0), p(2.0, 0.0)],
            "non-finite coordinate",
        ),
    ] {
        let error = on_both_routes(says, &machine, &points, &options)
            .unwrap_err()
            .to_string();
        assert!(error.contains(says), "{error}");
    }
    let error = delaunay(
        &Backend::Device(&machine),
        &[p(0.0, 0.0), p(1.0, 0.0), p(0.0, 1.0)],
        &DelaunayOptions::default().grid(Some(5)),
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains("margins"), "{error}");
}

#[test]
fn hundreds_of_degenerate_sets_on_every_kind_of_grid() {
    // Small lattices with repeats, flat boxes, rounded circles, few columns,
    // points crowded into a corner; on default, tiny and fine grids.
    let machine = crate::common::machine();
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    for round in 0..400 {
        let n = rng.gen_range(3..600);
        let kind = round % 5;
        let points: Vec<DVec2> = (0..n)
            .map(|_| match kind {
                0 => DVec2::new(rng.gen_range(0..12) as f64, rng.gen_range(0..12) as f64),
                1 => DVec2::new(rng.gen::<f64>(), rng.gen::<f64>() * 1e-6),
                2 => {
                    let a = rng.gen::<f64>() * std::f64::consts::TAU;
                    (DVec2::new(a.cos(), a.sin()) * 3.0).round()
                }
                3 => DVec2::new(rng.gen_range(0..5) as f64 * 0.1, rng.gen::<f64>()),
                _ => DVec2::new(rng.gen::<f64>().powi(8), rng.gen::<f64>().powi(8)),
            })
            .collect();
        let grid = [None, Some(10), Some(16), Some(33), Some(200)][rng.gen_range(0..5)];
        let options = DelaunayOptions::default().grid(grid);
        let name = format!("round {round}");
        let result = match on_both_routes(&name, &machine, &points, &options) {
            Ok(result) => result,
            Err(e) => {
                let e = e.to_string();
                assert!(
                    e.contains("one line") || e.contains("distinct"),
                    "{round}: {e}"
                );
                continue;
            }
        };
        let expected = result.distinct();
        let problems = check_delaunay(&points, &result.triangles, &expected);
        assert!(
            problems.is_empty(),
            "round {round}, kind {kind}, {n} points, grid {grid:?}: {problems:?}"
        );
    }
}

/// Vector Voronoi cells from the triangulation, against brute force: areas
/// sum to the rectangle's, each cell holds its site (when inside), and random
/// points of each cell are nearest to its site; on random and degenerate
/// sites.
#[test]
fn voronoi_cells_tile_the_frame_and_hold_their_nearest_points() {
    use pixgeo::{
        algorithms::cells::{voronoi_cells, CellsOptions},
        geometry::cell::Rect,
    };
    let machine = crate::common::machine();
    let rect = Rect {
        lo: DVec2::new(-1.0, -2.0),
        hi: DVec2::new(9.0, 6.0),
    };
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let random: Vec<DVec2> = (0..300)
        .map(|_| DVec2::new(rng.gen_range(-1.0..9.0), rng.gen_range(-2.0..6.0)))
        .collect();
    let lattice: Vec<DVec2> = (0..49)
        .map(|i| DVec2::new((i % 7) as f64, (i / 7) as f64 - 1.0))
        .collect();
    let circle: Vec<DVec2> = (0..12)
        .map(|i| {
            let a = i as f64 * std::f64::consts::TAU / 12.0;
            DVec2::new(4.0 + 3.0 * a.cos(), 2.0 + 3.0 * a.sin())
        })
        .chain([DVec2::new(4.0, 2.0)])
        .collect();
    let mut repeated = lattice.clone();
    repeated.extend_from_slice(&lattice[..10]);
    let cases: Vec<(&str, Vec<DVec2>)> = vec![
        ("random", random),
        ("lattice", lattice),
        ("co-circular", circle),
        ("repeated", repeated),
        (
            "collinear",
            (0..6)
                .map(|i| DVec2::new(i as f64, 0.5 * i as f64))
                .collect(),
        ),
        ("two", vec![DVec2::new(1.0, 1.0), DVec2::new(5.0, 3.0)]),
        ("one", vec![DVec2::new(2.0, 2.0)]),
        (
            "outside the frame",
            vec![
                DVec2::new(-30.0, 2.0),
                DVec2::new(3.0, 2.0),
                DVec2::new(5.0, 4.0),
                DVec2::new(50.0, 50.0),
                DVec2::new(4.0, -0.5),
            ],
        ),
    ];
    // The same lattice far out and tiny, in its own frame.
    let lattice = cases[1].1.clone();
    let scaled = |shift: f64, scale: f64| {
        let at = |p: DVec2| DVec2::splat(shift) + p * scale;
        let rect = Rect {
            lo: at(rect.lo),
            hi: at(rect.hi),
        };
        (lattice.iter().map(|&p| at(p)).collect::<Vec<_>>(), rect)
    };
    let mut cases: Vec<(&str, Vec<DVec2>, Rect)> =
        cases.into_iter().map(|(n, s)| (n, s, rect)).collect();
    let (far, far_rect) = scaled(1e15, 1.0);
    let (tiny, tiny_rect) = scaled(0.0, 1e-150);
    cases.push(("huge coordinates", far, far_rect));
    cases.push(("tiny coordinates", tiny, tiny_rect));
    for (name, sites, rect) in cases {
        let cells = voronoi_cells(&Backend::Device(&machine), &sites, &CellsOptions::new(rect))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let first: Vec<usize> = (0..sites.len())
            .map(|i| (0..=i).find(|&j| sites[j] == sites[i]).unwrap())
            .collect();
        let total: f64 = (0..sites.len())
            .filter(|&i| first[i] == i)
            .map(|i| cells.area(i))
            .sum();
        let frame_area = (rect.hi - rect.lo).x * (rect.hi - rect.lo).y;
        assert!(
            (total - frame_area).abs() <= 1e-9 * frame_area,
            "{name}: {total}"
        );
        let nearest = |q: DVec2| {
            sites
                .iter()
                .map(|s| s.distance_squared(q))
                .fold(f64::INFINITY, f64::min)
        };
        for (i, cell) in cells.polygons.iter().enumerate() {
            assert_eq!(
                cells.polygons[i], cells.polygons[first[i]],
                "{name}: site {i}"
            );
            let s = sites[i];
            let inside = s.x > rect.lo.x && s.x < rect.hi.x && s.y > rect.lo.y && s.y < rect.hi.y;
            if inside {
                let holds = (0..cell.len())
                    .all(|k| (cell[(k + 1) % cell.len()] - cell[k]).perp_dot(s - cell[k]) >= 0.0);
                assert!(
                    cell.len() >= 3 && holds,
                    "{name}: site {i} outside its cell"
                );
            }
            // Random convex combinations of the corners lie in the cell.
            for _ in 0..20.min(cell.len() * 4) {
                let weights: Vec<f64> = cell.iter().map(|_| rng.gen_range(0.0..1.0)).collect();
                let sum: f64 = weights.iter().sum();
                let q = cell
                    .iter()
                    .zip(&weights)
                    .map(|(&c, &w)| c * w)
                    .sum::<DVec2>()
                    / sum;
                let mine = s.distance_squared(q);
                // Far from the origin, q itself is rounded to the coordinates'
                // precision.
                let ulp = rect.hi.abs().max_element() * f64::EPSILON;
                let across = (rect.hi - rect.lo).length();
                let slack = 1e-9 * across * across + 8.0 * ulp * across;
                assert!(mine <= nearest(q) + slack, "{name}: site {i} at {q}");
            }
        }
    }
}
