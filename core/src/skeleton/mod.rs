//! Medial-axis skeleton of a structure's outline (docs/design.md step 3): a
//! constrained Delaunay triangulation of the sampled contour, circumcentres
//! of its inner triangles joined across non-constraint edges, short spurs
//! pruned.
//!
//! - [`graph`] — [`Skeleton`], the graph in xy.
//! - [`medial`] — [`medial_axis`] → [`Skeleton`].
//! - [`prune`] — removal of short leaf branches.

pub mod graph;
pub mod medial;
pub mod prune;

pub use graph::Skeleton;
pub use medial::{SkeletonParams, medial_axis};
