//! No input panics: the readers on arbitrary bytes, and every public entry
//! point on coordinates from the edges of f64 (NaN, infinities, 1e308,
//! subnormals, repeats, empty sets) returns `Ok` or `Err`, never unwinds.

use pixgeo::Backend;
use std::panic::{catch_unwind, AssertUnwindSafe};

use glam::DVec2;
use pixgeo::{
    algorithms::{
        alpha_hull::{alpha_hull, AlphaOptions},
        area::{extremal_quadrangle, extremal_triangle, AreaOptions, Extreme},
        delaunay::{delaunay, DelaunayOptions},
        distances::{diameter, hausdorff, HausdorffOptions},
        higher_order::{furthest, k_nearest, KNearestOptions},
        homothet::{enclose, largest_empty, EmptyOptions, EncloseOptions, Region, Unit},
        settle::{potential_areas, SettleOptions},
        voronoi::{voronoi, Accuracy, Speedup, VoronoiOptions},
    },
    geometry::{metric::Metric, Frame},
    Machine,
};
use pixgeo_io::sites::{parse_csv, parse_geojson, parse_json, sites_from_array};
use proptest::prelude::*;

/// Coordinates a user may give, ordinary or not.
fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        24 => -10.0..80.0f64,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(1e308),
        1 => Just(-1.7e308),
        1 => Just(5e-324),
        1 => Just(1e-310),
        1 => Just(0.0),
        1 => Just(1e155),
        1 => Just(-1e18),
        2 => -1e12..1e12f64,
    ]
}

/// Small sets, often with repeats of their first point.
fn points() -> impl Strategy<Value = Vec<DVec2>> {
    (
        prop::collection::vec((coordinate(), coordinate()), 0..9),
        0..4usize,
    )
        .prop_map(|(xy, repeats)| {
            let mut v: Vec<DVec2> = xy.into_iter().map(|(x, y)| DVec2::new(x, y)).collect();
            if let Some(&first) = v.first() {
                v.extend(std::iter::repeat_n(first, repeats));
            }
            v
        })
}

fn no_panic<T>(what: &str, input: &impl std::fmt::Debug, call: impl FnOnce() -> T) {
    if catch_unwind(AssertUnwindSafe(call)).is_err() {
        panic!("{what} panicked on {input:?}");
    }
}

fn entry_points(m: &Machine, p: &[DVec2], q: &[DVec2], scalar: f64) {
    let frame = Frame::pixels(24, 20).unwrap();
    no_panic("voronoi", &p, || {
        voronoi(&Backend::Device(m), p, &VoronoiOptions::exact(frame)).map(|_| ())
    });
    no_panic("voronoi fan", &p, || {
        let options = VoronoiOptions::exact(frame)
            .accuracy(Accuracy::FAN)
            .speedup(Speedup::Quadtree);
        voronoi(&Backend::Device(m), p, &options).map(|_| ())
    });
    no_panic("bbox frame", &(p, scalar), || {
        Frame::with_bbox(24, None, [scalar, scalar, scalar.abs() * 2.0 + 1.0, 3.0])
            .and_then(|f| voronoi(&Backend::Device(m), p, &VoronoiOptions::exact(f)).map(|_| ()))
    });
    no_panic("k_nearest", &p, || {
        let options = KNearestOptions::exact(frame, 2);
        k_nearest(&Backend::Device(m), p, &options).map(|_| ())
    });
    no_panic("cpu k_nearest", &p, || {
        k_nearest(
            &Backend::Cpu,
            p,
            &KNearestOptions::exact(frame, 1).metric(Metric::L1),
        )
        .map(|_| ())
    });
    no_panic("furthest", &p, || {
        furthest(&Backend::Device(m), p, &frame, Metric::L2).map(|_| ())
    });
    no_panic("delaunay", &p, || {
        delaunay(&Backend::Device(m), p, &DelaunayOptions::default()).map(|_| ())
    });
    no_panic("hausdorff", &(p, q), || {
        hausdorff(
            &Backend::Device(m),
            p,
            q,
            &HausdorffOptions::default().side(Some(32)),
        )
        .map(|_| ())
    });
    no_panic("diameter", &p, || diameter(m, p, Some(32)).map(|_| ()));
    no_panic("triangle", &p, || {
        extremal_triangle(
            &Backend::Device(m),
            p,
            &AreaOptions::new(Extreme::Smallest).side(Some(32)),
        )
        .map(|_| ())
    });
    no_panic("quadrangle", &p, || {
        extremal_quadrangle(
            &Backend::Device(m),
            p,
            &AreaOptions::new(Extreme::Largest).side(Some(32)),
        )
        .map(|_| ())
    });
    no_panic("alpha hull", &(p, scalar), || {
        alpha_hull(m, p, &AlphaOptions::new(scalar).side(32)).map(|_| ())
    });
    no_panic("enclose", &p, || {
        enclose(
            &Backend::Device(m),
            p,
            &EncloseOptions::new(Unit::Circle).k(1).side(32),
        )
        .map(|_| ())
    });
    no_panic("largest empty", &p, || {
        largest_empty(
            m,
            p,
            &EmptyOptions::new(Unit::Circle)
                .region(Region { rings: Vec::new() })
                .side(32),
        )
        .map(|_| ())
    });
    no_panic("settle", &(p, q), || {
        let options = SettleOptions::new(frame);
        potential_areas(&Backend::Device(m), p, q, &options).map(|_| ())
    });
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn every_entry_point_answers_or_refuses(
        p in points(),
        q in points(),
        scalar in coordinate(),
    ) {
        entry_points(&crate::common::machine(), &p, &q, scalar);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn readers_take_any_bytes(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
        let text = String::from_utf8_lossy(&bytes);
        no_panic("csv", &text, || parse_csv(&text).map(|_| ()));
        no_panic("json", &text, || parse_json(&text).map(|_| ()));
        no_panic("geojson", &text, || parse_geojson(&text).map(|_| ()));
        let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("robustness");
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("sites.npy");
        std::fs::write(&file, &bytes).unwrap();
        no_panic("npy", &bytes, || pixgeo_io::sites::read_general_sites(&file).map(|_| ()));
    }

    #[test]
    fn readers_take_any_text_of_their_grammar(
        text in r#"[-+0-9eE.,xyma#\n \[\]{}":a-zA-Z]{0,120}"#,
    ) {
        no_panic("csv", &text, || parse_csv(&text).map(|_| ()));
        no_panic("json", &text, || parse_json(&text).map(|_| ()));
        no_panic("geojson", &text, || parse_geojson(&text).map(|_| ()));
    }

    #[test]
    fn arrays_of_any_shape(rows in 0..5u64, columns in 0..6u64, values in prop::collection::vec(any::<f64>(), 0..30)) {
        let shape = [rows, columns];
        let n = (rows * columns) as usize;
        if values.len() >= n {
            no_panic("array", &shape, || sites_from_array(&shape, &values[..n]).map(|_| ()));
        }
    }
}
