//! Ways in and out: site files, rasters of features, NumPy arrays, GeoTIFFs,
//! pictures, vector cells.
#![forbid(unsafe_code)]

pub mod geotiff;
pub mod mask;
pub mod npy;
pub mod output;
pub mod picture;
pub mod raster;
pub mod sites;
pub mod vector;
