//! The error of loading a scene.

use std::path::PathBuf;

use super::cityjson::CityJsonError;
use super::obj::scene::ObjError;
use super::ply_mesh::PlyMeshError;
use crate::file::FileError;

/// Loading a scene failed; file errors start with the path.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// `reference:SEED` with a seed that is not a whole number.
    #[error(
        "scene `{spec}`: the reference seed must be a whole number (reference or reference:SEED)"
    )]
    BadSeed {
        /// The spec as given.
        spec: String,
    },
    /// The file's extension names no scene format.
    #[error("{}: unknown scene format (expected .obj, .ply, .json / .city.json, .jsonl / .city.jsonl, a directory or comma list of those, or `reference`)", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// Reading or writing the file failed.
    #[error(transparent)]
    Io(#[from] FileError),
    /// The OBJ file is malformed.
    #[error("{}: {source}", path.display())]
    Obj {
        /// The file.
        path: PathBuf,
        /// The cause, with its line.
        #[source]
        source: ObjError,
    },
    /// The PLY mesh file is malformed.
    #[error("{}: {source}", path.display())]
    PlyMesh {
        /// The file.
        path: PathBuf,
        /// The cause, with its line or row.
        #[source]
        source: PlyMeshError,
    },
    /// Two city model tiles name different CRSs.
    #[error(
        "{}: its CRS `{crs}` differs from `{first_crs}` of {}: tiles must share one CRS (reproject one, e.g. with cjio's `crs_reproject`)",
        path.display(),
        first.display()
    )]
    TileCrs {
        /// The first tile that named a CRS.
        first: PathBuf,
        /// Its CRS.
        first_crs: String,
        /// The tile that differs.
        path: PathBuf,
        /// Its CRS.
        crs: String,
    },
    /// A directory given as a scene holds no city model files.
    #[error("{}: no .json / .jsonl city model files in this directory", path.display())]
    NoCityFiles {
        /// The directory.
        path: PathBuf,
    },
    /// A list of several scene files that are not all city models.
    #[error("{}: only CityJSON / CityJSONSeq files load together as tiles of one scene", path.display())]
    NotTile {
        /// The file that is no city model.
        path: PathBuf,
    },
    /// The CityJSON file is malformed.
    #[error("{}: {source}", path.display())]
    CityJson {
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: CityJsonError,
    },
}
