//! Alpha hulls (thesis ch. 6) against the definitions evaluated per pixel
//! centre: the union of empty discs (α < 0), the intersection of holding discs
//! (α > 0), the convex hull (α = 0).

use glam::DVec2;
use pixgeo::{
    algorithms::alpha_hull::{alpha_hull, class, AlphaHull, AlphaMethod, AlphaOptions, HullMethod},
    Error, Invalid,
};
use pixgeo_reference::alpha_hull::{EmptyDiscs, HoldingDiscs};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::common::{machine, uniform};

const SIDE: u32 = 96;

fn inputs() -> Vec<(&'static str, Vec<DVec2>)> {
    let mut rng = ChaCha8Rng::seed_from_u64(61);
    let mut duplicates = uniform(&mut rng, 12, 100.0, 80.0);
    duplicates.extend(duplicates.clone());
    // Sets of any size fill the picture: the same shape far below 1e-9.
    let tiny = uniform(&mut rng, 30, 100.0, 100.0)
        .into_iter()
        .map(|p| p * 1e-12)
        .collect();
    vec![
        ("uniform", uniform(&mut rng, 30, 100.0, 100.0)),
        ("uniform at 1e-12", tiny),
        ("duplicates", duplicates),
        (
            "collinear",
            (0..9)
                .map(|i| DVec2::new(10.0 + 9.5 * i as f64, 20.0 + 6.0 * i as f64))
                .collect(),
        ),
        (
            "lattice",
            (0..25)
                .map(|k| DVec2::new((k % 5 * 20) as f64, (k / 5 * 20) as f64))
                .collect(),
        ),
    ]
}

/// Every pixel centre's world point, class and distance (pixels) to the
/// picture border.
fn pixels(hull: &AlphaHull) -> impl Iterator<Item = (DVec2, u8, f64)> + '_ {
    let (w, h) = (hull.width as usize, hull.height as usize);
    hull.pixels.iter().enumerate().map(move |(k, &c)| {
        let (i, j) = ((k % w) as f64, (k / w) as f64);
        let border = i.min(j).min(w as f64 - 1.0 - i).min(h as f64 - 1.0 - j) + 0.5;
        (hull.frame.to_world(DVec2::new(i, j)), c, border)
    })
}

#[test]
fn negative_alpha_lies_between_the_definition_and_its_pixel_bound() {
    let machine = machine();
    for (name, sites) in inputs() {
        // Radii in the sites' own units.
        let unit = if name.ends_with("1e-12") { 1e-12 } else { 1.0 };
        for r in [7.3 * unit, 16.9 * unit] {
            let hull =
                alpha_hull(&machine, &sites, &AlphaOptions::new(-1.0 / r).side(SIDE)).unwrap();
            let tau = 1e-3 / hull.frame.scale;
            let h = std::f64::consts::FRAC_1_SQRT_2 / hull.frame.scale;
            let exact = EmptyDiscs::new(&sites, r);
            let shrunk = EmptyDiscs::new(&sites, r + h);
            let (mut outside, mut inside) = (0, 0);
            for (x, c, border) in pixels(&hull) {
                if c == class::INSIDE {
                    inside += 1;
                    // Away from the border, every disc of radius r - h around a
                    // centre r + h from all sites is drawn.
                    if border >= r * hull.frame.scale + 1.0 {
                        assert!(
                            shrunk.margin(x) <= 2.0 * h + tau,
                            "{name} r {r}: {x} inside, though clearly in an empty disc"
                        );
                    }
                } else {
                    outside += 1;
                    assert!(
                        exact.margin(x) > -tau,
                        "{name} r {r}: {x} erased, though no empty disc holds it"
                    );
                }
            }
            assert!(outside > 0, "{name}: something is erased");
            assert_eq!(hull.inside, inside);
            assert_eq!(hull.method, HullMethod::Envelope);
            if name.starts_with("uniform") {
                assert!(inside > 0, "{name} r {r}: a hull is left");
            }
        }
    }
}

