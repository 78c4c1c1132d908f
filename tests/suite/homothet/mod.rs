//! Smallest enclosing and largest empty homothets (thesis ch. 4, 5) against
//! Welzl's algorithm and exhaustive searches over candidate determining sites.

use pixgeo::Backend;
use std::f64::consts::TAU;

use glam::DVec2;
use pixgeo::{
    algorithms::homothet::{enclose, largest_empty, EmptyOptions, EncloseOptions, Region, Unit},
    geometry::metric::{Gauge, Metric},
};
use pixgeo_reference::homothet::{self as oracle, welzl};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common::{clustered, machine, uniform};

mod clearing;
mod shapes;

fn gauge_of(metric: Metric) -> &'static Gauge {
    match metric {
        Metric::Polygon(g) => g,
        _ => unreachable!("a polygon"),
    }
}

/// A triangle (convex, not symmetric) and a four-pointed star (not convex).
fn polygons() -> Vec<(&'static str, &'static Gauge)> {
    let triangle = [
        DVec2::new(2.0, 0.0),
        DVec2::new(-1.0, 1.5),
        DVec2::new(-0.5, -1.0),
    ];
    let star: Vec<DVec2> = (0..8)
        .map(|k| {
            let a = TAU * k as f64 / 8.0 + 0.1;
            DVec2::new(a.cos(), a.sin()) * if k % 2 == 0 { 1.5 } else { 0.6 }
        })
        .collect();
    vec![
        (
            "triangle",
            gauge_of(Metric::polygon(&triangle, DVec2::ZERO).unwrap()),
        ),
        (
            "star",
            gauge_of(Metric::polygon(&star, DVec2::new(0.05, 0.0)).unwrap()),
        ),
    ]
}

fn inputs() -> Vec<(&'static str, Vec<DVec2>)> {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let cocircular: Vec<DVec2> = (0..12)
        .map(|k| {
            let a = TAU * k as f64 / 12.0;
            DVec2::new(50.0 + 30.0 * a.cos(), 40.0 + 30.0 * a.sin())
        })
        .collect();
    vec![
        ("uniform", uniform(&mut rng, 40, 100.0, 80.0)),
        ("clustered", clustered(&mut rng, 40, 100.0, 80.0)),
        (
            "collinear",
            (0..9)
                .map(|i| DVec2::new(3.0 + 7.0 * i as f64, 5.0 + 2.5 * i as f64))
                .collect(),
        ),
        ("cocircular", cocircular),
        ("two", vec![DVec2::new(1.0, 2.0), DVec2::new(9.0, 7.5)]),
    ]
}

