//! The world the simulation runs in: labelled triangle meshes, built-in or loaded.
//!
//! - [`Scene`] (`mesh`): the shared triangle soup with per-triangle objects;
//!   [`SceneBuilder`] / [`MeshPart`] assemble one; `summary` and `check` add
//!   read-only queries and topology checks.
//! - [`reference`]: the procedural, seeded reference scene.
//! - [`terrain`]: ground built around buildings shipped without it.
//! - Scene files (OBJ, PLY, CityJSON) are read and written in [`crate::io`].
//! - [`polygon`]: triangulating polygons with holes (2D and 3D rings).
//! - [`crop`]: one cluster of buildings cut out of a large scene.

mod builder;
mod check;
pub mod crop;
pub(crate) mod indexed;
mod mesh;
mod naming;
pub mod polygon;
pub mod reference;
mod summary;
pub mod terrain;
pub(crate) mod vec3;

pub use builder::{MeshPart, SceneBuilder};
pub use check::{EdgeDefects, SceneCheckError};
pub use crop::{CropError, Cropped, Window, busiest_window, crop_scene};
pub use mesh::{ObjectKind, Scene, SceneObject};
pub use naming::{MaterialClass, UnknownObjects, kind_from_material, kind_from_name};
pub use reference::{REFERENCE_SEED, ReferenceTerrain, reference_scene};
