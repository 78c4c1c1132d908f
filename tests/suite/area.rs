//! Smallest and largest triangles and quadrangles (thesis ch. 7) against
//! exhaustive search in exact arithmetic.

use glam::DVec2;
use pixgeo::{
    algorithms::area::{
        extremal_quadrangle, extremal_triangle, AreaAnswer, AreaOptions, Decided, Extreme,
    },
    Backend, Control, Error, Invalid,
};
use pixgeo_reference::area::{self as oracle, triangle_area};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::{Arc, Mutex};

use crate::common::{machine, uniform};

const SIDE: u32 = 256;

fn inputs() -> Vec<(&'static str, Vec<DVec2>)> {
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let mut duplicates = uniform(&mut rng, 30, 100.0, 100.0);
    duplicates.push(duplicates[4]);
    // Three collinear among random ones: the smallest triangle has area 0.
    let mut collinear = uniform(&mut rng, 40, 100.0, 100.0);
    collinear.extend([
        DVec2::new(10.0, 10.0),
        DVec2::new(20.5, 30.0),
        DVec2::new(31.0, 50.0),
    ]);
    // Nearly collinear: a thin triangle far smaller than a pixel.
    let mut thin = uniform(&mut rng, 40, 100.0, 100.0);
    thin.extend([
        DVec2::new(5.0, 5.0),
        DVec2::new(95.0, 90.0),
        DVec2::new(50.0, 47.500001),
    ]);
    // Many sites in few pixels, to exercise the shared-pixel search.
    let crowded: Vec<DVec2> = (0..50)
        .map(|_| DVec2::new(rng.gen_range(0.0..3.0), rng.gen_range(0.0..3.0)))
        .chain([DVec2::new(100.0, 100.0), DVec2::new(0.0, 100.0)])
        .collect();
    vec![
        ("uniform", uniform(&mut rng, 120, 200.0, 150.0)),
        ("duplicates", duplicates),
        ("collinear", collinear),
        ("thin", thin),
        ("crowded", crowded),
        (
            "lattice",
            (0..49)
                .map(|k| DVec2::new((k % 7 * 10) as f64, (k / 7 * 10) as f64))
                .collect(),
        ),
        // Unit lattices, whose collinear triples once made the pixels propose
        // slivers and hide the unit-area quadrangles.
        ("lattice 5x4", lattice(5, 4, 1.0)),
        ("lattice 10x10", lattice(10, 10, 1.0)),
        ("lattice 6x6 at 1e-7", lattice(6, 6, 1e-7)),
    ]
}

fn lattice(columns: u32, rows: u32, step: f64) -> Vec<DVec2> {
    (0..columns * rows)
        .map(|k| DVec2::new((k % columns) as f64 * step, (k / columns) as f64 * step))
        .collect()
}

/// Both methods: the roofs (on pixels, then exact) and the sweep.
const METHODS: [&str; 2] = ["roofs", "sweep"];

fn triangle_by(method: &str, machine: &pixgeo::Machine, sites: &[DVec2], e: Extreme) -> AreaAnswer {
    match method {
        "roofs" => extremal_triangle(
            &Backend::Device(machine),
            sites,
            &AreaOptions::new(e).side(Some(SIDE)),
        ),
        _ => extremal_triangle(&Backend::Cpu, sites, &AreaOptions::new(e)),
    }
    .unwrap()
}

fn quadrangle_by(
    method: &str,
    machine: &pixgeo::Machine,
    sites: &[DVec2],
    e: Extreme,
) -> AreaAnswer {
    match method {
        "roofs" => extremal_quadrangle(
            &Backend::Device(machine),
            sites,
            &AreaOptions::new(e).side(Some(SIDE)),
        ),
        _ => extremal_quadrangle(&Backend::Cpu, sites, &AreaOptions::new(e)),
    }
    .unwrap()
}

fn assert_close(name: &str, got: f64, want: f64) {
    assert!(
        (got - want).abs() <= 1e-9 * (1.0 + want.abs()),
        "{name}: area {got}, exhaustive search {want}"
    );
}