/// Points along a site's shape, `n` steps along each segment, circle and arc:
/// the shape as the definitions in these tests see it.
fn along(site: &pixgeo::geometry::site::Site, n: usize) -> Vec<DVec2> {
    use pixgeo::geometry::site::Shape;
    let t = |k: usize| k as f64 / n as f64;
    match site.shape {
        Shape::Point(p) => vec![p],
        Shape::Segment(a, b) => (0..=n).map(|k| a + (b - a) * t(k)).collect(),
        Shape::Circle { center, radius } => (0..n)
            .map(|k| center + radius * DVec2::from_angle(TAU * t(k)))
            .collect(),
        Shape::Arc {
            center,
            radius,
            start,
            end,
        } => (0..=n)
            .map(|k| center + radius * DVec2::from_angle(start + (end - start) * t(k)))
            .collect(),
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-7 * (1.0 + b.abs())
}

#[test]
fn smallest_enclosing_circle_equals_welzl() {
    let machine = machine();
    for (name, sites) in inputs() {
        let answer = enclose(
            &Backend::Device(&machine),
            &sites,
            &EncloseOptions::new(Unit::Circle).side(256),
        )
        .unwrap();
        let truth = welzl(&sites);
        assert!(
            close(answer.exact.scale, truth.radius),
            "{name}: {} vs Welzl {}",
            answer.exact.scale,
            truth.radius
        );
        assert!(
            DVec2::from(answer.exact.centre).distance(truth.centre) < 1e-6 * (1.0 + truth.radius)
        );
        // The picture's answer is within its own bound, from above.
        assert!(
            answer.pixel.scale >= truth.radius - 1e-3
                && answer.pixel.scale <= truth.radius + answer.pixel_bound + 1e-3,
            "{name}: pixel {} vs {} (bound {})",
            answer.pixel.scale,
            truth.radius,
            answer.pixel_bound
        );
        // Every site the answer names lies on the circle.
        for &s in &answer.exact.sites {
            let d = sites[s as usize].distance(truth.centre);
            assert!(close(d, truth.radius), "{name}: site {s} off the circle");
        }
    }
}

#[test]
fn welzl_is_the_smallest_of_all_determined_circles() {
    for (name, sites) in inputs() {
        let truth = welzl(&sites);
        let (_, r) = oracle::smallest_k_circle(&sites, sites.len());
        assert!(
            close(truth.radius, r),
            "{name}: Welzl {} vs brute force {r}",
            truth.radius
        );
    }
}

#[test]
fn smallest_k_enclosing_circle_against_brute_force() {
    let machine = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let sites = uniform(&mut rng, 14, 60.0, 50.0);
    for k in [1, 2, 5, 9] {
        let answer = enclose(
            &Backend::Device(&machine),
            &sites,
            &EncloseOptions::new(Unit::Circle).k(k).side(256),
        )
        .unwrap();
        let (_, r) = oracle::smallest_k_circle(&sites, k);
        assert!(
            close(answer.exact.scale, r),
            "k = {k}: {} vs {r}",
            answer.exact.scale
        );
    }
}

#[test]
fn smallest_enclosing_polygon_against_brute_force() {
    let machine = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let sites = uniform(&mut rng, 9, 60.0, 50.0);
    for (name, g) in polygons() {
        for k in [sites.len(), 4] {
            let answer = enclose(
                &Backend::Device(&machine),
                &sites,
                &EncloseOptions::new(Unit::Polygon(g)).k(k).side(256),
            )
            .unwrap();
            let (_, truth) = oracle::smallest_k_homothet(&sites, &g.vertices, |v| g.of(v), k);
            assert!(
                close(answer.exact.scale, truth),
                "{name}, k = {k}: {} vs brute force {truth}",
                answer.exact.scale
            );
            // The homothet holds k sites.
            let c = DVec2::from(answer.exact.centre);
            let held = sites
                .iter()
                .filter(|s| g.of(**s - c) <= answer.exact.scale * (1.0 + 1e-9))
                .count();
            assert!(held >= k, "{name}: holds {held} < {k}");
        }
    }
}

fn square_with_hole() -> Region {
    Region {
        rings: vec![
            vec![
                DVec2::new(0.0, 0.0),
                DVec2::new(100.0, 0.0),
                DVec2::new(100.0, 80.0),
                DVec2::new(0.0, 80.0),
            ],
            vec![
                DVec2::new(30.0, 20.0),
                DVec2::new(70.0, 20.0),
                DVec2::new(70.0, 60.0),
                DVec2::new(30.0, 60.0),
            ],
        ],
    }
}

fn edges(region: &Region) -> Vec<(DVec2, DVec2)> {
    region
        .rings
        .iter()
        .flat_map(|r| (0..r.len()).map(move |k| (r[k], r[(k + 1) % r.len()])))
        .collect()
}

#[test]
fn largest_empty_circle_against_brute_force() {
    let machine = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let sites = uniform(&mut rng, 25, 100.0, 80.0);
    let plain = Region::default();
    let holed = square_with_hole();
    for (name, region) in [("bounding box", &plain), ("square with a hole", &holed)] {
        let answer = largest_empty(
            &machine,
            &sites,
            &EmptyOptions::new(Unit::Circle)
                .region(region.clone())
                .side(256),
        )
        .unwrap();
        let truth = brute_empty_circle(&sites, region);
        assert!(
            close(answer.exact.scale, truth),
            "{name}: {} vs brute force {truth}",
            answer.exact.scale
        );
        assert!((answer.pixel.scale - truth).abs() <= answer.pixel_bound + 1e-3);
    }
}

/// The largest empty circle by brute force: centres in `region`, or in the
/// sites' bounding box when it has no rings.
fn brute_empty_circle(sites: &[DVec2], region: &Region) -> f64 {
    let boundary = if region.rings.is_empty() {
        let lo = sites.iter().fold(DVec2::INFINITY, |a, p| a.min(*p));
        let hi = sites.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
        Region {
            rings: vec![vec![lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)]],
        }
    } else {
        region.clone()
    };
    let e = edges(&boundary);
    let on_edge = |c: DVec2| {
        e.iter().any(|(a, b)| {
            let t = ((c - *a).dot(*b - *a) / (*b - *a).length_squared()).clamp(0.0, 1.0);
            c.distance(*a + (*b - *a) * t) < 1e-9
        })
    };
    oracle::largest_empty(
        sites,
        &[],
        |v| v.length(),
        &e,
        |c| boundary.contains(c) || on_edge(c),
    )
    .1
}

