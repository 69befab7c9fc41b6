//! Errors of the PLY mesh reader.

use std::fmt;

use crate::cloud::PlyError;

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
        reason: String,
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
    /// An ASCII row with too few or too many values.
    #[error("{at}: row has {found} values but needs {expected}")]
    RowLength {
        /// Where.
        at: PlyPlace,
        /// Values needed.
        expected: usize,
        /// Values on the line.
        found: usize,
    },
    /// Any other problem the shared PLY reader reports.
    #[error("{0}")]
    Invalid(String),
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

impl PlyMeshError {
    /// Converts an error of the header parser; `data` is the whole file, for
    /// quoting the offending line.
    pub(super) fn from_header(err: PlyError, data: &[u8]) -> Self {
        let header = |line: usize, reason: String| Self::Header {
            at: PlyPlace::Line(line),
            text: line_text(data, line),
            reason,
        };
        match err {
            PlyError::BadMagic => Self::NotPly,
            PlyError::MissingEndHeader => Self::NoEndHeader,
            PlyError::MissingFormat => {
                let line = data
                    .split(|&b| b == b'\n')
                    .position(|l| l.trim_ascii() == b"end_header")
                    .map_or(0, |i| i + 1);
                header(line, "no format line before end_header".into())
            }
            PlyError::UnknownFormat { line, .. } => header(line, "unknown format".into()),
            PlyError::UnsupportedVersion { line, .. } => {
                header(line, "unsupported version (only 1.0)".into())
            }
            PlyError::MalformedHeaderLine { line, reason } => header(line, reason),
            PlyError::UnknownPropertyType { line, .. } => {
                header(line, "unknown property type".into())
            }
            other => Self::Invalid(other.to_string()),
        }
    }

    /// Converts an error of the body readers; `at` is the row being read.
    pub(super) fn from_body(err: PlyError, at: PlyPlace) -> Self {
        match err {
            PlyError::Truncated { .. } => Self::Truncated { at },
            PlyError::BadAsciiNumber {
                line,
                token,
                type_name,
                ..
            } => Self::BadValue {
                at: PlyPlace::Line(line),
                token,
                ty: type_name,
            },
            PlyError::AsciiRowLength {
                line,
                expected,
                found,
                ..
            } => Self::RowLength {
                at: PlyPlace::Line(line),
                expected,
                found,
            },
            PlyError::BadListLength { value, .. } => Self::BadValue {
                at,
                token: value.to_string(),
                ty: "list count",
            },
            other => Self::Invalid(other.to_string()),
        }
    }
}

/// Line `line` (1-based) of `data`, without its line ending.
fn line_text(data: &[u8], line: usize) -> String {
    let raw = data
        .split(|&b| b == b'\n')
        .nth(line.saturating_sub(1))
        .unwrap_or_default();
    String::from_utf8_lossy(raw.strip_suffix(b"\r").unwrap_or(raw)).into_owned()
}
