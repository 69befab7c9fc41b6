//! The ground graph (docs/design.md step 5): ground points downsampled to nodes on
//! a square grid, edges where the vehicle fits (an obstacle map of non-ground
//! points between ground + clearance and ground + vehicle height, inflated by
//! the vehicle's radius) and the slope is drivable, cut to the component
//! reachable from the start.
//!
//! - [`GraphParams`] (`params`), [`GraphError`] (`error`);
//! - `cells`: ground binning on [`crate::geom::tiled::TiledFrame`], [`drivable`] classes; `obstacles`: the obstacle map;
//! - [`GroundGraph`] (`ground_graph`, adjacency in compressed rows), its
//!   searches ([`ShortestPaths`], `search`: multi-source Dijkstra with
//!   predecessors and roots, which `petgraph::algo` does not offer; petgraph
//!   stays for the union-find of the components) and spots found blocked
//!   while driving (`blocked`).

mod blocked;
mod cells;
mod error;
mod ground_graph;
mod obstacles;
mod params;
mod search;

/// Point-in-polygon for region rings (the shared [`crate::geom::ring::contains`]).
pub use crate::geom::ring::contains as polygon_contains;
pub use cells::drivable;
pub use error::GraphError;
pub use ground_graph::{GraphReport, GroundGraph};
pub use params::{GraphParams, MAX_OCCUPANCY_CELLS};
pub use search::{NONE, ShortestPaths};

#[cfg(test)]
mod tests;