/// Pictures from a few pixels (many sites, repeats, to a pixel) to fine ones,
/// and regions that hold the sites or cut some off, so that both pixel stages
/// (the distance transform of the snapped sites, cones where sites lie off the
/// picture) meet clusters, lattices with many equal maxima and collinear sites.
#[test]
fn largest_empty_circle_on_every_kind_of_picture() {
    let machine = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let lattice: Vec<DVec2> = (0..30)
        .map(|k| DVec2::new((k % 6) as f64 * 20.0, (k / 6 % 5) as f64 * 16.0))
        .collect();
    let mut repeats = clustered(&mut rng, 20, 100.0, 80.0);
    repeats.extend(repeats.clone());
    let sets = [
        ("clustered", clustered(&mut rng, 40, 100.0, 80.0)),
        ("lattice", lattice),
        ("repeats", repeats),
        (
            "collinear and one",
            (0..8)
                .map(|i| DVec2::new(10.0 * i as f64, 3.0 * i as f64))
                .chain([DVec2::new(20.0, 60.0)])
                .collect(),
        ),
    ];
    let inner = Region {
        rings: vec![vec![
            DVec2::new(20.0, 10.0),
            DVec2::new(75.0, 15.0),
            DVec2::new(60.0, 55.0),
        ]],
    };
    let wide = Region {
        rings: vec![vec![
            DVec2::new(-30.0, -20.0),
            DVec2::new(130.0, -20.0),
            DVec2::new(130.0, 100.0),
            DVec2::new(-30.0, 100.0),
        ]],
    };
    let regions = [
        ("the box", Region::default()),
        ("a triangle inside", inner),
        ("a wider box", wide),
        ("a square with a hole", square_with_hole()),
    ];
    for (name, sites) in &sets {
        for (place, region) in &regions {
            let truth = brute_empty_circle(sites, region);
            for side in [6, 40, 300] {
                let answer = largest_empty(
                    &machine,
                    sites,
                    &EmptyOptions::new(Unit::Circle)
                        .region(region.clone())
                        .side(side),
                )
                .unwrap_or_else(|e| panic!("{name} in {place} at {side} px: {e}"));
                assert!(
                    close(answer.exact.scale, truth),
                    "{name} in {place} at {side} px: {} vs brute force {truth}",
                    answer.exact.scale
                );
                assert!(
                    (answer.pixel.scale - truth).abs() <= answer.pixel_bound + 1e-9,
                    "{name} in {place} at {side} px: pixel {} vs {truth}, bound {}",
                    answer.pixel.scale,
                    answer.pixel_bound
                );
            }
        }
    }
}

#[test]
fn largest_empty_polygon_against_brute_force() {
    let machine = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let sites = uniform(&mut rng, 8, 100.0, 80.0);
    let region = square_with_hole();
    let e = edges(&region);
    for (name, g) in polygons() {
        let answer = largest_empty(
            &machine,
            &sites,
            &EmptyOptions::new(Unit::Polygon(g))
                .region(region.clone())
                .side(256),
        )
        .unwrap();
        let on_edge = |c: DVec2| {
            e.iter().any(|(a, b)| {
                let t = ((c - *a).dot(*b - *a) / (*b - *a).length_squared()).clamp(0.0, 1.0);
                c.distance(*a + (*b - *a) * t) < 1e-9
            })
        };
        let (_, truth) = oracle::largest_empty(
            &sites,
            &g.vertices,
            |v| g.of(v),
            &e,
            |c| region.contains(c) || on_edge(c),
        );
        assert!(
            close(answer.exact.scale, truth),
            "{name}: {} vs brute force {truth}",
            answer.exact.scale
        );
    }
}

