//! The surfaces pixgeo draws and the bounds that size them: sites and the picture
//! frame, triangle-fan cones with the thesis's error analysis (§3.3–3.4), and the
//! width bounds that truncate the cones (§3.5).
#![forbid(unsafe_code)]

pub mod buckets;
pub mod cell;
pub mod chain;
pub mod circle;
pub mod cone;
pub mod flips;
pub mod frame;
pub mod mesh;
pub mod metric;
pub mod predicates;
pub mod radius;
pub mod scale;
pub mod seed;
pub mod site;
pub mod surface;
pub mod sweep;
pub mod triangle;
pub mod triangulation;

pub use frame::Frame;
