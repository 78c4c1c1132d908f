//! Ways in and out: site files, NumPy arrays, pictures.
#![forbid(unsafe_code)]

pub mod npy;
pub mod output;
pub mod picture;
pub mod sites;
