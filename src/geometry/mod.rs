//! The surfaces pixgeo draws and the bounds that size them: sites and the picture
//! frame, triangle-fan cones with the thesis's error analysis (§3.3–3.4), and the
//! width bounds that truncate the cones (§3.5).
#![forbid(unsafe_code)]

pub(crate) mod buckets;
pub mod cell;
pub(crate) mod chain;
pub(crate) mod cone;
pub mod exact;
pub(crate) mod flips;
pub(crate) mod frame;
pub(crate) mod mesh;
pub mod metric;
pub(crate) mod radius;
pub(crate) mod scale;
pub mod seed;
pub mod site;
pub(crate) mod surface;
pub(crate) mod sweep;
pub mod triangulation;

pub use exact::{circle, power, predicates};
pub use frame::{check_sites, Frame};
