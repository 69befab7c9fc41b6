//! The world the simulation runs in: labelled triangle meshes, built-in or loaded.
//!
//! - [`Scene`] (`mesh`): the shared triangle soup with per-triangle objects;
//!   [`SceneBuilder`] / [`MeshPart`] assemble one; `summary` and `check` add
//!   read-only queries and topology checks.
//! - [`reference`]: the procedural, seeded reference scene.
//! - [`obj`], [`ply_mesh`], [`cityjson`]: scene files; [`load_scene`] picks
//!   one by name or extension.
//! - [`polygon`]: triangulating polygons with holes (2D and 3D rings).
//! - [`crop`]: one cluster of buildings cut out of a large scene;
//!   [`write_obj`] saves a scene so every reader of [`load_scene`] gets it.

mod builder;
mod check;
pub mod cityjson;
pub mod crop;
mod error;
mod indexed;
mod load;
mod mesh;
mod naming;
pub mod obj;
mod obj_write;
pub mod ply_mesh;
pub mod polygon;
pub mod reference;
mod summary;
pub(crate) mod vec3;

pub use builder::{MeshPart, SceneBuilder};
pub use check::{EdgeDefects, SceneCheckError};
pub use cityjson::{
    CityJsonError, CityJsonOptions, CityModel, parse_cityjson, read_city_files,
    read_city_files_and_crs, read_cityjson,
};
pub use crop::{CropError, Cropped, Window, busiest_window, crop_scene};
pub use error::SceneError;
pub use load::{load_scene, load_scene_and_crs};
pub use mesh::{ObjectKind, Scene, SceneObject};
pub use naming::{MaterialClass, UnknownObjects, kind_from_material, kind_from_name};
pub use obj::{ObjError, ObjErrorKind, ObjOptions, parse_obj, read_obj};
pub use obj_write::{obj_text, write_obj};
pub use ply_mesh::{PlyMeshError, parse_ply_mesh, read_ply_mesh};
pub use reference::{REFERENCE_SEED, ReferenceTerrain, reference_scene};
