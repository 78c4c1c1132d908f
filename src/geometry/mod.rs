//! The surfaces pixgeo draws and the bounds that size them: sites and the picture
//! frame, triangle-fan cones with the thesis's error analysis (§3.3–3.4), and the
//! width bounds that truncate the cones (§3.5).
#![forbid(unsafe_code)]

pub(crate) mod bisector;
pub(crate) mod bounded;
pub(crate) mod buckets;
pub mod cell;
pub(crate) mod chain;
pub mod circle;
pub(crate) mod cone;
pub(crate) mod exact;
pub(crate) mod exact_cell;
pub(crate) mod exact_site;
pub(crate) mod flips;
pub(crate) mod frame;
pub(crate) mod mesh;
pub mod metric;
pub mod power;
pub(crate) mod precise;
pub mod predicates;
pub(crate) mod radius;
pub(crate) mod scale;
pub mod seed;
pub mod site;
pub(crate) mod surd;
pub(crate) mod surface;
pub(crate) mod sweep;
pub(crate) mod triangle;
pub mod triangulation;

pub use frame::{check_sites, Frame};
