//! pixgeo: planar geometry computed by rendering.
//!
//! A Voronoi diagram is the lower envelope of cones standing on the sites; drawing
//! one cone per site with a depth test paints every pixel with its nearest site
//! (M. Denny, *Algorithmic Geometry via Graphics Hardware*, 2003). pixgeo runs that
//! machine on Vulkan ([`machine`]), builds the surfaces it draws in [`geometry`],
//! and writes the problems on it in [`algorithms`]. Beside it, `pixgeo-io`
//! reads and writes files, `pixgeo-cli` is the command line, `pixgeo-capi` the
//! C library, and the tests check every result against the brute-force
//! definitions of `pixgeo-reference`.
//!
//! # The thesis's model and the machine's types
//!
//! | thesis (ch. 1) | pixgeo |
//! | --- | --- |
//! | picture of p×p pixels, its colour buffers | [`machine::Image`] in a [`machine::Format`] (`R32Uint` ids, `R32Float`/`Rgba32Float` counters) |
//! | z buffer and stencil | an image of [`machine::Format::DepthStencil`] (or `Depth` alone) |
//! | state of the raster pipeline: depth, stencil, blending or logic op, write masks | [`machine::RasterState`], a plain value; each distinct one becomes a cached `VkPipeline` |
//! | stencil reference, blend constant, scissor rectangle | [`machine::DrawParams`], set per draw |
//! | a set of triangles entering the pipeline | [`algorithms::cones::draw_cones`] (instanced fans, one per site) and [`machine::Pass::draw_rect`] |
//! | display list translated per site | one unit fan mesh drawn instanced with a per-site buffer |
//! | cone bases of other metrics (§3.6) | `geometry::chain`: the polygonal chains of L_p circles, polygons as unit balls ([`geometry::metric::Metric::Polygon`]) |
//! | roofs, straw huts, weighted cones (§3.8–3.9) | `geometry::surface` (fan mode) and the per-fragment weighted distance of [`algorithms::voronoi::sites`] (exact mode) |
//! | depth texture (exact distance) | the fragment shader writes the squared distance as depth |
//! | second z buffer z' of the k-th level peeling (§3.7) | the previous level's depth in a storage buffer the fragment shader reads ([`algorithms::higher_order::k_nearest_peeled`]) |
//! | stencil counting equal distances | the stencil's low bits, incremented by the depth test EQUAL |
//! | read back a rectangle | [`machine::Machine::read_u32`], [`machine::Machine::read_f32`] |
//! | minmax, histogram | [`machine::Machine::minmax`], [`machine::Machine::histogram`]: compute passes; only their few numbers reach the host |
//! | the lowest or highest pixel of an envelope (ch. 4–5) | [`machine::Machine::depth_extremes`]: the depth buffer reduced on the device, its extreme's pixel and the pixels near it returned |
//!
//! # Example
//!
//! ```no_run
//! use glam::DVec2;
//! use pixgeo::{algorithms::voronoi::{voronoi, VoronoiOptions}, geometry::Frame, Backend, Machine};
//!
//! let machine = Machine::from_env()?; // PIXGEO_DEVICE, PIXGEO_VALIDATION
//! let sites = [DVec2::new(10.0, 20.0), DVec2::new(40.5, 7.0)];
//! let options = VoronoiOptions::exact(Frame::pixels(64, 48)?);
//! let diagram = voronoi(&Backend::Device(&machine), &sites, &options)?;
//! assert_eq!(diagram.labels[20 * 64 + 10], 0);
//! # Ok::<(), pixgeo::Error>(())
//! ```
//!
//! `unsafe` code lives in the Vulkan layer ([`machine`]) alone, every block
//! with a `// SAFETY:` note; the rest of the crate forbids it.

// Unit tests allocate as they like; the rule on allocations (clippy.toml) is
// the library's.
#![cfg_attr(test, allow(clippy::disallowed_macros, clippy::disallowed_methods))]

pub mod algorithms;
pub mod backend;
mod cancel;
pub mod control;
pub mod error;
pub mod geometry;
pub mod machine;
pub mod memory;
mod names;
mod simple;

pub use backend::{Backend, Chosen, Need};
pub use control::Control;
pub use error::{Error, Invalid, Result};
pub use geometry::{
    metric::Metric,
    site::{Shape, Site},
    Frame,
};
pub use machine::{DeviceChoice, Machine, MachineOptions};
pub use simple::{
    alpha_hull, delaunay, diameter, enclosing_circle, extremal_quadrangle, extremal_triangle,
    furthest, hausdorff, k_nearest, largest_empty_circle, settle, voronoi, with_default_backend,
    with_default_machine,
};

/// What pixgeo's own tests, oracles and benchmarks check against beyond the
/// API: the cone drawing, the fan error bound, the flips and the point
/// buckets. Not part of the API; it changes without notice.
#[doc(hidden)]
pub mod testing {
    pub use crate::algorithms::cones::{
        draw_cones, ConeDraw, ConeInstance, ConePush, SiteBatch, SiteShape, CONE_EXACT, CONE_PEEL,
        SITE_EXACT_BATCH,
    };
    pub use crate::geometry::{
        buckets::PointGrid, cone::bisector_deviation, flips::make_delaunay, frame::site_checks,
    };
}
