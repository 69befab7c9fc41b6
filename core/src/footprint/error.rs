//! Errors of the footprint readers and parameter checks.

use crate::file::FileError;
use std::path::PathBuf;

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
        source: Box<crate::io::SceneError>,
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

/// What is wrong with footprint data (without the file name).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParseError {
    /// No bytes (or only whitespace).
    #[error("the file is empty")]
    Empty,
    /// Not valid JSON.
    #[error("invalid JSON at line {line}, column {column}: {message}")]
    Json {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// serde_json's message.
        message: String,
    },
    /// Valid syntax but not the expected structure.
    #[error("{what}")]
    Shape {
        /// What was expected and found.
        what: String,
    },
    /// Nothing usable was left after skipping bad polygons.
    #[error("no usable footprint ({skipped} polygon(s) skipped{})", first.as_ref().map(|f| format!("; first: {f}")).unwrap_or_default())]
    NoFootprints {
        /// How many polygons were skipped.
        skipped: usize,
        /// Why the first one was skipped.
        first: Option<String>,
    },
}

/// A [`ParseError::Shape`] saying `what`.
pub(crate) fn shape(what: &str) -> ParseError {
    ParseError::Shape {
        what: what.to_string(),
    }
}

/// Why one polygon of a file was skipped (the file still loads).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RingProblem {
    /// Fewer than 3 distinct vertices.
    #[error("ring has {0} distinct vertices (3 or more needed)")]
    TooFewVertices(usize),
    /// GeoJSON rings must end where they start.
    #[error("ring is not closed (last position differs from the first)")]
    NotClosed,
    /// A coordinate is NaN or infinite, or a position has < 2 numbers.
    #[error("a position is not two or three finite numbers")]
    BadPosition,
    /// A geometry that is not a polygon (point, line, null).
    #[error("geometry type `{0}` is not a polygon")]
    NotPolygon(String),
    /// The polygon encloses no area (collinear or fully cancelled).
    #[error("polygon has no area")]
    NoArea,
}

/// One skipped polygon: where and why.
#[derive(Debug, Clone, PartialEq)]
pub struct Skipped {
    /// Which feature / object / face (as in the source).
    pub source: String,
    /// Why.
    pub problem: RingProblem,
}

impl std::fmt::Display for Skipped {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.source, self.problem)
    }
}
