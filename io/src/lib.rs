//! pixgeo's files: site files (CSV, JSON, GeoJSON, NumPy), rasters of
//! features (NumPy arrays, PNGs) and a machine's timeline as a Chrome trace.
//! The core reads no file format; the command line and Python read through
//! here.
#![forbid(unsafe_code)]
// Unit tests allocate as they like; the rule on allocations (clippy.toml) is
// the library's.
#![cfg_attr(test, allow(clippy::disallowed_macros, clippy::disallowed_methods))]

pub mod decoding;
pub(crate) mod json;
pub mod mask;
pub mod npy;
pub mod samples;
pub mod sites;
pub mod trace;
