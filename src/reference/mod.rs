//! CPU implementations of the definitions: the oracles every GPU result is checked
//! against.
#![forbid(unsafe_code)]

pub mod voronoi;
