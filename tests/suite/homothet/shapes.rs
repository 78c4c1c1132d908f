//! Homothets among segments, circles and arcs, weighted sites and `inside` a
//! region: against the definitions evaluated over grids and samples of the
//! sites' boundaries.

use super::*;
use pixgeo::Backend;

/// The largest clearance over a grid of allowed centres (spacing `h`): the
/// definition evaluated per point.
fn grid_best(
    lo: DVec2,
    hi: DVec2,
    h: f64,
    clearance: impl Fn(DVec2) -> f64,
    allowed: impl Fn(DVec2) -> bool,
) -> f64 {
    let (nx, ny) = (((hi.x - lo.x) / h) as usize, ((hi.y - lo.y) / h) as usize);
    let mut best = f64::NEG_INFINITY;
    for j in 0..=ny {
        for i in 0..=nx {
            let c = lo + DVec2::new(i as f64, j as f64) * h;
            if allowed(c) {
                best = best.max(clearance(c));
            }
        }
    }
    best
}

#[test]
fn largest_empty_among_segments_arcs_weights_and_inside_against_a_grid() {
    use pixgeo::{
        algorithms::homothet::{largest_empty, EmptyOptions},
        geometry::site::{Shape, Site},
    };
    let machine = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let points: Vec<Site> = uniform(&mut rng, 6, 100.0, 80.0)
        .into_iter()
        .map(Site::point)
        .collect();
    let mut obstacles = points.clone();
    obstacles.push(Site::new(Shape::Segment(
        DVec2::new(10.0, 70.0),
        DVec2::new(45.0, 50.0),
    )));
    obstacles.push(Site::new(Shape::Arc {
        center: DVec2::new(75.0, 25.0),
        radius: 12.0,
        start: 0.3,
        end: 2.5,
    }));
    let mut segments = points.clone();
    segments.push(Site::new(Shape::Segment(
        DVec2::new(10.0, 70.0),
        DVec2::new(45.0, 50.0),
    )));
    segments.push(Site::new(Shape::Segment(
        DVec2::new(80.0, 5.0),
        DVec2::new(95.0, 40.0),
    )));
    let mut weighted = points.clone();
    for (k, s) in weighted.iter_mut().enumerate() {
        s.multiplicative = 0.6 + 0.2 * k as f64;
    }
    let region = square_with_hole();
    let boundary = edges(&region);
    let allowed = |c: DVec2| region.contains(c);
    let (lo, hi) = (DVec2::ZERO, DVec2::new(100.0, 80.0));
    let h = 0.25;
    for (name, sites, inside) in [
        ("points inside", &points, true),
        ("segment and arc", &obstacles, false),
        ("segments", &segments, false),
        ("segments inside", &segments, true),
        ("weighted", &weighted, false),
    ] {
        let answer = largest_empty(
            &machine,
            sites,
            &EmptyOptions::new(Unit::Circle)
                .region(region.clone())
                .inside(inside)
                .side(256),
        )
        .unwrap();
        let clearance = |c: DVec2| {
            let to_sites = sites
                .iter()
                .map(|s| s.distance(Metric::L2, c))
                .fold(f64::INFINITY, f64::min);
            let to_boundary = boundary
                .iter()
                .map(|(a, b)| {
                    let t = ((c - *a).dot(*b - *a) / (*b - *a).length_squared()).clamp(0.0, 1.0);
                    c.distance(*a + (*b - *a) * t)
                })
                .fold(f64::INFINITY, f64::min);
            if inside {
                to_sites.min(to_boundary)
            } else {
                to_sites
            }
        };
        let grid = grid_best(lo, hi, h, clearance, allowed);
        let slope = sites
            .iter()
            .map(|s| 1.0 / s.multiplicative)
            .fold(1.0, f64::max);
        let c = DVec2::from(answer.exact.centre);
        assert!(
            allowed(c)
                || boundary.iter().any(|(a, b)| {
                    let t = ((c - *a).dot(*b - *a) / (*b - *a).length_squared()).clamp(0.0, 1.0);
                    c.distance(*a + (*b - *a) * t) < 1e-6
                }),
            "{name}: centre {c} outside the region"
        );
        // The answer's value is true at its centre, and no grid point beats it.
        assert!(
            (clearance(c) - answer.exact.scale).abs() <= 1e-9 * (1.0 + answer.exact.scale),
            "{name}"
        );
        assert!(
            answer.exact.scale >= grid - answer.tolerance - 1e-9
                && answer.exact.scale <= grid + slope * h * 0.75,
            "{name}: {} vs grid {grid}",
            answer.exact.scale
        );
        assert!(
            answer.tolerance <= 1e-6 * (1.0 + answer.exact.scale),
            "{name}: gap {}",
            answer.tolerance
        );
    }
}

