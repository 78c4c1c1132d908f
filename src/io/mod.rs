//! Ways in: site files (CSV, JSON, GeoJSON, NumPy) and rasters of features
//! (NumPy arrays, PNGs).
#![forbid(unsafe_code)]

pub mod decoding;
pub(crate) mod json;
pub mod mask;
pub mod npy;
pub mod samples;
pub mod sites;
