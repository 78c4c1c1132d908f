//! Ways in and out: site files, rasters of features, NumPy arrays, pictures.
#![forbid(unsafe_code)]

pub mod mask;
pub mod npy;
pub mod output;
pub mod picture;
pub mod sites;
