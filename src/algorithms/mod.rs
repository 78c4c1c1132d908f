//! The problems pixgeo solves, each written as passes over the pixel machine.
#![forbid(unsafe_code)]

pub mod alpha_hull;
pub mod area;
pub mod cells;
pub(crate) mod certify;
pub(crate) mod cones;
pub mod delaunay;
pub mod distances;
pub(crate) mod envelope;
pub mod flooding;
pub mod great_circle;
pub mod higher_order;
pub mod homothet;
pub mod interpolate;
pub mod lloyd;
pub mod locate;
pub mod power;
pub mod settle;
pub mod trace;
pub mod transform;
pub mod voronoi;

/// Milliseconds since `since`, for the timings answers report.
pub(crate) fn ms(since: std::time::Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}
