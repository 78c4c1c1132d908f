//! The core's integration tests, one binary: every problem against its oracle
//! in `pixgeo-reference` (brute force from the definitions), on random and
//! degenerate inputs, with machines shared between tests (`common::machine`).
#![allow(
    clippy::disallowed_macros,
    clippy::disallowed_methods,
    clippy::disallowed_types,
    reason = "the rules on allocations and rationals (clippy.toml) bind the library, not its users; the suite's oracles compute with their own rationals"
)]

mod common;

mod alpha;
mod area;
mod cancel;
mod cells;
mod certified;
mod certified_sites;
mod constructions;
mod crates;
mod delaunay;
mod distances;
mod flooding;
mod great_circle;
mod higher_order;
mod homothet;
mod interpolate;
mod lloyd;
mod machine;
mod magnitudes;
mod one_call;
mod parity;
mod polygon;
mod power;
mod predicates;
mod properties;
mod read_once;
mod robustness;
mod settle;
mod sites;
mod voronoi;
