//! The errors of loading a scene or a footprint file.

use std::path::PathBuf;

use super::cityjson::CityJsonError;
use super::obj::scene::ObjError;
use super::ply_mesh::PlyMeshError;
use crate::file::FileError;
use crate::footprint::ParseError;

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

/// A footprint file that could not be read.
#[derive(Debug, thiserror::Error)]
pub enum FootprintError {
    /// The file could not be opened or read.
    #[error(transparent)]
    Io(#[from] FileError),
    /// The file's content is wrong.
    #[error("{path}: {source}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        source: ParseError,
    },
    /// The file names a horizontal CRS other than the cloud's.
    #[error(
        "{path}: the footprints are in {file} but the cloud in {cloud}: reproject the footprints to the cloud's CRS first (e.g. ogr2ogr -t_srs)"
    )]
    CrsMismatch {
        /// The file.
        path: PathBuf,
        /// The CRS the file names.
        file: String,
        /// The cloud's CRS.
        cloud: String,
    },
    /// Neither the extension nor the content says GeoJSON, CityJSON, FlatGeobuf or OBJ.
    #[error(
        "{path}: unknown footprint format (expected GeoJSON .geojson/.json, CityJSON .json/.city.json, CityJSONSeq .jsonl, FlatGeobuf .fgb or OBJ .obj)"
    )]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// GeoPackage is not read (no maintained pure-Rust SQLite reader).
    #[error(
        "{path}: GeoPackage is not read here (it is SQLite, and no maintained pure-Rust SQLite reader exists): convert it first, e.g. `ogr2ogr -f FlatGeobuf footprints.fgb {path}` or `ogr2ogr -f GeoJSON footprints.geojson {path}`"
    )]
    GeoPackage {
        /// The file.
        path: PathBuf,
    },
    /// A CityJSON file (or tiles) that could not be read as a city model.
    #[error("{source}")]
    City {
        /// The city model reader's error (names the file).
        source: Box<SceneError>,
    },
    /// `--footprints model` without a CityJSON scene to take them from.
    #[error(
        "--footprints model takes a CityJSON scene's own buildings, but {}: give the footprint file instead",
        scene.as_ref().map_or_else(|| "there is no scene".to_string(), |s| format!("the scene `{s}` is not CityJSON"))
    )]
    ModelWithoutCity {
        /// The scene spec, when there is one.
        scene: Option<String>,
    },
    /// RFC 7946 GeoJSON (no `crs`) in longitude/latitude over a projected cloud.
    #[error(
        "{path}: the footprints are in longitude/latitude (GeoJSON without a `crs` member is WGS 84, RFC 7946) but the cloud is in {cloud}: reproject them to the cloud's CRS first (e.g. ogr2ogr -t_srs)"
    )]
    LongitudeLatitude {
        /// The file.
        path: PathBuf,
        /// The cloud's CRS.
        cloud: String,
    },
}
