//! pixgeo's files: site files (CSV, JSON, GeoJSON, NumPy), rasters of
//! features (NumPy arrays, PNGs), coordinate systems by EPSG code, the
//! writers of answers (arrays, GeoTIFFs, pictures, vector cells, each file
//! whole or not at all) and a machine's timeline as a Chrome trace. The core
//! reads and writes no file format; the command line and Python do it through
//! here.
#![forbid(unsafe_code)]
// Unit tests allocate as they like; the rule on allocations (clippy.toml) is
// the library's.
#![cfg_attr(test, allow(clippy::disallowed_macros, clippy::disallowed_methods))]

// Coordinate systems parse short texts; the writers hold a strip or a tag
// list beside answers already in memory: neither grows with the input.
#[allow(clippy::disallowed_macros, clippy::disallowed_methods)]
pub mod crs;
pub mod decoding;
pub(crate) mod json;
pub mod mask;
pub mod npy;
pub mod samples;
pub mod sites;
pub mod trace;
#[allow(clippy::disallowed_macros, clippy::disallowed_methods)]
pub mod write;