#[test]
fn positive_alpha_with_the_hull_walk_is_the_definition() {
    let machine = machine();
    for (name, sites) in inputs() {
        let mec = pixgeo_reference::homothet::welzl(&sites).radius;
        // Up to discs so large that their caps are thinner than the picture resolves
        // (computed as the convex hull).
        for factor in [1.0, 1.2, 3.0, 1e2, 1e3, 1e4, 1e5, 1e7] {
            let radius = mec * factor;
            let hull = alpha_hull(
                &machine,
                &sites,
                &AlphaOptions::new(1.0 / radius).side(SIDE),
            )
            .unwrap();
            let tau = 1e-3 / hull.frame.scale;
            let oracle = HoldingDiscs::new(&sites, radius * (1.0 + 1e-12));
            let mut checked = 0;
            for (x, c, _) in pixels(&hull) {
                let margin = oracle.margin(x);
                if margin.abs() < tau {
                    continue;
                }
                checked += 1;
                assert_eq!(
                    c == class::INSIDE,
                    margin > 0.0,
                    "{name} R = {factor} x mec: pixel {x} margin {margin}"
                );
            }
            assert!(checked > hull.pixels.len() / 2);
            // Collinear sites under huge discs make a lens thinner than a pixel.
            assert!(
                hull.inside > 0 || name == "collinear",
                "{name}: the hull has pixels"
            );
            assert!(!hull.boundary_sites.is_empty());
        }
    }
}

#[test]
fn positive_alpha_by_pixels_alone_lies_between_the_definition_and_its_bound() {
    let machine = machine();
    for (name, sites) in inputs() {
        let mec = pixgeo_reference::homothet::welzl(&sites).radius;
        for factor in [1.1, 2.0, 1e3, 1e5] {
            let radius = mec * factor;
            let hull = match alpha_hull(
                &machine,
                &sites,
                &AlphaOptions::new(1.0 / radius)
                    .method(AlphaMethod::Pixels)
                    .side(SIDE),
            ) {
                Ok(hull) => hull,
                // Discs far larger than the sites leave their hull under a pixel.
                Err(e) if factor >= 1e3 => {
                    assert!(e.to_string().contains("use the hull method"), "{e}");
                    continue;
                }
                Err(e) => panic!("{name} {factor}: {e}"),
            };
            // Caps thinner than the picture resolves: the convex hull, exactly.
            assert!(
                hull.method == HullMethod::Pixels
                    || (factor >= 1e3 && hull.method == HullMethod::Convex)
            );
            let tau = 1e-3 / hull.frame.scale;
            let h = std::f64::consts::FRAC_1_SQRT_2 / hull.frame.scale;
            let exact = HoldingDiscs::new(&sites, radius);
            let grown = HoldingDiscs::new(&sites, radius - h);
            for (x, c, _) in pixels(&hull) {
                if c == class::INSIDE {
                    assert!(
                        grown.margin(x) + 2.0 * h > -tau,
                        "{name} {factor}: {x} inside beyond the pixel bound"
                    );
                } else {
                    assert!(
                        exact.margin(x) < tau,
                        "{name} {factor}: {x} outside, though every holding disc holds it"
                    );
                }
            }
            // Collinear sites' convex hull holds no pixel centre.
            assert!(hull.inside > 0 || (name == "collinear" && hull.method == HullMethod::Convex));
        }
    }
}

#[test]
fn alpha_zero_is_the_convex_hull() {
    let machine = machine();
    for (name, sites) in inputs() {
        let hull = alpha_hull(&machine, &sites, &AlphaOptions::new(0.0).side(SIDE)).unwrap();
        assert_eq!(hull.method, HullMethod::Convex);
        let corners: Vec<DVec2> = hull
            .boundary_sites
            .iter()
            .map(|&i| sites[i as usize])
            .collect();
        let tau = 1e-3 / hull.frame.scale;
        for (x, c, _) in pixels(&hull) {
            // Signed distance inside every edge (counter-clockwise).
            let depth = (0..corners.len())
                .map(|k| {
                    let (a, b) = (corners[k], corners[(k + 1) % corners.len()]);
                    (b - a).perp_dot(x - a) / a.distance(b)
                })
                .fold(f64::INFINITY, f64::min);
            if corners.len() < 3 || depth.abs() < tau {
                continue;
            }
            assert_eq!(c == class::INSIDE, depth > 0.0, "{name}: pixel {x}");
        }
        if name == "collinear" {
            assert_eq!(hull.boundary_sites.len(), 2);
        }
    }
}