#[test]
fn triangles_match_exhaustive_search() {
    let machine = machine();
    for (name, sites) in inputs() {
        for (extreme, method) in [Extreme::Smallest, Extreme::Largest]
            .into_iter()
            .flat_map(|e| METHODS.map(|m| (e, m)))
        {
            let largest = extreme == Extreme::Largest;
            let name = &format!("{name} ({method})");
            let answer = triangle_by(method, &machine, &sites, extreme);
            let (_, want) = oracle::extremal_triangle(&sites, largest).unwrap();
            assert_close(name, answer.area, want);
            // The named sites make that area.
            let v: Vec<DVec2> = answer.sites.iter().map(|&i| sites[i as usize]).collect();
            assert_eq!(v.len(), 3);
            assert_close(name, triangle_area(v[0], v[1], v[2]), want);
            let distinct = answer
                .sites
                .iter()
                .collect::<std::collections::HashSet<_>>();
            assert_eq!(distinct.len(), 3, "{name}: {:?}", answer.sites);
            if ["collinear", "duplicates", "lattice"]
                .iter()
                .any(|n| name.starts_with(&format!("{n} ")))
                && !largest
            {
                assert_eq!(answer.area, 0.0, "{name}");
            }
            if name == "uniform (roofs)" && !largest {
                // The thesis's pigeonhole bound (§7.3.3): area <= W H / (n - 2).
                let lo = sites.iter().fold(DVec2::INFINITY, |a, p| a.min(*p));
                let hi = sites.iter().fold(DVec2::NEG_INFINITY, |a, p| a.max(*p));
                let box_area = (hi - lo).x * (hi - lo).y;
                let bound = answer.bound.expect("the roofs were bounded");
                assert!(bound <= box_area / (sites.len() - 2) as f64 * (1.0 + 1e-5));
                assert!(answer.area <= bound);
            }
            if name == "crowded (roofs)" && !largest && answer.decided_by == Decided::Pixels {
                assert!(answer.shared > 0, "{name}: sites share pixels");
            }
        }
    }
}

#[test]
fn quadrangles_match_exhaustive_search() {
    let machine = machine();
    for (name, sites) in inputs() {
        let mut distinct = sites.clone();
        distinct.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
        distinct.dedup();
        for (extreme, method) in [Extreme::Smallest, Extreme::Largest]
            .into_iter()
            .flat_map(|e| METHODS.map(|m| (e, m)))
        {
            let largest = extreme == Extreme::Largest;
            let name = &format!("{name} ({method})");
            let answer = quadrangle_by(method, &machine, &sites, extreme);
            let (_, want) = oracle::extremal_quadrangle(&distinct, largest).unwrap();
            assert_close(name, answer.area, want);
            // p, r, q, l: r right of p -> q, l left of it, areas adding up.
            let v: Vec<DVec2> = answer.sites.iter().map(|&i| sites[i as usize]).collect();
            let (p, r, q, l) = (v[0], v[1], v[2], v[3]);
            assert!(
                oracle::orient(p, q, l) > 0.0 && oracle::orient(p, q, r) < 0.0,
                "{name}"
            );
            assert_close(name, triangle_area(p, q, l) + triangle_area(p, q, r), want);
        }
    }
}

#[test]
fn quadrangles_on_lattice_subsets_match_exhaustive_search() {
    let machine = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for round in 0..12 {
        let full = lattice(6, 5, [1.0, 3.0, 0.25][round % 3]);
        let sites: Vec<DVec2> = full.into_iter().filter(|_| rng.gen_bool(0.6)).collect();
        let Some((_, want)) = oracle::extremal_quadrangle(&sites, false) else {
            continue;
        };
        let answer = extremal_quadrangle(
            &Backend::Device(&machine),
            &sites,
            &AreaOptions::new(Extreme::Smallest).side(Some(64)),
        )
        .unwrap();
        assert_close(&format!("lattice subset {round}"), answer.area, want);
    }
}

#[test]
fn the_rotational_sweep_matches_exhaustive_search() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for n in [3, 10, 80] {
        let sites = uniform(&mut rng, n, 100.0, 100.0);
        let (_, sweep) = oracle::smallest_triangle_sweep(&sites).unwrap();
        let (_, want) = oracle::extremal_triangle(&sites, false).unwrap();
        assert_close("sweep", sweep, want);
    }
}

