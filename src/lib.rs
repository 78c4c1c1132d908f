//! pixgeo: planar geometry computed by rendering.
//!
//! A Voronoi diagram is the lower envelope of cones standing on the sites; drawing
//! one cone per site with a depth test paints every pixel with its nearest site
//! (M. Denny, *Algorithmic Geometry via Graphics Hardware*, 2003). pixgeo runs that
//! machine on Vulkan ([`machine`]), builds the surfaces it draws in [`geometry`],
//! writes the problems on it in [`algorithms`], and checks every result against the
//! CPU definitions in [`reference`].

pub mod algorithms;
pub mod error;
pub mod ffi;
pub mod geometry;
pub mod io;
pub mod machine;
pub mod reference;

pub use error::{Error, Result};
pub use machine::{Machine, MachineOptions};
