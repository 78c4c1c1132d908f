//! Cancellation of the steps on the CPU: each one, run within a set flag,
//! stops with `Error::Cancelled`, and runs to its answer once the flag is
//! clear. (The device's runs look at their machine's flag instead.)

use pixgeo::Backend;
use std::sync::{
    atomic::{AtomicBool, Ordering},
    Arc,
};

use glam::DVec2;
use pixgeo::{
    algorithms::{
        cells::{voronoi_cells, CellsOptions},
        delaunay::{delaunay, DelaunayOptions},
        homothet::{largest_empty, EmptyOptions, Region, Unit},
        settle::refine,
        voronoi::{voronoi, VoronoiOptions},
    },
    geometry::{cell::Rect, site::Site, Frame},
    Control, Error,
};

use crate::common::machine;

/// Runs `work` within a set flag, then within a clear one: cancelled first,
/// answered second.
fn cancelled_then_answered<T: std::fmt::Debug>(what: &str, work: impl Fn() -> pixgeo::Result<T>) {
    let flag = Arc::new(AtomicBool::new(true));
    let first = Control::new().cancel(flag.clone()).run(&work);
    assert!(matches!(first, Err(Error::Cancelled)), "{what}: {first:?}");
    flag.store(false, Ordering::Relaxed);
    if let Err(e) = Control::new().cancel(flag).run(&work) {
        panic!("{what}: {e}");
    }
}

fn scattered(n: usize) -> Vec<DVec2> {
    (0..n)
        .map(|i| {
            let t = i as f64;
            DVec2::new(
                (t * 0.618_034).fract() * 100.0,
                (t * 0.414_213_7).fract() * 100.0,
            )
        })
        .collect()
}

#[test]
fn every_step_on_the_cpu_stops_when_cancelled() {
    let machine = machine();
    let points = scattered(500);
    cancelled_then_answered("delaunay", || {
        delaunay(
            &Backend::Device(&machine),
            &points,
            &DelaunayOptions::default(),
        )
    });
    let rect = Rect {
        lo: DVec2::ZERO,
        hi: DVec2::splat(100.0),
    };
    cancelled_then_answered("cells", || {
        voronoi_cells(
            &Backend::Device(&machine),
            &points,
            &CellsOptions::new(rect),
        )
    });
    // Refined by a branch and bound among points, inside a square.
    let sites: Vec<Site> = points[..20].iter().map(|&p| Site::point(p)).collect();
    let square = Region {
        rings: vec![vec![
            DVec2::ZERO,
            DVec2::new(100.0, 0.0),
            DVec2::splat(100.0),
            DVec2::new(0.0, 100.0),
        ]],
    };
    cancelled_then_answered("empty", || {
        largest_empty(
            &machine,
            &sites,
            &EmptyOptions::new(Unit::Circle)
                .region(square.clone())
                .inside(true)
                .side(128),
        )
    });
    let frame = Frame::pixels(64, 64).unwrap();
    let rivals = [DVec2::new(10.0, 10.0), DVec2::new(50.0, 40.0)];
    cancelled_then_answered("settle's refinement", || {
        refine(&rivals, &[], &frame, &[64 * 32 + 32])
    });
}

#[test]
fn cells_report_their_progress_to_the_whole() {
    let machine = machine();
    let points = scattered(40_000);
    let rect = Rect {
        lo: DVec2::ZERO,
        hi: DVec2::splat(100.0),
    };
    let reports = Arc::new(std::sync::Mutex::new(Vec::new()));
    let told = reports.clone();
    let control =
        Control::new().progress(move |done, total| told.lock().unwrap().push((done, total)));
    let options = CellsOptions::new(rect).control(control);
    voronoi_cells(&Backend::Device(&machine), &points, &options).unwrap();
    let reports = reports.lock().unwrap().clone();
    // Every 16384 cells, then the whole: rising to the total.
    assert!(reports.len() >= 3, "{reports:?}");
    assert!(reports.windows(2).all(|w| w[0].0 <= w[1].0));
    assert_eq!(reports.last(), Some(&(40_000, 40_000)));
}

#[test]
fn a_voronoi_diagram_reports_its_rows_and_stops_at_its_controls_flag() {
    let points = scattered(300);
    let frame = Frame::with_bbox(96, Some(80), [0.0, 0.0, 120.0, 100.0]).unwrap();
    let reports = Arc::new(std::sync::Mutex::new(Vec::new()));
    let told = reports.clone();
    let flag = Arc::new(AtomicBool::new(true));
    let control = Control::new()
        .progress(move |done, total| told.lock().unwrap().push((done, total)))
        .cancel(flag.clone());
    let options = VoronoiOptions::exact(frame).control(control);
    let first = voronoi(&Backend::Cpu, &points, &options);
    assert!(matches!(first, Err(Error::Cancelled)), "{first:?}");
    flag.store(false, Ordering::Relaxed);
    reports.lock().unwrap().clear();
    let d = voronoi(&Backend::Cpu, &points, &options).unwrap();
    assert_eq!(d.labels.len(), 96 * 80);
    let reports = reports.lock().unwrap().clone();
    assert!(reports.windows(2).all(|w| w[0].0 <= w[1].0), "{reports:?}");
    assert_eq!(reports.last(), Some(&(80, 80)));
}