#[test]
fn the_exact_sweep_orders_directions_rounding_cannot_tell_apart() {
    // A lattice nudged by a few units in the last place: pairs that are
    // parallel, and pairs that miss being parallel by 1e-16, side by side.
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for round in 0..6 {
        let nudge = [0.0, f64::EPSILON, 4.0 * f64::EPSILON][round % 3];
        let sites: Vec<DVec2> = lattice(6, 6, 1.0 + round as f64)
            .into_iter()
            .filter_map(|p| {
                let k = rng.gen_range(-2..=2) as f64;
                rng.gen_bool(0.7)
                    .then(|| p + DVec2::new(p.y * nudge * k, 0.0))
            })
            .collect();
        for extreme in [Extreme::Smallest, Extreme::Largest] {
            let largest = extreme == Extreme::Largest;
            let name = format!("nudged lattice {round} {extreme:?}");
            if let Some((_, want)) = oracle::extremal_triangle(&sites, largest) {
                let got =
                    extremal_triangle(&Backend::Cpu, &sites, &AreaOptions::new(extreme)).unwrap();
                assert_close(&name, got.area, want);
            }
            if let Some((_, want)) = oracle::extremal_quadrangle(&sites, largest) {
                let got =
                    extremal_quadrangle(&Backend::Cpu, &sites, &AreaOptions::new(extreme)).unwrap();
                assert_close(&name, got.area, want);
            }
        }
    }
}

#[test]
fn too_few_sites_are_clear_errors() {
    let machine = machine();
    let two = [DVec2::ZERO, DVec2::ONE];
    let err = extremal_triangle(
        &Backend::Device(&machine),
        &two,
        &AreaOptions::new(Extreme::Smallest).side(Some(SIDE)),
    )
    .unwrap_err();
    assert!(
        matches!(
            &err,
            Error::InvalidInput(Invalid::TooFew {
                needed: 3,
                given: 2,
                ..
            })
        ),
        "{err}"
    );
    let line: Vec<DVec2> = (0..6).map(|i| DVec2::splat(i as f64)).collect();
    let err = extremal_quadrangle(
        &Backend::Device(&machine),
        &line,
        &AreaOptions::new(Extreme::Largest).side(Some(SIDE)),
    )
    .unwrap_err();
    assert!(
        matches!(&err, Error::InvalidInput(Invalid::Degenerate(m)) if m.contains("one line")),
        "{err}"
    );
    // All on a line: every triangle is flat.
    let flat = extremal_triangle(
        &Backend::Device(&machine),
        &line,
        &AreaOptions::new(Extreme::Largest).side(Some(SIDE)),
    )
    .unwrap();
    assert_eq!(flat.area, 0.0);
    assert_eq!(flat.decided_by, Decided::Collinear);
    // All at one point: three distinct sites of area 0.
    let point = [DVec2::ONE; 4];
    for extreme in [Extreme::Smallest, Extreme::Largest] {
        let a = extremal_triangle(
            &Backend::Device(&machine),
            &point,
            &AreaOptions::new(extreme).side(Some(SIDE)),
        )
        .unwrap();
        assert_eq!(a.area, 0.0);
        let set: std::collections::HashSet<_> = a.sites.iter().collect();
        assert_eq!(set.len(), 3, "{:?}", a.sites);
    }
}

#[test]
fn progress_runs_to_the_end_over_many_submissions() {
    // 600 sites: 179700 pairs, drawn in 11 submissions and reduced.
    let machine = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let sites = uniform(&mut rng, 600, 300.0, 300.0);
    let device = Backend::Device(&machine);
    let (reports, options) = reported(AreaOptions::new(Extreme::Smallest).side(Some(256)));
    let with = extremal_quadrangle(&device, &sites, &options).unwrap();
    let seen = reports.lock().unwrap().clone();
    let plain = extremal_quadrangle(
        &Backend::Device(&machine),
        &sites,
        &AreaOptions::new(Extreme::Smallest).side(Some(256)),
    )
    .unwrap();
    assert_eq!((with.area, with.sites), (plain.area, plain.sites));
    let total = 2 * 600 * 599 / 2;
    assert!(seen.iter().all(|&(_, t)| t == total), "{seen:?}");
    assert!(seen.windows(2).all(|w| w[0].0 <= w[1].0), "{seen:?}");
    assert!(seen.len() > 11, "{} reports", seen.len());
    let (reports, options) = reported(AreaOptions::new(Extreme::Largest).side(Some(256)));
    extremal_triangle(&device, &sites, &options).unwrap();
    let seen = reports.lock().unwrap().clone();
    // The largest triangle's roofs are those of the hull's pairs.
    let &(done, total) = seen.last().unwrap();
    assert!(done == total && total > 0, "{seen:?}");
}

