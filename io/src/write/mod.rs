//! What the commands write: arrays, rasters and GeoTIFFs, pictures, vector
//! cells, each file appearing whole or not at all.

pub mod geotiff;
pub mod npy;
pub mod output;
pub mod picture;
pub mod raster;
pub mod vector;
