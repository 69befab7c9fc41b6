//! The shared geometry layer: one implementation of each small geometric
//! concept the pipeline steps use, on the field's crates.
//!
//! - [`eigen`]: the 3×3 symmetric eigen solver (nalgebra).
//! - [`segment`]: point-to-segment projection and distance in the plane (geo).
//! - [`grid`]: the 2D grid frame and the occupancy rasters' morphology.
//! - [`tiled`]: a grid frame's cells stored in tiles only where wanted.
//! - [`ring`]: point-in-polygon for a ring of points (geo).
//! - [`soup`]: a triangle soup as parry3d's `TriMesh`.
//! - [`triangle`]: a triangle's height over a point of its plan.
//! - `shape`: a neighbourhood's moments and eigen-features (line, plane, volume).
//! - `normals`, `planes`: PCA normals of k nearest neighbours and planes grown
//!   on them (the roof check of classification, the roofs of reconstruction).
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
pub mod triangle;
