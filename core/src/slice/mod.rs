//! Multi-layer slice projection (docs/design.md step 3): a building's points cut
//! into horizontal bands, each band's 2D contour, and the slice contours
//! clustered into single structures (podium, towers).
//!
//! - [`raster`] — occupancy grid over xy, closing, connected components.
//! - [`contour`] — boundary rings of an occupancy grid → `MultiPolygon` (holes kept).
//! - [`levels`] — slice heights and per-level contours of one building.
//! - [`structure`] — levels grouped into structures by overlap across heights.

pub mod contour;
pub mod levels;
pub mod raster;
pub mod structure;

pub use contour::occupancy_contour;
pub use levels::{Level, SliceParams, Sliced, slice_building};
pub use raster::Raster;
pub use structure::{Structure, cluster_structures};