#[test]
fn bad_input_is_an_error() {
    let machine = machine();
    let sites = [DVec2::new(0.0, 0.0), DVec2::new(1.0, 1.0)];
    assert!(enclose(
        &Backend::Device(&machine),
        &sites,
        &EncloseOptions::new(Unit::Circle).k(3).side(64)
    )
    .is_err());
    assert!(enclose(
        &Backend::Device(&machine),
        &[] as &[DVec2],
        &EncloseOptions::new(Unit::Circle).side(64)
    )
    .is_err());
    assert!(enclose(
        &Backend::Device(&machine),
        &[DVec2::new(f64::NAN, 0.0)],
        &EncloseOptions::new(Unit::Circle).side(64)
    )
    .is_err());
    let thin = Region {
        rings: vec![vec![DVec2::ZERO, DVec2::X]],
    };
    assert!(largest_empty(
        &machine,
        &sites,
        &EmptyOptions::new(Unit::Circle)
            .region(thin.clone())
            .side(64)
    )
    .is_err());
    // One site has no bounding box to search.
    let lone = [DVec2::new(5.0, 5.0)];
    assert!(largest_empty(&machine, &lone, &EmptyOptions::new(Unit::Circle).side(64)).is_err());
}

#[test]
fn more_levels_than_kept_are_refused_by_name() {
    // k-enclosing reads the k-th nearest level, of which at most 256 are kept;
    // holding every site reads the furthest-site envelope instead.
    let machine = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let sites = uniform(&mut rng, 300, 100.0, 100.0);
    let e = enclose(
        &Backend::Device(&machine),
        &sites,
        &EncloseOptions::new(Unit::Circle).k(280).side(128),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("at most 256 levels"), "{e}");
    assert!(enclose(
        &Backend::Device(&machine),
        &sites,
        &EncloseOptions::new(Unit::Circle).k(300).side(128)
    )
    .is_ok());
}

/// The circles at far magnitudes and near-degenerate ones: the
/// centre and radius printed are the doubles nearest to the exact ones, and
/// the sites named lie on the exact circle.
#[test]
fn largest_empty_circle_among_points_at_every_magnitude() {
    // Homothets scale with their sites: by a power of two, the answer scales
    // exactly; by 1e±150 and 1e±300 (depths once underflowed: "no empty
    // homothet found"), its radius is the double nearest the circumradius
    // of the three sites it names.
    use num_rational::BigRational;
    use pixgeo_reference::exact::is_nearest_root;
    let machine = machine();
    let quad = [(3.0, 4.0), (4.0, 0.0), (1.0, 0.0), (0.0, 3.0)].map(|(x, y)| DVec2::new(x, y));
    let empty = |sites: &[DVec2]| {
        largest_empty(&machine, sites, &EmptyOptions::new(Unit::Circle).side(256)).unwrap()
    };
    let unit = empty(&quad);
    for k in [-1000, -500, 500, 1000] {
        let f = 2f64.powi(k / 2) * 2f64.powi(k - k / 2);
        let answer = empty(&quad.map(|p| p * f));
        assert_eq!(answer.exact.scale, unit.exact.scale * f, "2^{k}");
        assert_eq!(
            answer.exact.centre,
            unit.exact.centre.map(|c| c * f),
            "2^{k}"
        );
    }
    for f in [1e-150, 1e-300, 1e150, 1e300] {
        let sites = quad.map(|p| p * f);
        let answer = empty(&sites);
        let on: Vec<DVec2> = answer
            .exact
            .sites
            .iter()
            .map(|&i| sites[i as usize])
            .collect();
        assert_eq!(on.len(), 3, "{f:e}: {answer:?}");
        let q = |x: f64| BigRational::from_float(x).unwrap();
        let [a, b, c] = [on[0], on[1], on[2]].map(|p| [q(p.x), q(p.y)]);
        // The circumcentre of a, b, c, exactly.
        let (bx, by) = (&b[0] - &a[0], &b[1] - &a[1]);
        let (cx, cy) = (&c[0] - &a[0], &c[1] - &a[1]);
        let d = BigRational::from_integer(2.into()) * (&bx * &cy - &by * &cx);
        let (b2, c2) = (&bx * &bx + &by * &by, &cx * &cx + &cy * &cy);
        let (ux, uy) = ((&cy * &b2 - &by * &c2) / &d, (&bx * &c2 - &cx * &b2) / &d);
        assert!(
            is_nearest_root(answer.exact.scale, &(&ux * &ux + &uy * &uy)),
            "{f:e}: {answer:?}"
        );
    }
}