#[test]
fn smallest_enclosing_circle_of_segments_circles_and_arcs() {
    use pixgeo::{
        algorithms::homothet::{enclose, EncloseOptions},
        geometry::site::{Shape, Site},
    };
    let machine = machine();
    // Two circles: the enclosing circle spans from -1 to 13 on the x axis.
    let two = [
        Site::new(Shape::Circle {
            center: DVec2::ZERO,
            radius: 1.0,
        }),
        Site::new(Shape::Circle {
            center: DVec2::new(10.0, 0.0),
            radius: 3.0,
        }),
    ];
    let answer = enclose(
        &Backend::Device(&machine),
        &two,
        &EncloseOptions::new(Unit::Circle).side(256),
    )
    .unwrap();
    assert!((answer.exact.scale - 7.0).abs() < 1e-7, "{answer:?}");
    assert!(DVec2::from(answer.exact.centre).distance(DVec2::new(6.0, 0.0)) < 1e-6);
    // Segments: Welzl on their ends.
    let segments = [
        Site::new(Shape::Segment(DVec2::new(0.0, 0.0), DVec2::new(5.0, 9.0))),
        Site::new(Shape::Segment(DVec2::new(12.0, 1.0), DVec2::new(7.0, -4.0))),
        Site::point(DVec2::new(3.0, -6.0)),
    ];
    let ends = [
        DVec2::new(0.0, 0.0),
        DVec2::new(5.0, 9.0),
        DVec2::new(12.0, 1.0),
        DVec2::new(7.0, -4.0),
        DVec2::new(3.0, -6.0),
    ];
    let answer = enclose(
        &Backend::Device(&machine),
        &segments,
        &EncloseOptions::new(Unit::Circle).side(256),
    )
    .unwrap();
    assert!(close(answer.exact.scale, welzl(&ends).radius));
    // Mixed with an arc: no grid centre does better, none much worse.
    let mut mixed = segments.to_vec();
    mixed.push(Site::new(Shape::Arc {
        center: DVec2::new(4.0, 3.0),
        radius: 8.0,
        start: 1.0,
        end: 2.6,
    }));
    mixed.push(Site::new(Shape::Circle {
        center: DVec2::new(10.0, 8.0),
        radius: 2.5,
    }));
    let answer = enclose(
        &Backend::Device(&machine),
        &mixed,
        &EncloseOptions::new(Unit::Circle).side(256),
    )
    .unwrap();
    let farthest = |c: DVec2| {
        let mut far = 0.0f64;
        for s in &mixed {
            // The definition: the farthest of many points along the shape.
            let pts = along(s, 4000);
            far = pts.iter().map(|p| p.distance(c)).fold(far, f64::max);
        }
        far
    };
    let mut grid = f64::INFINITY;
    for j in -40..=60 {
        for i in -20..=60 {
            grid = grid.min(farthest(DVec2::new(i as f64 * 0.25, j as f64 * 0.25)));
        }
    }
    let c = DVec2::from(answer.exact.centre);
    // Dense sampling of the curves reaches the farthest point within 1e-5.
    assert!(
        (farthest(c) - answer.exact.scale).abs() < 1e-5,
        "{answer:?}"
    );
    assert!(
        answer.exact.scale <= grid + 1e-9 && answer.exact.scale >= grid - 0.25,
        "{} vs {grid}",
        answer.exact.scale
    );
    assert!(enclose(
        &Backend::Device(&machine),
        &mixed,
        &EncloseOptions::new(Unit::Circle).k(2).side(64)
    )
    .is_err());
}

#[test]
fn smallest_enclosing_polygon_of_circles_arcs_and_segments_against_sampling() {
    use pixgeo::{
        algorithms::homothet::{enclose, EncloseOptions},
        geometry::site::{Shape, Site},
    };
    let machine = machine();
    let (_, triangle) = polygons()[0];
    let sites = [
        Site::new(Shape::Circle {
            center: DVec2::new(10.0, 10.0),
            radius: 4.0,
        }),
        Site::new(Shape::Arc {
            center: DVec2::new(30.0, 5.0),
            radius: 6.0,
            start: -1.0,
            end: 1.5,
        }),
        Site::new(Shape::Segment(
            DVec2::new(0.0, 25.0),
            DVec2::new(15.0, 30.0),
        )),
        Site::point(DVec2::new(25.0, 28.0)),
    ];
    let answer = enclose(
        &Backend::Device(&machine),
        &sites,
        &EncloseOptions::new(Unit::Polygon(triangle)).side(256),
    )
    .unwrap();
    // The definition: the largest gauge over dense samples of each shape.
    let samples: Vec<DVec2> = sites.iter().flat_map(|s| along(s, 20000)).collect();
    let c = DVec2::from(answer.exact.centre);
    let held = samples
        .iter()
        .map(|p| triangle.of(*p - c))
        .fold(0.0, f64::max);
    assert!(
        (held - answer.exact.scale).abs() < 1e-4 * answer.exact.scale,
        "{held} vs {answer:?}"
    );
    // Twelve points per curve: their optimum (a vertex search) is a lower
    // bound, and within the chords' loss of the true one.
    let coarse: Vec<DVec2> = sites.iter().flat_map(|s| along(s, 12)).collect();
    let (_, sampled) = oracle::smallest_k_homothet(
        &coarse,
        &triangle.vertices,
        |v| triangle.of(v),
        coarse.len(),
    );
    let loss = 6.0 * (1.0 - (TAU / 24.0).cos()) * Metric::Polygon(triangle).euclidean_bounds().1;
    assert!(
        answer.exact.scale >= sampled - 1e-9 && answer.exact.scale <= sampled + loss,
        "{} vs {sampled} (+{loss})",
        answer.exact.scale
    );
}

