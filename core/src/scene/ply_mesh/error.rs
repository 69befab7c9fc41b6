//! Errors of the PLY mesh reader.

use std::fmt;

/// Where in a PLY file a problem is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PlyPlace {
    /// A 1-based line (header, or body of an ASCII file).
    Line(usize),
    /// A row of an element in a binary body (0-based).
    Row {
        /// Element name.
        element: String,
        /// Row index.
        row: usize,
    },
}

impl fmt::Display for PlyPlace {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Line(l) => write!(f, "line {l}"),
            Self::Row { element, row } => write!(f, "element `{element}` row {row}"),
        }
    }
}

/// A problem in a PLY mesh file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlyMeshError {
    /// The file does not start with `ply`.
    #[error("not a PLY file (no `ply` magic line)")]
    NotPly,
    /// The header has no `end_header` line.
    #[error("header has no `end_header` line")]
    NoEndHeader,
    /// A header line that cannot be understood.
    #[error("{at}: bad header line `{text}`: {reason}")]
    Header {
        /// Where.
        at: PlyPlace,
        /// The line.
        text: String,
        /// Why it was rejected.
        reason: &'static str,
    },
    /// The body ends before every element row was read.
    #[error("{at}: file ends in the middle of the data")]
    Truncated {
        /// Where.
        at: PlyPlace,
    },
    /// A body value that is not a number of its declared type.
    #[error("{at}: `{token}` is not a valid {ty}")]
    BadValue {
        /// Where.
        at: PlyPlace,
        /// The token (ASCII) or a description of the value.
        token: String,
        /// The declared type.
        ty: &'static str,
    },
    /// A required property is missing.
    #[error("element `{element}` has no property `{property}`")]
    MissingProperty {
        /// Element name.
        element: &'static str,
        /// Property name(s).
        property: &'static str,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face}: vertex index {index} out of range ({vertices} vertices)")]
    FaceIndex {
        /// Face row.
        face: usize,
        /// The index.
        index: i64,
        /// Number of vertices.
        vertices: usize,
    },
    /// A face with fewer than three vertices.
    #[error("face {face} has {got} vertices, needs 3")]
    ShortFace {
        /// Face row.
        face: usize,
        /// Vertices in it.
        got: usize,
    },
    /// A vertex coordinate that is NaN, infinite or too large for the local frame.
    #[error("vertex {vertex} is not finite or does not fit the local frame")]
    NonFinite {
        /// Vertex row.
        vertex: usize,
    },
    /// The file has no faces.
    #[error("no faces")]
    NoFaces,
}