#[test]
fn smallest_enclosing_circle_is_exact_at_every_magnitude() {
    use pixgeo_reference::exact::{is_nearest, is_nearest_root, smallest_enclosing_circle};
    let machine = machine();
    let triangle = [
        DVec2::new(3.0, 4.0),
        DVec2::new(4.0, 0.0),
        DVec2::new(1.0, 0.0),
    ];
    let mut cases: Vec<(String, Vec<DVec2>)> = Vec::new();
    for scale in [
        1e-120,
        1e110,
        2f64.powi(-420),
        2f64.powi(200),
        1e-300,
        1e300,
    ] {
        cases.push((
            format!("triangle times {scale:e}"),
            triangle.map(|p| p * scale).to_vec(),
        ));
    }
    cases.push((
        "at 1e15".into(),
        vec![
            DVec2::new(1000000000000092.0, 53.0),
            DVec2::new(1000000000000011.0, 98.0),
            DVec2::new(1000000000000034.0, 26.0),
        ],
    ));
    // Nearly collinear: the middle point one ulp off the line.
    let a = DVec2::new(0.1, 0.7);
    let b = DVec2::new(0.30000000000000004, 2.1);
    cases.push((
        "nearly collinear".into(),
        vec![a, b, DVec2::new(0.2, 1.4000000000000001), (a + b) / 2.0],
    ));
    // Four nearly co-circular points at 1e-9.
    cases.push((
        "nearly co-circular".into(),
        vec![
            DVec2::new(1e-9, 0.0),
            DVec2::new(0.0, 1e-9),
            DVec2::new(-1e-9, 0.0),
            DVec2::new(0.0, -1.0000000000000002e-9),
        ],
    ));
    for (name, sites) in cases {
        let answer = enclose(
            &Backend::Device(&machine),
            &sites,
            &EncloseOptions::new(Unit::Circle).side(256),
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        let (centre, r2) = smallest_enclosing_circle(&sites);
        let [x, y] = answer.exact.centre;
        assert!(
            is_nearest(x, &centre[0]) && is_nearest(y, &centre[1]),
            "{name}: centre {x}, {y}"
        );
        assert!(
            is_nearest_root(answer.exact.scale, &r2),
            "{name}: radius {}",
            answer.exact.scale
        );
    }
}

/// Far from the origin the largest empty circle is the near one moved: four
/// sites 1e15 along x, whose offsets are exact there.
#[test]
fn largest_empty_circle_far_from_the_origin() {
    let machine = machine();
    let near = [
        DVec2::new(3.0, 4.0),
        DVec2::new(4.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(2.0, 1.0),
    ];
    let far: Vec<DVec2> = near.iter().map(|p| *p + DVec2::new(1e15, 0.0)).collect();
    let region = Region::default();
    let a = largest_empty(
        &machine,
        &near,
        &EmptyOptions::new(Unit::Circle)
            .region(region.clone())
            .side(256),
    )
    .unwrap();
    let b = largest_empty(
        &machine,
        &far,
        &EmptyOptions::new(Unit::Circle)
            .region(region.clone())
            .side(256),
    )
    .unwrap();
    assert_eq!(b.exact.scale, a.exact.scale);
    assert_eq!(
        b.exact.centre,
        [a.exact.centre[0] + 1e15, a.exact.centre[1]]
    );
    assert_eq!(b.exact.sites, a.exact.sites);
}

/// Repeats of a site change no enclosing circle; they are merged before the
/// exact tests (10^6 copies on the circle took 7 s of rational arithmetic),
/// and the answer names the first of each.
#[test]
fn smallest_enclosing_circle_of_repeated_sites() {
    let machine = machine();
    let distinct = [
        DVec2::new(3.5, 7.25),
        DVec2::new(10.0, 20.0),
        DVec2::new(40.0, 5.0),
    ];
    let mut repeated = vec![distinct[0]; 1000];
    repeated.extend(&distinct[1..]);
    let once = enclose(
        &Backend::Device(&machine),
        &distinct,
        &EncloseOptions::new(Unit::Circle).side(256),
    )
    .unwrap();
    let many = enclose(
        &Backend::Device(&machine),
        &repeated,
        &EncloseOptions::new(Unit::Circle).side(256),
    )
    .unwrap();
    assert_eq!(many.exact.centre, once.exact.centre);
    assert_eq!(many.exact.scale, once.exact.scale);
    let named = |sites: &[u32]| {
        let mut v = sites.to_vec();
        v.sort();
        v
    };
    assert_eq!(named(&many.exact.sites), [0, 1001]);
    assert_eq!(named(&once.exact.sites), [0, 2]);
}

/// A picture with fewer pixels than the sites is made finer before the exact
/// search: the answer is the one a fine picture gives, where 1000 sites on a
/// 2x2 picture took minutes and over 4 GB.
#[test]
fn largest_empty_circle_on_a_picture_coarser_than_its_sites() {
    let machine = machine();
    let sites = uniform(&mut ChaCha8Rng::seed_from_u64(7), 1000, 1000.0, 1000.0);
    let region = Region::default();
    let coarse = largest_empty(
        &machine,
        &sites,
        &EmptyOptions::new(Unit::Circle)
            .region(region.clone())
            .side(2),
    )
    .unwrap();
    let fine = largest_empty(
        &machine,
        &sites,
        &EmptyOptions::new(Unit::Circle)
            .region(region.clone())
            .side(1024),
    )
    .unwrap();
    assert_eq!(coarse.exact, fine.exact);
    assert!(coarse.width >= 64, "{}", coarse.width);
}

/// The smallest circle holding k of the sites, against every circle through
/// two or three of them in rationals: far from the origin (where float
/// circumcentres lose their digits), on decimal lattices with one-ulp moves
/// and with outliers; the centre and radius printed are the doubles nearest
/// the exact ones.
#[test]
fn smallest_k_enclosing_circle_is_exact() {
    use pixgeo_reference::exact::{is_nearest, is_nearest_root, smallest_k_enclosing_circle};
    let machine = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(48);
    let mut cases: Vec<(String, Vec<DVec2>, usize)> = vec![(
        "at 1e15 with an outlier".into(),
        vec![
            DVec2::new(1000000000000092.0, 53.0),
            DVec2::new(1000000000000011.0, 98.0),
            DVec2::new(1000000000000034.0, 26.0),
            DVec2::new(0.0, 0.0),
        ],
        3,
    )];
    for round in 0..12 {
        let step = [0.1, 0.3, 1.0 / 7.0][round % 3];
        let mut sites: Vec<DVec2> = (0..8)
            .map(|k| DVec2::new((k % 3) as f64, (k / 3) as f64) * step)
            .map(|p| {
                let mut nudge = |v: f64| match v {
                    0.0 => v,
                    _ => f64::from_bits((v.to_bits() as i64 + rng.gen_range(-1..=1)) as u64),
                };
                DVec2::new(nudge(p.x), nudge(p.y))
            })
            .collect();
        sites.push(DVec2::new(5.0, -3.0));
        let k = rng.gen_range(2..8);
        cases.push((format!("lattice {round}"), sites, k));
    }
    for (name, sites, k) in cases {
        let answer = enclose(
            &Backend::Device(&machine),
            &sites,
            &EncloseOptions::new(Unit::Circle).k(k).side(256),
        )
        .unwrap();
        let (centre, r2) = smallest_k_enclosing_circle(&sites, k);
        let [x, y] = answer.exact.centre;
        assert!(
            is_nearest_root(answer.exact.scale, &r2),
            "{name}, k = {k}: radius {}",
            answer.exact.scale
        );
        // Where several circles of that radius hold k sites, any will do.
        let unique = is_nearest(x, &centre[0]) && is_nearest(y, &centre[1]);
        assert!(
            unique || !answer.exact.sites.is_empty(),
            "{name}: centre {x}, {y}"
        );
    }
}

#[test]
fn a_region_far_larger_than_its_sites_answers_right_or_is_refused() {
    // A square of half-side m around three sites near the origin: the largest
    // circle inside it and empty sits in a corner, through the origin and
    // touching two sides, of radius m (2 - √2), whatever the picture can
    // resolve of the sites (from 1e6 they share a pixel): the double nearest
    // it, at every magnitude.
    use num_rational::BigRational;
    use pixgeo::{
        algorithms::homothet::{largest_empty, EmptyOptions},
        geometry::site::{Shape, Site},
    };
    use pixgeo_reference::exact::is_nearest_surd;
    let machine = machine();
    let sites: Vec<Site> = [(0.0, 0.0), (1.0, 1.0), (5.0, 2.0)]
        .into_iter()
        .map(|(x, y)| Site::point(DVec2::new(x, y)))
        .collect();
    let square = |m: f64| Region {
        rings: vec![vec![
            DVec2::new(-m, -m),
            DVec2::new(m, -m),
            DVec2::new(m, m),
            DVec2::new(-m, m),
        ]],
    };
    // Far larger (past 1e75 the refinement's products of coordinates would
    // overflow doubles without a power of two to bring them near 1), then all
    // of it scaled down.
    let cases = [1e3, 1e4, 1e6, 1e10, 1e20, 1e60, 1e80, 1e160, 1e300]
        .map(|m| (1.0, m))
        .into_iter()
        .chain([3e-10, 1e-100, 1e-290].map(|s| (s, 1e3 * s)));
    for (s, m) in cases {
        let scaled: Vec<Site> = sites
            .iter()
            .map(|site| match site.shape {
                Shape::Point(p) => Site::point(p * s),
                _ => unreachable!("points"),
            })
            .collect();
        let answer = largest_empty(
            &machine,
            &scaled,
            &EmptyOptions::new(Unit::Circle)
                .region(square(m))
                .inside(true)
                .side(1024),
        )
        .unwrap();
        // The double nearest m (2 - √2) = 2m - √(2m²), its centre the nearest
        // to (-m + r, -m + r) in the corner nearest (0, 0) and (1, 1)'s
        // far side, and no bound left.
        let m2 = BigRational::from_float(m).unwrap();
        let two = BigRational::from_integer(2.into());
        let (w, minus_one) = (&two * &m2, BigRational::from_integer((-1).into()));
        assert!(
            is_nearest_surd(answer.exact.scale, &w, &minus_one, &(&two * &m2 * &m2)),
            "{m}: {answer:?}"
        );
        assert_eq!(answer.tolerance, 0.0, "{m}: {answer:?}");
    }
    // A corridor: the best centres fill a line, and any of them is exact.
    let corridor = Region {
        rings: vec![vec![
            DVec2::ZERO,
            DVec2::new(100.0, 0.0),
            DVec2::new(100.0, 4.0),
            DVec2::new(0.0, 4.0),
        ]],
    };
    let answer = largest_empty(
        &machine,
        &[Site::point(DVec2::new(50.0, 2.0))],
        &EmptyOptions::new(Unit::Circle)
            .region(corridor.clone())
            .inside(true)
            .side(256),
    )
    .unwrap();
    assert!(
        (answer.exact.scale - 2.0).abs() <= answer.tolerance,
        "{answer:?}"
    );
    assert!(answer.tolerance < 1e-2, "{answer:?}");
    // Where no power of two brings every magnitude near 1 exactly, the
    // refusal names the range.
    let mixed = [Site::point(DVec2::new(0.0, 5e-324)), sites[1], sites[2]];
    let refused = largest_empty(
        &machine,
        &mixed,
        &EmptyOptions::new(Unit::Circle)
            .region(square(1e80))
            .inside(true)
            .side(1024),
    )
    .unwrap_err();
    assert!(refused.to_string().contains("1e75"), "{refused}");
}

/// The smallest enclosing circle and polygons on the CPU alone: the same
/// exact homothet as the device's, on random, co-circular, lattice and
/// repeated sites.
#[test]
fn enclosing_on_the_cpu_is_the_devices_answer() {
    let m = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let square: Vec<DVec2> = [(0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0), (2.0, 2.0)]
        .map(|(x, y)| DVec2::new(x, y))
        .to_vec();
    let lattice: Vec<DVec2> = (0..36)
        .map(|k| DVec2::new((k % 6) as f64 * 0.7, (k / 6) as f64 * 0.3))
        .collect();
    let mut repeats = uniform(&mut rng, 30, 50.0, 40.0);
    repeats.extend(repeats.clone());
    let cases = [
        ("uniform", uniform(&mut rng, 200, 90.0, 70.0)),
        ("square", square),
        ("lattice", lattice),
        ("repeats", repeats),
    ];
    let units: Vec<Unit> = std::iter::once(Unit::Circle)
        .chain(polygons().into_iter().map(|(_, g)| Unit::Polygon(g)))
        .collect();
    for (name, sites) in cases {
        for &unit in &units {
            let device = enclose(
                &Backend::Device(&m),
                &sites,
                &EncloseOptions::new(unit).side(256),
            )
            .unwrap();
            let cpu = enclose(&Backend::Cpu, &sites, &EncloseOptions::new(unit).side(256)).unwrap();
            assert_eq!(device.exact, cpu.exact, "{name} {unit:?}");
        }
        // Holding k of them, equal optima are many: the device alone.
        let error = enclose(
            &Backend::Cpu,
            &sites,
            &EncloseOptions::new(Unit::Circle).k(3).side(256),
        )
        .unwrap_err();
        assert!(error.to_string().contains("holding k"), "{error}");
    }
}

/// The smallest enclosing circle of points in the subnormal range is rounded
/// once, at their magnitude: its centre is the double nearest the exact
/// centre and its radius the double nearest the exact radius.
#[test]
fn enclosing_circles_of_subnormal_points_are_rounded_once() {
    let m = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for _ in 0..20 {
        let points: Vec<DVec2> = (0..5)
            .map(|_| DVec2::new(rng.gen_range(0.0..1.0), rng.gen_range(0.0..1.0)) * 1e-308)
            .collect();
        let (centre, squared) = pixgeo_reference::exact::smallest_enclosing_circle(&points);
        for backend in [Backend::Device(&m), Backend::Cpu] {
            let c = enclose(
                &backend,
                &points,
                &EncloseOptions::new(Unit::Circle).side(64),
            )
            .unwrap()
            .exact;
            for (got, want) in c.centre.iter().zip(&centre) {
                let nearest = pixgeo_reference::exact::is_nearest(*got, want);
                assert!(nearest, "centre {:?} of {points:?}", c.centre);
            }
            let root = pixgeo_reference::exact::is_nearest_root(c.scale, &squared);
            assert!(root, "radius {:e} of {points:?}", c.scale);
        }
    }
}

/// Sites far from the origin along one axis alone are moved near it on that
/// axis: at x = 1e15 beside y near 50, no empty circle was found (the shift
/// asked for exact differences on both axes, and y's are not).
#[test]
fn empty_circles_far_along_one_axis_are_the_ones_near_the_origin() {
    let m = machine();
    let sites = [
        DVec2::new(86.5, 85.686),
        DVec2::new(78.125, 45.183),
        DVec2::new(85.5, 18.99),
    ];
    let none = Region { rings: Vec::new() };
    let near = largest_empty(
        &m,
        &sites,
        &EmptyOptions::new(Unit::Circle)
            .region(none.clone())
            .side(256),
    )
    .unwrap()
    .exact;
    let far: Vec<DVec2> = sites.iter().map(|p| *p + DVec2::new(1e15, 0.0)).collect();
    let far = largest_empty(
        &m,
        &far,
        &EmptyOptions::new(Unit::Circle)
            .region(none.clone())
            .side(256),
    )
    .unwrap()
    .exact;
    assert_eq!(
        (far.scale, far.centre[1], &far.sites),
        (near.scale, near.centre[1], &near.sites)
    );
    assert_eq!(far.centre[0], near.centre[0] + 1e15);
}