#[test]
fn largest_empty_polygon_among_obstacles_against_sampled_gauges() {
    use pixgeo::{
        algorithms::homothet::{largest_empty, EmptyOptions},
        geometry::site::{Shape, Site},
    };
    let machine = machine();
    let (_, triangle) = polygons()[0];
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let mut sites: Vec<Site> = uniform(&mut rng, 5, 100.0, 80.0)
        .into_iter()
        .map(Site::point)
        .collect();
    sites.push(Site::new(Shape::Segment(
        DVec2::new(10.0, 60.0),
        DVec2::new(50.0, 40.0),
    )));
    sites.push(Site::new(Shape::Arc {
        center: DVec2::new(70.0, 30.0),
        radius: 10.0,
        start: 0.5,
        end: 3.0,
    }));
    let region = Region {
        rings: vec![vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(100.0, 0.0),
            DVec2::new(100.0, 80.0),
            DVec2::new(0.0, 80.0),
        ]],
    };
    let answer = largest_empty(
        &machine,
        &sites,
        &EmptyOptions::new(Unit::Polygon(triangle))
            .region(region.clone())
            .inside(true)
            .side(256),
    )
    .unwrap();
    // The definition on dense samples of every shape and of the region's edges.
    let mut samples: Vec<DVec2> = sites.iter().flat_map(|s| along(s, 2000)).collect();
    for (a, b) in edges(&region) {
        samples.extend((0..=4000).map(|t| a + (b - a) * (t as f64 / 4000.0)));
    }
    let clearance = |c: DVec2| {
        samples
            .iter()
            .map(|p| triangle.of(*p - c))
            .fold(f64::INFINITY, f64::min)
    };
    let c = DVec2::from(answer.exact.centre);
    // Sampling overestimates a clearance by at most a sample spacing's gauge.
    let spacing = 100.0 / 2000.0 * Metric::Polygon(triangle).euclidean_bounds().1;
    assert!(
        (clearance(c) - answer.exact.scale).abs() <= spacing,
        "{} vs {}",
        clearance(c),
        answer.exact.scale
    );
    let grid = grid_best(DVec2::ZERO, DVec2::new(100.0, 80.0), 1.0, clearance, |c| {
        region.contains(c)
    });
    assert!(
        answer.exact.scale >= grid - spacing,
        "{} vs grid {grid}",
        answer.exact.scale
    );
    assert!(
        answer.tolerance <= 1e-6 * (1.0 + answer.exact.scale),
        "gap {}",
        answer.tolerance
    );
}

#[test]
fn smallest_enclosing_star_of_segments_and_circles_against_the_definition() {
    use pixgeo::{
        algorithms::homothet::{enclose, EncloseOptions},
        geometry::site::{Shape, Site},
    };
    let machine = machine();
    let (_, star) = polygons()[1];
    let sites = [
        Site::new(Shape::Segment(DVec2::new(0.0, 0.0), DVec2::new(20.0, 6.0))),
        Site::new(Shape::Circle {
            center: DVec2::new(8.0, 18.0),
            radius: 3.0,
        }),
        Site::new(Shape::Arc {
            center: DVec2::new(22.0, 20.0),
            radius: 5.0,
            start: 2.0,
            end: 4.5,
        }),
        Site::point(DVec2::new(-4.0, 12.0)),
    ];
    let answer = enclose(
        &Backend::Device(&machine),
        &sites,
        &EncloseOptions::new(Unit::Polygon(star)).side(256),
    )
    .unwrap();
    let samples: Vec<DVec2> = sites.iter().flat_map(|s| along(s, 3000)).collect();
    let held = |c: DVec2| samples.iter().map(|p| star.of(*p - c)).fold(0.0, f64::max);
    let c = DVec2::from(answer.exact.centre);
    assert!(
        (held(c) - answer.exact.scale).abs() < 1e-3 * answer.exact.scale,
        "{} vs {answer:?}",
        held(c)
    );
    // No centre on a grid around it holds the samples with a smaller star.
    let slope = Metric::Polygon(star).euclidean_bounds().1 * 4.0;
    let mut best = f64::INFINITY;
    for j in -20..=20 {
        for i in -20..=20 {
            best = best.min(held(c + DVec2::new(i as f64, j as f64) * 0.5));
        }
    }
    assert!(
        answer.exact.scale <= best + 1e-9,
        "{} vs grid {best}",
        answer.exact.scale
    );
    assert!(
        answer.exact.scale >= best - slope * 0.5,
        "{} vs grid {best}",
        answer.exact.scale
    );
}
