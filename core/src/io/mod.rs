//! The file edge of the library: OBJ, PLY meshes, CityJSON, GeoJSON and
//! FlatGeobuf read into scenes, footprints and city models, and scenes and
//! models written back. One folder per format; readers and writers take
//! the path first. Point clouds (LAS/LAZ, PLY points) are [`crate::cloud`]'s.
//!
//! - [`scene`]: [`load_scene`] picks a scene reader by name or extension;
//!   [`SceneError`] (`error`) is what loading a scene can fail with.
//! - [`footprints`]: [`read_footprints`] picks a footprint reader.
//! - [`obj`], [`ply_mesh`], [`cityjson`], [`geojson`], [`flatgeobuf`]: the formats.

pub mod cityjson;
mod error;
pub mod flatgeobuf;
pub mod footprints;
pub mod geojson;
pub mod obj;
pub mod ply_mesh;
pub mod scene;

pub use cityjson::footprints::{cityjson_footprints, parse_cityjson_footprints};
pub use cityjson::{
    CityJsonError, CityJsonOptions, CityModel, parse_cityjson, read_city_files,
    read_city_files_and_crs, read_cityjson,
};
pub use error::{FootprintError, SceneError};
pub use flatgeobuf::parse_fgb;
pub use footprints::{
    MODEL_KEYWORD, SourceFootprints, load_footprints, load_footprints_in, load_given,
    read_footprints, resolve_source,
};
pub use geojson::footprints::{parse_geojson, parse_geojson_with};
pub use obj::footprints::parse_obj_footprints;
pub use obj::scene::{ObjError, ObjErrorKind, ObjOptions, parse_obj, read_obj};
pub use obj::scene_write::{obj_text, write_obj};
pub use ply_mesh::{PlyMeshError, parse_ply_mesh, read_ply_mesh};
pub use scene::{load_scene, load_scene_and_crs};
