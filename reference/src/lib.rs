//! CPU implementations of the definitions: the oracles every GPU result is checked
//! against; and `.npy` files written as NumPy writes them.
#![forbid(unsafe_code)]

pub mod alpha_hull;
pub mod area;
pub mod clearing;
pub mod exact;
pub mod flooding;
pub mod higher_order;
pub mod homothet;
pub mod hostile;
pub mod metric;
pub mod npy;
pub mod settle;
pub mod sibson;
pub mod sites;
pub mod voronoi;