type Reports = Arc<Mutex<Vec<(u64, u64)>>>;

/// `options` reporting their progress to the list returned.
fn reported(options: AreaOptions) -> (Reports, AreaOptions) {
    let reports = Reports::default();
    let told = reports.clone();
    let control = Control::new().progress(move |d, t| told.lock().unwrap().push((d, t)));
    (reports, options.control(control))
}

/// Nearly collinear doubles (the issue's four sites on y = 7x in tenths,
/// decimal points along a line, a lattice of tenths one ulp off), at far
/// magnitudes too: the triangle named is an exact extreme, counter-clockwise,
/// and the area printed is its exact area rounded to the nearest double.
#[test]
fn extremal_triangles_are_exact_on_nearly_collinear_doubles() {
    use pixgeo_reference::exact::{
        double_area, extremal_quadrangle_double_area, extremal_triangles, is_nearest,
    };
    let machine = machine();
    let mut rng = ChaCha8Rng::seed_from_u64(29);
    let issue = vec![
        DVec2::new(2.7, 18.9),
        DVec2::new(3.7, 25.9),
        DVec2::new(1.7, 11.9),
        DVec2::new(0.9, 6.3),
    ];
    let line: Vec<DVec2> = (0..9)
        .map(|_| {
            let x = rng.gen_range(1..100) as f64 / 10.0;
            DVec2::new(x, x * 3.3)
        })
        .collect();
    let tenths: Vec<DVec2> = (0..10)
        .map(|k| {
            let p = DVec2::new((k % 4) as f64 * 0.1 + 0.05, (k / 4) as f64 * 0.3 + 0.05);
            let mut nudge =
                |v: f64| f64::from_bits((v.to_bits() as i64 + rng.gen_range(-1..=1)) as u64);
            DVec2::new(nudge(p.x), nudge(p.y))
        })
        .collect();
    let mut cases = vec![("issue", issue.clone()), ("line", line), ("tenths", tenths)];
    let far: Vec<DVec2> = issue.iter().map(|p| *p * 1e150).collect();
    let near: Vec<DVec2> = issue.iter().map(|p| *p * 1e-140).collect();
    cases.push(("issue at 1e150", far));
    cases.push(("issue at 1e-140", near));
    for (name, sites) in cases {
        for extreme in [Extreme::Smallest, Extreme::Largest] {
            let (best, twice) = extremal_triangles(&sites, extreme == Extreme::Largest);
            for method in ["roofs", "sweep"] {
                let answer = triangle_by(method, &machine, &sites, extreme);
                let what = format!("{name} {extreme:?} {method}");
                let mut set = [answer.sites[0], answer.sites[1], answer.sites[2]];
                set.sort_unstable();
                assert!(
                    best.contains(&set),
                    "{what}: {:?} is not among {best:?}",
                    answer.sites
                );
                let half = twice.clone() / num_rational::BigRational::from_integer(2.into());
                assert!(
                    is_nearest(answer.area, &half),
                    "{what}: area {}",
                    answer.area
                );
                let p = |k: usize| sites[answer.sites[k] as usize];
                if twice != num_rational::BigRational::from_integer(0.into()) {
                    let ccw = pixgeo::geometry::predicates::orient(p(0), p(1), p(2)) > 0.0;
                    assert!(ccw, "{what}: {:?} clockwise", answer.sites);
                }
            }
            // Quadrangles: the ring named has the extreme exact area.
            let Some(twice) = extremal_quadrangle_double_area(&sites, extreme == Extreme::Largest)
            else {
                continue;
            };
            for method in ["roofs", "sweep"] {
                let answer = quadrangle_by(method, &machine, &sites, extreme);
                let what = format!("{name} {extreme:?} quadrangle {method}");
                let v = answer
                    .sites
                    .iter()
                    .map(|&k| sites[k as usize])
                    .collect::<Vec<_>>();
                let named = double_area(v[0], v[1], v[2]) + double_area(v[2], v[3], v[0]);
                assert_eq!(named, twice, "{what}: {:?}", answer.sites);
                let half = twice.clone() / num_rational::BigRational::from_integer(2.into());
                assert!(
                    is_nearest(answer.area, &half),
                    "{what}: area {}",
                    answer.area
                );
            }
        }
    }
}
