//! The shared geometry layer: one implementation of each small geometric
//! concept the pipeline steps use, on the field's crates.
//!
//! - [`eigen`]: the 3×3 symmetric eigen solver (nalgebra).
//! - [`segment`]: point-to-segment projection and distance in the plane (geo).
//! - [`grid`]: the 2D grid frame and the occupancy rasters' morphology.
//! - [`tiled`]: a grid frame's cells stored in tiles only where wanted.
//! - [`ring`]: point-in-polygon for a ring of points (geo).
//! - [`soup`]: a triangle soup as parry3d's `TriMesh`.
//! - `fixtures` (tests only): point sets the unit tests share.

pub mod eigen;
#[cfg(test)]
pub(crate) mod fixtures;
pub mod grid;
pub(crate) mod normals;
pub(crate) mod planes;
pub mod ring;
pub mod segment;
pub(crate) mod shape;
pub mod soup;
pub mod tiled;
