//! Errors of the CityJSON reader.

/// A problem in a CityJSON file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CityJsonError {
    /// The JSON itself is malformed or has the wrong shape (e.g. a vertex
    /// that is not three numbers).
    #[error("line {line}, column {column}: {message}")]
    Json {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What serde_json reported.
        message: String,
    },
    /// The top-level `type` is not `CityJSON`.
    #[error("not a CityJSON file (type is `{found}`)")]
    NotCityJson {
        /// The `type` found.
        found: String,
    },
    /// A version other than 1.x or 2.x.
    #[error(
        "unsupported CityJSON version `{version}` (1.0, 1.1 and 2.0 are read; cjio upgrades older files)"
    )]
    Version {
        /// The version found.
        version: String,
    },
    /// The transform has a zero or non-finite scale or a non-finite translate.
    #[error("transform has a zero or non-finite scale, or a non-finite translate")]
    Transform,
    /// A geometry's `boundaries` do not nest as its type requires.
    #[error("city object `{object}`, geometry {geometry} ({kind}): {reason}")]
    Boundaries {
        /// City object id.
        object: String,
        /// Index of the geometry in the object.
        geometry: usize,
        /// Geometry type.
        kind: String,
        /// What is wrong.
        reason: &'static str,
    },
    /// A boundary refers to a vertex that does not exist.
    #[error("city object `{object}`: vertex index {index} out of range ({vertices} vertices)")]
    VertexIndex {
        /// City object id.
        object: String,
        /// The index.
        index: u64,
        /// Number of vertices.
        vertices: usize,
    },
    /// A vertex that is not finite or does not fit the local frame.
    #[error("vertex {vertex} is not finite or does not fit the local frame")]
    NonFinite {
        /// Vertex index.
        vertex: usize,
    },
    /// No Building or BuildingPart has usable surface geometry.
    #[error(
        "no Building/BuildingPart with Solid, MultiSurface or CompositeSurface geometry ({ground_objects} ground objects): skyground completes buildings, give it a model with buildings"
    )]
    NoBuildings {
        /// Ground objects (roads, land use, relief) found instead.
        ground_objects: usize,
    },
    /// A CityJSONSeq header without `transform` (mandatory: its features'
    /// integer vertices mean nothing without the scale).
    #[error(
        "CityJSONSeq header (line 1) has no `transform`: the features' integer vertices have no scale or translate (CityJSON 2.0 makes it mandatory)"
    )]
    SeqWithoutTransform,
    /// A CityJSONSeq line after the header is not a `CityJSONFeature`.
    #[error(
        "line {line}: a CityJSONSeq line after the header must be a CityJSONFeature (type is `{found}`)"
    )]
    NotFeature {
        /// 1-based line.
        line: usize,
        /// The `type` found.
        found: String,
    },
}
