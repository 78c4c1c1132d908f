//! Input read once: each problem checks its sites where they enter and not
//! again on the way to its answer, on the device and on the CPU, however
//! the problems it uses call one another.

use glam::DVec2;
use pixgeo::{
    algorithms::{
        alpha_hull::{alpha_hull, AlphaMethod, AlphaOptions},
        area::{extremal_quadrangle, extremal_triangle, AreaOptions, Extreme},
        cells::{voronoi_cells, CellsOptions},
        delaunay::{delaunay, DelaunayOptions},
        distances::{diameter, hausdorff, max_distance, HausdorffOptions},
        higher_order::{furthest, k_nearest, k_nearest_peeled, KNearestOptions},
        homothet::{enclose, largest_empty, EmptyOptions, EncloseOptions, Region, Unit},
        interpolate::{interpolate, InterpolateOptions, Method as Natural},
        lloyd::{lloyd, LloydOptions},
        settle::{potential_areas, SettleOptions},
        voronoi::{voronoi, VoronoiOptions},
    },
    geometry::{cell::Rect, metric::Metric, Frame},
    testing::site_checks,
    Backend, Error, Invalid,
};

use crate::common::machine;

/// How many site lists `run` checked.
fn checks<T>(what: &str, run: impl FnOnce() -> pixgeo::Result<T>) -> u64 {
    let before = site_checks();
    run().unwrap_or_else(|e| panic!("{what}: {e}"));
    site_checks() - before
}

#[test]
fn every_problem_checks_its_sites_once() {
    let pooled = machine();
    let m = &*pooled;
    let sites: Vec<DVec2> = (0..40)
        .map(|i| DVec2::new((i * 37 % 61) as f64 * 0.5, (i * 53 % 47) as f64 * 0.6) + 1.0)
        .collect();
    let (a, b) = sites.split_at(20);
    let frame = Frame::pixels(32, 32).unwrap();
    let values: Vec<f64> = (0..sites.len()).map(|i| i as f64).collect();
    let rect = Rect {
        lo: DVec2::ZERO,
        hi: DVec2::splat(32.0),
    };
    let second = KNearestOptions::exact(frame, 2);
    let (lloyds, settle) = (
        LloydOptions::new(frame).iterations(3),
        SettleOptions::new(frame),
    );
    let no_region = Region { rings: Vec::new() };
    let mut wrong = Vec::new();
    let mut once = |what: String, sets: u64, n: u64| {
        if n != sets {
            wrong.push(format!("{what}: {n} checks of {sets} site lists"));
        }
    };
    for (name, on) in [("device", &Backend::Device(m)), ("cpu", &Backend::Cpu)] {
        let mut count = |what: &str, sets: u64, n: u64| once(format!("{name}: {what}"), sets, n);
        let diagram = VoronoiOptions::exact(frame);
        count(
            "voronoi",
            1,
            checks("voronoi", || voronoi(on, &sites, &diagram)),
        );
        let far = || furthest(on, &sites, &frame, Metric::L2);
        count("furthest", 1, checks("furthest", far));
        let mesh = || delaunay(on, &sites, &DelaunayOptions::default());
        count("delaunay", 1, checks("delaunay", mesh));
        count(
            "cells",
            1,
            checks("cells", || {
                voronoi_cells(on, &sites, &CellsOptions::new(rect))
            }),
        );
        count(
            "hausdorff",
            2,
            checks("hausdorff", || {
                hausdorff(on, a, b, &HausdorffOptions::default().side(Some(64)))
            }),
        );
        let circle = || enclose(on, &sites, &EncloseOptions::new(Unit::Circle).side(64));
        count("enclose", 1, checks("enclose", circle));
        for method in [
            Natural::Exact,
            Natural::Linear,
            Natural::Nearest,
            Natural::Discrete,
        ] {
            let run = || interpolate(on, &sites, &values, &InterpolateOptions::new(frame, method));
            count(&format!("{method:?}"), 1, checks("interpolate", run));
        }
        let run = || lloyd(on, &sites, None, &lloyds);
        count("lloyd", 1, checks("lloyd", run));
    }
    let mut count = |what: &str, sets: u64, n: u64| once(what.to_string(), sets, n);
    count(
        "k nearest",
        1,
        checks("k nearest", || {
            k_nearest(&Backend::Device(m), &sites, &second)
        }),
    );
    let run = || k_nearest(&Backend::Cpu, &sites, &KNearestOptions::exact(frame, 2));
    count("k nearest on the cpu", 1, checks("k nearest", run));
    count(
        "peeled",
        1,
        checks("peeled", || k_nearest_peeled(m, &sites, &second)),
    );
    let run = || {
        enclose(
            &Backend::Device(m),
            &sites,
            &EncloseOptions::new(Unit::Circle).k(30).side(64),
        )
    };
    count("enclose 30 of 40", 1, checks("enclose", run));
    let run = || potential_areas(&Backend::Device(m), a, b, &settle);
    count("settle", 2, checks("settle", run));
    let run = || potential_areas(&Backend::Cpu, a, b, &SettleOptions::new(frame));
    count("settle on the cpu", 2, checks("settle", run));
    count(
        "max distance",
        2,
        checks("max distance", || max_distance(m, a, b, None)),
    );
    count(
        "diameter",
        2,
        checks("diameter", || diameter(m, &sites, None)),
    );
    let run = || {
        largest_empty(
            m,
            &sites,
            &EmptyOptions::new(Unit::Circle)
                .region(no_region.clone())
                .side(64),
        )
    };
    count("empty", 1, checks("empty", run));
    for method in [AlphaMethod::Hull, AlphaMethod::Pixels] {
        let run = || alpha_hull(m, &sites, &AlphaOptions::new(0.03).method(method).side(64));
        count(&format!("alpha by {method:?}"), 1, checks("alpha", run));
    }
    let run = || {
        extremal_triangle(
            &Backend::Device(m),
            &sites,
            &AreaOptions::new(Extreme::Smallest).side(Some(64)),
        )
    };
    count("triangle", 1, checks("triangle", run));
    let run = || {
        extremal_quadrangle(
            &Backend::Device(m),
            &sites,
            &AreaOptions::new(Extreme::Largest).side(Some(64)),
        )
    };
    count("quadrangle", 1, checks("quadrangle", run));
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn refused_sites_say_why_by_kind() {
    let options = VoronoiOptions::exact(Frame::pixels(8, 8).unwrap());
    let err = voronoi(&Backend::Cpu, &[] as &[DVec2], &options).unwrap_err();
    let few = matches!(
        err,
        Error::InvalidInput(Invalid::TooFew {
            needed: 1,
            given: 0,
            ..
        })
    );
    assert!(few, "{err}");
    let sites = [DVec2::ZERO, DVec2::ONE, DVec2::new(f64::NAN, 1.0)];
    let err = voronoi(&Backend::Cpu, &sites, &options).unwrap_err();
    let nan = matches!(
        err,
        Error::InvalidInput(Invalid::NotFinite { index: Some(2), .. })
    );
    assert!(nan, "{err}");
    let err = hausdorff(
        &Backend::Cpu,
        &sites[..2],
        &sites,
        &HausdorffOptions::default(),
    )
    .unwrap_err();
    let named = matches!(&err, Error::InvalidInput(Invalid::NotFinite { index: Some(2), message })
        if message.starts_with("second set"));
    assert!(named, "{err}");
}
