//! The ground graph (docs/design.md step 5): ground points downsampled to nodes on
//! a square grid, edges where the vehicle fits (an obstacle map of non-ground
//! points between ground + clearance and ground + vehicle height, inflated by
//! the vehicle's radius) and the slope is drivable, cut to the component
//! reachable from the start.
//!
//! - [`GraphParams`] (`params`), [`GraphError`] (`error`);
//! - `cells`: ground binning; `obstacles`: the obstacle map; `grid`: the cell frame;
//! - [`GroundGraph`] (`ground_graph`), its searches ([`ShortestPaths`], `search`),
//!   point-in-polygon (`polygon`) and spots found blocked while driving (`blocked`).

mod blocked;
mod cells;
mod error;
mod grid;
mod ground_graph;
mod obstacles;
mod params;
mod polygon;
mod search;

pub use error::GraphError;
pub use ground_graph::{GraphReport, GroundGraph};
pub use params::{GraphParams, MAX_OCCUPANCY_CELLS};
pub use polygon::contains as polygon_contains;
pub use search::{NONE, ShortestPaths};

#[cfg(test)]
mod tests;