#[test]
fn a_radius_below_the_smallest_enclosing_circle_is_an_error() {
    let machine = machine();
    let sites = [
        DVec2::new(0.0, 0.0),
        DVec2::new(10.0, 0.0),
        DVec2::new(5.0, 8.0),
    ];
    for method in [AlphaMethod::Hull, AlphaMethod::Pixels] {
        let err = alpha_hull(
            &machine,
            &sites,
            &AlphaOptions::new(1.0 / 4.0).method(method).side(SIDE),
        )
        .unwrap_err();
        assert!(
            matches!(&err, Error::InvalidInput(Invalid::OutOfRange(m)) if m.contains("smallest enclosing circle")),
            "{err}"
        );
    }
    let err = alpha_hull(&machine, &sites, &AlphaOptions::new(f64::NAN).side(SIDE)).unwrap_err();
    assert!(matches!(
        err,
        Error::InvalidInput(Invalid::NotFinite { index: None, .. })
    ));
    assert!(alpha_hull(&machine, &[], &AlphaOptions::new(-1.0).side(SIDE)).is_err());
}

#[test]
fn alpha_hulls_grow_with_alpha() {
    // EKS83: α1 <= α2 gives α1-hull ⊆ α2-hull; on one picture the masks nest.
    let machine = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let sites = uniform(&mut rng, 40, 100.0, 100.0);
    let mec = pixgeo_reference::homothet::welzl(&sites).radius;
    let small = alpha_hull(
        &machine,
        &sites,
        &AlphaOptions::new(1.0 / (3.0 * mec)).side(SIDE),
    )
    .unwrap();
    let large = alpha_hull(
        &machine,
        &sites,
        &AlphaOptions::new(1.0 / (1.05 * mec)).side(SIDE),
    )
    .unwrap();
    assert_eq!(small.frame, large.frame);
    assert!(small.inside < large.inside);
    for (a, b) in small.mask().iter().zip(large.mask()) {
        assert!(*a <= b);
    }
}

/// Repeats of a site change no hull: they are merged before any cone or disc
/// is drawn (a million copies took over a minute at α < 0), and the boundary
/// names the first of each.
#[test]
fn repeated_sites_give_the_hull_of_their_positions() {
    let machine = machine();
    let distinct = [
        DVec2::new(3.5, 7.25),
        DVec2::new(10.0, 20.0),
        DVec2::new(40.0, 5.0),
    ];
    let mut repeated = vec![distinct[0]; 500];
    repeated.extend(&distinct[1..]);
    for alpha in [-0.01, 0.0, 0.01] {
        let once = alpha_hull(&machine, &distinct, &AlphaOptions::new(alpha).side(SIDE)).unwrap();
        let many = alpha_hull(&machine, &repeated, &AlphaOptions::new(alpha).side(SIDE)).unwrap();
        assert_eq!(many.pixels, once.pixels, "alpha {alpha}");
        let moved: Vec<u32> = once
            .boundary_sites
            .iter()
            .map(|&i| if i == 0 { 0 } else { i + 499 })
            .collect();
        assert_eq!(many.boundary_sites, moved, "alpha {alpha}");
    }
}

/// A hull far from the origin is the hull near it: the picture is fitted to
/// the set's extent, not its magnitude (at 1e15 the convex hull was 0 pixels,
/// a 2e6-wide box around a triangle 4 wide), and the circles are measured
/// from a hull point (at 1e9, α = 0.4 found no circle: "a pixgeo bug").
#[test]
fn hulls_far_from_the_origin_are_the_hulls_near_it() {
    let machine = machine();
    let triangle = [
        DVec2::new(0.0, 0.0),
        DVec2::new(4.0, 0.0),
        DVec2::new(1.0, 3.0),
    ];
    let hull = |offset: f64, alpha: f64| {
        let sites = triangle.map(|p| p + DVec2::new(offset, 0.0));
        alpha_hull(&machine, &sites, &AlphaOptions::new(alpha).side(64))
            .unwrap_or_else(|e| panic!("{offset:e}, {alpha}: {e}"))
    };
    for alpha in [0.0, 0.4] {
        let near = hull(0.0, alpha);
        for offset in [1e9, 1e15] {
            let far = hull(offset, alpha);
            assert_eq!(
                (far.width, far.height),
                (near.width, near.height),
                "{offset:e}, {alpha}"
            );
            // Circle centres at 1e15 are doubles 0.125 apart: a pixel may move.
            let moved = far.inside.abs_diff(near.inside);
            assert!(
                moved <= 2,
                "{offset:e}, α {alpha}: {} inside, not {}",
                far.inside,
                near.inside
            );
        }
    }
}
